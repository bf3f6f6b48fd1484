//! A live run over the Foxglove WebSocket protocol, for the Foxglove app.
//!
//! The server speaks `foxglove.websocket.v1` (also offered as `foxglove.sdk.v1`, the same
//! messages) on `/` of its own port, with JSON-encoded channels described by JSON Schemas: the
//! channels a recording has, defined once in [`vitro_record::channels`] (`/vitro/scene`,
//! `/vitro/frame`, `/map`, `/entities`, `/detections`, `/intentions`, `/sensors`, `/tf`, a
//! `/gps/NAME` per entity, `/log`, `/metrics`). Timestamps are simulated nanoseconds since the
//! start of the run, as in a recording; the server declares the `time` capability and sends the
//! simulated time with every frame, so Foxglove's clock is the simulation's. The scenario's
//! calendar start is the `start` entry of the server's metadata.
//!
//! The frames are those the page viewer gets (the same [`LiveRun`] stream: latest frame
//! wins, a slow client gets fewer). The run's controls are parameters ([`params`]):
//! `paused`, `speed` and `step`, applied through the run's control handle, so watching and
//! steering never change the trace.
//!
//! Every request is checked as the page viewer's are ([`HostPolicy`]): a `Host` that is not a
//! loopback name or the bound address (with its port) gets 403 Forbidden.

pub mod params;
mod session;
pub mod wire;

use crate::ViewError;
use crate::hosts::HostPolicy;
use crate::live::LiveRun;
use axum::Router;
use axum::extract::{State, WebSocketUpgrade};
use axum::http::{HeaderMap, StatusCode, header};
use axum::middleware;
use axum::response::{IntoResponse, Response};
use axum::routing::get;
use std::collections::BTreeMap;
use std::future::Future;
use std::sync::Arc;
use tokio::net::TcpListener;
use wire::ServerOp;

/// The port the Foxglove app connects to unless told otherwise.
pub const DEFAULT_PORT: u16 = 8765;

/// The Foxglove web app's origin, answered besides this machine's own.
pub const FOXGLOVE_APP_ORIGIN: &str = "https://app.foxglove.dev";

/// The longest client message accepted, in bytes (a subscription to every channel of a large
/// run fits).
pub const MAX_CLIENT_BYTES: usize = 256 << 10;

/// What every connection shares.
#[derive(Clone)]
struct Served {
    run: LiveRun,
    info: Arc<ServerOp>,
}

/// The route: a WebSocket on `/`; requests that `hosts` does not permit get 403.
pub fn router(run: LiveRun, hosts: HostPolicy) -> Router {
    let info = Arc::new(server_info(&run));
    Router::new()
        .route("/", get(upgrade))
        .with_state(Served { run, info })
        .layer(middleware::from_fn_with_state(hosts, crate::server::guard))
}

/// Serves `run` over the Foxglove WebSocket protocol on `listener` until `shutdown`
/// completes, answering to the hosts `hosts` permits.
pub async fn serve(
    listener: TcpListener,
    run: LiveRun,
    hosts: HostPolicy,
    shutdown: impl Future<Output = ()> + Send + 'static,
) -> Result<(), ViewError> {
    crate::server::serve_router(listener, router(run, hosts), shutdown).await
}

/// The first message of every connection.
fn server_info(run: &LiveRun) -> ServerOp {
    let hello = run.hello();
    let scene = run.scene();
    let start = vitro::time::UtcTime::from_unix_millis(scene.start_unix_ms).to_string();
    let nanos = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| d.as_nanos());
    ServerOp::ServerInfo {
        name: format!("vitro: {}", hello.title),
        capabilities: wire::CAPABILITIES.to_vec(),
        supported_encodings: Vec::new(),
        metadata: BTreeMap::from([
            ("scene".to_owned(), scene.name.clone()),
            ("start".to_owned(), start),
            ("time".to_owned(), "simulated ns since start".to_owned()),
        ]),
        session_id: format!("{}-{nanos}", std::process::id()),
    }
}

/// Accepts a WebSocket that asks for the protocol (its `Host` checked by the guard).
async fn upgrade(ws: WebSocketUpgrade, headers: HeaderMap, State(s): State<Served>) -> Response {
    let offered = headers
        .get_all(header::SEC_WEBSOCKET_PROTOCOL)
        .iter()
        .filter_map(|h| h.to_str().ok())
        .flat_map(|h| h.split(','))
        .any(|p| wire::SUBPROTOCOLS.contains(&p.trim()));
    if !offered {
        return (
            StatusCode::BAD_REQUEST,
            "expected the WebSocket subprotocol foxglove.websocket.v1",
        )
            .into_response();
    }
    ws.protocols(wire::SUBPROTOCOLS)
        .max_message_size(MAX_CLIENT_BYTES)
        .max_frame_size(MAX_CLIENT_BYTES)
        .on_upgrade(move |socket| async move {
            // A client that goes away ends its own task; nothing else to do.
            let _ = session::client(socket, s.run, s.info).await;
        })
}
