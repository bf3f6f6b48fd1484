//! Communication: addressed messages through simulated channels.
//!
//! Channels live inside the event queue (no threads): a sent message becomes a delivery event
//! at `now + transmission time + delay + jitter`, or is lost (Bernoulli, from the simulation's
//! own random stream), or comes back to its sender as an error (unknown receiver, out of range).
//! The [`Network`] decides; the simulation driver schedules what it decides.

pub mod network;

pub use network::{
    Address, DeliveryError, Envelope, GroupId, LinkParams, MessageCounts, Network, Outgoing,
    Performative, Protocol, Route,
};
