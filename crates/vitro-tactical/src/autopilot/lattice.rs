//! The discrete level's autopilot, for both aircraft types: the aircraft moves from cell to
//! cell of its [`Lattice`](crate::entity::air::Lattice), one maneuver per event.
//!
//! - Fixed-wing: every maneuver moves one cell along the heading after a turn of −45°, 0 or
//!   +45° (and optionally one layer up or down); it never stops. Waypoints are reached by a
//!   shortest maneuver sequence found by A* over (cell, heading) with the octile distance as
//!   heuristic; after the last one it flies on straight.
//! - Helicopter: every maneuver moves to one of the 26 neighbouring cells (straight at the
//!   goal); after the last waypoint it hovers.
//!
//! A maneuver takes its length at the commanded speed (a climb no faster than the type's
//! climb rate for a helicopter), so a lattice trajectory never jumps further than its speed
//! allows. Under a calibration with a fit for the type ([`crate::calibration::air`]), a
//! waypoint command is flown at an effective speed, the commanded one divided by the
//! predicted stretch of its route.

use super::plan::{ctol_move, sign, waypoint_step};
use super::{FlyError, engage, reached, validate};
use crate::arena::{Arena, Ev};
use crate::entity::air::{AirKind, DIRS, FlightCommand, dir_of};
use crate::entity::route::dist3;
use vitro::entity::EntityId;
use vitro::env::{Actuator, Effects};
use vitro::event::Target;
use vitro::time::SimDuration;

pub use super::plan::{maneuvers, plan_ctol};

/// The discrete-level autopilot (both airframes).
#[derive(Copy, Clone, Debug, Default)]
pub struct Autopilot;

impl Actuator<Arena, Ev> for Autopilot {
    type Command = FlightCommand;
    type Error = FlyError;
    fn actuate(
        &self,
        w: &mut Arena,
        me: EntityId,
        cmd: FlightCommand,
        fx: &mut Effects<'_, Ev>,
    ) -> Result<(), FlyError> {
        validate(&cmd)?;
        let b = w.lattice.get(me).ok_or(FlyError::NoBody(me))?;
        let moving = b.moving_to.is_some();
        // A calibration flies the command at its effective speed (`calibration::air`).
        let cmd = w
            .calibration
            .as_ref()
            .and_then(|c| c.air_command(&w.types, b, &cmd))
            .unwrap_or(cmd);
        engage(w, me, cmd);
        if !moving {
            start_next(w, me, fx);
        }
        Ok(())
    }
}

/// The end of a maneuver: the aircraft is in its new cell; the next one starts.
pub(crate) fn arrive(w: &mut Arena, who: EntityId, fx: &mut Effects<'_, Ev>) {
    let fired = fx.fired();
    if fired.is_some() && w.lattice.get(who).and_then(|b| b.pending) != fired {
        return; // not the maneuver this aircraft waits for (stale or forged)
    }
    let mut done = false;
    w.lattice.update(who, |b| {
        if let Some((cell, dir)) = b.moving_to.take() {
            b.cell = cell;
            b.dir = dir;
            b.pending = None;
            done = true;
        }
    });
    if done {
        start_next(w, who, fx);
    }
}

/// Decides and schedules the next maneuver (or a hover).
fn start_next(w: &mut Arena, me: EntityId, fx: &mut Effects<'_, Ev>) {
    let (Some(b), Some(mut pilot)) = (w.lattice.get(me).cloned(), w.pilots.get(me).cloned()) else {
        return;
    };
    let (ctol, speed, climb_rate) = match b.kind {
        AirKind::Ctol(k) => {
            let ty = w.types.ctol(k);
            let v = command_speed(&pilot.cmd).unwrap_or(ty.cruise_speed);
            (true, v.clamp(ty.min_speed, ty.max_speed), f64::INFINITY)
        }
        AirKind::Vtol(k) => {
            let ty = w.types.vtol(k);
            let v = command_speed(&pilot.cmd).unwrap_or(ty.cruise_speed);
            (false, v.clamp(0.1, ty.max_speed), ty.max_climb)
        }
    };
    // A calibrated command's speed is the effective speed, already within the envelope
    // before the calibration's stretch: flown as it stands.
    let speed = match command_speed(&pilot.cmd) {
        Some(v)
            if w.calibration
                .as_ref()
                .is_some_and(|c| c.air_fit(b.kind).is_some()) =>
        {
            v
        }
        _ => speed,
    };
    let l = b.lattice;
    // Waypoints reached now (in the cell, at the layer for a helicopter).
    if let FlightCommand::Waypoints { points, .. } = &pilot.cmd {
        while let Some(&p) = points.get(pilot.next) {
            let g = l.cell_of(p);
            let here = b.cell[0] == g[0] && b.cell[1] == g[1] && (ctol || b.cell[2] == g[2]);
            if !here {
                break;
            }
            reached(me, pilot.next, fx);
            pilot.next += 1;
            pilot.plan.clear();
        }
        if pilot.next >= points.len() {
            if ctol {
                // It cannot stop: fly on straight at the last waypoint's altitude.
                let altitude = points.last().map_or(l.point(b.cell)[2], |p| p[2]);
                pilot.cmd = FlightCommand::Straight {
                    heading: b.heading(),
                    altitude,
                    speed: Some(speed),
                };
            } else {
                w.pilots.insert(me, pilot);
                w.lattice.update(me, |b| b.speed = 0.0);
                return;
            }
        }
    }
    let (to, dir) = match &pilot.cmd {
        FlightCommand::Waypoints { points, .. } => {
            let g = l.cell_of(points[pilot.next]);
            waypoint_step(&b, g, ctol, &mut pilot.plan)
        }
        FlightCommand::Straight {
            heading, altitude, ..
        } => {
            let want = dir_of(*heading);
            let climb = sign(l.cell_of([0.0, 0.0, *altitude])[2] - b.cell[2]);
            if ctol {
                let diff = (i32::from(want) - i32::from(b.dir)).rem_euclid(8);
                let turn = match diff {
                    0 => 0,
                    1..=4 => 1,
                    _ => -1,
                };
                ctol_move(&b, turn, climb)
            } else {
                let s = DIRS[want as usize];
                (
                    [b.cell[0] + s[0], b.cell[1] + s[1], b.cell[2] + climb],
                    want,
                )
            }
        }
    };
    let (p0, p1) = (l.point(b.cell), l.point(to));
    let horizontal = libm::hypot(p1[0] - p0[0], p1[1] - p0[1]);
    let secs = (horizontal / speed).max((p1[2] - p0[2]).abs() / climb_rate);
    let id = fx.schedule_in(
        SimDuration::from_secs_f64(secs),
        Target::Env,
        Ev::Maneuver(me),
    );
    let mean = if secs > 0.0 {
        dist3(p0, p1) / secs
    } else {
        0.0
    };
    w.pilots.insert(me, pilot);
    w.lattice.update(me, |b| {
        b.moving_to = Some((to, dir));
        b.pending = Some(id);
        b.speed = mean;
    });
}

/// The speed a command asks for.
fn command_speed(cmd: &FlightCommand) -> Option<f64> {
    match cmd {
        FlightCommand::Straight { speed, .. } | FlightCommand::Waypoints { speed, .. } => *speed,
    }
}
