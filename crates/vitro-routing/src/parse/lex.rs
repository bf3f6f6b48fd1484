//! The readers' shared pieces: tokens with their positions, and the errors they make.

/// The most nodes (depot included) an instance may have: every solver works on the full
/// distance matrix, `MAX_NODES²` numbers (800 MB here). A file that asks for more is refused
/// with its line and column instead of running out of memory.
pub const MAX_NODES: usize = 10_000;

/// Why a text is not a valid instance.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum ParseError {
    /// Something else was found where a token of a given kind was expected.
    #[error("line {line}, column {column}: expected {expected}, found {found}")]
    Expected {
        /// 1-based line.
        line: usize,
        /// 1-based column (characters).
        column: usize,
        /// What the reader expected there.
        expected: String,
        /// What it found (`end of file` or the token, quoted).
        found: String,
    },
    /// A well-formed value the readers do not support (e.g. an `EDGE_WEIGHT_TYPE` other than
    /// `EUC_2D`).
    #[error("line {line}, column {column}: unsupported {what} {found:?}")]
    Unsupported {
        /// 1-based line.
        line: usize,
        /// 1-based column.
        column: usize,
        /// The field.
        what: String,
        /// Its value.
        found: String,
    },
    /// A value that contradicts the rest of the file (a node number out of range, given twice).
    #[error("line {line}, column {column}: {message}")]
    Invalid {
        /// 1-based line.
        line: usize,
        /// 1-based column.
        column: usize,
        /// What is wrong.
        message: String,
    },
}

/// A whitespace-separated token with its 1-based position.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Token<'a> {
    pub text: &'a str,
    pub line: usize,
    pub column: usize,
}

/// The tokens of one line.
pub(crate) fn tokens(line: &str, line_no: usize) -> Vec<Token<'_>> {
    let mut out = Vec::new();
    let mut start: Option<usize> = None;
    let mut col = 0;
    let mut start_col = 0;
    for (i, ch) in line.char_indices() {
        col += 1;
        if ch.is_whitespace() {
            if let Some(s) = start.take() {
                out.push(Token {
                    text: &line[s..i],
                    line: line_no,
                    column: start_col,
                });
            }
        } else if start.is_none() {
            start = Some(i);
            start_col = col;
        }
    }
    if let Some(s) = start {
        out.push(Token {
            text: &line[s..],
            line: line_no,
            column: start_col,
        });
    }
    out
}

/// An `Expected` error at a token.
pub(crate) fn expected(tok: &Token<'_>, what: &str) -> ParseError {
    ParseError::Expected {
        line: tok.line,
        column: tok.column,
        expected: what.to_string(),
        found: format!("{:?}", tok.text),
    }
}

/// An `Expected` error where a line ends (column one past its last character).
pub(crate) fn expected_at_end(line: usize, text: &str, what: &str) -> ParseError {
    ParseError::Expected {
        line,
        column: text.chars().count() + 1,
        expected: what.to_string(),
        found: "end of line".to_string(),
    }
}

/// An `Expected` error at the end of the file.
pub(crate) fn expected_eof(line: usize, what: &str) -> ParseError {
    ParseError::Expected {
        line,
        column: 1,
        expected: what.to_string(),
        found: "end of file".to_string(),
    }
}

/// A finite number.
pub(crate) fn number(tok: &Token<'_>, what: &str) -> Result<f64, ParseError> {
    match tok.text.parse::<f64>() {
        Ok(v) if v.is_finite() => Ok(v),
        _ => Err(expected(tok, what)),
    }
}

/// A non-negative integer.
pub(crate) fn unsigned(tok: &Token<'_>, what: &str) -> Result<u64, ParseError> {
    tok.text.parse::<u64>().map_err(|_| expected(tok, what))
}

/// Takes the `i`-th token of a line or says what was missing at its end.
pub(crate) fn nth<'a>(
    toks: &[Token<'a>],
    i: usize,
    line: usize,
    text: &str,
    what: &str,
) -> Result<Token<'a>, ParseError> {
    toks.get(i)
        .copied()
        .ok_or_else(|| expected_at_end(line, text, what))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tokens_carry_columns() {
        let t = tokens("  ab\tc  def", 3);
        let cols: Vec<_> = t.iter().map(|t| (t.text, t.line, t.column)).collect();
        assert_eq!(cols, vec![("ab", 3, 3), ("c", 3, 6), ("def", 3, 9)]);
    }
}
