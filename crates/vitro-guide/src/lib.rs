//! # The Vitro guide, tested
//!
//! The guide lives in `docs/guide` as an mdBook (`mdbook build docs/guide`). This crate
//! includes every page as the documentation of one module, so that
//! `cargo test -p vitro-guide --doc` compiles and runs every Rust block of every page: the
//! guide cannot drift from the code it teaches. Its own code is what the pages share: the
//! tutorial's inspection controller ([`inspect`]) and the mission the mission tutorial builds
//! ([`watch`]), whose files the page quotes and whose test runs it.

pub mod inspect;
pub mod watch;

/// Introduction (`docs/guide/src/introduction.md`).
#[doc = include_str!("../../../docs/guide/src/introduction.md")]
pub mod introduction {}

/// Time, events and determinism (`docs/guide/src/events.md`).
#[doc = include_str!("../../../docs/guide/src/events.md")]
pub mod events {}

/// Storages, sensors and actuators (`docs/guide/src/environment.md`).
#[doc = include_str!("../../../docs/guide/src/environment.md")]
pub mod environment {}

/// The radio (`docs/guide/src/radio.md`).
#[doc = include_str!("../../../docs/guide/src/radio.md")]
pub mod radio {}

/// What an agent knows (`docs/guide/src/briefing.md`).
#[doc = include_str!("../../../docs/guide/src/briefing.md")]
pub mod briefing {}

/// The paper's algorithms in the mission (`docs/guide/src/algorithms.md`).
#[doc = include_str!("../../../docs/guide/src/algorithms.md")]
pub mod algorithms {}

/// Tutorial part 1: a controller on a synthetic graph (`docs/guide/src/tutorial-1-graph.md`).
#[doc = include_str!("../../../docs/guide/src/tutorial-1-graph.md")]
pub mod tutorial_1_graph {}

/// Tutorial part 2: the town at three levels (`docs/guide/src/tutorial-2-town.md`).
#[doc = include_str!("../../../docs/guide/src/tutorial-2-town.md")]
pub mod tutorial_2_town {}

/// Tutorial part 3: a property and the cross-level check (`docs/guide/src/tutorial-3-check.md`).
#[doc = include_str!("../../../docs/guide/src/tutorial-3-check.md")]
pub mod tutorial_3_check {}

/// Tutorial part 4: a batch experiment and a plot (`docs/guide/src/tutorial-4-batch.md`).
#[doc = include_str!("../../../docs/guide/src/tutorial-4-batch.md")]
pub mod tutorial_4_batch {}

/// Tutorial part 5: a mission of your own (`docs/guide/src/tutorial-5-mission.md`).
#[doc = include_str!("../../../docs/guide/src/tutorial-5-mission.md")]
pub mod tutorial_5_mission {}

/// Scenarios (`docs/guide/src/scenarios.md`).
#[doc = include_str!("../../../docs/guide/src/scenarios.md")]
pub mod scenarios {}

/// Experiments (`docs/guide/src/experiments.md`).
#[doc = include_str!("../../../docs/guide/src/experiments.md")]
pub mod experiments {}

/// Calibrating the abstract levels (`docs/guide/src/calibration.md`).
#[doc = include_str!("../../../docs/guide/src/calibration.md")]
pub mod calibration {}

/// From one machine to a cluster (`docs/guide/src/cluster.md`).
#[doc = include_str!("../../../docs/guide/src/cluster.md")]
pub mod cluster {}

/// Python and PettingZoo (`docs/guide/src/python.md`).
#[doc = include_str!("../../../docs/guide/src/python.md")]
pub mod python {}

/// Recordings and the viewer (`docs/guide/src/recordings.md`).
#[doc = include_str!("../../../docs/guide/src/recordings.md")]
pub mod recordings {}

/// Writing your own mission (`docs/guide/src/missions.md`).
#[doc = include_str!("../../../docs/guide/src/missions.md")]
pub mod missions {}
