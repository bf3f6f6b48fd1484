//! The server answers only to this machine: a request whose `Host` names another site (DNS
//! rebinding), one from a foreign or a `null` `Origin`, gets 403 for the page, the assets and
//! the WebSocket; loopback names, the bound address and names allowed on purpose are served.

mod common;

use common::*;
use std::net::SocketAddr;
use tokio::io::{AsyncReadExt, AsyncWriteExt};
use vitro_viz::server::{Feed, serve_with};
use vitro_viz::{HostPolicy, LiveRun};

/// The status code of a GET of `path` with these `Host` and `Origin` headers; `upgrade`
/// makes it a WebSocket handshake.
async fn status(
    addr: SocketAddr,
    path: &str,
    host: &str,
    origin: Option<&str>,
    upgrade: bool,
) -> u16 {
    let mut s = tokio::net::TcpStream::connect(addr).await.expect("connect");
    let mut req = format!("GET {path} HTTP/1.1\r\nHost: {host}\r\n");
    if let Some(o) = origin {
        req += &format!("Origin: {o}\r\n");
    }
    if upgrade {
        req += "Connection: Upgrade\r\nUpgrade: websocket\r\nSec-WebSocket-Version: 13\r\n\
                Sec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==\r\n";
    } else {
        req += "Connection: close\r\n";
    }
    req += "\r\n";
    s.write_all(req.as_bytes()).await.expect("request");
    let mut head = Vec::new();
    let mut byte = [0u8; 1];
    while !head.ends_with(b"\r\n") {
        let n = s.read(&mut byte).await.expect("response");
        assert_eq!(n, 1, "the response has a status line");
        head.push(byte[0]);
    }
    let line = String::from_utf8_lossy(&head).to_string();
    line[9..12].parse().expect("status code")
}

fn run() -> LiveRun {
    LiveRun::start(ToySource::new(3, 60, 0), Some(1.0), true).expect("start")
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn the_rebinding_request_is_refused_for_the_page_the_assets_and_the_websocket() {
    let run = run();
    let addr = start(Feed::Live(run.clone())).await;
    let port = addr.port();
    let evil = format!("evil.example:{port}");
    let evil_origin = format!("http://{evil}");
    for path in ["/", "/js/main.js", "/index.html"] {
        assert_eq!(
            status(addr, path, &evil, Some(&evil_origin), false).await,
            403,
            "{path}"
        );
        assert_eq!(status(addr, path, &evil, None, false).await, 403, "{path}");
    }
    assert_eq!(
        status(addr, "/ws", &evil, Some(&evil_origin), true).await,
        403
    );
    assert_eq!(status(addr, "/ws", &evil, None, true).await, 403);
    // A different port on a loopback name is another server's page.
    let other = format!("127.0.0.1:{}", port.wrapping_add(1));
    assert_eq!(status(addr, "/", &other, None, false).await, 403);
    run.stop();
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn foreign_and_null_origins_are_refused_on_a_local_host() {
    let run = run();
    let addr = start(Feed::Live(run.clone())).await;
    let host = addr.to_string();
    for origin in [
        "http://evil.example".to_owned(),
        format!("http://evil.example:{}", addr.port()),
        "null".to_owned(),
        format!("http://127.0.0.1:{}", addr.port().wrapping_add(1)),
    ] {
        assert_eq!(
            status(addr, "/ws", &host, Some(&origin), true).await,
            403,
            "{origin}"
        );
        assert_eq!(
            status(addr, "/", &host, Some(&origin), false).await,
            403,
            "{origin}"
        );
    }
    run.stop();
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn loopback_names_and_the_bound_address_are_served() {
    let run = run();
    let addr = start(Feed::Live(run.clone())).await;
    let port = addr.port();
    for host in [
        addr.to_string(),
        format!("localhost:{port}"),
        format!("viewer.localhost:{port}"),
        format!("127.0.0.2:{port}"),
        format!("[::1]:{port}"),
    ] {
        let origin = format!("http://{host}");
        assert_eq!(status(addr, "/", &host, None, false).await, 200, "{host}");
        assert_eq!(
            status(addr, "/", &host, Some(&origin), false).await,
            200,
            "{host}"
        );
        assert_eq!(
            status(addr, "/ws", &host, Some(&origin), true).await,
            101,
            "{host}"
        );
        assert_eq!(status(addr, "/ws", &host, None, true).await, 101, "{host}");
    }
    run.stop();
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_name_allowed_on_purpose_is_served_and_others_still_refused() {
    let run = run();
    let listener = tokio::net::TcpListener::bind("127.0.0.1:0")
        .await
        .expect("bind");
    let addr = listener.local_addr().expect("address");
    let hosts = HostPolicy::new(addr).allow("viewer.example").expect("name");
    tokio::spawn(serve_with(
        listener,
        Feed::Live(run.clone()),
        hosts,
        std::future::pending(),
    ));
    assert_eq!(status(addr, "/", "viewer.example", None, false).await, 200);
    assert_eq!(
        status(
            addr,
            "/ws",
            "viewer.example",
            Some("https://viewer.example"),
            true
        )
        .await,
        101
    );
    assert_eq!(status(addr, "/", "evil.example", None, false).await, 403);
    assert_eq!(
        status(
            addr,
            "/ws",
            "viewer.example",
            Some("https://evil.example"),
            true
        )
        .await,
        403
    );
    run.stop();
}
