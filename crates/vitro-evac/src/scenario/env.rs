//! The `[env]` table: settings of the learning environment that runs the scenario (the
//! Python package's `vitro.env`). The mission never reads it: `vitro run` ignores the table
//! and a scenario without it runs exactly as before.
//!
//! ```
//! use vitro_evac::scenario::EnvSpec;
//!
//! let env: EnvSpec = toml::from_str("hunt = true\nreward = { cover_s = 0.05 }").unwrap();
//! assert!(env.hunt);
//! assert_eq!(env.reward.cover_s, 0.05);
//! assert_eq!(env.reward.success, 10.0);
//! ```

use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

/// Settings of the learning environment.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(default, deny_unknown_fields)]
pub struct EnvSpec {
    /// Whether an episode goes on through the HVT hunt once the mission is decided (the VIP
    /// extracted or down); by default it ends then.
    pub hunt: bool,
    /// The reward's weights.
    pub reward: RewardSpec,
}

/// The reward's weights. Team terms go to every agent alike; per-agent terms to the agent
/// that earned them.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(default, deny_unknown_fields)]
pub struct RewardSpec {
    /// Team: once, when the VIP reaches the extraction point.
    pub success: f64,
    /// Team: once, when the VIP is down.
    pub vip_down: f64,
    /// Team: per blue person (trooper or VIP) down.
    pub casualty: f64,
    /// Team: per adversary the blue side reports for the first time.
    pub detection: f64,
    /// Team: per second some team member (the truck, a trooper, the VIP) has no friendly
    /// aircraft within `mission.cover_radius_m`, until the VIP is out.
    pub uncovered_s: f64,
    /// Per agent: per second the agent (an aircraft) is within `mission.cover_radius_m` of
    /// an active team member, until the VIP is out.
    pub cover_s: f64,
    /// Per agent: once, when the agent itself goes down.
    pub down: f64,
}

impl Default for RewardSpec {
    fn default() -> Self {
        RewardSpec {
            success: 10.0,
            vip_down: -10.0,
            casualty: -5.0,
            detection: 1.0,
            uncovered_s: -0.01,
            cover_s: 0.0,
            down: 0.0,
        }
    }
}

impl RewardSpec {
    /// The weights by key, in the order of the table's fields.
    pub fn weights(&self) -> [(&'static str, f64); 7] {
        [
            ("success", self.success),
            ("vip_down", self.vip_down),
            ("casualty", self.casualty),
            ("detection", self.detection),
            ("uncovered_s", self.uncovered_s),
            ("cover_s", self.cover_s),
            ("down", self.down),
        ]
    }
}
