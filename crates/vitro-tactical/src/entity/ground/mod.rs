//! Ground vehicles (car, cargo truck, MDARS) above the discrete level: along the street
//! polyline ([`interpolated`]) and as rigid bodies on the terrain ([`physical`]).

pub mod interpolated;
pub mod physical;
