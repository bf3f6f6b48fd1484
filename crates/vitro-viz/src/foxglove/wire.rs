//! The messages of the Foxglove WebSocket protocol that this server sends and reads
//! (<https://github.com/foxglove/ws-protocol/blob/main/docs/spec.md>): JSON text for control,
//! binary for message data and time.

use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// The subprotocols a client may ask for (the same messages under two names: the protocol's
/// own and the Foxglove SDK's).
pub const SUBPROTOCOLS: [&str; 2] = ["foxglove.websocket.v1", "foxglove.sdk.v1"];

/// What this server offers besides publishing: parameters (and updates of them) and time.
pub const CAPABILITIES: [&str; 3] = ["parameters", "parametersSubscribe", "time"];

/// Binary opcode of message data (server to client).
const MESSAGE_DATA: u8 = 1;
/// Binary opcode of a time update (server to client).
const TIME: u8 = 2;

/// A JSON message from the server.
#[derive(Debug, Serialize)]
#[serde(tag = "op", rename_all = "camelCase", rename_all_fields = "camelCase")]
pub enum ServerOp {
    /// The first message: who the server is and what it can do.
    ServerInfo {
        /// Server name.
        name: String,
        /// [`CAPABILITIES`].
        capabilities: Vec<&'static str>,
        /// Encodings accepted from clients (none: clients do not publish).
        supported_encodings: Vec<&'static str>,
        /// Free key-value pairs (the scene, its calendar start).
        metadata: BTreeMap<String, String>,
        /// Identifies this run.
        session_id: String,
    },
    /// A notice to show the user (0 info, 1 warning, 2 error).
    Status {
        /// Severity.
        level: u8,
        /// The notice.
        message: String,
    },
    /// Channels the client may subscribe to.
    Advertise {
        /// The channels.
        channels: Vec<Advertised>,
    },
    /// Parameter values, asked for or changed.
    ParameterValues {
        /// The values.
        parameters: Vec<Parameter>,
        /// The request answered, if it had an id.
        #[serde(skip_serializing_if = "Option::is_none")]
        id: Option<String>,
    },
}

impl ServerOp {
    /// The message as JSON text.
    pub fn to_json(&self) -> String {
        // Plain data with string keys: serialising it cannot fail.
        serde_json::to_string(self).unwrap_or_else(|e| {
            format!(r#"{{"op":"status","level":2,"message":"cannot encode a message: {e}"}}"#)
        })
    }

    /// An error notice.
    pub fn error(message: impl Into<String>) -> Self {
        ServerOp::Status {
            level: 2,
            message: message.into(),
        }
    }
}

/// One advertised channel.
#[derive(Clone, Debug, Serialize)]
#[serde(rename_all = "camelCase")]
pub struct Advertised {
    /// Channel id (this connection's).
    pub id: u32,
    /// Topic.
    pub topic: String,
    /// Message encoding: `json`.
    pub encoding: &'static str,
    /// Schema name (`foxglove.SceneUpdate`, ...).
    pub schema_name: &'static str,
    /// The JSON Schema text.
    pub schema: String,
    /// Schema encoding: `jsonschema`.
    pub schema_encoding: &'static str,
}

/// A named parameter value.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Parameter {
    /// Name.
    pub name: String,
    /// Value: a boolean or a number here.
    pub value: serde_json::Value,
    /// `float64` for a number that must stay a float.
    #[serde(rename = "type", default, skip_serializing_if = "Option::is_none")]
    pub kind: Option<String>,
}

/// One subscription a client asks for.
#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(rename_all = "camelCase")]
pub struct Subscription {
    /// The client's id for it (message data carries it).
    pub id: u32,
    /// The channel.
    pub channel_id: u32,
}

/// A JSON message from a client (the operations this server supports).
#[derive(Clone, Debug, PartialEq, Deserialize)]
#[serde(tag = "op", rename_all = "camelCase", rename_all_fields = "camelCase")]
pub enum ClientOp {
    /// Start receiving channels.
    Subscribe {
        /// What to receive.
        subscriptions: Vec<Subscription>,
    },
    /// Stop receiving.
    Unsubscribe {
        /// Subscriptions to end.
        subscription_ids: Vec<u32>,
    },
    /// Ask for parameter values (none named: all).
    GetParameters {
        /// Names.
        parameter_names: Vec<String>,
        /// Request id, echoed in the answer.
        #[serde(default)]
        id: Option<String>,
    },
    /// Change parameters.
    SetParameters {
        /// New values.
        parameters: Vec<Parameter>,
        /// Request id, echoed in the answer.
        #[serde(default)]
        id: Option<String>,
    },
    /// Be told when these parameters change.
    SubscribeParameterUpdates {
        /// Names.
        parameter_names: Vec<String>,
    },
    /// Stop being told.
    UnsubscribeParameterUpdates {
        /// Names.
        parameter_names: Vec<String>,
    },
}

/// Binary message data: opcode 1, subscription id (u32 LE), time (u64 LE, ns), payload.
pub fn message_data(subscription: u32, t_ns: u64, payload: &[u8]) -> Vec<u8> {
    let mut out = Vec::with_capacity(13 + payload.len());
    out.push(MESSAGE_DATA);
    out.extend_from_slice(&subscription.to_le_bytes());
    out.extend_from_slice(&t_ns.to_le_bytes());
    out.extend_from_slice(payload);
    out
}

/// Binary time update: opcode 2, time (u64 LE, ns).
pub fn time(t_ns: u64) -> Vec<u8> {
    let mut out = Vec::with_capacity(9);
    out.push(TIME);
    out.extend_from_slice(&t_ns.to_le_bytes());
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn binary_messages_are_little_endian_with_their_opcode() {
        let m = message_data(0x0102_0304, 5, b"{}");
        assert_eq!(m, [1, 4, 3, 2, 1, 5, 0, 0, 0, 0, 0, 0, 0, b'{', b'}']);
        assert_eq!(time(1), [2, 1, 0, 0, 0, 0, 0, 0, 0]);
    }

    #[test]
    fn ops_use_the_protocols_names() {
        let info = ServerOp::ServerInfo {
            name: "x".into(),
            capabilities: CAPABILITIES.to_vec(),
            supported_encodings: vec![],
            metadata: BTreeMap::new(),
            session_id: "s".into(),
        };
        let v: serde_json::Value = serde_json::from_str(&info.to_json()).unwrap();
        assert_eq!(v["op"], "serverInfo");
        assert_eq!(v["sessionId"], "s");
        assert!(v["supportedEncodings"].is_array());
        let op: ClientOp =
            serde_json::from_str(r#"{"op":"subscribe","subscriptions":[{"id":3,"channelId":7}]}"#)
                .unwrap();
        assert_eq!(
            op,
            ClientOp::Subscribe {
                subscriptions: vec![Subscription {
                    id: 3,
                    channel_id: 7
                }]
            }
        );
        let op: ClientOp = serde_json::from_str(
            r#"{"op":"setParameters","parameters":[{"name":"paused","value":true}],"id":"a"}"#,
        )
        .unwrap();
        assert!(matches!(op, ClientOp::SetParameters { id: Some(_), .. }));
        assert!(serde_json::from_str::<ClientOp>(r#"{"op":"advertise","channels":[]}"#).is_err());
    }
}
