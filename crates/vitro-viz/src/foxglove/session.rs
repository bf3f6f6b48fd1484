//! One Foxglove client's connection: advertise, subscribe, and the frames as they come.

use super::params;
use super::wire::{self, Advertised, ClientOp, Parameter, ServerOp, Subscription};
use crate::live::LiveRun;
use crate::server::SEND_TIMEOUT;
use axum::extract::ws::{Message, WebSocket};
use std::collections::{BTreeMap, BTreeSet, HashMap};
use std::sync::Arc;
use tokio::time::{MissedTickBehavior, interval, timeout};
use vitro_record::channels::{self, Channel};
use vitro_record::{Frame, Scene, schema};

/// How often subscribed parameters are looked at for changes.
const PARAMETER_EVERY: std::time::Duration = crate::server::STATUS_EVERY;

/// Why a connection ended (never reported: the client is simply gone).
#[derive(Debug)]
pub(super) struct Gone;

/// Messages for each channel, by the subscriptions that receive it.
type Targets = HashMap<Channel, Vec<u32>>;

/// What one connection knows.
struct Session {
    run: LiveRun,
    scene: Arc<Scene>,
    /// Advertised channels; channel id `i + 1` is `channels[i]`.
    channels: Vec<Channel>,
    ids: HashMap<Channel, u32>,
    /// Subscription id → channel id.
    subs: BTreeMap<u32, u32>,
    /// Parameters the client follows, with the values it was last sent.
    followed: BTreeMap<String, Option<Parameter>>,
    buf: Vec<u8>,
}

impl Session {
    /// Adds the channels not advertised yet; the advertise message for them, if any.
    fn advertise(&mut self, channels: impl IntoIterator<Item = Channel>) -> Option<ServerOp> {
        let mut new = Vec::new();
        for channel in channels {
            if self.ids.contains_key(&channel) {
                continue;
            }
            self.channels.push(channel.clone());
            // Fewer channels than u32::MAX: a frame has fewer entities.
            let id = self.channels.len() as u32;
            let name = channel.schema();
            new.push(Advertised {
                id,
                topic: channel.topic().into_owned(),
                encoding: "json",
                schema_name: name,
                schema: schema::schema_text(name).unwrap_or_default(),
                schema_encoding: "jsonschema",
            });
            self.ids.insert(channel, id);
        }
        (!new.is_empty()).then_some(ServerOp::Advertise { channels: new })
    }

    /// The channels of `subs` (subscription id, channel id) and who receives each.
    fn targets<'a>(&self, subs: impl IntoIterator<Item = (&'a u32, &'a u32)>) -> Targets {
        let mut out = Targets::new();
        for (&sub, &channel) in subs {
            if let Some(c) = channel
                .checked_sub(1)
                .and_then(|i| self.channels.get(i as usize))
            {
                out.entry(c.clone()).or_default().push(sub);
            }
        }
        out
    }

    /// The binary messages of the scene and of `frame` for `targets`.
    fn encode(
        &mut self,
        scene: bool,
        frame: Option<&Frame>,
        targets: &Targets,
    ) -> Result<Vec<Vec<u8>>, serde_json::Error> {
        let mut out = Vec::new();
        let mut put = |c: &Channel, t: u64, json: &[u8]| -> Result<(), serde_json::Error> {
            for &sub in targets.get(c).into_iter().flatten() {
                out.push(wire::message_data(sub, t, json));
            }
            Ok(())
        };
        let wants = |c: &Channel| targets.contains_key(c);
        if scene {
            channels::scene_messages(&self.scene, wants, &mut self.buf, &mut put)?;
        }
        if let Some(frame) = frame {
            channels::frame_messages(&self.scene.geo, frame, wants, &mut self.buf, &mut put)?;
        }
        Ok(out)
    }

    /// The subscribed parameters whose values changed since they were last sent.
    fn changed_parameters(&mut self) -> Vec<Parameter> {
        let mut out = Vec::new();
        for (name, last) in &mut self.followed {
            let now = params::get(&self.run, name);
            if now != *last {
                out.extend(now.clone());
                *last = now;
            }
        }
        out
    }
}

async fn send(socket: &mut WebSocket, msg: Message) -> Result<(), Gone> {
    match timeout(SEND_TIMEOUT, socket.send(msg)).await {
        Ok(Ok(())) => Ok(()),
        _ => Err(Gone),
    }
}

async fn send_op(socket: &mut WebSocket, op: &ServerOp) -> Result<(), Gone> {
    send(socket, Message::Text(op.to_json().into())).await
}

async fn send_all(socket: &mut WebSocket, messages: Vec<Vec<u8>>) -> Result<(), Gone> {
    for m in messages {
        send(socket, Message::Binary(m.into())).await?;
    }
    Ok(())
}

/// Serves one client until it goes away.
pub(super) async fn client(
    mut socket: WebSocket,
    run: LiveRun,
    info: Arc<ServerOp>,
) -> Result<(), Gone> {
    send_op(&mut socket, &info).await?;
    let mut frames = run.frames();
    let latest = frames.borrow_and_update().clone();
    let mut s = Session {
        scene: run.scene(),
        run,
        channels: Vec::new(),
        ids: HashMap::new(),
        subs: BTreeMap::new(),
        followed: BTreeMap::new(),
        buf: Vec::with_capacity(64 << 10),
    };
    let gps = latest
        .iter()
        .flat_map(|p| p.frame.entities.iter().map(Channel::gps));
    let fixed = Channel::FIXED.into_iter().chain(gps.collect::<Vec<_>>());
    if let Some(op) = s.advertise(fixed) {
        send_op(&mut socket, &op).await?;
    }
    let mut latest = latest.map(|p| p.frame);
    let mut ticker = interval(PARAMETER_EVERY);
    ticker.set_missed_tick_behavior(MissedTickBehavior::Delay);
    loop {
        tokio::select! {
            changed = frames.changed() => {
                if changed.is_err() {
                    return Err(Gone);
                }
                let Some(p) = frames.borrow_and_update().clone() else { continue };
                if let Some(op) = s.advertise(p.frame.entities.iter().map(Channel::gps)) {
                    send_op(&mut socket, &op).await?;
                }
                send(&mut socket, Message::Binary(wire::time(p.frame.t_ns).into())).await?;
                let targets = s.targets(&s.subs);
                match s.encode(false, Some(&p.frame), &targets) {
                    Ok(m) => send_all(&mut socket, m).await?,
                    Err(e) => send_op(&mut socket, &ServerOp::error(e.to_string())).await?,
                }
                latest = Some(p.frame);
            }
            _ = ticker.tick() => {
                let parameters = s.changed_parameters();
                if !parameters.is_empty() {
                    send_op(&mut socket, &ServerOp::ParameterValues { parameters, id: None }).await?;
                }
            }
            msg = socket.recv() => {
                let Some(Ok(msg)) = msg else { return Err(Gone) };
                let op = match msg {
                    Message::Text(t) => serde_json::from_str::<ClientOp>(t.as_str())
                        .map_err(|e| format!("unsupported or malformed message: {e}")),
                    Message::Binary(_) => Err("clients do not publish to this server".to_owned()),
                    Message::Close(_) => return Err(Gone),
                    Message::Ping(_) | Message::Pong(_) => continue,
                };
                match op {
                    Ok(op) => handle(&mut socket, &mut s, op, latest.as_deref()).await?,
                    Err(e) => send_op(&mut socket, &ServerOp::error(e)).await?,
                }
            }
        }
    }
}

/// Answers one client operation.
async fn handle(
    socket: &mut WebSocket,
    s: &mut Session,
    op: ClientOp,
    latest: Option<&Frame>,
) -> Result<(), Gone> {
    match op {
        ClientOp::Subscribe { subscriptions } => {
            let mut new = BTreeMap::new();
            for Subscription { id, channel_id } in subscriptions {
                let known = channel_id
                    .checked_sub(1)
                    .is_some_and(|i| (i as usize) < s.channels.len());
                if known {
                    s.subs.insert(id, channel_id);
                    new.insert(id, channel_id);
                } else {
                    let e = format!("subscription {id}: no channel {channel_id}");
                    send_op(socket, &ServerOp::error(e)).await?;
                }
            }
            // What the new subscriptions would have had: the scene, the latest frame.
            let targets = s.targets(&new);
            match s.encode(true, latest, &targets) {
                Ok(m) => send_all(socket, m).await?,
                Err(e) => send_op(socket, &ServerOp::error(e.to_string())).await?,
            }
        }
        ClientOp::Unsubscribe { subscription_ids } => {
            for id in subscription_ids {
                s.subs.remove(&id);
            }
        }
        ClientOp::GetParameters {
            parameter_names,
            id,
        } => {
            let parameters = params::get_all(&s.run, &parameter_names);
            send_op(socket, &ServerOp::ParameterValues { parameters, id }).await?;
        }
        ClientOp::SetParameters { parameters, id } => {
            for p in &parameters {
                if let Err(e) = params::set(&s.run, p) {
                    send_op(socket, &ServerOp::error(e)).await?;
                }
            }
            let names: Vec<String> = parameters.into_iter().map(|p| p.name).collect();
            let parameters = params::get_all(&s.run, &names);
            for p in &parameters {
                if let Some(last) = s.followed.get_mut(&p.name) {
                    *last = Some(p.clone());
                }
            }
            send_op(socket, &ServerOp::ParameterValues { parameters, id }).await?;
        }
        ClientOp::SubscribeParameterUpdates { parameter_names } => {
            let names = if parameter_names.is_empty() {
                params::NAMES.iter().map(|n| (*n).to_owned()).collect()
            } else {
                parameter_names
            };
            for name in names {
                let now = params::get(&s.run, &name);
                s.followed.insert(name, now);
            }
        }
        ClientOp::UnsubscribeParameterUpdates { parameter_names } => {
            let gone: BTreeSet<String> = parameter_names.into_iter().collect();
            s.followed.retain(|n, _| !gone.contains(n));
        }
    }
    Ok(())
}
