//! The server: the page and its assets over HTTP, the scene then frames over the WebSocket,
//! time controls, replays, many tabs.

mod common;

use common::*;
use serde_json::Value;
use std::collections::BTreeSet;
use tokio::io::{AsyncReadExt, AsyncWriteExt};
use vitro_viz::server::Feed;
use vitro_viz::{LiveRun, MemoryRecording, ReplayFeed};

/// A plain HTTP/1.1 GET: (status, content type, body).
async fn get(addr: std::net::SocketAddr, path: &str) -> (u16, String, Vec<u8>) {
    let mut s = tokio::net::TcpStream::connect(addr).await.expect("connect");
    let req = format!("GET {path} HTTP/1.1\r\nHost: {addr}\r\nConnection: close\r\n\r\n");
    s.write_all(req.as_bytes()).await.expect("request");
    let mut raw = Vec::new();
    s.read_to_end(&mut raw).await.expect("response");
    let split = raw
        .windows(4)
        .position(|w| w == b"\r\n\r\n")
        .expect("headers end");
    let head = String::from_utf8_lossy(&raw[..split]).to_string();
    let status = head[9..12].parse().expect("status code");
    let ctype = head
        .lines()
        .find_map(|l| {
            l.to_ascii_lowercase()
                .strip_prefix("content-type: ")
                .map(str::to_owned)
        })
        .unwrap_or_default();
    (status, ctype, raw[split + 4..].to_vec())
}

fn live(seed: u64, end_s: u64, speed: Option<f64>, paused: bool) -> LiveRun {
    LiveRun::start(ToySource::new(seed, end_s, 0), speed, paused).expect("start")
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn http_serves_the_page_and_every_asset_it_imports() {
    let run = live(1, 10, Some(1.0), true);
    let addr = start(Feed::Live(run.clone())).await;
    let (status, ctype, body) = get(addr, "/").await;
    assert_eq!(status, 200);
    assert!(ctype.starts_with("text/html"), "{ctype}");
    let page = String::from_utf8(body).expect("utf-8");
    assert!(page.contains("/js/main.js") && page.contains("importmap"));

    // Every module the page loads, and every module those import, is served.
    let mut todo = vec![
        "/js/main.js".to_owned(),
        "/vendor/three/three.module.js".to_owned(),
    ];
    let mut seen = BTreeSet::new();
    while let Some(path) = todo.pop() {
        if !seen.insert(path.clone()) {
            continue;
        }
        let (status, ctype, body) = get(addr, &path).await;
        assert_eq!(status, 200, "{path}");
        assert!(ctype.contains("javascript"), "{path}: {ctype}");
        let text = String::from_utf8(body).expect("utf-8");
        let dir = &path[..path.rfind('/').expect("a directory") + 1];
        // Import statements start a line (`import ...`, or `} from '...'` closing a
        // multi-line one); examples in doc comments do not.
        for line in text.lines().filter(|l| {
            let l = l.trim_start();
            l.starts_with("import ") || l.starts_with("} from ") || l.starts_with("export ")
        }) {
            let Some(spec) = line
                .split(" from '")
                .nth(1)
                .or_else(|| line.strip_prefix("import '"))
                .and_then(|s| s.split('\'').next())
            else {
                continue;
            };
            let resolved = match spec {
                "three" => "/vendor/three/three.module.js".to_owned(),
                s if s.starts_with("three/addons/") => {
                    format!("/vendor/three/{}", &s["three/addons/".len()..])
                }
                s if s.starts_with("./") => format!("{dir}{}", &s[2..]),
                s => panic!("{path} imports {s}: not a vendored module"),
            };
            todo.push(resolved);
        }
    }
    assert!(seen.len() >= 10, "{seen:?}");
    assert!(seen.contains("/vendor/three/three.core.js"));
    assert!(seen.contains("/vendor/three/OrbitControls.js"));

    let (status, ctype, _) = get(addr, "/style.css").await;
    assert_eq!((status, ctype.starts_with("text/css")), (200, true));
    let (status, _, licence) = get(addr, "/vendor/three/LICENSE").await;
    assert_eq!(status, 200);
    assert!(String::from_utf8_lossy(&licence).contains("MIT"));
    assert_eq!(get(addr, "/no/such/file.js").await.0, 404);
    run.stop();
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn websocket_gives_the_scene_once_then_frames() {
    let run = live(2, 3600, Some(50.0), false);
    let addr = start(Feed::Live(run.clone())).await;
    let mut ws = connect(addr).await;
    let hello = next(&mut ws).await.expect("hello");
    assert_eq!(hello["type"], "hello");
    assert_eq!(hello["mode"], "live");
    assert_eq!(hello["end_ns"], 3_600_000_000_000u64);
    let scene = next(&mut ws).await.expect("scene");
    assert_eq!(scene["type"], "scene");
    assert_eq!(scene["scene"]["name"], "toy");
    assert_eq!(next(&mut ws).await.expect("history")["type"], "history");
    let mut last = 0;
    let mut frames = 0;
    while frames < 10 {
        let v = next(&mut ws).await.expect("open");
        assert_ne!(v["type"], "scene", "the scene comes once");
        if v["type"] == "frame" {
            let t = v["frame"]["t_ns"].as_u64().expect("t_ns");
            assert!(t >= last, "frames in time order");
            assert_eq!(v["frame"]["entities"].as_array().map(Vec::len), Some(5));
            last = t;
            frames += 1;
        }
    }
    assert!(last > 0, "the clock advances");
    let status = next_of(&mut ws, "status").await;
    assert_eq!(status["paused"], false);
    assert_eq!(status["speed"], 50.0);
    run.stop();
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn pause_step_speed_and_resume_drive_the_run() {
    let run = live(3, 3600, Some(20.0), false);
    let addr = start(Feed::Live(run.clone())).await;
    let mut ws = connect(addr).await;
    wait_for(&mut ws, "frame", |v| v["frame"]["t_ns"].as_u64() > Some(0)).await;

    send(&mut ws, r#"{"cmd":"pause"}"#).await;
    // The frame showing where the run stopped may come before or after the status that
    // says it is paused.
    let (_, before) = wait_noting(&mut ws, "status", |v| v["paused"] == true, "frame").await;
    // The run stops, and shows where it stopped.
    let control = run.control();
    let at = control.events_fired();
    tokio::time::sleep(std::time::Duration::from_millis(300)).await;
    assert_eq!(control.events_fired(), at, "paused runs fire nothing");
    let shown = match before.filter(|v| v["frame"]["events"] == at) {
        Some(v) => v,
        None => wait_for(&mut ws, "frame", |v| v["frame"]["events"] == at).await,
    };
    let t_paused = shown["frame"]["t_ns"].as_u64().expect("t");

    for k in 1..=3 {
        send(&mut ws, r#"{"cmd":"step","n":1}"#).await;
        let f = wait_for(&mut ws, "frame", |v| v["frame"]["events"] != at + k - 1).await;
        assert_eq!(f["frame"]["events"], at + k, "one step, one event");
        assert!(f["frame"]["t_ns"].as_u64() >= Some(t_paused));
    }
    tokio::time::sleep(std::time::Duration::from_millis(200)).await;
    assert_eq!(control.events_fired(), at + 3);

    send(&mut ws, r#"{"cmd":"speed","factor":200}"#).await;
    wait_for(&mut ws, "status", |v| v["speed"] == 200.0).await;
    assert!(control.is_paused(), "a speed change does not resume");
    send(&mut ws, r#"{"cmd":"resume"}"#).await;
    wait_for(&mut ws, "status", |v| v["paused"] == false).await;
    wait_for(&mut ws, "frame", |v| {
        v["frame"]["events"].as_u64() > Some(at + 100)
    })
    .await;
    run.stop();
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn many_tabs_each_get_the_scene_and_frames() {
    let run = live(4, 3600, Some(100.0), false);
    let addr = start(Feed::Live(run.clone())).await;
    let mut tabs = Vec::new();
    for _ in 0..6 {
        tabs.push(connect(addr).await);
    }
    for ws in &mut tabs {
        next_of(ws, "scene").await;
        next_of(ws, "frame").await;
    }
    // A tab that closes leaves the others going.
    drop(tabs.pop());
    for ws in &mut tabs {
        let a = next_of(ws, "frame").await["frame"]["t_ns"].as_u64();
        let b = wait_for(ws, "frame", |v| v["frame"]["t_ns"].as_u64() > a).await;
        assert!(b["frame"]["t_ns"].as_u64() > a);
    }
    run.stop();
}

fn recording() -> MemoryRecording {
    let frames = (0..50u64)
        .map(|i| vitro_record::Frame {
            t_ns: i * 1_000_000_000,
            events: i * 10,
            metrics: [("i".to_owned(), i as f64)].into(),
            ..Default::default()
        })
        .collect();
    MemoryRecording::new("rec", scene(), frames)
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn replay_plays_seeks_and_steps_per_tab() {
    let feed = ReplayFeed::new(recording()).expect("open");
    let addr = start(Feed::Replay(feed)).await;
    let mut a = connect(addr).await;
    let mut b = connect(addr).await;
    let hello = next(&mut a).await.expect("hello");
    assert_eq!(hello["mode"], "replay");
    assert_eq!(hello["end_ns"], 49_000_000_000u64);
    let history = next_of(&mut a, "history").await;
    assert_eq!(history["t_ns"].as_array().map(Vec::len), Some(50));

    send(&mut a, r#"{"cmd":"seek","t_ns":30500000000}"#).await;
    let f = wait_for(&mut a, "frame", |v| v["frame"]["events"] == 300).await;
    assert_eq!(f["frame"]["t_ns"], 30_000_000_000u64);
    send(&mut a, r#"{"cmd":"step","n":2}"#).await;
    wait_for(&mut a, "frame", |v| v["frame"]["events"] == 320).await;
    wait_for(&mut a, "status", |v| v["paused"] == true).await;
    send(&mut a, r#"{"cmd":"seek","t_ns":2000000000}"#).await;
    wait_for(&mut a, "frame", |v| v["frame"]["events"] == 20).await;

    // The other tab's playhead did not move: it plays from the start at 1x.
    let fb: Value = next_of(&mut b, "frame").await;
    assert!(fb["frame"]["t_ns"].as_u64() < Some(5_000_000_000), "{fb}");
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn mcap_recordings_replay() {
    let path = std::env::temp_dir().join(format!("vitro-viz-replay-{}.mcap", std::process::id()));
    let scene = vitro_record::synthetic::scene();
    let mut rec = vitro_record::Recorder::create(&path, &scene).expect("create");
    for i in 0..40 {
        rec.frame(&vitro_record::synthetic::frame(&scene, i, 6))
            .expect("frame");
    }
    rec.finish().expect("finish");
    let recording = vitro_viz::McapRecording::open(&path).expect("open");
    let feed = ReplayFeed::new(recording).expect("index");
    std::fs::remove_file(&path).expect("remove");
    let addr = start(Feed::Replay(feed)).await;
    let mut ws = connect(addr).await;
    let hello = next(&mut ws).await.expect("hello");
    let (t0, t1) = (
        hello["start_ns"].as_u64().expect("start"),
        hello["end_ns"].as_u64().expect("end"),
    );
    assert!(t1 > t0);
    let scene_msg = next_of(&mut ws, "scene").await;
    assert_eq!(scene_msg["scene"]["name"], scene.name.as_str());
    let mid = t0 + (t1 - t0) / 2;
    send(&mut ws, &format!(r#"{{"cmd":"seek","t_ns":{mid}}}"#)).await;
    let f = wait_for(&mut ws, "frame", |v| {
        v["frame"]["t_ns"]
            .as_u64()
            .is_some_and(|t| t <= mid && t + 2_000_000_000 > mid)
    })
    .await;
    assert_eq!(f["frame"]["entities"].as_array().map(Vec::len), Some(6));
}
