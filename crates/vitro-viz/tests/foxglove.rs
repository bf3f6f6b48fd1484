//! The Foxglove WebSocket server, seen by a client speaking the protocol: handshake,
//! advertise, subscribe, decodable messages on every channel, parameters that pause, step and
//! speed the run without changing its trace, and 403 for a foreign `Host`.

mod common;

use common::{ToySource, WALKERS, unwatched};
use futures_util::{SinkExt, StreamExt};
use serde_json::{Value, json};
use std::collections::{BTreeMap, BTreeSet};
use std::net::SocketAddr;
use std::time::Duration;
use tokio::io::{AsyncReadExt, AsyncWriteExt};
use tokio::net::TcpStream;
use tokio_tungstenite::tungstenite::Message;
use tokio_tungstenite::tungstenite::client::IntoClientRequest;
use tokio_tungstenite::{MaybeTlsStream, WebSocketStream, connect_async};
use vitro_viz::foxglove::{FOXGLOVE_APP_ORIGIN, serve};
use vitro_viz::{HostPolicy, LiveRun};

type Ws = WebSocketStream<MaybeTlsStream<TcpStream>>;

const WAIT: Duration = Duration::from_secs(30);

/// Serves `run` over the Foxglove protocol on a free port of 127.0.0.1.
async fn start(run: &LiveRun) -> SocketAddr {
    let listener = tokio::net::TcpListener::bind("127.0.0.1:0")
        .await
        .expect("bind");
    let addr = listener.local_addr().expect("address");
    let hosts = HostPolicy::new(addr).allow_origin(FOXGLOVE_APP_ORIGIN);
    tokio::spawn(serve(listener, run.clone(), hosts, std::future::pending()));
    addr
}

async fn connect(addr: SocketAddr) -> Ws {
    let mut req = format!("ws://{addr}/").into_client_request().expect("url");
    req.headers_mut().insert(
        "Sec-WebSocket-Protocol",
        "foxglove.websocket.v1".parse().expect("header"),
    );
    let (ws, response) = connect_async(req).await.expect("websocket");
    assert_eq!(
        response.headers()["sec-websocket-protocol"],
        "foxglove.websocket.v1"
    );
    ws
}

/// What the server sent: a JSON op, or a binary message (opcode and the rest).
enum Got {
    Op(Value),
    Binary(u8, Vec<u8>),
}

async fn next(ws: &mut Ws) -> Got {
    loop {
        let msg = tokio::time::timeout(WAIT, ws.next())
            .await
            .expect("a message within the wait")
            .expect("connection open")
            .expect("a message");
        match msg {
            Message::Text(t) => return Got::Op(serde_json::from_str(t.as_str()).expect("JSON")),
            Message::Binary(b) => return Got::Binary(b[0], b[1..].to_vec()),
            _ => {}
        }
    }
}

async fn next_op(ws: &mut Ws, op: &str) -> Value {
    loop {
        if let Got::Op(v) = next(ws).await
            && v["op"] == op
        {
            return v;
        }
    }
}

async fn send(ws: &mut Ws, v: Value) {
    ws.send(Message::Text(v.to_string().into()))
        .await
        .expect("send");
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn every_advertised_channel_delivers_decodable_messages_in_simulated_time() {
    let run = LiveRun::start(ToySource::new(7, 600, 8), Some(20.0), false).expect("start");
    let addr = start(&run).await;
    let mut ws = connect(addr).await;
    let info = next_op(&mut ws, "serverInfo").await;
    let caps: Vec<&str> = info["capabilities"]
        .as_array()
        .expect("capabilities")
        .iter()
        .filter_map(Value::as_str)
        .collect();
    assert!(
        caps.contains(&"time") && caps.contains(&"parameters"),
        "{caps:?}"
    );
    assert_eq!(info["metadata"]["start"], "1970-01-01T00:00:00Z");
    let adv = next_op(&mut ws, "advertise").await;
    let mut channels: BTreeMap<u64, (String, String)> = BTreeMap::new();
    for c in adv["channels"].as_array().expect("channels") {
        assert_eq!(c["encoding"], "json");
        assert_eq!(c["schemaEncoding"], "jsonschema");
        let schema: Value = serde_json::from_str(c["schema"].as_str().expect("schema text"))
            .expect("the schema is JSON");
        assert_eq!(schema["title"], c["schemaName"]);
        let id = c["id"].as_u64().expect("id");
        let topic = c["topic"].as_str().expect("topic").to_owned();
        channels.insert(id, (topic, c["schemaName"].as_str().expect("name").into()));
    }
    let topics: BTreeSet<&str> = channels.values().map(|(t, _)| t.as_str()).collect();
    for t in [
        "/vitro/scene",
        "/vitro/frame",
        "/map",
        "/entities",
        "/tf",
        "/log",
        "/metrics",
    ] {
        assert!(topics.contains(t), "{t} advertised");
    }
    assert_eq!(
        topics.iter().filter(|t| t.starts_with("/gps/")).count(),
        WALKERS as usize
    );
    // Subscription ids other than the channel ids, to check the server uses the client's.
    let subscriptions: Vec<Value> = channels
        .keys()
        .map(|&id| json!({"id": id + 100, "channelId": id}))
        .collect();
    send(
        &mut ws,
        json!({"op": "subscribe", "subscriptions": subscriptions}),
    )
    .await;
    let mut unseen: BTreeSet<u64> = channels.keys().copied().collect();
    let mut times = 0;
    let got_all = async {
        while !unseen.is_empty() || times == 0 {
            match next(&mut ws).await {
                Got::Binary(1, rest) => {
                    let sub = u32::from_le_bytes(rest[..4].try_into().expect("4 bytes"));
                    let t = u64::from_le_bytes(rest[4..12].try_into().expect("8 bytes"));
                    let payload: Value =
                        serde_json::from_slice(&rest[12..]).expect("a JSON payload");
                    let channel = u64::from(sub) - 100;
                    let (topic, schema) = &channels[&channel];
                    if schema == "foxglove.LocationFix" || schema == "foxglove.Log" {
                        let stamp = &payload["timestamp"];
                        let ns = stamp["sec"].as_u64().expect("sec") * 1_000_000_000
                            + stamp["nsec"].as_u64().expect("nsec");
                        assert_eq!(ns, t, "{topic}: the message time is its own");
                    }
                    unseen.remove(&channel);
                }
                Got::Binary(2, rest) => {
                    assert_eq!(rest.len(), 8);
                    times += 1;
                }
                Got::Binary(op, _) => panic!("unexpected binary opcode {op}"),
                Got::Op(v) => assert_ne!(v["op"], "status", "{v}"),
            }
        }
    };
    tokio::time::timeout(WAIT, got_all)
        .await
        .expect("a message on every channel within the wait");
    run.stop();
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn parameters_pause_step_and_speed_the_run_and_leave_its_trace_alone() {
    let (seed, end_s) = (11, 40);
    let run = LiveRun::start(ToySource::new(seed, end_s, 0), Some(1.0), false).expect("start");
    let addr = start(&run).await;
    let mut ws = connect(addr).await;
    send(
        &mut ws,
        json!({"op": "getParameters", "parameterNames": [], "id": "all"}),
    )
    .await;
    let all = next_op(&mut ws, "parameterValues").await;
    assert_eq!(all["id"], "all");
    let names: Vec<&str> = all["parameters"]
        .as_array()
        .expect("parameters")
        .iter()
        .filter_map(|p| p["name"].as_str())
        .collect();
    assert_eq!(names, ["paused", "speed", "step"]);
    send(
        &mut ws,
        json!({"op": "subscribeParameterUpdates", "parameterNames": ["paused"]}),
    )
    .await;
    let set = |name: &str, value: Value| json!({"op": "setParameters", "parameters": [{"name": name, "value": value}], "id": name});
    send(&mut ws, set("paused", json!(true))).await;
    let v = next_op(&mut ws, "parameterValues").await;
    assert_eq!(v["parameters"][0]["value"], true);
    assert!(run.status().paused);
    // Let an interrupted slice settle, then step exactly 3 events.
    tokio::time::sleep(Duration::from_millis(200)).await;
    let before = run.status().events;
    send(&mut ws, set("step", json!(3))).await;
    next_op(&mut ws, "parameterValues").await;
    let stepped = async {
        while run.status().events < before + 3 {
            tokio::time::sleep(Duration::from_millis(10)).await;
        }
    };
    tokio::time::timeout(WAIT, stepped)
        .await
        .expect("the steps fire");
    tokio::time::sleep(Duration::from_millis(200)).await;
    assert_eq!(run.status().events, before + 3);
    // Out of range or unknown: refused with a status, the run untouched.
    send(&mut ws, set("speed", json!(1e9))).await;
    assert_eq!(next_op(&mut ws, "status").await["level"], 2);
    send(&mut ws, set("warp", json!(1))).await;
    assert_eq!(next_op(&mut ws, "status").await["level"], 2);
    send(&mut ws, set("speed", json!(1000.0))).await;
    send(&mut ws, set("paused", json!(false))).await;
    let outcome = tokio::time::timeout(WAIT, run.finished())
        .await
        .expect("the run ends");
    assert_eq!((outcome.trace_hash, outcome.events), unwatched(seed, end_s));
    run.stop();
}

/// The status code of a WebSocket handshake on `/` with these headers.
async fn handshake(addr: SocketAddr, host: &str, origin: Option<&str>, proto: bool) -> u16 {
    let mut s = TcpStream::connect(addr).await.expect("connect");
    let mut req = format!(
        "GET / HTTP/1.1\r\nHost: {host}\r\nConnection: Upgrade\r\nUpgrade: websocket\r\n\
         Sec-WebSocket-Version: 13\r\nSec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==\r\n"
    );
    if let Some(o) = origin {
        req += &format!("Origin: {o}\r\n");
    }
    if proto {
        req += "Sec-WebSocket-Protocol: foxglove.websocket.v1\r\n";
    }
    req += "\r\n";
    s.write_all(req.as_bytes()).await.expect("request");
    let mut head = [0u8; 12];
    tokio::time::timeout(WAIT, s.read_exact(&mut head))
        .await
        .expect("an answer within the wait")
        .expect("a status line");
    String::from_utf8_lossy(&head[9..12])
        .parse()
        .expect("status code")
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn only_this_machine_and_the_foxglove_app_are_answered() {
    let run = LiveRun::start(ToySource::new(3, 60, 0), Some(1.0), true).expect("start");
    let addr = start(&run).await;
    let port = addr.port();
    let own = format!("127.0.0.1:{port}");
    let evil = format!("evil.example:{port}");
    assert_eq!(handshake(addr, &own, None, true).await, 101);
    assert_eq!(
        handshake(addr, &format!("localhost:{port}"), None, true).await,
        101
    );
    assert_eq!(
        handshake(addr, &own, Some(FOXGLOVE_APP_ORIGIN), true).await,
        101
    );
    assert_eq!(handshake(addr, &evil, None, true).await, 403);
    assert_eq!(
        handshake(addr, &evil, Some(FOXGLOVE_APP_ORIGIN), true).await,
        403
    );
    assert_eq!(
        handshake(addr, &format!("127.0.0.1:{}", port ^ 1), None, true).await,
        403
    );
    assert_eq!(
        handshake(addr, &own, Some("http://evil.example"), true).await,
        403
    );
    assert_eq!(handshake(addr, &own, None, false).await, 400);
    run.stop();
}
