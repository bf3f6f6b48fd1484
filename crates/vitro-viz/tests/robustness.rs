//! Clients never hurt the run: bad or oversized messages are rejected, a stalled client does
//! not stall the simulation, and a watched run has the unwatched run's trace hash.

mod common;

use common::*;
use futures_util::SinkExt;
use std::time::{Duration, Instant};
use tokio_tungstenite::tungstenite::Message;
use vitro_viz::LiveRun;
use vitro_viz::server::Feed;

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn bad_messages_are_rejected_and_oversized_ones_close_the_connection() {
    let run = LiveRun::start(ToySource::new(5, 3600, 0), Some(10.0), false).expect("start");
    let addr = start(Feed::Live(run.clone())).await;
    let mut ws = connect(addr).await;
    next_of(&mut ws, "scene").await;
    for bad in [
        "not json",
        "{}",
        r#"{"cmd":"explode"}"#,
        r#"{"cmd":"pause","now":true}"#,
        r#"{"cmd":"speed","factor":1e12}"#,
        r#"{"cmd":"step","n":0}"#,
        r#"{"cmd":"seek","t_ns":5}"#,
    ] {
        send(&mut ws, bad).await;
        let e = next_of(&mut ws, "error").await;
        assert!(
            e["message"].as_str().is_some_and(|m| !m.is_empty()),
            "{bad}"
        );
    }
    ws.send(Message::Binary(vec![1u8, 2, 3].into()))
        .await
        .expect("send");
    next_of(&mut ws, "error").await;
    assert!(!run.control().is_paused(), "nothing bad was obeyed");
    assert_eq!(run.control().speed(), Some(10.0));
    // Still listening to good commands.
    send(&mut ws, r#"{"cmd":"pause"}"#).await;
    wait_for(&mut ws, "status", |v| v["paused"] == true).await;
    send(&mut ws, r#"{"cmd":"resume"}"#).await;

    // Over the size limit: the connection is closed, the server goes on.
    let huge = format!(r#"{{"cmd":"pause","pad":"{}"}}"#, "x".repeat(64 * 1024));
    let _ = ws.send(Message::Text(huge.into())).await;
    let mut closed = false;
    for _ in 0..1000 {
        match next(&mut ws).await {
            None => {
                closed = true;
                break;
            }
            Some(v) => assert_ne!(v["type"], "status_never"),
        }
    }
    assert!(closed, "an oversized message closes the connection");
    assert!(!run.control().is_paused());
    let mut again = connect(addr).await;
    next_of(&mut again, "frame").await;
    assert!(run.outcome().is_none(), "the run goes on");
    run.stop();
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_stalled_client_does_not_stall_the_run() {
    // Heavy frames (256 KiB each) to a client that never reads: its socket buffers fill in
    // well under a second, long before the run ends.
    const END_S: u64 = 4000;
    let run =
        LiveRun::start(ToySource::new(6, END_S, 256 * 1024), Some(1000.0), false).expect("start");
    let addr = start(Feed::Live(run.clone())).await;
    let stalled = connect(addr).await;
    let mut live = connect(addr).await;
    next_of(&mut live, "scene").await;
    let started = Instant::now();
    let outcome = tokio::time::timeout(Duration::from_secs(60), run.finished())
        .await
        .expect("the run ends although one client reads nothing");
    // Paced at 1000x, 4000 s take 4 s of wall time; a stall would take forever.
    assert!(started.elapsed() < Duration::from_secs(30));
    assert_eq!((outcome.trace_hash, outcome.events), unwatched(6, END_S));
    // The reading client saw the end.
    wait_for(&mut live, "status", |v| v["finished"] == true).await;
    drop(stalled);
    run.stop();
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_watched_and_driven_run_has_the_unwatched_trace_hash() {
    const END_S: u64 = 600;
    let run = LiveRun::start(ToySource::new(7, END_S, 0), Some(300.0), false).expect("start");
    let addr = start(Feed::Live(run.clone())).await;
    let mut ws = connect(addr).await;
    let mut other = connect(addr).await;
    wait_for(&mut ws, "frame", |v| {
        v["frame"]["t_ns"].as_u64() > Some(1_000_000_000)
    })
    .await;
    for cmd in [
        r#"{"cmd":"pause"}"#,
        r#"{"cmd":"step","n":1}"#,
        r#"{"cmd":"step","n":5}"#,
        r#"{"cmd":"speed","factor":0.5}"#,
        r#"{"cmd":"resume"}"#,
        r#"{"cmd":"speed","factor":1000}"#,
        r#"{"cmd":"step","n":2}"#,
        r#"{"cmd":"resume"}"#,
    ] {
        send(&mut ws, cmd).await;
        next_of(&mut ws, "status").await;
        tokio::time::sleep(Duration::from_millis(60)).await;
    }
    let outcome = tokio::time::timeout(Duration::from_secs(60), run.finished())
        .await
        .expect("the run ends");
    assert_eq!(outcome.failure, None);
    assert!(!outcome.stopped);
    assert_eq!(outcome.t_ns, END_S * 1_000_000_000);
    assert_eq!((outcome.trace_hash, outcome.events), unwatched(7, END_S));
    let last = wait_for(&mut other, "status", |v| v["finished"] == true).await;
    assert_eq!(
        last["trace_hash"],
        format!("{:016x}", outcome.trace_hash).as_str()
    );
    run.stop();
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn cross_origin_pages_cannot_connect() {
    use tokio_tungstenite::tungstenite::client::IntoClientRequest;
    let run = LiveRun::start(ToySource::new(8, 60, 0), Some(1.0), true).expect("start");
    let addr = start(Feed::Live(run.clone())).await;
    let mut req = format!("ws://{addr}/ws")
        .into_client_request()
        .expect("request");
    req.headers_mut()
        .insert("origin", "http://evil.example".parse().expect("header"));
    assert!(tokio_tungstenite::connect_async(req).await.is_err());
    let mut req = format!("ws://{addr}/ws")
        .into_client_request()
        .expect("request");
    req.headers_mut()
        .insert("origin", format!("http://{addr}").parse().expect("header"));
    assert!(tokio_tungstenite::connect_async(req).await.is_ok());
    run.stop();
}

#[tokio::test(flavor = "multi_thread", worker_threads = 2)]
async fn a_run_over_early_ends_at_its_last_event_and_one_at_its_end_time_there() {
    use vitro::prelude::{SimTime, Simulation, Target};
    // Nothing after 5.5 s: over early, at its last event.
    let mut sim = Simulation::<Toy>::new((), 1);
    sim.schedule(SimTime::from_nanos(5_500_000_000), Target::Broadcast, ())
        .expect("future");
    let source = ToySource {
        sim,
        end_ns: 60_000_000_000,
        pad: 0,
    };
    let run = LiveRun::start(source, Some(1000.0), false).expect("start");
    let o = tokio::time::timeout(Duration::from_secs(30), run.finished())
        .await
        .expect("over");
    assert_eq!((o.t_ns, o.events), (5_500_000_000, 1));
    // Walkers go on for ever: over at the end time, whenever the last event was.
    let run = LiveRun::start(ToySource::new(2, 7, 0), Some(1000.0), false).expect("start");
    let o = tokio::time::timeout(Duration::from_secs(30), run.finished())
        .await
        .expect("over");
    assert_eq!(o.t_ns, 7_000_000_000);
}
