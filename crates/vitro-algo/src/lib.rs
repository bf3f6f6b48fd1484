//! Domain-independent algorithms for Vitro: classical planning and the algorithms the
//! tactical simulator builds on.

pub mod cops;
pub mod graph;
pub mod patrol;
pub mod planning;
pub mod pursuit;
pub mod repair;
pub mod rules;
