//! The mission's agents. Each acts only through its `Context`: its own sensors, the
//! actuators of [`act`](crate::act) and the radio ([`Net`](crate::net::Net)); what each knows
//! beforehand is its [`brief`](crate::brief).
//!
//! - [`station::Station`], the ground control station: shares the sectors out by contract net;
//! - [`uav::Uav`], a UAV: bids, searches its sectors, locks on and follows red units;
//! - [`red::Prowler`], a red unit: moves from junction to junction at random.

mod plan;
pub mod red;
pub mod station;
pub mod uav;
