//! A toy model to watch (walkers on circles), a server on a free port, and WebSocket helpers.

#![allow(dead_code)] // each test file uses part of it

use futures_util::{SinkExt, StreamExt};
use rand::Rng;
use serde_json::Value;
use std::net::SocketAddr;
use std::time::Duration;
use tokio::net::TcpStream;
use tokio_tungstenite::tungstenite::Message;
use tokio_tungstenite::{MaybeTlsStream, WebSocketStream, connect_async};
use vitro::prelude::*;
use vitro::sim::Control;
use vitro_record::{EntityState, Frame, Geo, Heightmap, Scene, Side};
use vitro_viz::server::{Feed, serve};
use vitro_viz::{LiveSource, SourceError, advance_sim};

/// Walkers that step around a circle at random intervals.
pub struct Toy;

pub struct Walker {
    pub angle: f64,
}

impl Agent<Toy> for Walker {
    fn handle(&mut self, input: Input<'_, Toy>, cx: &mut Context<'_, Toy>) {
        if matches!(input, Input::Event(()) | Input::Timer(_)) {
            let r = cx.rng("walk");
            self.angle += r.random_range(0.01..0.1);
            let ms = r.random_range(20..200);
            cx.set_timer(SimDuration::from_millis(ms), 0);
        }
    }
}

impl Model for Toy {
    type Env = ();
    type Event = ();
    type Msg = ();
    type Agent = Walker;
}

pub const WALKERS: u32 = 5;

pub fn toy_sim(seed: u64) -> Simulation<Toy> {
    let mut sim = Simulation::<Toy>::new((), seed);
    for i in 0..WALKERS {
        sim.add_agent(format!("walker-{i}"), Walker { angle: 0.0 })
            .expect("unique names");
    }
    sim.schedule(SimTime::ZERO, Target::Broadcast, ())
        .expect("future");
    sim
}

/// The toy as a live source; `pad` bytes of log per frame make frames heavy.
pub struct ToySource {
    pub sim: Simulation<Toy>,
    pub end_ns: u64,
    pub pad: usize,
}

impl ToySource {
    pub fn new(seed: u64, end_s: u64, pad: usize) -> Self {
        ToySource {
            sim: toy_sim(seed),
            end_ns: end_s * 1_000_000_000,
            pad,
        }
    }
}

/// The trace hash and event count of the toy run to its end, unwatched.
pub fn unwatched(seed: u64, end_s: u64) -> (u64, u64) {
    let mut sim = toy_sim(seed);
    sim.run_until(SimTime::from_secs(end_s));
    (sim.trace_hash(), sim.events_fired())
}

pub fn scene() -> Scene {
    Scene {
        name: "toy".into(),
        start_unix_ms: 0,
        geo: Geo {
            lat0: 60.0,
            lon0: 25.0,
            m_per_deg_lat: 111_000.0,
            m_per_deg_lon: 55_000.0,
            offset: [0.0, 0.0],
            z0: 0.0,
        },
        extent: [-100.0, -100.0, 100.0, 100.0],
        streets: vec![vec![[-100.0, 0.0, 0.0], [100.0, 0.0, 0.0]]],
        paths: vec![],
        buildings: vec![],
        bridges: vec![],
        forbidden: vec![],
        places: Default::default(),
        terrain: Heightmap {
            nx: 2,
            ny: 2,
            origin: [-100.0, -100.0],
            cell: 200.0,
            z: vec![0.0, 1.0, 2.0, 3.0],
        },
    }
}

impl LiveSource for ToySource {
    fn title(&self) -> String {
        "toy".into()
    }
    fn scene(&self) -> Scene {
        scene()
    }
    fn control(&self) -> Control {
        self.sim.control()
    }
    fn end_ns(&self) -> Option<u64> {
        Some(self.end_ns)
    }
    fn advance(&mut self, until_ns: u64) -> Result<bool, SourceError> {
        Ok(advance_sim(&mut self.sim, until_ns))
    }
    fn frame(&mut self, t_ns: u64) -> Frame {
        let entities = (0..WALKERS)
            .map(|i| {
                let a = self
                    .sim
                    .agent(vitro::entity::EntityId(i))
                    .map_or(0.0, |w| w.angle);
                EntityState {
                    id: i,
                    name: format!("walker-{i}"),
                    kind: "trooper".into(),
                    side: Side::Friendly,
                    level: "discrete".into(),
                    pos: [50.0 * a.cos(), 50.0 * a.sin(), 0.0],
                    heading: a,
                    speed: 1.0,
                    status: "active".into(),
                }
            })
            .collect();
        Frame {
            t_ns,
            events: self.sim.events_fired(),
            entities,
            metrics: [("events".to_owned(), self.sim.events_fired() as f64)].into(),
            log: if self.pad > 0 {
                vec!["x".repeat(self.pad)]
            } else {
                vec![]
            },
            ..Frame::default()
        }
    }
    fn trace_hash(&self) -> u64 {
        self.sim.trace_hash()
    }
}

/// Serves `feed` on a free port of 127.0.0.1 (on the test's runtime).
pub async fn start(feed: Feed) -> SocketAddr {
    let listener = tokio::net::TcpListener::bind("127.0.0.1:0")
        .await
        .expect("bind");
    let addr = listener.local_addr().expect("address");
    tokio::spawn(serve(listener, feed, std::future::pending()));
    addr
}

pub type Ws = WebSocketStream<MaybeTlsStream<TcpStream>>;

pub async fn connect(addr: SocketAddr) -> Ws {
    connect_async(format!("ws://{addr}/ws"))
        .await
        .expect("websocket")
        .0
}

/// The next text message as JSON (`None` when the connection ends); fails after 10 s.
pub async fn next(ws: &mut Ws) -> Option<Value> {
    loop {
        let msg = tokio::time::timeout(Duration::from_secs(10), ws.next())
            .await
            .expect("a message within 10 s");
        match msg {
            Some(Ok(Message::Text(t))) => {
                return Some(serde_json::from_str(t.as_str()).expect("JSON"));
            }
            Some(Ok(Message::Close(_))) | None | Some(Err(_)) => return None,
            Some(Ok(_)) => {}
        }
    }
}

/// The next message of type `kind`, skipping others.
pub async fn next_of(ws: &mut Ws, kind: &str) -> Value {
    loop {
        let v = next(ws).await.expect("connection open");
        if v["type"] == kind {
            return v;
        }
    }
}

/// How long a test waits for a message it expects: status messages keep coming, so a
/// wait for one that never does would otherwise hang rather than fail.
pub const WAIT: Duration = Duration::from_secs(30);

/// The first message of type `kind` for which `pred` holds, skipping others.
pub async fn wait_for(ws: &mut Ws, kind: &str, pred: impl Fn(&Value) -> bool) -> Value {
    wait_noting(ws, kind, pred, "").await.0
}

/// The first message of type `kind` for which `pred` holds, and the last message of type
/// `noted` skipped on the way (a frame that came before the status that was waited for).
pub async fn wait_noting(
    ws: &mut Ws,
    kind: &str,
    pred: impl Fn(&Value) -> bool,
    noted: &str,
) -> (Value, Option<Value>) {
    let mut last = None;
    let wait = async {
        loop {
            let v = next(ws).await.expect("connection open");
            if v["type"] == kind && pred(&v) {
                return v;
            }
            if v["type"] == noted {
                last = Some(v);
            }
        }
    };
    let found = tokio::time::timeout(WAIT, wait)
        .await
        .unwrap_or_else(|_| panic!("no {kind} message as expected within {WAIT:?}"));
    (found, last)
}

pub async fn send(ws: &mut Ws, text: &str) {
    ws.send(Message::Text(text.into())).await.expect("send");
}
