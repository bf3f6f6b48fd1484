//! # The Vitro guide, tested
//!
//! The guide lives in `docs/guide` as an mdBook (`mdbook build docs/guide`). This crate
//! includes every page as the documentation of one module, so that
//! `cargo test -p vitro-guide --doc` compiles and runs every Rust block of every page: the
//! guide cannot drift from the code it teaches. The crate has no code of its own.


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
