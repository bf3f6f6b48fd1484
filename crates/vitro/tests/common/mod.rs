//! A small but busy model shared by the driver and determinism tests: agents that tick at
//! random intervals, gossip over a lossy jittery channel, and write what they hear into
//! storages through an actuator.

#![allow(dead_code)]

use rand::Rng;
use serde::{Deserialize, Serialize};
use std::convert::Infallible;
use vitro::prelude::*;

#[derive(Clone, Debug, Default, Serialize, Deserialize)]
pub struct World {
    pub heard: EntityStorage<u64>,
    pub last: KeyValueStorage<u32, u64>,
}

#[derive(Clone, Debug, Serialize, Deserialize)]
pub enum Ev {
    Tick,
}

/// Writes what an agent heard.
pub struct Record;
impl Actuator<World, Ev> for Record {
    type Command = u64;
    type Error = Infallible;
    fn actuate(
        &self,
        w: &mut World,
        me: EntityId,
        v: u64,
        _: &mut Effects<Ev>,
    ) -> Result<(), Infallible> {
        if !w
            .heard
            .update(me, |h| *h = h.wrapping_mul(31).wrapping_add(v))
        {
            w.heard.insert(me, v);
        }
        w.last.set(me.0, v);
        Ok(())
    }
}

/// Reads how much an agent heard.
pub struct Heard;
impl Sensor<World> for Heard {
    type Reading = u64;
    fn read(&self, w: &World, me: EntityId, _: &mut Probe) -> u64 {
        w.heard.get(me).copied().unwrap_or(0)
    }
}

#[derive(Clone, Debug, Default, Serialize, Deserialize)]
pub struct Gossip {
    pub n_agents: u32,
    pub ticks: u64,
    pub received: u64,
}

impl Agent<GossipModel> for Gossip {
    fn handle(&mut self, input: Input<'_, GossipModel>, cx: &mut Context<'_, GossipModel>) {
        match input {
            Input::Event(Ev::Tick) => {
                self.ticks += 1;
                let delay_ms = cx.rng("tick").random_range(1..2000u64);
                cx.schedule_in(SimDuration::from_millis(delay_ms), Ev::Tick);
                let r: f64 = cx.rng("talk").random();
                if r < 0.3 {
                    let to = cx.rng("talk").random_range(0..self.n_agents);
                    let v = cx.sense(&Heard) ^ self.ticks;
                    cx.send(Outgoing::new(Address::Agent(EntityId(to)), v));
                } else if r < 0.35 {
                    cx.send(Outgoing::new(Address::Broadcast, self.ticks));
                }
            }
            Input::Message(m) => {
                self.received += 1;
                let _ = cx.act(&Record, m.body);
            }
            Input::Undeliverable(..) | Input::Timer(_) => {}
        }
    }
}

pub struct GossipModel;
impl Model for GossipModel {
    type Env = World;
    type Event = Ev;
    type Msg = u64;
    type Agent = Gossip;
    fn state_digest(w: &World) -> u64 {
        w.heard.digest() ^ w.last.digest().rotate_left(1)
    }
}

/// A gossip simulation of `n` agents on a lossy, jittery channel.
pub fn gossip(n: u32, seed: u64) -> Simulation<GossipModel> {
    let mut sim = Simulation::<GossipModel>::new(World::default(), seed);
    sim.network_mut().set_default_link(LinkParams {
        delay: SimDuration::from_millis(20),
        jitter: SimDuration::from_millis(15),
        loss: 0.2,
        range_m: None,
        bandwidth_bps: Some(1e6),
    });
    for i in 0..n {
        let id = sim
            .add_agent(
                format!("agent-{i}"),
                Gossip {
                    n_agents: n,
                    ..Default::default()
                },
            )
            .expect("unique names");
        sim.schedule(SimTime::ZERO, Target::Entity(id), Ev::Tick)
            .expect("t=0");
    }
    sim
}
