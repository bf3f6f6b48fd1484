//! The recursive-descent parser of rule programs (grammar in the [module](super) docs).

use super::ast::{Literal, MacroDef, Stmt};
use super::error::{ErrorKind, Pos, RuleError};
use super::lexer::{Tok, Token, is_keyword, tokenize};
use super::term::{Term, Var};

/// A parsed file: its macro definitions and its main statement.
pub(crate) struct Parsed {
    pub macros: Vec<MacroDef>,
    pub body: Stmt,
}

/// Parses a whole program (macros not yet expanded).
pub(crate) fn parse_program(file: &str, src: &str) -> Result<Parsed, RuleError> {
    let mut p = Parser::new(file, src)?;
    let mut macros = Vec::new();
    while p.at("define") {
        macros.push(p.definition()?);
    }
    let body = if p.peek().tok == Tok::End || p.at("define") {
        Stmt::Skip
    } else {
        p.expr()?
    };
    while p.at("define") {
        macros.push(p.definition()?);
    }
    p.expect_end("',' or ';' or end of input")?;
    Ok(Parsed { macros, body })
}

/// Parses exactly one term.
pub(crate) fn parse_term(file: &str, src: &str) -> Result<Term, RuleError> {
    let mut p = Parser::new(file, src)?;
    let t = p.term()?;
    p.expect_end("end of input after the term")?;
    Ok(t)
}

impl Term {
    /// Reads one term, e.g. `at(guard, X)`.
    ///
    /// # Errors
    /// A [`RuleError`] (file name `term`) if `text` is not exactly one term.
    pub fn parse(text: &str) -> Result<Term, RuleError> {
        parse_term("term", text)
    }
}

struct Parser<'f> {
    file: &'f str,
    toks: Vec<Token>,
    i: usize,
    /// Anonymous variables (`_`) so far: each is a variable of its own.
    anonymous: u32,
}

impl<'f> Parser<'f> {
    fn new(file: &'f str, src: &str) -> Result<Self, RuleError> {
        Ok(Parser {
            file,
            toks: tokenize(file, src)?,
            i: 0,
            anonymous: 0,
        })
    }

    fn peek(&self) -> &Token {
        // The token list always ends with `End`, and `next` never moves past it.
        &self.toks[self.i.min(self.toks.len() - 1)]
    }
    fn peek_at(&self, k: usize) -> &Tok {
        &self.toks[(self.i + k).min(self.toks.len() - 1)].tok
    }
    fn next(&mut self) -> Token {
        let t = self.peek().clone();
        if t.tok != Tok::End {
            self.i += 1;
        }
        t
    }
    fn at(&self, s: &str) -> bool {
        self.peek().tok.is(s)
    }

    fn error(&self, pos: Pos, kind: ErrorKind) -> RuleError {
        RuleError::new(self.file, pos, kind)
    }
    /// "expected `what`, found (the next token)", at the next token.
    fn expected(&self, what: impl Into<String>) -> RuleError {
        let t = self.peek();
        self.error(
            t.pos,
            ErrorKind::Expected {
                expected: what.into(),
                found: t.tok.describe(),
            },
        )
    }
    /// Consumes the keyword or punctuation `s`, or fails with "expected `what`".
    fn expect(&mut self, s: &str, what: impl Into<String>) -> Result<Pos, RuleError> {
        if self.at(s) {
            Ok(self.next().pos)
        } else {
            Err(self.expected(what))
        }
    }
    fn expect_end(&self, what: &str) -> Result<(), RuleError> {
        if self.peek().tok == Tok::End {
            Ok(())
        } else {
            Err(self.expected(what))
        }
    }
    /// A name that is not a keyword.
    fn name(&mut self, what: &str) -> Result<(String, Pos), RuleError> {
        match &self.peek().tok {
            Tok::Ident(s) if !is_keyword(s) => {
                let s = s.clone();
                Ok((s, self.next().pos))
            }
            _ => Err(self.expected(what)),
        }
    }

    /// `define name(params) expr end`
    fn definition(&mut self) -> Result<MacroDef, RuleError> {
        let pos = self.expect("define", "'define'")?;
        let (name, _) = self.name("a macro name after 'define'")?;
        let mut params = Vec::new();
        if self.at("(") {
            self.next();
            if !self.at(")") {
                loop {
                    let t = self.peek().clone();
                    let Tok::Var(v) = &t.tok else {
                        return Err(self.expected("a variable as macro parameter"));
                    };
                    let var = Term::Var(Var {
                        name: v.clone(),
                        scope: 0,
                        pos: t.pos,
                    });
                    if params.contains(&var) {
                        return Err(self.error(t.pos, ErrorKind::DuplicateParameter(v.clone())));
                    }
                    self.next();
                    params.push(var);
                    if !self.at(",") {
                        break;
                    }
                    self.next();
                }
            }
            self.expect(")", format!("',' or ')' in the parameters of '{name}'"))?;
        }
        let body = self.expr()?;
        let close = format!(
            "'end' to close macro '{name}' defined at {}:{}",
            pos.line, pos.column
        );
        self.expect("end", close)?;
        Ok(MacroDef {
            name,
            params,
            body,
            pos,
        })
    }

    /// `seq (';' seq)*`
    fn expr(&mut self) -> Result<Stmt, RuleError> {
        let mut branches = vec![self.seq()?];
        while self.at(";") {
            self.next();
            branches.push(self.seq()?);
        }
        Ok(if branches.len() == 1 {
            branches.remove(0)
        } else {
            Stmt::Choice(branches)
        })
    }

    /// `stmt (',' stmt)*`
    fn seq(&mut self) -> Result<Stmt, RuleError> {
        let mut items = vec![self.stmt("a statement")?];
        while self.at(",") {
            self.next();
            items.push(self.stmt("a statement after ','")?);
        }
        Ok(if items.len() == 1 {
            items.remove(0)
        } else {
            Stmt::Seq(items)
        })
    }

    fn stmt(&mut self, what: &str) -> Result<Stmt, RuleError> {
        let t = self.peek().clone();
        match &t.tok {
            Tok::Ident(k) if k == "when" => {
                self.next();
                let query = self.query()?;
                self.expect("then", "'then' after query")?;
                let body = self.stmt("a statement after 'then'")?;
                Ok(Stmt::When {
                    query,
                    body: Box::new(body),
                })
            }
            Tok::Ident(k) if k == "skip" => {
                self.next();
                Ok(Stmt::Skip)
            }
            Tok::Punct("{") => {
                self.next();
                let e = self.expr()?;
                let close = format!(
                    "'}}' to close the block opened at {}:{}",
                    t.pos.line, t.pos.column
                );
                self.expect("}", close)?;
                Ok(e)
            }
            Tok::Ident(first) if !is_keyword(first) => {
                let first = first.clone();
                match self.peek_at(1).clone() {
                    Tok::Ident(module) if !is_keyword(&module) => {
                        self.next();
                        self.next();
                        self.expect("[", format!("'[' after module '{module}'"))?;
                        let term = self.term()?;
                        self.expect("]", "']' after update term")?;
                        Ok(Stmt::Update {
                            op: first,
                            module,
                            term,
                            pos: t.pos,
                        })
                    }
                    Tok::Punct("[") => {
                        self.next();
                        Err(self.expected("a statement (a query goes after 'when')"))
                    }
                    _ => {
                        self.next();
                        let args = if self.at("(") {
                            self.next();
                            self.arguments(&format!("the arguments of '{first}'"))?
                        } else {
                            Vec::new()
                        };
                        Ok(Stmt::Call {
                            name: first,
                            args,
                            pos: t.pos,
                        })
                    }
                }
            }
            _ => Err(self.expected(what)),
        }
    }

    /// `literal ('and' literal)*`
    fn query(&mut self) -> Result<Vec<Literal>, RuleError> {
        let mut lits = vec![self.literal("a query after 'when'")?];
        while self.at("and") {
            self.next();
            lits.push(self.literal("a query after 'and'")?);
        }
        Ok(lits)
    }

    fn literal(&mut self, what: &str) -> Result<Literal, RuleError> {
        let negated = self.at("not");
        if negated {
            self.next();
        }
        let t = self.peek().clone();
        if let (Tok::Ident(m), Tok::Punct("[")) = (&t.tok, self.peek_at(1))
            && !is_keyword(m)
        {
            let module = m.clone();
            self.next();
            self.next();
            let term = self.term()?;
            self.expect("]", "']' after query term")?;
            return Ok(Literal::Ask {
                module,
                term,
                negated,
                pos: t.pos,
            });
        }
        if negated {
            return Err(self.expected("a module query 'module [term]' after 'not'"));
        }
        if !starts_term(&t.tok) {
            return Err(self.expected(what));
        }
        let left = self.term()?;
        let equal = if self.at("==") {
            true
        } else if self.at("!=") {
            false
        } else {
            return Err(self.expected("'==' or '!=' after the term (or 'module [term]')"));
        };
        self.next();
        let right = self.term()?;
        Ok(Literal::Compare { left, right, equal })
    }

    /// Terms up to the closing `)` (the `(` is consumed).
    fn arguments(&mut self, of: &str) -> Result<Vec<Term>, RuleError> {
        let mut args = Vec::new();
        if self.at(")") {
            self.next();
            return Ok(args);
        }
        loop {
            args.push(self.term()?);
            if self.at(",") {
                self.next();
            } else {
                self.expect(")", format!("',' or ')' in {of}"))?;
                return Ok(args);
            }
        }
    }

    fn term(&mut self) -> Result<Term, RuleError> {
        let t = self.peek().clone();
        match t.tok {
            Tok::Var(v) => {
                self.next();
                let name = if v == "_" {
                    self.anonymous += 1;
                    format!("_#{}", self.anonymous)
                } else {
                    v
                };
                Ok(Term::Var(Var {
                    name,
                    scope: 0,
                    pos: t.pos,
                }))
            }
            Tok::Int(i) => {
                self.next();
                Ok(Term::Int(i))
            }
            Tok::Punct("-") => {
                self.next();
                match self.peek().tok {
                    Tok::Int(i) => {
                        self.next();
                        Ok(Term::Int(-i))
                    }
                    _ => Err(self.expected("an integer after '-'")),
                }
            }
            Tok::Str(s) => {
                self.next();
                Ok(Term::Str(s))
            }
            Tok::Ident(name) if !is_keyword(&name) => {
                self.next();
                if self.at("(") {
                    self.next();
                    let args = self.arguments(&format!("the arguments of '{name}'"))?;
                    // `f()` is the atom `f`.
                    Ok(if args.is_empty() {
                        Term::Atom(name)
                    } else {
                        Term::Compound(name, args)
                    })
                } else {
                    Ok(Term::Atom(name))
                }
            }
            _ => Err(self.expected("a term")),
        }
    }
}

fn starts_term(t: &Tok) -> bool {
    match t {
        Tok::Var(_) | Tok::Int(_) | Tok::Str(_) | Tok::Punct("-") => true,
        Tok::Ident(s) => !is_keyword(s),
        _ => false,
    }
}
