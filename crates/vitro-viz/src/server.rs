//! The HTTP server: the page and its assets from the binary, the state over a WebSocket.
//!
//! Every request, the page's, an asset's or the WebSocket's, is answered only if its `Host`
//! (and its `Origin`, when it sends one) names this machine ([`HostPolicy`]); any other gets
//! 403 Forbidden.
//!
//! Each connection gets its own task. A client that reads slowly only gets fewer frames (it
//! picks the newest when it is ready); one that stops reading is dropped after
//! [`SEND_TIMEOUT`]; neither ever blocks the simulation.

use crate::hosts::HostPolicy;
use crate::live::LiveRun;
use crate::protocol::{Command, CommandError, MAX_COMMAND_BYTES, ServerMsg, Status};
use crate::replay::{Player, ReplayFeed};
use crate::{ViewError, assets};
use axum::Router;
use axum::extract::ws::{Message, WebSocket, WebSocketUpgrade};
use axum::extract::{Request, State};
use axum::http::{StatusCode, header};
use axum::middleware::{self, Next};
use axum::response::{IntoResponse, Response};
use axum::routing::get;
use std::future::Future;
use std::time::Duration;
use tokio::net::TcpListener;
use tokio::time::{Instant, MissedTickBehavior, interval, timeout};

/// How often a client gets a status message.
pub const STATUS_EVERY: Duration = Duration::from_millis(250);
/// How long one send to a client may take before the client is dropped.
pub const SEND_TIMEOUT: Duration = Duration::from_secs(10);
/// How often a replay playhead moves.
const REPLAY_TICK: Duration = Duration::from_millis(40);

/// What the server shows.
#[derive(Clone)]
pub enum Feed {
    /// A simulation running now.
    Live(LiveRun),
    /// A recording.
    Replay(ReplayFeed),
}

/// The routes: `/ws` for the WebSocket, every other path an embedded asset (`/` is the page);
/// requests that `hosts` does not permit get 403.
pub fn router(feed: Feed, hosts: HostPolicy) -> Router {
    Router::new()
        .route("/ws", get(upgrade))
        .fallback(asset)
        .with_state(feed)
        .layer(middleware::from_fn_with_state(hosts, guard))
}

/// Serves `feed` on `listener` until `shutdown` completes, answering only to loopback names
/// and the address `listener` is bound to.
pub async fn serve(
    listener: TcpListener,
    feed: Feed,
    shutdown: impl Future<Output = ()> + Send + 'static,
) -> Result<(), ViewError> {
    let bound = listener.local_addr().map_err(ViewError::Bind)?;
    serve_with(listener, feed, HostPolicy::new(bound), shutdown).await
}

/// Serves `feed` on `listener` until `shutdown` completes, answering to the hosts `hosts`
/// permits.
pub async fn serve_with(
    listener: TcpListener,
    feed: Feed,
    hosts: HostPolicy,
    shutdown: impl Future<Output = ()> + Send + 'static,
) -> Result<(), ViewError> {
    serve_router(listener, router(feed, hosts), shutdown).await
}

/// Serves `app` on `listener` until `shutdown` completes: the page viewer's and the Foxglove
/// server's common end.
pub(crate) async fn serve_router(
    listener: TcpListener,
    app: Router,
    shutdown: impl Future<Output = ()> + Send + 'static,
) -> Result<(), ViewError> {
    axum::serve(listener, app)
        .with_graceful_shutdown(shutdown)
        .await
        .map_err(ViewError::Serve)
}

/// Passes on a request whose `Host` and `Origin` `hosts` permits; answers 403 to any other.
pub(crate) async fn guard(
    State(hosts): State<HostPolicy>,
    request: Request,
    next: Next,
) -> Response {
    let headers = request.headers();
    let host = headers.get(header::HOST).map(|h| h.as_bytes());
    let origin = headers.get(header::ORIGIN).map(|o| o.as_bytes());
    if hosts.permits(host, origin) {
        next.run(request).await
    } else {
        (
            StatusCode::FORBIDDEN,
            "forbidden: this viewer answers only to this machine's own addresses \
             (vitro view --allow-host NAME serves it under another name)",
        )
            .into_response()
    }
}

async fn asset(uri: axum::http::Uri) -> Response {
    let path = uri.path().trim_start_matches('/');
    let path = if path.is_empty() { "index.html" } else { path };
    match assets::get(path) {
        Some((body, mime)) => (
            [
                (header::CONTENT_TYPE, mime),
                (header::CACHE_CONTROL, "no-cache".to_owned()),
            ],
            body,
        )
            .into_response(),
        None => (StatusCode::NOT_FOUND, "not found").into_response(),
    }
}

/// Accepts a WebSocket (its `Host` and `Origin` checked by [`guard`]), with client messages
/// capped in size.
async fn upgrade(ws: WebSocketUpgrade, State(feed): State<Feed>) -> Response {
    ws.max_message_size(MAX_COMMAND_BYTES)
        .max_frame_size(MAX_COMMAND_BYTES)
        .on_upgrade(move |socket| async move {
            // A client that goes away ends its own task; nothing else to do.
            let _ = match feed {
                Feed::Live(run) => live_client(socket, run).await,
                Feed::Replay(replay) => replay_client(socket, replay).await,
            };
        })
}

/// Why a connection ended (never reported: the client is simply gone).
#[derive(Debug)]
struct Gone;

async fn send(socket: &mut WebSocket, text: impl Into<String>) -> Result<(), Gone> {
    let msg = Message::Text(text.into().into());
    match timeout(SEND_TIMEOUT, socket.send(msg)).await {
        Ok(Ok(())) => Ok(()),
        _ => Err(Gone),
    }
}

async fn send_msg(socket: &mut WebSocket, msg: &ServerMsg) -> Result<(), Gone> {
    send(socket, msg.to_json()).await
}

async fn send_status(socket: &mut WebSocket, status: Status) -> Result<(), Gone> {
    send_msg(socket, &ServerMsg::Status(status)).await
}

/// What a client sent: a command, or an answer to give it (a rejection), or nothing to do.
enum Incoming {
    Command(Command),
    Reject(CommandError),
    Ignore,
}

fn read(msg: Message) -> Result<Incoming, Gone> {
    Ok(match msg {
        Message::Text(t) => match Command::parse(t.as_str()) {
            Ok(cmd) => Incoming::Command(cmd),
            Err(e) => Incoming::Reject(e),
        },
        Message::Binary(_) => Incoming::Reject(CommandError::Malformed(
            "binary message (commands are JSON text)".into(),
        )),
        Message::Close(_) => return Err(Gone),
        Message::Ping(_) | Message::Pong(_) => Incoming::Ignore,
    })
}

async fn reject(socket: &mut WebSocket, e: CommandError) -> Result<(), Gone> {
    send_msg(
        socket,
        &ServerMsg::Error {
            message: e.to_string(),
        },
    )
    .await
}

async fn live_client(mut socket: WebSocket, run: LiveRun) -> Result<(), Gone> {
    send_msg(&mut socket, &ServerMsg::Hello(run.hello())).await?;
    send(&mut socket, &*run.scene_json()).await?;
    send_msg(&mut socket, &ServerMsg::History(run.history())).await?;
    let mut frames = run.frames();
    frames.mark_changed();
    let mut status = interval(STATUS_EVERY);
    status.set_missed_tick_behavior(MissedTickBehavior::Delay);
    loop {
        tokio::select! {
            changed = frames.changed() => {
                if changed.is_err() {
                    return Err(Gone);
                }
                let latest = frames.borrow_and_update().clone();
                if let Some(latest) = latest {
                    send(&mut socket, &*latest.json).await?;
                }
            }
            _ = status.tick() => send_status(&mut socket, run.status()).await?,
            msg = socket.recv() => {
                let Some(Ok(msg)) = msg else { return Err(Gone) };
                match read(msg)? {
                    Incoming::Command(cmd) => match run.apply(&cmd) {
                        Ok(()) => send_status(&mut socket, run.status()).await?,
                        Err(e) => reject(&mut socket, e).await?,
                    },
                    Incoming::Reject(e) => reject(&mut socket, e).await?,
                    Incoming::Ignore => {}
                }
            }
        }
    }
}

async fn replay_client(mut socket: WebSocket, feed: ReplayFeed) -> Result<(), Gone> {
    send_msg(&mut socket, &ServerMsg::Hello(feed.hello())).await?;
    send(&mut socket, &*feed.scene_json()).await?;
    send_msg(&mut socket, &ServerMsg::History(feed.history())).await?;
    let mut player = feed.player();
    let mut tick = interval(REPLAY_TICK);
    tick.set_missed_tick_behavior(MissedTickBehavior::Delay);
    let mut status = interval(STATUS_EVERY);
    status.set_missed_tick_behavior(MissedTickBehavior::Delay);
    let mut last = Instant::now();
    loop {
        tokio::select! {
            _ = tick.tick() => {
                let now = Instant::now();
                let wall = now.duration_since(last).as_secs_f64();
                last = now;
                let (p, shown) = blocking(player, move |p| {
                    let r = p.advance(wall);
                    r.map_err(|e| e.to_string())
                }).await?;
                player = p;
                match shown {
                    Ok(Some(json)) => send(&mut socket, json).await?,
                    Ok(None) => {}
                    Err(e) => reject(&mut socket, CommandError::OutOfRange(e)).await?,
                }
            }
            _ = status.tick() => send_status(&mut socket, player.status()).await?,
            msg = socket.recv() => {
                let Some(Ok(msg)) = msg else { return Err(Gone) };
                match read(msg)? {
                    Incoming::Command(cmd) => {
                        let (p, shown) = blocking(player, move |p| p.apply(&cmd)).await?;
                        player = p;
                        match shown {
                            Ok(frames) => {
                                for f in frames {
                                    send(&mut socket, f).await?;
                                }
                                send_status(&mut socket, player.status()).await?;
                            }
                            Err(e) => reject(&mut socket, e).await?,
                        }
                    }
                    Incoming::Reject(e) => reject(&mut socket, e).await?,
                    Incoming::Ignore => {}
                }
            }
        }
    }
}

/// Runs `f` on the player off the async workers (reading a recording may block).
async fn blocking<T: Send + 'static>(
    mut player: Player,
    f: impl FnOnce(&mut Player) -> T + Send + 'static,
) -> Result<(Player, T), Gone> {
    tokio::task::spawn_blocking(move || {
        let out = f(&mut player);
        (player, out)
    })
    .await
    .map_err(|_| Gone)
}
