//! Tokenizer for PDDL: parentheses and symbols, with `;` comments and case folding.

/// One PDDL token.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) enum TokenKind {
    /// `(`
    Open,
    /// `)`
    Close,
    /// Any other run of characters (names, `?variables`, `:keywords`, `-`), lower-cased.
    Symbol(String),
}

/// A token with the 1-based line and column of its first character.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct Token {
    pub kind: TokenKind,
    pub line: u32,
    pub column: u32,
}

impl Token {
    /// How the token reads in an error message (`'('`, `':effect'`).
    pub fn describe(&self) -> String {
        match &self.kind {
            TokenKind::Open => "'('".to_string(),
            TokenKind::Close => "')'".to_string(),
            TokenKind::Symbol(s) => format!("'{s}'"),
        }
    }
}

/// Splits `src` into tokens. Symbols are lower-cased (PDDL is case-insensitive).
///
/// Returns the tokens and the position just past the last character (for
/// "end of file" errors).
pub(crate) fn tokenize(src: &str) -> (Vec<Token>, (u32, u32)) {
    let mut tokens = Vec::new();
    let (mut line, mut column) = (1u32, 1u32);
    let mut chars = src.chars().peekable();
    while let Some(&c) = chars.peek() {
        match c {
            '\n' => {
                chars.next();
                line += 1;
                column = 1;
            }
            ';' => {
                while let Some(&c) = chars.peek() {
                    if c == '\n' {
                        break;
                    }
                    chars.next();
                }
            }
            c if c.is_whitespace() => {
                chars.next();
                column += 1;
            }
            '(' | ')' => {
                chars.next();
                let kind = if c == '(' {
                    TokenKind::Open
                } else {
                    TokenKind::Close
                };
                tokens.push(Token { kind, line, column });
                column += 1;
            }
            _ => {
                let start = column;
                let mut text = String::new();
                while let Some(&c) = chars.peek() {
                    if c.is_whitespace() || c == '(' || c == ')' || c == ';' {
                        break;
                    }
                    text.extend(c.to_lowercase());
                    chars.next();
                    column += 1;
                }
                tokens.push(Token {
                    kind: TokenKind::Symbol(text),
                    line,
                    column: start,
                });
            }
        }
    }
    (tokens, (line, column))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn positions_comments_and_case() {
        let (toks, end) = tokenize("(Define ; note\n  (domain D-1))");
        let kinds: Vec<_> = toks.iter().map(|t| t.kind.clone()).collect();
        assert_eq!(
            kinds,
            vec![
                TokenKind::Open,
                TokenKind::Symbol("define".into()),
                TokenKind::Open,
                TokenKind::Symbol("domain".into()),
                TokenKind::Symbol("d-1".into()),
                TokenKind::Close,
                TokenKind::Close,
            ]
        );
        assert_eq!((toks[2].line, toks[2].column), (2, 3));
        assert_eq!((toks[4].line, toks[4].column), (2, 11));
        assert_eq!(end, (2, 16));
    }
}
