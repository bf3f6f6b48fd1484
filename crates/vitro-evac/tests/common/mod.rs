//! Shared helpers of the mission tests: the controllers of a running mission, percentiles.

#![allow(dead_code)]

use vitro::entity::EntityId;
use vitro_evac::EvacRun;
use vitro_evac::agents::commander::Commander;
use vitro_evac::agents::trooper::Trooper;

/// The truck's commander in a mission.
pub fn commander(m: &EvacRun) -> &Commander {
    m.sim
        .agent(m.brief.truck)
        .and_then(|a| a.as_any().downcast_ref::<Commander>())
        .expect("the truck's commander")
}

/// The controller of trooper (or VIP) `id` in a mission.
pub fn trooper(m: &EvacRun, id: EntityId) -> &Trooper {
    m.sim
        .agent(id)
        .and_then(|a| a.as_any().downcast_ref::<Trooper>())
        .expect("a trooper")
}

/// Percentile `q` (0..=1) of `v` (NaN if `v` is empty).
pub fn pct(v: &[f64], q: f64) -> f64 {
    let mut v = v.to_vec();
    v.sort_by(f64::total_cmp);
    v.get(((v.len().max(1) - 1) as f64 * q).round() as usize)
        .copied()
        .unwrap_or(f64::NAN)
}
