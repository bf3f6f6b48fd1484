//! [`Located`]: a message about a place in a TOML file, rendered like a compiler's.

use std::fmt;
use std::ops::Range;
use toml::de::DeTable;

/// A message about a TOML file: `file:line:column: message`, then the line with a caret
/// under the culprit.
#[derive(Clone, Debug, PartialEq)]
pub struct Located {
    /// The file.
    pub file: String,
    /// 1-based line and column (in characters), when the problem has a place.
    pub position: Option<(usize, usize)>,
    /// What is wrong and what was expected.
    pub message: String,
    /// The offending line and the caret's (column, width).
    snippet: Option<(String, usize, usize)>,
}

impl Located {
    /// A message about `src` (the text of `file`) at byte range `span`, if any.
    pub fn new(file: &str, src: &str, span: Option<Range<usize>>, message: String) -> Self {
        let Some(span) = span.filter(|s| s.start <= src.len()) else {
            return Located {
                file: file.to_owned(),
                position: None,
                message,
                snippet: None,
            };
        };
        let mut start = span.start;
        while !src.is_char_boundary(start) {
            start -= 1;
        }
        let line_start = src[..start].rfind('\n').map_or(0, |i| i + 1);
        let line_end = src[start..].find('\n').map_or(src.len(), |i| start + i);
        let line_no = src[..start].matches('\n').count() + 1;
        let col = src[line_start..start].chars().count() + 1;
        let text = src[line_start..line_end].trim_end_matches('\r').to_owned();
        let end = span.end.clamp(start, line_end);
        let width = src.get(start..end).map_or(1, |s| s.chars().count().max(1));
        Located {
            file: file.to_owned(),
            position: Some((line_no, col)),
            message,
            snippet: Some((text, col, width)),
        }
    }

    /// A message about the value at key path `keys` of `src` (its whole file if absent).
    pub fn at_key(file: &str, src: &str, keys: &[&str], message: String) -> Self {
        Located::new(file, src, span_of(src, keys), message)
    }

    /// A TOML parse or type error.
    pub fn from_toml(file: &str, src: &str, e: &toml::de::Error) -> Self {
        Located::new(file, src, e.span(), e.message().trim_end().to_owned())
    }
}

impl fmt::Display for Located {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.position {
            Some((line, col)) => write!(f, "{}:{line}:{col}: {}", self.file, self.message)?,
            None => write!(f, "{}: {}", self.file, self.message)?,
        }
        if let (Some((line, _)), Some((text, col, width))) = (self.position, &self.snippet) {
            let gutter = line.to_string().len();
            write!(
                f,
                "\n{:gutter$} |\n{line} | {text}\n{:gutter$} | {:pad$}{}",
                "",
                "",
                "",
                "^".repeat(*width),
                pad = col - 1
            )?;
        }
        Ok(())
    }
}

impl std::error::Error for Located {}

/// The byte span of the value at key path `keys` (each element one key, so a key may hold
/// dots: `["parameters", "channel.loss"]`), if present.
pub fn span_of(src: &str, keys: &[&str]) -> Option<Range<usize>> {
    let root = DeTable::parse(src).ok()?;
    let mut table = root.get_ref();
    let (last, parents) = keys.split_last()?;
    for key in parents {
        table = table.get(*key)?.get_ref().as_table()?;
    }
    Some(table.get(*last)?.span())
}

/// The byte offset of the key `keys` (its name, not its value), for ordering entries as
/// written; `usize::MAX` if absent.
pub fn key_offset(src: &str, keys: &[&str]) -> usize {
    let Some(root) = DeTable::parse(src).ok() else {
        return usize::MAX;
    };
    let mut table = root.get_ref();
    let Some((last, parents)) = keys.split_last() else {
        return usize::MAX;
    };
    for key in parents {
        match table.get(*key).and_then(|v| v.get_ref().as_table()) {
            Some(t) => table = t,
            None => return usize::MAX,
        }
    }
    table
        .iter()
        .find(|(k, _)| k.get_ref().as_ref() == *last)
        .map_or(usize::MAX, |(k, _)| k.span().start)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn caret_under_the_value() {
        let src = "a = 1\n[t]\n\"x.y\" = [1, 2]\n";
        let e = Located::at_key("f.toml", src, &["t", "x.y"], "bad".into());
        assert_eq!(e.position, Some((3, 9)));
        assert!(
            e.to_string()
                .ends_with("3 | \"x.y\" = [1, 2]\n  |         ^^^^^^")
        );
        assert!(key_offset(src, &["t", "x.y"]) < src.len());
        assert_eq!(key_offset(src, &["t", "z"]), usize::MAX);
    }

    #[test]
    fn no_place_no_snippet() {
        let e = Located::at_key("f.toml", "a = 1", &["b"], "missing".into());
        assert_eq!(e.to_string(), "f.toml: missing");
    }
}
