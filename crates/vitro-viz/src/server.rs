//! The HTTP server: the page and its assets from the binary, the state over a WebSocket.
//!
//! Each connection gets its own task. A client that reads slowly only gets fewer frames (it
//! picks the newest when it is ready); one that stops reading is dropped after
//! [`SEND_TIMEOUT`]; neither ever blocks the simulation.

use crate::live::LiveRun;
use crate::protocol::{Command, CommandError, MAX_COMMAND_BYTES, ServerMsg, Status};
use crate::replay::{Player, ReplayFeed};
use crate::{ViewError, assets};
use axum::Router;
use axum::extract::State;
use axum::extract::ws::{Message, WebSocket, WebSocketUpgrade};
use axum::http::{HeaderMap, StatusCode, header};
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

/// The routes: `/ws` for the WebSocket, every other path an embedded asset (`/` is the page).
pub fn router(feed: Feed) -> Router {
    Router::new()
        .route("/ws", get(upgrade))
        .fallback(asset)
        .with_state(feed)
}

/// Serves `feed` on `listener` until `shutdown` completes.
pub async fn serve(
    listener: TcpListener,
    feed: Feed,
    shutdown: impl Future<Output = ()> + Send + 'static,
) -> Result<(), ViewError> {
    axum::serve(listener, router(feed))
        .with_graceful_shutdown(shutdown)
        .await
        .map_err(ViewError::Serve)
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

/// Accepts a WebSocket from a page of this server (or from a client that sends no
/// `Origin`, such as a test or a script), with client messages capped in size.
async fn upgrade(ws: WebSocketUpgrade, headers: HeaderMap, State(feed): State<Feed>) -> Response {
    if !same_origin(&headers) {
        return (StatusCode::FORBIDDEN, "cross-origin WebSocket refused").into_response();
    }
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

/// True if the request has no `Origin` or one whose host is the `Host` it was sent to.
fn same_origin(headers: &HeaderMap) -> bool {
    let Some(origin) = headers.get(header::ORIGIN) else {
        return true;
    };
    let host = headers.get(header::HOST).and_then(|h| h.to_str().ok());
    let origin_host = origin
        .to_str()
        .ok()
        .and_then(|o| o.split_once("://"))
        .map(|(_, rest)| rest.trim_end_matches('/'));
    matches!((origin_host, host), (Some(o), Some(h)) if o.eq_ignore_ascii_case(h))
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
                if let Some(json) = latest {
                    send(&mut socket, &*json).await?;
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

#[cfg(test)]
mod tests {
    use super::*;

    fn headers(origin: Option<&str>, host: &str) -> HeaderMap {
        let mut h = HeaderMap::new();
        h.insert(header::HOST, host.parse().unwrap());
        if let Some(o) = origin {
            h.insert(header::ORIGIN, o.parse().unwrap());
        }
        h
    }

    #[test]
    fn only_same_origin_pages_may_connect() {
        assert!(same_origin(&headers(None, "127.0.0.1:8080")));
        assert!(same_origin(&headers(
            Some("http://127.0.0.1:8080"),
            "127.0.0.1:8080"
        )));
        assert!(!same_origin(&headers(
            Some("http://evil.example"),
            "127.0.0.1:8080"
        )));
        assert!(!same_origin(&headers(
            Some("http://127.0.0.1:9999"),
            "127.0.0.1:8080"
        )));
    }
}
