//! # vitro-viz: watch a run live or replay a recording, in the browser
//!
//! A small web server (axum) that serves one page (a 2D map on a canvas, a 3D view with
//! three.js, time controls, an inspector, metric charts; all compiled into the binary) and
//! streams the run over a WebSocket as JSON: a [`Scene`](vitro_record::Scene) once, then
//! [`Frame`](vitro_record::Frame)s ([`protocol`]).
//!
//! - **Live** ([`live`]): a [`LiveSource`] (a scenario's simulation, seen through a small
//!   trait so this crate knows no model) runs on its own thread, paced; viewers pause, step
//!   and change its speed through its [`Control`](vitro::sim::Control) handle and never
//!   slow it down or change its trace.
//! - **Foxglove** (`foxglove`, feature `foxglove`): the same live run over the Foxglove
//!   WebSocket protocol, with the channels of a recording, for the Foxglove app.
//! - **Replay** ([`replay`]): a [`Recording`] (a Vitro MCAP file: [`McapRecording`])
//!   played back, each browser tab with its own playhead (play, pause, step, seek).
//!
//! ```no_run
//! # async fn demo(source: impl vitro_viz::LiveSource + Send) -> Result<(), vitro_viz::ViewError> {
//! use vitro_viz::{LiveRun, server::{Feed, serve}};
//! let run = LiveRun::start(source, Some(1.0), false)?;
//! let listener = tokio::net::TcpListener::bind("127.0.0.1:8080").await.map_err(vitro_viz::ViewError::Bind)?;
//! serve(listener, Feed::Live(run.clone()), std::future::pending()).await?;
//! run.stop();
//! # Ok(()) }
//! ```

pub mod assets;
mod error;
#[cfg(feature = "foxglove")]
pub mod foxglove;
pub mod hosts;
pub mod live;
pub mod protocol;
pub mod replay;
pub mod server;

pub use error::ViewError;
pub use hosts::{BadHostName, HostPolicy};
pub use live::{LiveRun, LiveSource, Outcome, Published, SourceError, advance_sim};
pub use replay::{McapRecording, MemoryRecording, Recording, ReplayFeed};
