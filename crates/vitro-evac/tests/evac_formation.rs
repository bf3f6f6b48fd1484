//! The escort of the evacuation mission walks to the VIP and back as a squad in formation
//! (the formation controllers embedded in the mission's troopers): at the discrete and
//! interpolated levels the squad keeps its slots, changes formation with what it sees, takes
//! the VIP in, and the VIP is extracted; a leader shot down mid-walk is replaced.

// Measurements of the outcome (distances, angles, fits), not model code: platform math is
// allowed here (clippy.toml bans it where it could change a trace hash).
#![allow(clippy::disallowed_methods)]

mod common;

use common::{commander, pct, trooper};
use std::collections::{BTreeMap, BTreeSet};
use vitro::entity::EntityId;
use vitro::time::SimTime;
use vitro_behaviour::formation::{Switch, TrackPoint};
use vitro_evac::EvacRun;
use vitro_evac::Mission;
use vitro_evac::agents::commander::Phase;
use vitro_evac::scenario::ScenarioFile;
use vitro_tactical::condition::Status;
use vitro_tactical::scenario::{EntityType, FidelitySpec, Preset, SideSpec};

const SCENARIO: &str = concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../../scenarios/evacuation.toml"
);

/// A house about 80 m (by the streets) from the safehouse's crossroads, town metres.
const VIP_HOUSE: [f64; 2] = [147.1, 64.6];

/// The default mission at `preset`, the VIP waiting at `vip` (town metres).
fn mission(preset: Preset, vip: [f64; 2]) -> EvacRun {
    let mut v = ScenarioFile::validate(SCENARIO).expect("the default scenario validates");
    v.loaded.file.fidelity = FidelitySpec {
        level: preset,
        ..FidelitySpec::default()
    };
    for e in &mut v.loaded.file.entities {
        if e.kind == EntityType::Vip {
            e.start = Some(vip);
        }
    }
    Mission::build(v, None).expect("the mission builds")
}

/// The blue troopers and the VIP.
fn people(m: &EvacRun) -> Vec<EntityId> {
    let mut p = m.brief.team.clone();
    p.push(m.brief.vip);
    p
}

/// What a run showed of the squad, sampled every second.
#[derive(Default)]
struct Seen {
    /// The squad's log (positions and slots), from every leader it had.
    track: Vec<TrackPoint>,
    /// Its changes of formation.
    switches: Vec<Switch>,
    /// Seconds the leader walked while the VIP was in its squad.
    vip_escorted_s: u32,
    /// Seconds a leader was under way.
    walked_s: u32,
    /// Intentions of squad members and leaders, text.
    intentions: BTreeSet<String>,
    /// The leaders the squad had, in order.
    leaders: Vec<EntityId>,
    /// How much of each leader's log was copied.
    copied: BTreeMap<EntityId, usize>,
}

impl Seen {
    /// Looks at the squad once.
    fn look(&mut self, m: &EvacRun) {
        for id in people(m) {
            let t = trooper(m, id);
            let Some(intent) = vitro_tactical::model::Controller::intention(t) else {
                continue;
            };
            if t.member().is_some() {
                self.intentions.insert(intent.text.clone());
            }
            let Some(l) = t.leader() else { continue };
            if commander(m).squad.as_ref().map(|s| s.leader) != Some(id) {
                continue; // a squad of one walking back to the truck
            }
            if self.leaders.last() != Some(&id) {
                self.leaders.push(id);
            }
            if l.under_way() {
                self.walked_s += 1;
                if l.roster().contains(&m.brief.vip) {
                    self.vip_escorted_s += 1;
                }
                assert!(!intent.path.is_empty(), "the leader shows its route");
            }
            self.intentions.insert(intent.text);
            // The leader's log grows: copy its new entries.
            let log = l.trajectory();
            let from = self.copied.get(&id).copied().filter(|&n| n <= log.len());
            self.track.extend_from_slice(&log[from.unwrap_or(0)..]);
            self.copied.insert(id, log.len());
            for s in l.switches() {
                if !self.switches.contains(s) {
                    self.switches.push(s.clone());
                }
            }
        }
    }

    /// Each member's distance to its slot, metres, at every logged second.
    fn slot_errors(&self) -> Vec<f64> {
        self.track
            .iter()
            .filter_map(|p| {
                let s = p.slot?;
                Some((p.pos[0] - s[0]).hypot(p.pos[1] - s[1]))
            })
            .collect()
    }
}

/// Runs `m` to `end` (or its end), looking at the squad every second; `hook` may change the
/// world after each second.
fn watch(m: &mut EvacRun, end: u64, mut hook: impl FnMut(&mut EvacRun, &Seen)) -> Seen {
    let mut seen = Seen::default();
    let mut t = SimTime::ZERO;
    while t < SimTime::from_secs(end) && m.advance(t) {
        t += vitro::time::SimDuration::from_secs(1);
        if matches!(commander(m).phase, Phase::Pickup | Phase::Escort) {
            seen.look(m);
        }
        hook(m, &seen);
    }
    seen
}

#[test]
fn escort_walks_in_formation_and_the_vip_is_extracted() {
    for preset in [Preset::Discrete, Preset::Interpolated] {
        let mut m = mission(preset, VIP_HOUSE);
        let seen = watch(&mut m, 900, |_, _| {});
        let metrics = m.metrics();
        let errors = seen.slot_errors();
        let patterns: BTreeSet<_> = seen.switches.iter().map(|s| s.to.name()).collect();
        println!(
            "{preset:?}: extracted at {:?} s, walked {} s ({} s with the VIP), {} slot samples, \
             error median {:.1} m, p80 {:.1} m, formations {patterns:?}, leaders {:?}",
            metrics.time_to_extraction_s,
            seen.walked_s,
            seen.vip_escorted_s,
            errors.len(),
            pct(&errors, 0.5),
            pct(&errors, 0.8),
            seen.leaders,
        );
        assert!(metrics.success, "{preset:?}: {metrics:?}");
        assert!(seen.walked_s >= 60, "{preset:?}: the squad walked");
        assert!(
            seen.vip_escorted_s >= 30,
            "{preset:?}: the VIP walked inside the squad"
        );
        assert!(
            seen.intentions
                .iter()
                .any(|t| t.starts_with("in formation: ")),
            "{:?}",
            seen.intentions
        );
        assert!(patterns.len() >= 2, "{preset:?}: one formation only");
        match preset {
            // At the directed level members keep within a few metres of their slots.
            Preset::Interpolated => {
                assert!(errors.len() > 100);
                assert!(pct(&errors, 0.8) < 5.0, "{:.1}", pct(&errors, 0.8));
            }
            // At the discrete level slots are walk-graph nodes (metres to tens of metres
            // apart): members stand on the node nearest their slot most of the time.
            _ => assert!(pct(&errors, 0.5) < 1.0, "{:.1}", pct(&errors, 0.5)),
        }
    }
}

#[test]
fn formation_follows_the_ground() {
    // The VIP farther away, south-east of the safehouse: the way there passes between
    // houses close on both sides. The run stops at the first ground-driven change to a file
    // or a column. No red troopers hide in the town: their contacts (a line, whatever the
    // ground) would decide the squad's formation instead of the ground, and where they are
    // seen changes with every change to what the team knows.
    let mut v = ScenarioFile::validate(SCENARIO).expect("the default scenario validates");
    v.loaded.file.fidelity = FidelitySpec {
        level: Preset::Interpolated,
        ..FidelitySpec::default()
    };
    v.loaded
        .file
        .entities
        .retain(|e| !(e.kind == EntityType::Trooper && e.side == SideSpec::Red));
    for e in &mut v.loaded.file.entities {
        if e.kind == EntityType::Vip {
            e.start = Some([303.5, -165.7]);
        }
    }
    let mut m = Mission::build(v, None).expect("the mission builds");
    let seen = watch(&mut m, 900, |m, seen| {
        if seen
            .switches
            .iter()
            .any(|s| s.reason != "contact" && s.reason != "open")
        {
            m.end = m.sim.now();
        }
    });
    let grounds: BTreeSet<_> = seen.switches.iter().map(|s| s.reason.as_str()).collect();
    println!(
        "{:?}",
        seen.switches
            .iter()
            .map(|s| (s.t.as_secs_f64() as u64, s.to.name(), &s.reason))
            .collect::<Vec<_>>()
    );
    assert!(grounds.contains("open"), "{grounds:?}");
    assert!(
        grounds.contains("narrow") || grounds.contains("street"),
        "{grounds:?}"
    );
    for s in &seen.switches {
        let want = match s.reason.as_str() {
            "contact" => "line",
            "narrow" => "file",
            "street" => "column",
            _ => "wedge",
        };
        assert_eq!(s.to.name(), want, "{s:?}");
    }
}

#[test]
fn a_leader_shot_mid_walk_is_replaced() {
    let mut m = mission(Preset::Interpolated, VIP_HOUSE);
    let mut shot = None;
    let seen = watch(&mut m, 900, |m, seen| {
        let Some(s) = commander(m).squad.clone() else {
            return;
        };
        if shot.is_none() && seen.walked_s >= 20 && commander(m).phase == Phase::Pickup {
            // The leader is hit (the world changes under the agents; they learn it only
            // through their sensors).
            m.sim
                .env_mut()
                .conditions
                .update(s.leader, |c| c.status = Status::Down);
            shot = Some((s.leader, m.sim.now()));
        }
    });
    let (down, at) = shot.expect("the leader was shot during the walk");
    let metrics = m.metrics();
    let c = commander(&m);
    println!(
        "leader {down:?} down at {:.0} s; leaders {:?}; phases {:?}; {metrics:?}",
        at.as_secs_f64(),
        seen.leaders,
        c.log
    );
    assert!(
        c.fallen.contains(&down),
        "the squad reported its leader down"
    );
    let after = seen.leaders.iter().position(|&l| l == down).map(|i| i + 1);
    let next = after.and_then(|i| seen.leaders.get(i));
    assert!(
        next.is_some_and(|&l| l != down),
        "another trooper led the squad"
    );
    assert!(metrics.success, "{metrics:?}");
}
