//! Tokenizer of the rule language: identifiers, variables, integers, strings, punctuation,
//! `//` and `/* */` comments.

use super::error::{ErrorKind, Pos, RuleError};

/// What a token is.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) enum Tok {
    /// A name starting with a lower-case letter (keywords included).
    Ident(String),
    /// A name starting with an upper-case letter or `_`.
    Var(String),
    /// An integer.
    Int(i64),
    /// A double-quoted string (escapes `\"`, `\\`, `\n` resolved).
    Str(String),
    /// One of `( ) [ ] { } , ;`, or `==`, `!=`, `-`.
    Punct(&'static str),
    /// End of input.
    End,
}

impl Tok {
    /// How the token reads in an error message.
    pub fn describe(&self) -> String {
        match self {
            Tok::Ident(s) if is_keyword(s) => format!("'{s}'"),
            Tok::Ident(s) => format!("identifier '{s}'"),
            Tok::Var(s) => format!("variable '{s}'"),
            Tok::Int(i) => format!("integer {i}"),
            Tok::Str(s) => format!("string {s:?}"),
            Tok::Punct(p) => format!("'{p}'"),
            Tok::End => "end of input".to_string(),
        }
    }
    /// Whether this is the keyword or punctuation `s`.
    pub fn is(&self, s: &str) -> bool {
        match self {
            Tok::Ident(i) => i == s && is_keyword(s),
            Tok::Punct(p) => *p == s,
            _ => false,
        }
    }
}

/// The reserved words.
pub(crate) const KEYWORDS: [&str; 7] = ["when", "then", "define", "end", "and", "not", "skip"];

/// Whether `s` is a reserved word.
pub(crate) fn is_keyword(s: &str) -> bool {
    KEYWORDS.contains(&s)
}

/// A token and where it starts.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct Token {
    pub tok: Tok,
    pub pos: Pos,
}

const PUNCT: [&str; 11] = ["==", "!=", "(", ")", "[", "]", "{", "}", ",", ";", "-"];

/// Splits `src` into tokens, ending with [`Tok::End`].
///
/// # Errors
/// An unexpected character, an unterminated string or comment, an integer out of range.
pub(crate) fn tokenize(file: &str, src: &str) -> Result<Vec<Token>, RuleError> {
    let mut lx = Lexer {
        chars: src.chars().collect(),
        i: 0,
        pos: Pos { line: 1, column: 1 },
    };
    let mut out = Vec::new();
    loop {
        lx.skip_blank(file)?;
        let pos = lx.pos;
        let Some(c) = lx.peek(0) else {
            out.push(Token { tok: Tok::End, pos });
            return Ok(out);
        };
        let tok = if c.is_alphabetic() || c == '_' {
            let word = lx.take_while(|c| c.is_alphanumeric() || c == '_');
            if c.is_uppercase() || c == '_' {
                Tok::Var(word)
            } else {
                Tok::Ident(word)
            }
        } else if c.is_ascii_digit() {
            let digits = lx.take_while(|c| c.is_ascii_digit());
            let value = digits
                .parse()
                .map_err(|_| RuleError::new(file, pos, ErrorKind::IntegerRange(digits)))?;
            Tok::Int(value)
        } else if c == '"' {
            Tok::Str(lx.string(file)?)
        } else if let Some(p) = PUNCT.iter().find(|p| lx.starts_with(p)) {
            for _ in 0..p.len() {
                lx.bump();
            }
            Tok::Punct(p)
        } else {
            return Err(RuleError::new(file, pos, ErrorKind::Character(c)));
        };
        out.push(Token { tok, pos });
    }
}

struct Lexer {
    chars: Vec<char>,
    i: usize,
    pos: Pos,
}

impl Lexer {
    fn peek(&self, k: usize) -> Option<char> {
        self.chars.get(self.i + k).copied()
    }

    fn bump(&mut self) -> Option<char> {
        let c = self.peek(0)?;
        self.i += 1;
        if c == '\n' {
            self.pos.line += 1;
            self.pos.column = 1;
        } else {
            self.pos.column += 1;
        }
        Some(c)
    }

    fn starts_with(&self, s: &str) -> bool {
        s.chars().enumerate().all(|(k, c)| self.peek(k) == Some(c))
    }

    fn take_while(&mut self, f: impl Fn(char) -> bool) -> String {
        let mut s = String::new();
        while let Some(c) = self.peek(0).filter(|&c| f(c)) {
            s.push(c);
            self.bump();
        }
        s
    }

    /// Skips white space and comments.
    fn skip_blank(&mut self, file: &str) -> Result<(), RuleError> {
        loop {
            match self.peek(0) {
                Some(c) if c.is_whitespace() => {
                    self.bump();
                }
                Some('/') if self.peek(1) == Some('/') => {
                    while self.peek(0).is_some_and(|c| c != '\n') {
                        self.bump();
                    }
                }
                Some('/') if self.peek(1) == Some('*') => {
                    let start = self.pos;
                    self.bump();
                    self.bump();
                    while !self.starts_with("*/") {
                        if self.bump().is_none() {
                            return Err(RuleError::new(
                                file,
                                start,
                                ErrorKind::UnterminatedComment,
                            ));
                        }
                    }
                    self.bump();
                    self.bump();
                }
                _ => return Ok(()),
            }
        }
    }

    /// A string literal (the opening quote is next).
    fn string(&mut self, file: &str) -> Result<String, RuleError> {
        let start = self.pos;
        self.bump();
        let mut s = String::new();
        loop {
            match self.bump() {
                None | Some('\n') => {
                    return Err(RuleError::new(file, start, ErrorKind::UnterminatedString));
                }
                Some('"') => return Ok(s),
                Some('\\') => {
                    let at = self.pos;
                    match self.bump() {
                        Some('"') => s.push('"'),
                        Some('\\') => s.push('\\'),
                        Some('n') => s.push('\n'),
                        Some(c) => return Err(RuleError::new(file, at, ErrorKind::Escape(c))),
                        None => {
                            return Err(RuleError::new(file, start, ErrorKind::UnterminatedString));
                        }
                    }
                }
                Some(c) => s.push(c),
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn kinds(src: &str) -> Vec<Tok> {
        tokenize("t", src)
            .expect("lexes")
            .into_iter()
            .map(|t| t.tok)
            .collect()
    }

    #[test]
    fn tokens_and_positions() {
        let t = tokenize("t", "when X\n  [f(-3)] // c\n/* x */ \"a\\\"b\" != ;").expect("lexes");
        let got: Vec<(Tok, u32, u32)> = t
            .into_iter()
            .map(|t| (t.tok, t.pos.line, t.pos.column))
            .collect();
        assert_eq!(
            got,
            vec![
                (Tok::Ident("when".into()), 1, 1),
                (Tok::Var("X".into()), 1, 6),
                (Tok::Punct("["), 2, 3),
                (Tok::Ident("f".into()), 2, 4),
                (Tok::Punct("("), 2, 5),
                (Tok::Punct("-"), 2, 6),
                (Tok::Int(3), 2, 7),
                (Tok::Punct(")"), 2, 8),
                (Tok::Punct("]"), 2, 9),
                (Tok::Str("a\"b".into()), 3, 9),
                (Tok::Punct("!="), 3, 16),
                (Tok::Punct(";"), 3, 19),
                (Tok::End, 3, 20),
            ]
        );
    }

    #[test]
    fn underscore_starts_a_variable() {
        assert_eq!(
            kinds("_x y_1"),
            [Tok::Var("_x".into()), Tok::Ident("y_1".into()), Tok::End]
        );
    }
}
