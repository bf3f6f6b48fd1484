//! Places in a scenario's source text, and the diagnostics that point at them.
//!
//! [`SourceMap`] finds the span of a key or value by its dotted path (`"channel.loss"`,
//! `"entity.2.start.0"`: a number indexes an array), falling back to the nearest enclosing
//! table when the key is absent; a [`Diagnostic`] turns a span into `file:line:column` and
//! keeps the offending line to show under the message.

use std::fmt;
use std::ops::Range;
use std::path::{Path, PathBuf};
use toml::Spanned;
use toml::de::{DeTable, DeValue};

/// Most problems reported for one file: past them, a file is rarely the file meant (a
/// binary, a file of another kind), and each problem costs a pass over the text. The rest are
/// counted in one [`Diagnostic::more`].
pub const MAX_PROBLEMS: usize = 100;

/// One problem in a scenario file.
///
/// Its [`Display`](fmt::Display) is one line, `file:line:column: message (expected ...)`;
/// [`Diagnostic::render`] adds the offending line with a caret under the place.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("{}{}: {message}{}", .file.display(), show_position(*.position), show_expected(.expected))]
pub struct Diagnostic {
    /// The scenario file, as it was named.
    pub file: PathBuf,
    /// 1-based line and column (in characters); `None` when the problem has no place
    /// (the file cannot be read).
    pub position: Option<(usize, usize)>,
    /// What is wrong.
    pub message: String,
    /// What was expected there, if that can be said.
    pub expected: Option<String>,
    /// The offending line and the caret's width in characters.
    snippet: Option<(String, usize)>,
}

fn show_position(p: Option<(usize, usize)>) -> String {
    p.map(|(l, c)| format!(":{l}:{c}")).unwrap_or_default()
}

fn show_expected(e: &Option<String>) -> String {
    e.as_ref()
        .map(|e| format!(" (expected {e})"))
        .unwrap_or_default()
}

impl Diagnostic {
    /// The note that `n` more problems of `file` were found and not shown.
    pub fn more(file: &Path, n: usize) -> Self {
        Diagnostic {
            file: file.to_path_buf(),
            position: None,
            message: format!("{n} more problems not shown (the first {MAX_PROBLEMS} found are)"),
            expected: None,
            snippet: None,
        }
    }

    /// A problem at byte range `span` of `source` (none: no place).
    pub fn new(
        file: &Path,
        source: &str,
        span: Option<Range<usize>>,
        message: impl Into<String>,
        expected: Option<String>,
    ) -> Self {
        let place = span.filter(|s| s.start <= source.len()).map(|span| {
            let mut start = span.start;
            while !source.is_char_boundary(start) {
                start -= 1;
            }
            let line_start = source[..start].rfind('\n').map_or(0, |i| i + 1);
            let line_end = source[start..]
                .find('\n')
                .map_or(source.len(), |i| start + i);
            let line = source[..start].matches('\n').count() + 1;
            let column = source[line_start..start].chars().count() + 1;
            let text = source[line_start..line_end]
                .trim_end_matches('\r')
                .to_owned();
            let end = span.end.clamp(start, line_end);
            let width = source
                .get(start..end)
                .map_or(1, |s| s.chars().count().max(1));
            ((line, column), (text, width))
        });
        Diagnostic {
            file: file.to_path_buf(),
            position: place.as_ref().map(|p| p.0),
            message: message.into(),
            expected,
            snippet: place.map(|p| p.1),
        }
    }

    /// The one-line form followed by the offending line with a caret under the place.
    ///
    /// ```text
    /// my.toml:20:8: invalid value 1.5 for `channel.loss` (expected a probability in [0, 1])
    ///    |
    /// 20 | loss = 1.5
    ///    |        ^^^
    /// ```
    pub fn render(&self) -> String {
        let mut out = self.to_string();
        if let (Some((line, col)), Some((text, width))) = (self.position, &self.snippet) {
            let gutter = line.to_string().len();
            out.push_str(&format!(
                "\n{:gutter$} |\n{line} | {text}\n{:gutter$} | {:pad$}{}",
                "",
                "",
                "",
                "^".repeat(*width),
                pad = col - 1
            ));
        }
        out
    }
}

/// Every problem found in a scenario file, in the order of their places.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub struct Diagnostics(pub Vec<Diagnostic>);

impl Diagnostics {
    /// The problems sorted by place (those without a place first), duplicates dropped.
    pub fn new(mut items: Vec<Diagnostic>) -> Self {
        items.sort_by_key(|d| d.position);
        items.dedup();
        Diagnostics(items)
    }

    /// Every problem with its offending line, separated by blank lines.
    pub fn render(&self) -> String {
        let parts: Vec<String> = self.0.iter().map(Diagnostic::render).collect();
        parts.join("\n\n")
    }

    /// The count of problems on a line (`1 problem`, `3 problems`), then each
    /// [rendered](Self::render): what a tool prints for a refused file.
    pub fn report(&self) -> String {
        let n = self.len();
        let problems = if n == 1 { "problem" } else { "problems" };
        format!("{n} {problems}\n{}", self.render())
    }

    /// Number of problems.
    pub fn len(&self) -> usize {
        self.0.len()
    }

    /// True if there is no problem.
    pub fn is_empty(&self) -> bool {
        self.0.is_empty()
    }
}

impl fmt::Display for Diagnostics {
    /// One problem a line.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        for (i, d) in self.0.iter().enumerate() {
            if i > 0 {
                writeln!(f)?;
            }
            write!(f, "{d}")?;
        }
        Ok(())
    }
}

/// At most [`MAX_PROBLEMS`] diagnostics, each made only if it is kept, and a count of the
/// rest.
pub(crate) struct Capped<'a> {
    file: &'a Path,
    out: Vec<Diagnostic>,
    dropped: usize,
}

impl<'a> Capped<'a> {
    pub(crate) fn new(file: &'a Path) -> Self {
        Capped {
            file,
            out: Vec::new(),
            dropped: 0,
        }
    }

    pub(crate) fn push(&mut self, make: impl FnOnce() -> Diagnostic) {
        if self.out.len() < MAX_PROBLEMS {
            self.out.push(make());
        } else {
            self.dropped += 1;
        }
    }

    pub(crate) fn finish(mut self) -> Vec<Diagnostic> {
        if self.dropped > 0 {
            self.out.push(Diagnostic::more(self.file, self.dropped));
        }
        self.out
    }
}

/// The spans of a parsed TOML document, found by dotted path.
pub struct SourceMap<'i> {
    file: &'i Path,
    text: &'i str,
    root: Option<Spanned<DeTable<'i>>>,
}

impl<'i> SourceMap<'i> {
    /// The spans of `text` (read from `file`); a document that does not parse has none.
    pub fn new(file: &'i Path, text: &'i str) -> Self {
        SourceMap {
            file,
            text,
            root: DeTable::parse(text).ok(),
        }
    }

    /// The file the text was read from, as it was named.
    pub fn file(&self) -> &Path {
        self.file
    }

    /// The values found along `path`, outermost first (fewer than the path's segments when
    /// a key or index is absent).
    fn walk(&self, path: &str) -> Vec<&Spanned<DeValue<'i>>> {
        let mut found: Vec<&Spanned<DeValue<'i>>> = Vec::new();
        let Some(root) = &self.root else {
            return found;
        };
        for seg in path.split('.').filter(|s| !s.is_empty()) {
            let next = match (found.last().map(|v| v.get_ref()), seg.parse::<usize>()) {
                (None, _) => root.get_ref().get(seg),
                (Some(DeValue::Table(t)), _) => t.get(seg),
                (Some(DeValue::Array(a)), Ok(i)) => a.get(i),
                _ => None,
            };
            match next {
                Some(v) => found.push(v),
                None => break,
            }
        }
        found
    }

    /// The value at `path`, if present.
    fn value(&self, path: &str) -> Option<&DeValue<'i>> {
        let segments = path.split('.').filter(|s| !s.is_empty()).count();
        let found = self.walk(path);
        (found.len() == segments).then(|| found.last().map(|v| v.get_ref()))?
    }

    /// The span of the value at `path`, or of the nearest enclosing value present (the whole
    /// document when nothing on the path is).
    pub fn find(&self, path: &str) -> Range<usize> {
        match self.walk(path).last() {
            Some(v) => v.span(),
            None => self.root.as_ref().map_or(0..0, |r| r.span()),
        }
    }

    /// The number of items of the array at `path`, if there is one.
    pub fn array_len(&self, path: &str) -> Option<usize> {
        match self.value(path)? {
            DeValue::Array(a) => Some(a.len()),
            _ => None,
        }
    }

    /// A diagnostic at the value at `path` (or the nearest enclosing one).
    pub fn at(&self, path: &str, message: impl Into<String>, expected: &str) -> Diagnostic {
        let span = self.find(path);
        Diagnostic::new(
            self.file,
            self.text,
            Some(span),
            message,
            Some(expected.to_owned()).filter(|e| !e.is_empty()),
        )
    }

    /// A diagnostic at byte range `span`.
    pub fn at_span(
        &self,
        span: Range<usize>,
        message: impl Into<String>,
        expected: Option<String>,
    ) -> Diagnostic {
        Diagnostic::new(self.file, self.text, Some(span), message, expected)
    }
}

impl Diagnostic {
    /// A toml error as a diagnostic at its place: its message split into what is wrong and
    /// what was expected, serde's type names in words (`f64` is "a number").
    pub fn from_toml(file: &Path, text: &str, e: &toml::de::Error) -> Self {
        Self::from_toml_or_at(file, text, e, None)
    }

    /// [`from_toml`](Self::from_toml), placed at `fallback` when the error has no place of
    /// its own (a value deserialized on its own, outside its table).
    pub fn from_toml_or_at(
        file: &Path,
        text: &str,
        e: &toml::de::Error,
        fallback: Option<Range<usize>>,
    ) -> Self {
        let message = e.message().trim();
        let (what, expected) = match message.split_once(", expected ") {
            Some((what, exp)) => (what.to_owned(), Some(plain(exp))),
            None => match message.split_once("\nexpected ") {
                Some((what, exp)) => (what.to_owned(), Some(exp.to_owned())),
                None => (message.replace('\n', "; "), None),
            },
        };
        let expected = expected.or_else(|| {
            let key = what.strip_prefix("missing field `")?.strip_suffix('`')?;
            Some(format!("a key `{key}` in this table"))
        });
        Diagnostic::new(file, text, e.span().or(fallback), what, expected)
    }
}

/// Rust type names in serde's messages, in words.
fn plain(expected: &str) -> String {
    match expected {
        "f64" => "a number".to_owned(),
        "u32" => "a whole number in 0..=4294967295".to_owned(),
        "u64" => "a whole number, 0 or more".to_owned(),
        "a sequence" => "an array".to_owned(),
        other if other.starts_with("struct ") => "a table".to_owned(),
        other => other.to_owned(),
    }
}
