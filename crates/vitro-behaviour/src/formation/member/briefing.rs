//! The leader's briefing as a member reads it: `"<pattern> <slot> <spacing> <facing|->"` or
//! `"none"`.

use crate::formation::pattern::Pattern;
use serde::{Deserialize, Serialize};

/// What the leader told this member.
#[derive(Copy, Clone, Debug, PartialEq, Serialize, Deserialize)]
pub(super) struct Brief {
    /// The pattern.
    pub pattern: Pattern,
    /// The member's slot number, 1, 2, ...
    pub slot: usize,
    /// Metres between neighbours.
    pub spacing: f64,
    /// The line's facing, radians (`None`: along the leader's way).
    pub facing: Option<f64>,
}

impl Brief {
    /// Reads `"<pattern> <slot> <spacing> <facing|->"`; `Ok(None)` for `"none"`.
    pub fn parse(text: &str) -> Result<Option<Brief>, String> {
        let words: Vec<&str> = text.split_whitespace().collect();
        match words.as_slice() {
            ["none"] => Ok(None),
            [p, k, s, f] => {
                let pattern = Pattern::from_name(p).ok_or(format!("no pattern {p:?}"))?;
                let slot = k.parse().map_err(|_| format!("bad slot {k:?}"))?;
                let spacing: f64 = s.parse().map_err(|_| format!("bad spacing {s:?}"))?;
                let facing = match *f {
                    "-" => None,
                    f => Some(f.parse().map_err(|_| format!("bad facing {f:?}"))?),
                };
                Ok(Some(Brief {
                    pattern,
                    slot,
                    spacing,
                    facing,
                }))
            }
            _ => Err(format!("unreadable briefing {text:?}")),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn briefings_read_back() {
        let b = Brief::parse("wedge 3 5 -").unwrap();
        assert_eq!(
            b,
            Some(Brief {
                pattern: Pattern::Wedge,
                slot: 3,
                spacing: 5.0,
                facing: None
            })
        );
        let b = Brief::parse("line 1 4.5 1.25").unwrap().unwrap();
        assert_eq!(
            (b.pattern, b.slot, b.facing),
            (Pattern::Line, 1, Some(1.25))
        );
        assert_eq!(Brief::parse("none").unwrap(), None);
        for bad in ["", "wedge", "square 1 5 -", "file x 5 -", "file 1 5 north"] {
            assert!(Brief::parse(bad).is_err(), "{bad:?}");
        }
    }
}
