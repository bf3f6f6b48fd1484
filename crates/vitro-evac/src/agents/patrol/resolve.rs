//! The receding-horizon re-solve: when the truck runs off its timetable, the patrol game of
//! the rest of the trip, re-timed from where the truck is now, solved again
//! ([`PatrolGame::retimed`]), and the Skeldar's switch to it ([`PatrolUnit::resolve`]).
//!
//! When a Skeldar's believed truck progress (from the truck's radio position reports, as
//! for the lock) is off its game's timetable beyond
//! [`LOCK_TOLERANCE_M`](super::LOCK_TOLERANCE_M) — the lock would hold it (late) or skip a
//! phase (early), [`PatrolGame::deviates`] — it re-solves: the mission's game of the rest
//! of the trip, re-timed from the step of the timetable nearest where the truck is (of a
//! wait's equal steps, the one nearest the Skeldar's phase: a truck late to the pickup
//! takes the wait in full, one late to leave it is taken to leave now), the same graph,
//! targets, units, LP iterations and seed ([`PatrolGame::retimed`]). Its phase 0 is now;
//! the Skeldar's checkpoint is where it starts: its next move is drawn from the new policy
//! at phase 0 from that checkpoint, or, if the new policy never has it there, is a rejoin
//! step towards the new policy's checkpoints. The re-solve is bounded: at most
//! [`MAX_RESOLVES`] per Skeldar, at least the attack's steps and [`RESOLVE_GAP_STEPS`]
//! apart, none with less than an attack's steps of the trip left (then it holds or skips as
//! before). It is the full game of the remaining trip, not a shorter horizon: its cost
//! falls with the trip left. Measured on the default scenario (`cargo run -p vitro-evac
//! [--release] --example patrol_resolve_cost`, one core of the 2-core development machine,
//! each of the 21 possible re-timings solved once, the machine busy with other builds):
//! release build 0.002–1.85 s, mean 0.31 s (the mission's own game: 1.5 s to build the
//! mission); debug build 0.04–10.4 s, mean 2.0 s. The long ones are the early re-timings (a
//! late start: most of the trip left). Its wall time is reported by that example only, not charged to the simulated
//! Skeldar (the step it re-solves at is a normal patrol step); a process solves each
//! re-timing once (the runs of a batch share them). The metric `patrol_resolves` counts the
//! re-solves; `patrol_capture_probability` becomes the least of the mission's game's and
//! the last re-solved game's capture probability over its trip; the Skeldar's intention
//! shows the game it plays.
//!
//! **When the guarantee holds after a re-solve.** The re-solved game's capture probability
//! of an attack is exact under the same three conditions as the mission's game (see the
//! parent module), read on the new game: (1) the attacker read the state in the *new* game
//! (every Skeldar at the vertex and new phase it believed, with the new policy in hand);
//! (2) through the attack's steps every Skeldar drew from the new policy (no hold, skip,
//! rejoin — the step right after a re-solve is a rejoin when the Skeldar's checkpoint is
//! off the new policy's support — and no further re-solve in the window); (3) the attack
//! ends by the extraction point. An attack whose window spans a re-solve is off schedule.
//! **The attacker is not told the new policy**: it was briefed once, with the mission's
//! game, and keeps it (it is not given the re-solve rule). Its attacks started after a
//! Skeldar re-solved are computed in the old game and are judged misread (the Skeldar's
//! step log carries the game it played, [`StepLog::plan`](super::steps::StepLog::plan));
//! they are never counted on schedule, and for them the game guarantees nothing either way.
//! So, after a re-solve, the guarantee holds only for an attacker that learns the new
//! policy — not implemented; it would need the re-solve rule in its briefing and the same
//! estimate of the truck's progress (its own sightings can put its re-solve at a different
//! step, a misread) — and in the default scenario (seed 42, discrete level) the one attack
//! is made before the pickup overrun that triggers the re-solve.

use super::solved::Frame;
use super::{PatrolGame, PatrolUnit, assemble};
use std::sync::Arc;

/// Most re-solves a Skeldar makes in a mission (each costs a solve; see the module docs for
/// the measured cost).
pub const MAX_RESOLVES: u64 = 6;
/// Fewest patrol steps between two re-solves of a Skeldar, beyond the game's attack length:
/// a re-solve is not repeated while the truck is still catching up with the last one.
pub const RESOLVE_GAP_STEPS: usize = 1;

impl PatrolGame {
    /// Where the re-timed trip of a truck `s` metres along the route starts: the step of the
    /// timetable nearest it; of equals (a wait), the one nearest `phase` (the Skeldar's,
    /// on this timetable): a truck late to a wait takes it in full, a truck late to leave
    /// one is taken to leave now (if it does not, the next re-solve re-times again).
    pub fn retime_index(&self, s: f64, phase: usize) -> usize {
        let mut best = (f64::INFINITY, usize::MAX, 0);
        for (k, &x) in self.timetable.iter().enumerate() {
            let (d, gap) = ((x - s).abs(), k.abs_diff(phase));
            if d < best.0 - 1e-9 || (d < best.0 + 1e-9 && gap < best.1) {
                best = (d.min(best.0), gap, k);
            }
        }
        best.2
    }

    /// The game of the rest of the trip from step `from` of this game's timetable, re-timed
    /// to start now (its phase 0 is this game's phase `from`), solved as this one was (the
    /// same graph, targets, units, iterations and seed; a game this process solved already
    /// is not solved again); `None` if fewer than an attack's steps of the trip are left.
    ///
    /// # Errors
    /// The solver's, as text.
    pub fn retimed(&self, from: usize) -> Result<Option<PatrolGame>, String> {
        let last = self.last_phase();
        if from + self.attack_steps() >= last {
            return Ok(None);
        }
        let frame = Frame {
            points: self.points.clone(),
            graph: self.plan.graph.clone(),
            step_s: self.step_s,
            reach_m: self.reach_m,
            route: self.route.clone(),
            along: self.along.clone(),
        };
        let timetable = self.timetable[from..].to_vec();
        let trip = self.trip[from..].to_vec();
        assemble(frame, timetable, trip, self.spec).map(Some)
    }

    /// Whether a Skeldar at `phase`, the truck `s` metres along the route, is off the
    /// timetable beyond [`LOCK_TOLERANCE_M`](super::LOCK_TOLERANCE_M): the lock holds it (the truck late) or skips a
    /// phase (early). At or past the end of the trip nothing deviates.
    pub fn deviates(&self, phase: usize, s: f64) -> bool {
        phase < self.last_phase()
            && match self.lock(phase, s) {
                None => true,
                Some(next) => next > phase + 1,
            }
    }
}

impl PatrolUnit {
    /// The game it plays now: the mission's, or its last re-solve (rebuilt, from the
    /// process's solved games, after a snapshot is restored).
    pub fn playing(&mut self) -> Arc<PatrolGame> {
        if self.offset > 0 && self.current.is_none() {
            self.current = self.game.retimed(self.offset).ok().flatten().map(Arc::new);
        }
        self.current.clone().unwrap_or_else(|| self.game.clone())
    }

    /// The game it plays now, if it has it (see [`PatrolUnit::playing`]).
    pub fn game_now(&self) -> &PatrolGame {
        self.current.as_deref().unwrap_or(&self.game)
    }

    /// Re-solves if the truck's progress is off the schedule of the game it plays (see
    /// [`PatrolGame::deviates`]), it has re-solves left ([`MAX_RESOLVES`]) and the last one
    /// is at least an attack and [`RESOLVE_GAP_STEPS`] steps back: the mission's game of
    /// the rest of the trip, re-timed from where the truck is now, its phase 0 now. Returns
    /// the game it plays from now on.
    pub fn resolve(&mut self, playing: Arc<PatrolGame>) -> Arc<PatrolGame> {
        let gap = playing.attack_steps() + RESOLVE_GAP_STEPS;
        let due = self.last_resolve.is_none_or(|l| self.log.len() >= l + gap);
        if !due || self.resolves >= MAX_RESOLVES || !playing.deviates(self.phase, self.progress) {
            return playing;
        }
        let from = self
            .game
            .retime_index(self.progress, self.offset + self.phase);
        let Ok(Some(game)) = self.game.retimed(from) else {
            return playing;
        };
        let game = Arc::new(game);
        self.current = Some(game.clone());
        self.offset = from;
        self.phase = 0;
        self.resolves += 1;
        self.last_resolve = Some(self.log.len());
        game
    }
}

#[cfg(test)]
mod tests {
    use super::super::steps::StepKind;
    use super::*;
    use rand::SeedableRng;
    use rand_chacha::ChaCha8Rng;

    #[test]
    fn a_late_truck_re_solves_the_rest_of_the_trip_from_where_it_is() {
        // The test game: timetable 0, 100, 300 (a wait of three steps), 500, 700 metres.
        let g = Arc::new(super::super::tests::game());
        let mut rng = ChaCha8Rng::seed_from_u64(3);
        let mut unit = PatrolUnit::new(g.clone(), 0);
        // On time to 100 m, then the truck stays there.
        for x in [0.0, 100.0] {
            unit.step(Some([x, 0.0]), 0.0, &mut rng);
        }
        assert_eq!(unit.resolves, 0);
        let mut steps = 0;
        while unit.resolves == 0 {
            let at = unit.at.expect("started");
            unit.step(Some([100.0, 0.0]), 0.0, &mut rng);
            steps += 1;
            assert!(steps < 5, "no re-solve");
            if unit.resolves == 1 {
                // Re-timed from the step of the timetable where the truck is (100 m): the
                // rest of the trip, its phase 0 now, and the step drawn from the new policy
                // at phase 0 from the Skeldar's checkpoint (or towards it, off its support).
                let new = unit.game_now();
                assert_eq!(unit.offset, 1);
                assert_eq!(new.timetable, g.timetable[1..]);
                assert_eq!(new.trip, g.trip[1..]);
                assert_eq!(new.trip[0], 1, "the convoy's checkpoint now");
                let e = *unit.log.last().expect("a step");
                assert_eq!((e.plan, e.phase), (1, 1));
                let on = new.plan.policies[0].moves_at(at, 0).is_some();
                assert_eq!(e.kind == StepKind::Policy, on, "{e:?} from {at}");
                assert!(on || e.kind == StepKind::Rejoin);
                let next = e.at.expect("a checkpoint");
                assert!(next == at || g.plan.graph.has_edge(at, next));
                // Its capture probability is the new game's.
                let p = new.trip_capture_probability;
                assert!(p > 0.0 && p <= 1.0);
            }
        }
        // Still late: no second re-solve within an attack's steps and the gap.
        for _ in 0..g.attack_steps() {
            unit.step(Some([100.0, 0.0]), 0.0, &mut rng);
        }
        assert_eq!(unit.resolves, 1);
        // Never more than the bound, however late.
        for _ in 0..40 {
            unit.step(Some([100.0, 0.0]), 0.0, &mut rng);
        }
        assert!(unit.resolves > 1 && unit.resolves <= MAX_RESOLVES);
        // On time: no re-solve at all.
        let mut on_time = PatrolUnit::new(g.clone(), 0);
        for x in [0.0, 100.0, 300.0, 300.0, 300.0, 500.0, 700.0] {
            on_time.step(Some([x, 0.0]), 0.0, &mut rng);
        }
        assert_eq!((on_time.resolves, on_time.offset), (0, 0));
        // Too little of the trip left to re-solve.
        assert!(g.retimed(g.last_phase() - 1).unwrap().is_none());
    }
}
