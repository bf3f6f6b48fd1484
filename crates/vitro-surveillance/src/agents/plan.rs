//! A UAV's flight planning, from its briefing and what it holds: the search route over its
//! sectors, the cost it bids for one more, and the points it flies to watch a target.

use crate::brief::{Airframe, TeamBrief};
use crate::sector::{Rect, Sector, centre, dist, orbit, sweep, sweep_length, tour};
use std::collections::BTreeMap;

/// Points of a fixed-wing orbit.
const ORBIT_POINTS: usize = 8;

/// A world point `altitude_m` above the ground under town point `p`.
pub fn above(brief: &TeamBrief, frame: &Airframe, p: [f64; 2]) -> [f64; 3] {
    let w = brief.site.to_world(p);
    let g = brief.site.ground(w).unwrap_or(0.0);
    [w[0], w[1], g + frame.altitude_m]
}

/// The search route from town point `from`: the sectors held in tour order, each swept
/// from its corner nearest the way in; the whole operation area when it holds none.
pub fn search_route(
    brief: &TeamBrief,
    frame: &Airframe,
    held: &BTreeMap<u32, Rect>,
    from: [f64; 2],
) -> Vec<[f64; 3]> {
    let sectors: Vec<Sector> = if held.is_empty() {
        vec![Sector {
            id: u32::MAX,
            area: brief.area,
        }]
    } else {
        held.iter()
            .map(|(&id, &area)| Sector { id, area })
            .collect()
    };
    let mut at = from;
    let mut out = Vec::new();
    for s in tour(from, &sectors) {
        for p in sweep(s.area, brief.spacing_m, at) {
            out.push(above(brief, frame, p));
            at = p;
        }
    }
    out
}

/// The bid for sector `area`: the seconds until it would have searched it once, after the
/// sectors it holds or has offered for (`load`), starting from town point `from`.
pub fn cost(brief: &TeamBrief, frame: &Airframe, load: &[Rect], area: Rect, from: [f64; 2]) -> f64 {
    let work: f64 = load.iter().map(|r| sweep_length(*r, brief.spacing_m)).sum();
    // The legs between the sectors it holds, then the way to the new one.
    let mut sectors: Vec<Sector> = (load.iter().enumerate())
        .map(|(i, &area)| Sector { id: i as u32, area })
        .collect();
    sectors = tour(from, &sectors);
    let mut at = from;
    let mut legs = 0.0;
    for s in &sectors {
        legs += dist(at, centre(s.area));
        at = centre(s.area);
    }
    legs += dist(at, centre(area));
    (work + legs + sweep_length(area, brief.spacing_m)) / frame.cruise_mps.max(1.0)
}

/// Where to fly to watch a target at town point `p`: over it (a helicopter), or an orbit
/// round it (a fixed-wing aircraft, or `wide` for a search round a lost track).
pub fn watch(brief: &TeamBrief, frame: &Airframe, p: [f64; 2], wide: bool) -> Vec<[f64; 3]> {
    if frame.fixed_wing || wide {
        let r = if frame.fixed_wing {
            brief.orbit_m
        } else {
            brief.orbit_m / 2.0
        };
        orbit(p, r, ORBIT_POINTS)
            .into_iter()
            .map(|q| above(brief, frame, q))
            .collect()
    } else {
        vec![above(brief, frame, p)]
    }
}
