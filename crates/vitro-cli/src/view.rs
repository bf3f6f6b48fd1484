//! `vitro view`: watch a scenario run live, or replay a recording, in the browser.
//!
//! `vitro view SCENARIO.toml` runs the scenario on its own thread, paced at `--speed`
//! simulated seconds per wall second, and serves the viewer on `--addr`; `vitro view
//! RUN.mcap` replays a recording. The page, its scripts and three.js come from the binary.
//! With `--foxglove [ADDR]` the live run is also served over the Foxglove WebSocket protocol
//! (default `127.0.0.1:8765`), for the Foxglove app: the same frames, the same controls.

mod live;

use crate::Failure;
use crate::missions::{failure, registry};
use anyhow::{Context as _, anyhow};
use clap::Args;
use std::io::Write as _;
use std::net::SocketAddr;
use std::path::PathBuf;
use vitro::time::SimTime;
use vitro_mission::BuildOptions;
use vitro_viz::server::{Feed, serve_with};
use vitro_viz::{HostPolicy, LiveRun, McapRecording, Outcome, ReplayFeed, ViewError};

/// The longest run `--until` accepts, simulated seconds.
const MAX_UNTIL_S: f64 = 1.0e6;

#[derive(Debug, Args)]
pub(crate) struct ViewArgs {
    /// A scenario file (TOML) to run live, or a recording (.mcap) to replay.
    target: PathBuf,
    /// Address to serve on (port 0: any free port; the address is printed).
    #[arg(long, default_value = "127.0.0.1:8080")]
    addr: SocketAddr,
    /// Simulated seconds per wall second (0.1 to 1000).
    #[arg(long, default_value_t = 1.0, value_name = "X")]
    speed: f64,
    /// Starts paused (live).
    #[arg(long)]
    paused: bool,
    /// Master seed (overrides the scenario's).
    #[arg(long)]
    seed: Option<u64>,
    /// Simulated seconds to run (overrides the scenario's end time).
    #[arg(long, value_name = "SECONDS")]
    until: Option<f64>,
    /// Also answer to this host name (with a port: only that port), for a viewer served
    /// under another name on purpose; repeatable. Without it the viewer answers only to
    /// loopback names and the address it is bound to.
    #[arg(long = "allow-host", value_name = "NAME")]
    allow_host: Vec<String>,
    /// Also answer to requests from pages of this origin (`https://viewer.example`, exactly),
    /// their `Host` still checked; repeatable. The Foxglove server always answers to the
    /// Foxglove web app's, https://app.foxglove.dev.
    #[arg(long = "allow-origin", value_name = "ORIGIN")]
    allow_origin: Vec<String>,
    /// Also serves the live run over the Foxglove WebSocket protocol on ADDR (default
    /// 127.0.0.1:8765), for the Foxglove app: Open connection, Foxglove WebSocket,
    /// ws://ADDR. Put it after the scenario.
    #[cfg(feature = "foxglove")]
    #[arg(
        long,
        value_name = "ADDR",
        num_args = 0..=1,
        default_missing_value = "127.0.0.1:8765"
    )]
    foxglove: Option<SocketAddr>,
}

impl ViewArgs {
    /// Where to serve the Foxglove protocol, if asked.
    fn foxglove(&self) -> Option<SocketAddr> {
        #[cfg(feature = "foxglove")]
        return self.foxglove;
        #[cfg(not(feature = "foxglove"))]
        None
    }
}

pub(crate) fn view(args: &ViewArgs) -> Result<(), Failure> {
    // Checked before anything runs: a bad name is bad input.
    hosts(args.addr, args)?;
    let is_recording = args
        .target
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("mcap"));
    if is_recording && args.foxglove().is_some() {
        return Err(Failure::Input(anyhow!(
            "--foxglove serves a live run: open a recording ({}) in Foxglove as a file",
            args.target.display()
        )));
    }
    let feed = if is_recording {
        vitro_tools::input_file(&args.target)?;
        let recording = McapRecording::open(&args.target)
            .with_context(|| format!("cannot replay {}", args.target.display()))
            .map_err(Failure::Input)?;
        let feed = ReplayFeed::new(recording)
            .with_context(|| format!("cannot replay {}", args.target.display()))
            .map_err(Failure::Input)?;
        Feed::Replay(feed)
    } else {
        let until = until_ns(args.until)?;
        // The scenario is checked here, so that bad input is reported before the server
        // starts; the run is built on its simulation thread (a run need not move between
        // threads).
        registry()
            .validate(&args.target)
            .map_err(|e| failure(&args.target, e))?;
        let (path, options) = (
            args.target.clone(),
            BuildOptions {
                seed: args.seed,
                fidelity: None,
            },
        );
        let build = move || {
            let mut run = registry().build(&path, &options)?;
            if let Some(u) = until {
                run.set_end(run.end().min(SimTime::from_nanos(u)));
            }
            Ok(live::RunSource::new(run))
        };
        let run = LiveRun::spawn(build, Some(args.speed), args.paused);
        Feed::Live(run.map_err(|e| match e {
            ViewError::Speed(_) => Failure::Input(anyhow::Error::new(e).context("--speed")),
            e => Failure::Runtime(anyhow::Error::new(e).context("cannot start the run")),
        })?)
    };
    let runtime = tokio::runtime::Builder::new_multi_thread()
        .worker_threads(2)
        .enable_all()
        .build()
        .context("starting the server's runtime")
        .map_err(Failure::Runtime)?;
    let result = runtime.block_on(serve_until_interrupted(args, feed.clone()));
    if let Feed::Live(run) = &feed {
        let reported = run.outcome().is_some();
        if let (Some(o), false) = (run.stop(), reported) {
            report(&o);
        }
    }
    result
}

/// The hosts a server on `bound` answers to: loopback names, `bound`, and those `args`
/// allow (`--allow-host`, `--allow-origin`).
fn hosts(bound: SocketAddr, args: &ViewArgs) -> Result<HostPolicy, Failure> {
    let policy = args
        .allow_host
        .iter()
        .try_fold(HostPolicy::new(bound), |p, name| {
            p.allow(name)
                .map_err(|e| Failure::Input(anyhow::Error::new(e).context("--allow-host")))
        })?;
    args.allow_origin
        .iter()
        .try_fold(policy, |p, origin| match origin.split_once("://") {
            Some((scheme, host)) if !scheme.is_empty() && !host.is_empty() => {
                Ok(p.allow_origin(origin))
            }
            _ => Err(Failure::Input(anyhow!(
                "--allow-origin {origin:?}: expected SCHEME://HOST[:PORT] (https://viewer.example)"
            ))),
        })
}

async fn serve_until_interrupted(args: &ViewArgs, feed: Feed) -> Result<(), Failure> {
    let (listener, bound) = listen(args.addr).await?;
    let hosts = hosts(bound, args)?;
    say(&format!("serving http://{bound}/ (Ctrl-C to stop)"));
    let foxglove = match (args.foxglove(), &feed) {
        (Some(addr), Feed::Live(run)) => Some(foxglove(addr, args, run.clone()).await?),
        _ => None,
    };
    if let Feed::Live(run) = &feed {
        let run = run.clone();
        tokio::spawn(async move { report(&run.finished().await) });
    }
    let page = async {
        serve_with(listener, feed, hosts, interrupted())
            .await
            .context("serving the view")
            .map_err(Failure::Runtime)
    };
    match foxglove {
        Some(foxglove) => tokio::try_join!(page, foxglove).map(|_| ()),
        None => page.await,
    }
}

/// Binds `addr`; the listener and the address it got.
async fn listen(addr: SocketAddr) -> Result<(tokio::net::TcpListener, SocketAddr), Failure> {
    let listener = tokio::net::TcpListener::bind(addr)
        .await
        .with_context(|| format!("cannot listen on {addr}"))
        .map_err(Failure::Input)?;
    let bound = listener
        .local_addr()
        .context("reading the bound address")
        .map_err(Failure::Runtime)?;
    Ok((listener, bound))
}

/// Completes at Ctrl-C (never, without a signal handler: then the server runs until the
/// process is killed).
async fn interrupted() {
    if tokio::signal::ctrl_c().await.is_err() {
        std::future::pending::<()>().await;
    }
}

/// Binds `addr` and returns the Foxglove server of `run` on it, to be awaited.
#[cfg(feature = "foxglove")]
async fn foxglove(
    addr: SocketAddr,
    args: &ViewArgs,
    run: LiveRun,
) -> Result<impl std::future::Future<Output = Result<(), Failure>>, Failure> {
    use vitro_viz::foxglove;
    let (listener, bound) = listen(addr).await.map_err(|e| match e {
        Failure::Input(e) => Failure::Input(e.context("--foxglove")),
        e => e,
    })?;
    let hosts = hosts(bound, args)?.allow_origin(foxglove::FOXGLOVE_APP_ORIGIN);
    say(&format!(
        "serving Foxglove ws://{bound} (Foxglove: Open connection, Foxglove WebSocket)"
    ));
    Ok(async move {
        foxglove::serve(listener, run, hosts, interrupted())
            .await
            .context("serving Foxglove")
            .map_err(Failure::Runtime)
    })
}

/// Without the feature there is no `--foxglove`: nothing to serve.
#[cfg(not(feature = "foxglove"))]
async fn foxglove(
    _addr: SocketAddr,
    _args: &ViewArgs,
    _run: LiveRun,
) -> Result<std::future::Ready<Result<(), Failure>>, Failure> {
    Ok(std::future::ready(Ok(())))
}

/// Prints a line on stdout now (scripts wait for these lines).
fn say(line: &str) {
    let mut out = std::io::stdout().lock();
    // stdout closed: nobody is listening, nothing to do.
    let _ = writeln!(out, "{line}").and_then(|()| out.flush());
}

fn report(o: &Outcome) {
    let how = match (&o.failure, o.stopped) {
        (Some(f), _) => format!("failed: {f}"),
        (None, true) => "stopped".to_owned(),
        (None, false) => "finished".to_owned(),
    };
    say(&format!(
        "run {how} at t={:.3} s after {} events; trace hash {:016x}",
        o.t_ns as f64 / 1e9,
        o.events,
        o.trace_hash
    ));
}

/// `--until` in nanoseconds, checked.
fn until_ns(until: Option<f64>) -> Result<Option<u64>, Failure> {
    match until {
        None => Ok(None),
        Some(u) if u > 0.0 && u <= MAX_UNTIL_S => Ok(Some(SimTime::from_secs_f64(u).as_nanos())),
        Some(u) => Err(Failure::Input(anyhow!(
            "--until {u}: expected a number of simulated seconds in (0, {MAX_UNTIL_S:e}]"
        ))),
    }
}
