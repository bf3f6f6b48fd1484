//! Calendar time in UTC, to the millisecond: what simulated time 0 of a run is on the
//! calendar (a scenario's `start`). It labels recordings, KML tracks and the viewer's clock
//! and never enters a simulation, so it changes no trace.

use serde::{Deserialize, Deserializer, Serialize, Serializer};
use std::fmt;
use std::str::FromStr;

/// An instant in UTC, milliseconds since 1970-01-01T00:00:00Z (proleptic Gregorian
/// calendar, years 0000 to 9999), read and written as RFC 3339.
///
/// ```
/// use vitro::time::UtcTime;
/// let t: UtcTime = "2024-06-01T08:30:00+02:00".parse().unwrap();
/// assert_eq!(t.to_string(), "2024-06-01T06:30:00Z");
/// assert_eq!(t.plus_nanos(1_500_000_000).to_string(), "2024-06-01T06:30:01.500Z");
/// assert_eq!(UtcTime::DEFAULT_START.to_string(), "2024-06-01T06:00:00Z");
/// assert!("2024-02-30T00:00:00Z".parse::<UtcTime>().is_err());
/// ```
#[derive(Copy, Clone, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct UtcTime(i64);

/// Why a text is not an RFC 3339 date and time.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
pub enum UtcError {
    /// Not of the form `YYYY-MM-DDTHH:MM:SS[.fff](Z|±HH:MM)`.
    #[error("`{0}` is not of the form YYYY-MM-DDTHH:MM:SS[.fff]Z")]
    Form(String),
    /// A month, day, hour, minute, second or offset out of its range.
    #[error("`{text}` has no such {field}")]
    Range {
        /// The text.
        text: String,
        /// The field out of range.
        field: &'static str,
    },
}

/// What a scenario's `start` must be, for messages.
pub const EXPECTED: &str = "an RFC 3339 date and time, e.g. \"2024-06-01T06:00:00Z\"";

const MS_PER_DAY: i64 = 86_400_000;

/// Days since 1970-01-01 of a proleptic Gregorian date.
const fn days_from_civil(y: i64, m: i64, d: i64) -> i64 {
    let y = if m <= 2 { y - 1 } else { y };
    let era = y.div_euclid(400);
    let yoe = y.rem_euclid(400);
    let mp = (m + 9) % 12;
    let doy = (153 * mp + 2) / 5 + d - 1;
    let doe = yoe * 365 + yoe / 4 - yoe / 100 + doy;
    era * 146_097 + doe - 719_468
}

/// Year, month, day of a day count since 1970-01-01.
fn civil_from_days(days: i64) -> (i64, i64, i64) {
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z.rem_euclid(146_097);
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let d = doy - (153 * mp + 2) / 5 + 1;
    let m = if mp < 10 { mp + 3 } else { mp - 9 };
    (yoe + era * 400 + i64::from(m <= 2), m, d)
}

fn days_in_month(y: i64, m: i64) -> i64 {
    match m {
        2 if (y % 4 == 0 && y % 100 != 0) || y % 400 == 0 => 29,
        2 => 28,
        4 | 6 | 9 | 11 => 30,
        _ => 31,
    }
}

impl UtcTime {
    /// The start of a scenario that names none: 2024-06-01T06:00:00Z.
    pub const DEFAULT_START: UtcTime =
        UtcTime(days_from_civil(2024, 6, 1) * MS_PER_DAY + 6 * 3_600_000);

    /// The instant `ms` milliseconds after 1970-01-01T00:00:00Z.
    pub const fn from_unix_millis(ms: i64) -> Self {
        UtcTime(ms)
    }

    /// Milliseconds since 1970-01-01T00:00:00Z.
    pub const fn unix_millis(self) -> i64 {
        self.0
    }

    /// The instant `ns` nanoseconds later (simulated time after the start), to the
    /// millisecond below.
    pub fn plus_nanos(self, ns: u64) -> Self {
        // u64 nanoseconds / 1e6 fits i64.
        UtcTime(self.0.saturating_add((ns / 1_000_000) as i64))
    }

    /// Parses RFC 3339 (`2024-06-01T06:00:00Z`, `2024-06-01t08:00:00.250+02:00`): a
    /// fraction of up to 9 digits is kept to the millisecond, an offset is taken off; no
    /// leap seconds.
    ///
    /// # Errors
    /// [`UtcError`] naming what is wrong.
    pub fn parse(text: &str) -> Result<Self, UtcError> {
        let form = || UtcError::Form(text.to_owned());
        let range = |field| UtcError::Range {
            text: text.to_owned(),
            field,
        };
        let b = text.as_bytes();
        let digits = |from: usize, n: usize| -> Result<i64, UtcError> {
            let part = b.get(from..from + n).ok_or_else(form)?;
            part.iter().try_fold(0i64, |acc, &c| {
                c.is_ascii_digit()
                    .then(|| acc * 10 + i64::from(c - b'0'))
                    .ok_or_else(form)
            })
        };
        let at = |i: usize, want: &[u8]| b.get(i).is_some_and(|c| want.contains(c));
        if !(at(4, b"-") && at(7, b"-") && at(10, b"Tt") && at(13, b":") && at(16, b":")) {
            return Err(form());
        }
        let (y, mo, d) = (digits(0, 4)?, digits(5, 2)?, digits(8, 2)?);
        let (h, mi, s) = (digits(11, 2)?, digits(14, 2)?, digits(17, 2)?);
        let mut i = 19;
        let mut ms = 0;
        if at(i, b".") {
            let n = b[i + 1..].iter().take_while(|c| c.is_ascii_digit()).count();
            if !(1..=9).contains(&n) {
                return Err(form());
            }
            let kept = n.min(3);
            ms = digits(i + 1, kept)? * 10i64.pow(3 - kept as u32);
            i += 1 + n;
        }
        let offset_min = match b.get(i..) {
            Some(b"Z" | b"z") => 0,
            Some([sign @ (b'+' | b'-'), _, _, b':', _, _]) => {
                let (oh, om) = (digits(i + 1, 2)?, digits(i + 4, 2)?);
                if oh > 23 || om > 59 {
                    return Err(range("offset"));
                }
                let m = oh * 60 + om;
                if *sign == b'-' { -m } else { m }
            }
            _ => return Err(form()),
        };
        if !(1..=12).contains(&mo) {
            return Err(range("month"));
        }
        if !(1..=days_in_month(y, mo)).contains(&d) {
            return Err(range("day"));
        }
        if h > 23 {
            return Err(range("hour"));
        }
        if mi > 59 {
            return Err(range("minute"));
        }
        if s > 59 {
            return Err(range("second"));
        }
        let secs = ((days_from_civil(y, mo, d) * 24 + h) * 60 + mi - offset_min) * 60 + s;
        Ok(UtcTime(secs * 1000 + ms))
    }
}

impl FromStr for UtcTime {
    type Err = UtcError;
    fn from_str(s: &str) -> Result<Self, UtcError> {
        UtcTime::parse(s)
    }
}

impl fmt::Display for UtcTime {
    /// RFC 3339 in UTC: `2024-06-01T06:00:00Z`, with `.fff` when the milliseconds are not 0.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let (days, ms) = (self.0.div_euclid(MS_PER_DAY), self.0.rem_euclid(MS_PER_DAY));
        let (y, mo, d) = civil_from_days(days);
        let s = ms / 1000;
        let (h, mi, s, ms) = (s / 3600, s % 3600 / 60, s % 60, ms % 1000);
        write!(f, "{y:04}-{mo:02}-{d:02}T{h:02}:{mi:02}:{s:02}")?;
        if ms != 0 {
            write!(f, ".{ms:03}")?;
        }
        f.write_str("Z")
    }
}

impl Serialize for UtcTime {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.collect_str(self)
    }
}

/// Reads a [`UtcTime`] from a string (a TOML date-time literal, unquoted, is refused with
/// what to write instead).
struct Rfc3339;

impl serde::de::Visitor<'_> for Rfc3339 {
    type Value = UtcTime;

    fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{EXPECTED} in quotes")
    }

    fn visit_str<E: serde::de::Error>(self, text: &str) -> Result<UtcTime, E> {
        UtcTime::parse(text).map_err(|e| E::custom(format!("{e}, expected {EXPECTED}")))
    }
}

impl<'de> Deserialize<'de> for UtcTime {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        d.deserialize_str(Rfc3339)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn p(s: &str) -> Result<UtcTime, UtcError> {
        s.parse()
    }

    #[test]
    fn known_instants() {
        assert_eq!(p("1970-01-01T00:00:00Z").unwrap().unix_millis(), 0);
        assert_eq!(
            p("2000-02-29T00:00:00Z").unwrap().unix_millis(),
            951_782_400_000
        );
        assert_eq!(
            p("2024-12-31T00:00:00.5Z").unwrap().unix_millis(),
            1_735_603_200_500
        );
        assert_eq!(
            UtcTime::DEFAULT_START.unix_millis(),
            1_717_221_600_000,
            "2024-06-01T06:00:00Z"
        );
        assert_eq!(p("1969-12-31T23:59:59.999Z").unwrap().unix_millis(), -1);
    }

    #[test]
    fn text_round_trips_and_offsets_come_off() {
        for s in [
            "2024-06-01T06:00:00Z",
            "1999-12-31T23:59:59.001Z",
            "0001-01-01T00:00:00Z",
            "9999-12-31T23:59:59.999Z",
        ] {
            assert_eq!(p(s).unwrap().to_string(), s);
        }
        assert_eq!(
            p("2024-06-01t00:30:00.123456-05:30").unwrap().to_string(),
            "2024-06-01T06:00:00.123Z"
        );
    }

    #[test]
    fn bad_texts_say_what_is_wrong() {
        for s in [
            "",
            "2024-06-01",
            "2024-06-01 06:00:00Z",
            "2024-06-01T06:00:00",
            "2024-06-01T06:00Z",
            "2024-06-01T06:00:00.Z",
            "2024-6-01T06:00:00Z",
            "2024-06-01T06:00:00+0200",
            "2024-06-01T06:00:00Zjunk",
        ] {
            assert!(matches!(p(s), Err(UtcError::Form(_))), "{s}");
        }
        let field = |s| match p(s) {
            Err(UtcError::Range { field, .. }) => field,
            other => panic!("{s}: {other:?}"),
        };
        assert_eq!(field("2024-13-01T00:00:00Z"), "month");
        assert_eq!(field("2023-02-29T00:00:00Z"), "day");
        assert_eq!(field("2024-06-01T24:00:00Z"), "hour");
        assert_eq!(field("2024-06-01T06:60:00Z"), "minute");
        assert_eq!(field("2024-06-01T06:00:60Z"), "second");
        assert_eq!(field("2024-06-01T06:00:00+24:00"), "offset");
    }
}
