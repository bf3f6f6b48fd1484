//! The squad's pace: a squad walking in formation ([`Leader`], [`Member`]) is slower at the
//! directed level than its leader's hops make it at the discrete level. At the directed level
//! the leader walks at half its speed when it is in contact or a member lags
//! ([`FormationParams::slow_factor`]) and steers round corners with its members in slots; a
//! discrete hop cannot slow down. The calibration measures it: sample squad walks (a leader
//! and two members) at the directed and the discrete level, calm and in contact (a red
//! contact reported to the leader every [`CONTACT_EVERY_S`]), and fits the stretch of the
//! leader's discrete hops at the slow pace from the walks in contact: the median over the
//! walks of the ratio of the directed to the discrete walking time, corrected once by a
//! second round of walks at that stretch (the leader's waits at the nodes do not stretch
//! with its hops). The median, not the ratio of the summed times: in a few walks the
//! discrete squad stalls at a node for minutes, waiting for members bunched on other nodes
//! (a discrete-level artefact that no stretch of the hops corrects), and those walks
//! dominated a sum, leaving the typical walk (the mission's) about 20 % short. The walks in
//! contact are walked again with a VIP in the squad's last slot (the mission's walk back)
//! and evaluated with the fitted stretch ([`SquadFit::escorted`]). The normal pace
//! keeps its plan (`normal = 1`): calm discrete squads are not faster than directed ones
//! (their leader waits at every node), which the calm walks' residuals record. A calibrated
//! discrete leader hops at its pace's stretch
//! ([`vitro_tactical::actuate::troop::discrete::PacedWalkToNode`]).

use crate::trips::{Trip, par_map};
use std::sync::Arc;
use vitro::entity::EntityId;
use vitro::event::Target;
use vitro::sim::Simulation;
use vitro::time::SimTime;
use vitro_behaviour::formation::{FormationParams, LEADER_PROGRAM, Leader, Member, Script};
use vitro_check::CheckError;
use vitro_tactical::arena::Ev;
use vitro_tactical::calibration::{Calibration, Residuals, SquadFit};
use vitro_tactical::entity::Level;
use vitro_tactical::entity::discrete::NodeKind;
use vitro_tactical::model::Tactical;
use vitro_tactical::radio::{Basic, Command, Contact, Message, Signal};
use vitro_tactical::setup::Setup;
use vitro_tactical::types::TroopKind;
use vitro_tactical::world::Side;

/// Members of a sample squad (besides its leader).
pub const MEMBERS: usize = 2;
/// A contact is reported to the leader this often in a walk in contact, seconds.
pub const CONTACT_EVERY_S: f64 = 10.0;
/// Distance of the reported contact from the walk's start, across its first piece, metres.
pub const CONTACT_M: f64 = 80.0;
/// When the walk is ordered, seconds after the start.
const ORDER_S: f64 = 1.0;

/// A sample squad walk: a trooper trip's ends, calm or in contact, with or without an
/// escorted member.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct Walk {
    /// The leader's trip.
    pub trip: Trip,
    /// True if a contact is reported to the leader all the way.
    pub contact: bool,
    /// True if the squad escorts a VIP (unloaded, in the last slot), as on the mission's
    /// walk back.
    pub escort: bool,
}

/// Walks `w` with a squad at `level`; the time from the order to the leader's `arrived`,
/// seconds (`None`: not within the limit).
pub fn walk(setup: &Setup, w: &Walk, level: Level) -> Result<Option<f64>, CheckError> {
    let err = |e: String| CheckError::Scenario {
        scenario: "squad walk".into(),
        message: e,
    };
    let arena = setup.arena();
    let g = arena.roads.of(vitro_site::map::Mode::Walk);
    let node = |n: vitro::env::NodeId| g.graph.node(n).map(|s| s.pos);
    let (Some(a), Some(b)) = (node(w.trip.from), node(w.trip.to)) else {
        return Ok(None);
    };
    let goal = arena.site.to_world(b);
    let heading = libm::atan2(b[1] - a[1], b[0] - a[0]);
    let mut sim: Simulation<Tactical> = Simulation::new(arena, setup.seed);
    let params = FormationParams::default();
    // Ids in creation order: the members first (the escorted one last), then the leader,
    // then the script.
    let kinds: Vec<TroopKind> = (0..MEMBERS)
        .map(|_| TroopKind::Blue)
        .chain(w.escort.then_some(TroopKind::Vip))
        .collect();
    let leader_id = EntityId(kinds.len() as u32);
    let mut ids = Vec::new();
    for k in 0..kinds.len() {
        let m = Member::new(leader_id, params.clone());
        ids.push(
            sim.add_agent(format!("member-{k}"), Box::new(m))
                .map_err(|e| err(e.to_string()))?,
        );
    }
    let leader =
        Leader::new(LEADER_PROGRAM, ids.clone(), params).map_err(|e| err(e.to_string()))?;
    let lid = sim
        .add_agent("leader", Box::new(leader))
        .map_err(|e| err(e.to_string()))?;
    if lid != leader_id {
        return Err(err("the leader's id is not the expected one".into()));
    }
    let mut plan = vec![(
        SimTime::from_secs_f64(ORDER_S),
        lid,
        Basic::from(Command::GoTo(goal)),
    )];
    let limit = 1200.0;
    if w.contact {
        // A red body off to the left of the way out, reported again and again.
        let side = [
            a[0] - CONTACT_M * libm::sin(heading),
            a[1] + CONTACT_M * libm::cos(heading),
        ];
        let pos = sim.env().site.on_ground(side);
        let mut t = ORDER_S;
        while t < limit {
            plan.push((
                SimTime::from_secs_f64(t),
                lid,
                Basic::from(Contact {
                    target: EntityId(u32::MAX),
                    pos,
                    seen_as: Side::Red,
                }),
            ));
            t += CONTACT_EVERY_S;
        }
    }
    let hq = sim
        .add_agent("hq", Box::new(Script::new(plan)))
        .map_err(|e| err(e.to_string()))?;
    for (&id, &kind) in ids.iter().zip(&kinds).chain([(&lid, &TroopKind::Blue)]) {
        sim.env_mut()
            .add_trooper(id, kind, level, w.trip.from, heading)
            .map_err(|e| err(e.to_string()))?;
    }
    for &id in ids.iter().chain([&lid, &hq]) {
        sim.schedule(SimTime::ZERO, Target::Entity(id), Ev::Start)
            .map_err(|e| err(e.to_string()))?;
    }
    let arrived = |s: &Simulation<Tactical>| {
        s.agent(hq)
            .and_then(|a| a.as_any().downcast_ref::<Script>())
            .and_then(|sc| {
                sc.heard
                    .iter()
                    .find(|(_, _, m)| m.read::<Signal>().is_some_and(|s| s.is("arrived")))
                    .map(|(t, _, _)| t.as_secs_f64() - ORDER_S)
            })
    };
    let mut t = 0.0;
    while t < limit {
        t += 5.0;
        sim.run_until(SimTime::from_secs_f64(t));
        if let Some(a) = arrived(&sim) {
            return Ok(Some(a));
        }
    }
    Ok(None)
}

/// The blue trooper trips of `trips` that the fit uses, each walked calm and in contact.
fn walks(trips: &[Trip]) -> Vec<Walk> {
    let blue = trips
        .iter()
        .filter(|t| t.fit && t.kind == NodeKind::Troop(TroopKind::Blue));
    blue.flat_map(|&trip| {
        [false, true].map(|contact| Walk {
            trip,
            contact,
            escort: false,
        })
    })
    .collect()
}

/// Runs needed by [`fit_squad`] for `trips`: each walk at both levels, the walks in
/// contact at the first stretch, then every walk at the calibrated discrete level, and the
/// escorted walks in contact at the directed and at the discrete level without and with
/// the stretches.
pub fn runs_needed(trips: &[Trip]) -> usize {
    let w = walks(trips);
    let contact = w.iter().filter(|w| w.contact).count();
    3 * w.len() + contact + 3 * contact
}

/// The median over the walks that arrived at both levels of the ratio of their concrete
/// to their abstract time (1 with none).
pub fn median_ratio(conc: &[Option<f64>], abs: &[Option<f64>]) -> f64 {
    let r: Vec<f64> = conc
        .iter()
        .zip(abs)
        .filter_map(|(x, y)| match (x, y) {
            (Some(x), Some(y)) if *y > 0.0 => Some(x / y),
            _ => None,
        })
        .collect();
    if r.is_empty() {
        return 1.0;
    }
    vitro_tactical::calibration::median(r)
}

/// The residuals of the walks that arrived at every level: concrete times, abstract ones
/// without and with the stretches.
fn paired(conc: &[Option<f64>], before: &[Option<f64>], after: &[Option<f64>]) -> Residuals {
    let (mut x, mut b, mut a) = (Vec::new(), Vec::new(), Vec::new());
    for ((xc, bd), ad) in conc.iter().zip(before).zip(after) {
        if let (Some(xc), Some(bd), Some(ad)) = (xc, bd, ad) {
            x.push(*xc);
            b.push(*bd);
            a.push(*ad);
        }
    }
    Residuals::of(&x, &b, &a)
}

/// Fits the discrete leader's pace stretches from squad walks over `trips`' blue trooper
/// trips (see the module doc); `cal` is the calibration made so far (its trip fits apply
/// to the discrete walks). `tick` is called after each run.
pub fn fit_squad(
    setup: &Setup,
    trips: &[Trip],
    cal: &Calibration,
    threads: usize,
    tick: &(dyn Fn() + Sync),
) -> Result<Option<SquadFit>, CheckError> {
    let ws = walks(trips);
    if ws.is_empty() {
        return Ok(None);
    }
    // The discrete walks before the squad fit follow the trip fits made so far.
    let mut plain = cal.clone();
    plain.squads.clear();
    let before = Setup {
        calibration: Some(Arc::new(plain)),
        ..setup.clone()
    };
    let jobs: Vec<(usize, Level)> = (0..ws.len())
        .flat_map(|i| [(i, Level::Directed), (i, Level::Discrete)])
        .collect();
    let out = par_map(&jobs, threads, |&(i, l)| walk(&before, &ws[i], l), tick);
    let times: Vec<Option<f64>> = out.into_iter().map(|r| r.ok().flatten()).collect();
    let (mut conc, mut disc) = ([Vec::new(), Vec::new()], [Vec::new(), Vec::new()]);
    for (k, w) in ws.iter().enumerate() {
        let c = usize::from(w.contact);
        conc[c].push(times.get(2 * k).copied().flatten());
        disc[c].push(times.get(2 * k + 1).copied().flatten());
    }
    // The slow pace: the median ratio of the directed to the discrete times of the walks
    // in contact, then once more over the walks at that stretch (the leader's waits at the
    // nodes do not stretch with its hops). The normal pace keeps the plan: calm discrete
    // squads are not faster than directed ones (they wait at every node; the residuals
    // say by how much), and shrinking hops would not remove waits.
    let slow0 = median_ratio(&conc[1], &disc[1]);
    let mut fit = SquadFit {
        level: Level::Discrete.name().into(),
        concrete: Level::Directed.name().into(),
        normal: 1.0,
        slow: slow0,
        walks: ws.len(),
        calm: Residuals::default(),
        contact: Residuals::default(),
        escorted: Residuals::default(),
    };
    let with_fit = |fit: &SquadFit| {
        let mut with = cal.clone();
        with.squads = vec![fit.clone()];
        Setup {
            calibration: Some(Arc::new(with)),
            ..setup.clone()
        }
    };
    let contact: Vec<Walk> = ws.iter().copied().filter(|w| w.contact).collect();
    let first = with_fit(&fit);
    let again: Vec<Option<f64>> = par_map(
        &contact,
        threads,
        |w| walk(&first, w, Level::Discrete),
        tick,
    )
    .into_iter()
    .map(|r| r.ok().flatten())
    .collect();
    fit.slow = (slow0 * median_ratio(&conc[1], &again)).clamp(
        vitro_tactical::calibration::STRETCH_MIN,
        vitro_tactical::calibration::STRETCH_MAX,
    );
    // Every walk again at the calibrated discrete level.
    let checked = with_fit(&fit);
    let after: Vec<Option<f64>> =
        par_map(&ws, threads, |w| walk(&checked, w, Level::Discrete), tick)
            .into_iter()
            .map(|r| r.ok().flatten())
            .collect();
    let mut after_by = [Vec::new(), Vec::new()];
    for (w, a) in ws.iter().zip(after) {
        after_by[usize::from(w.contact)].push(a);
    }
    fit.calm = paired(&conc[0], &disc[0], &after_by[0]);
    fit.contact = paired(&conc[1], &disc[1], &after_by[1]);
    // The walks in contact again with a VIP in the last slot: directed, plain discrete,
    // calibrated discrete (evaluation only: the fit did not see them).
    let escorted: Vec<Walk> = contact
        .iter()
        .map(|w| Walk { escort: true, ..*w })
        .collect();
    let jobs: Vec<(usize, usize)> = (0..escorted.len())
        .flat_map(|i| [(i, 0), (i, 1), (i, 2)])
        .collect();
    let setups = [setup, &before, &checked];
    let levels = [Level::Directed, Level::Discrete, Level::Discrete];
    let e: Vec<Option<f64>> = par_map(
        &jobs,
        threads,
        |&(i, k)| walk(setups[k], &escorted[i], levels[k]),
        tick,
    )
    .into_iter()
    .map(|r| r.ok().flatten())
    .collect();
    let col = |k: usize| -> Vec<Option<f64>> { e.iter().skip(k).step_by(3).copied().collect() };
    fit.escorted = paired(&col(0), &col(1), &col(2));
    Ok(Some(fit))
}

#[cfg(test)]
mod tests {
    use super::median_ratio;

    #[test]
    fn a_walk_that_stalls_does_not_set_the_stretch() {
        // Five walks 1.25 times longer at the concrete level, one where the abstract squad
        // stalled (twice as long as the concrete one), one that did not arrive.
        let conc = [125.0, 250.0, 375.0, 500.0, 625.0, 400.0, 100.0].map(Some);
        let mut abs = [100.0, 200.0, 300.0, 400.0, 500.0, 800.0, 0.0].map(Some);
        abs[6] = None;
        let m = median_ratio(&conc, &abs);
        assert!((m - 1.25).abs() < 1e-12, "{m}");
        // The ratio of the sums would be pulled under 1 by the one stall.
        let (c, a): (f64, f64) = (
            conc[..6].iter().flatten().sum(),
            abs[..6].iter().flatten().sum(),
        );
        assert!(c / a < 1.0);
        assert_eq!(median_ratio(&[], &[]), 1.0);
        assert_eq!(
            median_ratio(&[Some(3.0), Some(1.0)], &[Some(2.0), Some(1.0)]),
            1.25
        );
    }
}
