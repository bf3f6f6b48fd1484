//! What a run's listener keeps between frames and samples.

use serde::{Deserialize, Serialize};
use vitro::sim::{Fired, Input, Model};
use vitro_record::MessageEvent;

/// What a run's listener keeps of the fired events: the radio messages once the run is
/// watched (its scene was asked for: a recorder or a viewer asks before it asks for frames,
/// and a run nobody watches keeps none), and the mission's own `X` (e.g. the contacts its
/// referee reads at each sample).
#[derive(Clone, Debug, Default, Serialize, Deserialize)]
pub struct Heard<X> {
    /// Whether messages are kept (not saved: a restored run keeps them once watched).
    #[serde(skip)]
    pub watched: bool,
    /// The messages delivered or bounced since the last frame.
    pub messages: Vec<MessageEvent>,
    /// What the mission keeps itself.
    pub own: X,
}

impl<X> Heard<X> {
    /// Keeps the message `f` delivers or bounces, if the run is watched, as a
    /// [`MessageEvent`] of kind `kind(body)`.
    #[inline]
    pub fn keep<M: Model>(&mut self, f: &Fired<'_, M>, kind: impl FnOnce(&M::Msg) -> &'static str) {
        if !self.watched {
            return;
        }
        let (env, delivered) = match &f.input {
            Input::Message(env) => (*env, true),
            Input::Undeliverable(env, _) => (*env, false),
            _ => return,
        };
        self.messages.push(MessageEvent {
            t_ns: env.sent_at.as_nanos(),
            from: env.from.0,
            to: delivered.then_some(env.receiver.0),
            kind: kind(&env.body).into(),
            delivered,
        });
    }
}
