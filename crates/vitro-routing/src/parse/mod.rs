//! Readers of the standard text formats: CVRPLIB (TSPLIB-style `.vrp`) and Solomon (VRPTW).
//!
//! Bad input is a [`ParseError`] naming the line and column (both 1-based) and what was
//! expected there; the readers never panic.

mod cvrplib;
mod lex;
mod solomon;

pub use cvrplib::parse_cvrplib;
pub use lex::{MAX_NODES, ParseError};
pub use solomon::parse_solomon;

use crate::Instance;

/// Reads either format: CVRPLIB when the first non-blank line is a `KEY : value` header,
/// Solomon otherwise.
///
/// # Errors
/// A [`ParseError`] for bad input.
pub fn parse(text: &str) -> Result<Instance, ParseError> {
    let first = text.lines().find(|l| !l.trim().is_empty()).unwrap_or("");
    if first.contains(':') || first.trim_start().to_ascii_uppercase().starts_with("NAME") {
        parse_cvrplib(text)
    } else {
        parse_solomon(text)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_format_is_told_by_the_first_line() {
        let e = parse("NAME : x\n").unwrap_err();
        assert!(matches!(e, ParseError::Expected { .. }), "{e}");
        let e = parse("C101\n\nVEHICLE\n").unwrap_err();
        assert!(e.to_string().contains("NUMBER"), "{e}");
    }
}
