//! Recursive-descent parser from tokens to [`Domain`] and [`Problem`], checking names,
//! arities and types as it goes so that every error points at the offending token.
//!
//! This file holds the entry points and the token-level helpers; the grammar of domains
//! and problems is in `domain.rs` and `problem.rs`.

use std::collections::HashMap;

use super::error::{ParseError, ParseErrorKind};
use super::lexer::{Token, TokenKind, tokenize};
use super::{Domain, Predicate, Problem, TypeId};

/// Requirement flags this parser understands.
const SUPPORTED_REQUIREMENTS: [&str; 3] = [":strips", ":typing", ":equality"];

/// Parses a domain. `file` names the source in error messages.
///
/// # Errors
/// A [`ParseError`] at the first token that breaks the grammar or refers to something
/// undeclared.
pub fn parse_domain(src: &str, file: &str) -> Result<Domain, ParseError> {
    let mut p = Parser::new(src, file);
    let domain = p.domain()?;
    p.end_of_input()?;
    Ok(domain)
}

/// Parses a problem for `domain`. `file` names the source in error messages.
///
/// # Errors
/// A [`ParseError`] at the first token that breaks the grammar, names an unknown object or
/// predicate, or gives an object of the wrong type.
pub fn parse_problem(domain: &Domain, src: &str, file: &str) -> Result<Problem, ParseError> {
    let mut p = Parser::new(src, file);
    let problem = p.problem(domain)?;
    p.end_of_input()?;
    Ok(problem)
}

/// A typed-list entry as written: name, its token, and its type name with token.
pub(super) type RawTyped = (String, Token, Option<(String, Token)>);

/// Cursor over the tokens of one file.
pub(super) struct Parser<'a> {
    file: &'a str,
    pub(super) tokens: Vec<Token>,
    pub(super) pos: usize,
    end: (u32, u32),
}

impl<'a> Parser<'a> {
    fn new(src: &str, file: &'a str) -> Self {
        let (tokens, end) = tokenize(src);
        Parser {
            file,
            tokens,
            pos: 0,
            end,
        }
    }

    // ---- token-level helpers ------------------------------------------------------------

    pub(super) fn peek(&self) -> Option<&Token> {
        self.tokens.get(self.pos)
    }

    pub(super) fn peek_symbol(&self) -> Option<&str> {
        match self.peek().map(|t| &t.kind) {
            Some(TokenKind::Symbol(s)) => Some(s),
            _ => None,
        }
    }

    pub(super) fn at_close(&self) -> bool {
        matches!(self.peek().map(|t| &t.kind), Some(TokenKind::Close))
    }

    pub(super) fn at_open(&self) -> bool {
        matches!(self.peek().map(|t| &t.kind), Some(TokenKind::Open))
    }

    pub(super) fn error_at(&self, tok: Option<&Token>, kind: ParseErrorKind) -> ParseError {
        let (line, column) = tok.map_or(self.end, |t| (t.line, t.column));
        ParseError {
            file: self.file.to_string(),
            line,
            column,
            kind: Box::new(kind),
        }
    }

    /// An error at the current token.
    pub(super) fn error_here(&self, kind: ParseErrorKind) -> ParseError {
        self.error_at(self.peek(), kind)
    }

    /// "expected {what}, found {current token}".
    pub(super) fn expected(&self, what: &str) -> ParseError {
        let found = self
            .peek()
            .map_or_else(|| "end of file".to_string(), Token::describe);
        self.error_here(ParseErrorKind::Expected {
            expected: what.to_string(),
            found,
        })
    }

    pub(super) fn open(&mut self, what: &str) -> Result<(), ParseError> {
        if self.at_open() {
            self.pos += 1;
            Ok(())
        } else {
            Err(self.expected(&format!("'(' {what}")))
        }
    }

    pub(super) fn close(&mut self, what: &str) -> Result<(), ParseError> {
        if self.at_close() {
            self.pos += 1;
            Ok(())
        } else {
            Err(self.expected(&format!("')' {what}")))
        }
    }

    /// Consumes the symbol `word` or fails with "expected '{word}' {what}".
    pub(super) fn keyword(&mut self, word: &str, what: &str) -> Result<(), ParseError> {
        if self.peek_symbol() == Some(word) {
            self.pos += 1;
            Ok(())
        } else {
            Err(self.expected(&format!("'{word}' {what}")))
        }
    }

    /// Consumes a plain name (not a `?variable` or `:keyword`).
    pub(super) fn name(&mut self, what: &str) -> Result<(String, Token), ParseError> {
        match self.peek() {
            Some(
                tok @ Token {
                    kind: TokenKind::Symbol(s),
                    ..
                },
            ) if !s.starts_with('?') && !s.starts_with(':') => {
                let out = (s.clone(), tok.clone());
                self.pos += 1;
                Ok(out)
            }
            _ => Err(self.expected(what)),
        }
    }

    fn end_of_input(&self) -> Result<(), ParseError> {
        if self.peek().is_some() {
            Err(self.expected("end of file after the closing ')'"))
        } else {
            Ok(())
        }
    }

    /// Parses `name* [- type]` groups up to (not including) `)`.
    ///
    /// `variables` demands `?names`; `ctx` describes the list for messages
    /// (`action parameters`).
    pub(super) fn typed_list(
        &mut self,
        variables: bool,
        ctx: &str,
    ) -> Result<Vec<RawTyped>, ParseError> {
        let mut out: Vec<RawTyped> = Vec::new();
        let mut untyped_from = 0;
        loop {
            let Some(tok) = self.peek().cloned() else {
                return Err(self.expected(&format!("')' after {ctx}")));
            };
            let TokenKind::Symbol(s) = &tok.kind else {
                if self.at_close() {
                    break;
                }
                return Err(self.expected(&format!("')' after {ctx}")));
            };
            if s == "-" {
                self.pos += 1;
                if untyped_from == out.len() {
                    return Err(self.error_at(
                        Some(&tok),
                        ParseErrorKind::Expected {
                            expected: format!("a name before '-' in {ctx}"),
                            found: "'-'".to_string(),
                        },
                    ));
                }
                if self.at_open() {
                    return Err(
                        self.error_here(ParseErrorKind::Unsupported("'either' types".to_string()))
                    );
                }
                let ty = self.name(&format!("a type name after '-' in {ctx}"))?;
                for entry in &mut out[untyped_from..] {
                    entry.2 = Some(ty.clone());
                }
                untyped_from = out.len();
            } else if s.starts_with(':') {
                return Err(self.expected(&format!("')' after {ctx}")));
            } else if variables != s.starts_with('?') {
                let want = if variables { "a ?variable" } else { "a name" };
                return Err(self.expected(&format!("{want} or ')' in {ctx}")));
            } else {
                let name = s.trim_start_matches('?').to_string();
                self.pos += 1;
                out.push((name, tok, None));
            }
        }
        Ok(out)
    }

    pub(super) fn requirements(&mut self) -> Result<Vec<String>, ParseError> {
        let mut reqs = Vec::new();
        while let Some(s) = self.peek_symbol() {
            if !s.starts_with(':') {
                return Err(self.expected("a requirement flag or ')'"));
            }
            if !SUPPORTED_REQUIREMENTS.contains(&s) {
                return Err(self.error_here(ParseErrorKind::UnsupportedRequirement(s.into())));
            }
            reqs.push(s.to_string());
            self.pos += 1;
        }
        self.close("after the requirements")?;
        Ok(reqs)
    }

    pub(super) fn resolve_type(
        &self,
        type_ids: &HashMap<String, TypeId>,
        ty: Option<(String, Token)>,
    ) -> Result<TypeId, ParseError> {
        match ty {
            None => Ok(0),
            Some((name, tok)) => type_ids
                .get(&name)
                .copied()
                .ok_or_else(|| self.error_at(Some(&tok), ParseErrorKind::UnknownType(name))),
        }
    }
}

pub(super) fn check_arity(
    p: &Parser<'_>,
    decl: &Predicate,
    found: usize,
    tok: &Token,
) -> Result<(), ParseError> {
    if decl.params.len() == found {
        Ok(())
    } else {
        Err(p.error_at(
            Some(tok),
            ParseErrorKind::Arity {
                predicate: decl.name.clone(),
                expected: decl.params.len(),
                found,
            },
        ))
    }
}
