//! Recursive-descent parser from tokens to [`Domain`] and [`Problem`], checking names,
//! arities and types as it goes so that every error points at the offending token.

use std::collections::HashMap;

use super::error::{ParseError, ParseErrorKind};
use super::lexer::{Token, TokenKind, tokenize};
use super::{
    ActionSchema, AtomSchema, Condition, Domain, GroundAtom, ObjId, Predicate, Problem, Term,
    TypeDecl, TypeId, TypedName,
};

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
type RawTyped = (String, Token, Option<(String, Token)>);

struct Parser<'a> {
    file: &'a str,
    tokens: Vec<Token>,
    pos: usize,
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

    fn peek(&self) -> Option<&Token> {
        self.tokens.get(self.pos)
    }

    fn peek_symbol(&self) -> Option<&str> {
        match self.peek().map(|t| &t.kind) {
            Some(TokenKind::Symbol(s)) => Some(s),
            _ => None,
        }
    }

    fn at_close(&self) -> bool {
        matches!(self.peek().map(|t| &t.kind), Some(TokenKind::Close))
    }

    fn at_open(&self) -> bool {
        matches!(self.peek().map(|t| &t.kind), Some(TokenKind::Open))
    }

    fn error_at(&self, tok: Option<&Token>, kind: ParseErrorKind) -> ParseError {
        let (line, column) = tok.map_or(self.end, |t| (t.line, t.column));
        ParseError {
            file: self.file.to_string(),
            line,
            column,
            kind: Box::new(kind),
        }
    }

    /// An error at the current token.
    fn error_here(&self, kind: ParseErrorKind) -> ParseError {
        self.error_at(self.peek(), kind)
    }

    /// "expected {what}, found {current token}".
    fn expected(&self, what: &str) -> ParseError {
        let found = self
            .peek()
            .map_or_else(|| "end of file".to_string(), Token::describe);
        self.error_here(ParseErrorKind::Expected {
            expected: what.to_string(),
            found,
        })
    }

    fn open(&mut self, what: &str) -> Result<(), ParseError> {
        if self.at_open() {
            self.pos += 1;
            Ok(())
        } else {
            Err(self.expected(&format!("'(' {what}")))
        }
    }

    fn close(&mut self, what: &str) -> Result<(), ParseError> {
        if self.at_close() {
            self.pos += 1;
            Ok(())
        } else {
            Err(self.expected(&format!("')' {what}")))
        }
    }

    /// Consumes the symbol `word` or fails with "expected '{word}' {what}".
    fn keyword(&mut self, word: &str, what: &str) -> Result<(), ParseError> {
        if self.peek_symbol() == Some(word) {
            self.pos += 1;
            Ok(())
        } else {
            Err(self.expected(&format!("'{word}' {what}")))
        }
    }

    /// Consumes a plain name (not a `?variable` or `:keyword`).
    fn name(&mut self, what: &str) -> Result<(String, Token), ParseError> {
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
    fn typed_list(&mut self, variables: bool, ctx: &str) -> Result<Vec<RawTyped>, ParseError> {
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

    // ---- domain -------------------------------------------------------------------------

    fn domain(&mut self) -> Result<Domain, ParseError> {
        self.open("to start the domain definition")?;
        self.keyword("define", "at the start of the domain")?;
        self.open("before 'domain'")?;
        self.keyword("domain", "after '(define ('")?;
        let (name, _) = self.name("a domain name")?;
        self.close("after the domain name")?;

        let mut b = DomainBuilder::new(name);
        while self.at_open() {
            self.pos += 1;
            let Some(section) = self.peek().cloned() else {
                return Err(self.expected("a domain section keyword"));
            };
            match self.peek_symbol() {
                Some(":requirements") => {
                    self.pos += 1;
                    b.domain.requirements = self.requirements()?;
                }
                Some(":types") => {
                    self.pos += 1;
                    self.types(&mut b, &section)?;
                }
                Some(":constants") => {
                    self.pos += 1;
                    let list = self.typed_list(false, "constants")?;
                    for (name, tok, ty) in list {
                        let ty = self.resolve_type(&b.type_ids, ty)?;
                        if b.constant_ids.contains_key(&name) {
                            return Err(self.error_at(
                                Some(&tok),
                                ParseErrorKind::Duplicate {
                                    what: "constant",
                                    name,
                                },
                            ));
                        }
                        b.constant_ids
                            .insert(name.clone(), b.domain.constants.len());
                        b.domain.constants.push(TypedName { name, ty });
                    }
                    self.close("after the constants")?;
                }
                Some(":predicates") => {
                    self.pos += 1;
                    self.predicates(&mut b)?;
                }
                Some(":action") => {
                    self.pos += 1;
                    let action = self.action(&b)?;
                    if b.domain.actions.iter().any(|a| a.name == action.name) {
                        return Err(self.error_at(
                            Some(&section),
                            ParseErrorKind::Duplicate {
                                what: "action",
                                name: action.name,
                            },
                        ));
                    }
                    b.domain.actions.push(action);
                }
                Some(s) if s.starts_with(':') => {
                    return Err(
                        self.error_here(ParseErrorKind::Unsupported(format!("section '{s}'")))
                    );
                }
                _ => return Err(self.expected("a domain section keyword")),
            }
        }
        self.close("to end the domain definition")?;
        Ok(b.domain)
    }

    fn requirements(&mut self) -> Result<Vec<String>, ParseError> {
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

    fn types(&mut self, b: &mut DomainBuilder, section: &Token) -> Result<(), ParseError> {
        let list = self.typed_list(false, "types")?;
        for (name, tok, parent) in list {
            let parent = match parent {
                Some((p, _)) => Some(b.declare_type(&p, false)),
                None => Some(0),
            };
            if name == "object" {
                continue;
            }
            if b.explicit_types.contains(&name) {
                return Err(
                    self.error_at(Some(&tok), ParseErrorKind::Duplicate { what: "type", name })
                );
            }
            let id = b.declare_type(&name, true);
            b.domain.types[id].parent = parent;
        }
        // A chain of supertypes longer than the number of types is a cycle.
        for t in 0..b.domain.types.len() {
            let (mut cur, mut steps) = (Some(t), 0);
            while let Some(c) = cur {
                steps += 1;
                if steps > b.domain.types.len() {
                    let name = b.domain.types[t].name.clone();
                    return Err(self.error_at(Some(section), ParseErrorKind::TypeCycle(name)));
                }
                cur = b.domain.types[c].parent;
            }
        }
        self.close("after the types")
    }

    fn resolve_type(
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

    fn predicates(&mut self, b: &mut DomainBuilder) -> Result<(), ParseError> {
        while self.at_open() {
            self.pos += 1;
            let (name, tok) = self.name("a predicate name")?;
            let params = self.typed_list(true, "predicate parameters")?;
            self.close("after predicate parameters")?;
            let mut types = Vec::with_capacity(params.len());
            for (_, _, ty) in params {
                types.push(self.resolve_type(&b.type_ids, ty)?);
            }
            if b.pred_ids.contains_key(&name) {
                return Err(self.error_at(
                    Some(&tok),
                    ParseErrorKind::Duplicate {
                        what: "predicate",
                        name,
                    },
                ));
            }
            b.pred_ids.insert(name.clone(), b.domain.predicates.len());
            b.domain.predicates.push(Predicate {
                name,
                params: types,
            });
        }
        self.close("after the predicates")
    }

    fn action(&mut self, b: &DomainBuilder) -> Result<ActionSchema, ParseError> {
        let (name, _) = self.name("an action name")?;
        let mut action = ActionSchema {
            name,
            params: Vec::new(),
            precondition: Vec::new(),
            add: Vec::new(),
            del: Vec::new(),
        };
        if self.peek_symbol() == Some(":parameters") {
            self.pos += 1;
            self.open("before action parameters")?;
            for (name, tok, ty) in self.typed_list(true, "action parameters")? {
                let ty = self.resolve_type(&b.type_ids, ty)?;
                if action.params.iter().any(|p| p.name == name) {
                    return Err(self.error_at(
                        Some(&tok),
                        ParseErrorKind::Duplicate {
                            what: "parameter",
                            name: format!("?{name}"),
                        },
                    ));
                }
                action.params.push(TypedName { name, ty });
            }
            self.close("after action parameters")?;
        }
        if self.peek_symbol() == Some(":precondition") {
            self.pos += 1;
            let mut pre = Vec::new();
            self.condition(b, &action, &mut pre, true)?;
            action.precondition = pre;
        }
        if self.peek_symbol() == Some(":effect") {
            self.pos += 1;
            let (mut add, mut del) = (Vec::new(), Vec::new());
            self.effect(b, &action, &mut add, &mut del, true)?;
            action.add = add;
            action.del = del;
        }
        self.close(&format!(
            "to end action '{}' (after :parameters, :precondition, :effect)",
            action.name
        ))?;
        Ok(action)
    }

    /// Parses one precondition formula into conjuncts.
    fn condition(
        &mut self,
        b: &DomainBuilder,
        action: &ActionSchema,
        out: &mut Vec<Condition>,
        top: bool,
    ) -> Result<(), ParseError> {
        self.open("to start a precondition")?;
        match self.peek_symbol() {
            None if top && self.at_close() => {}
            Some("and") => {
                self.pos += 1;
                while self.at_open() {
                    self.condition(b, action, out, false)?;
                }
            }
            Some("=") => {
                self.pos += 1;
                let (x, y) = self.equality(b, action)?;
                out.push(Condition::Equal(x, y));
                return Ok(());
            }
            Some("not") => {
                self.pos += 1;
                self.open("after 'not'")?;
                if self.peek_symbol() != Some("=") {
                    return Err(self.error_here(ParseErrorKind::Unsupported(format!(
                        "negative precondition in action '{}' (only (not (= ...)) is allowed)",
                        action.name
                    ))));
                }
                self.pos += 1;
                let (x, y) = self.equality(b, action)?;
                out.push(Condition::NotEqual(x, y));
            }
            Some(s @ ("or" | "imply" | "exists" | "forall" | "when")) => {
                let what = format!("'{s}' in the precondition of action '{}'", action.name);
                return Err(self.error_here(ParseErrorKind::Unsupported(what)));
            }
            _ => {
                out.push(Condition::Atom(self.atom_schema(b, action)?));
                return Ok(());
            }
        }
        self.close("to end the precondition")
    }

    /// The two terms of `(= a b)` after the `=`, and the closing parenthesis.
    fn equality(
        &mut self,
        b: &DomainBuilder,
        action: &ActionSchema,
    ) -> Result<(Term, Term), ParseError> {
        let x = self.term(b, action, "=")?;
        let y = self.term(b, action, "=")?;
        self.close("after the two arguments of '='")?;
        Ok((x, y))
    }

    /// Parses one effect formula into add and delete lists.
    fn effect(
        &mut self,
        b: &DomainBuilder,
        action: &ActionSchema,
        add: &mut Vec<AtomSchema>,
        del: &mut Vec<AtomSchema>,
        top: bool,
    ) -> Result<(), ParseError> {
        self.open("to start an effect")?;
        match self.peek_symbol() {
            None if top && self.at_close() => {}
            Some("and") => {
                self.pos += 1;
                while self.at_open() {
                    self.effect(b, action, add, del, false)?;
                }
            }
            Some("not") => {
                self.pos += 1;
                self.open("after 'not'")?;
                del.push(self.atom_schema(b, action)?);
            }
            Some(s @ ("forall" | "when" | "increase" | "decrease" | "assign")) => {
                let what = format!("'{s}' in the effect of action '{}'", action.name);
                return Err(self.error_here(ParseErrorKind::Unsupported(what)));
            }
            _ => {
                add.push(self.atom_schema(b, action)?);
                return Ok(());
            }
        }
        self.close("to end the effect")
    }

    /// After the `(`: `pred term* )`.
    fn atom_schema(
        &mut self,
        b: &DomainBuilder,
        action: &ActionSchema,
    ) -> Result<AtomSchema, ParseError> {
        let (name, tok) = self.name("a predicate name")?;
        let pred = *b.pred_ids.get(&name).ok_or_else(|| {
            self.error_at(
                Some(&tok),
                ParseErrorKind::UndeclaredPredicate(name.clone()),
            )
        })?;
        let mut args = Vec::new();
        while !self.at_close() {
            args.push(self.term(b, action, &name)?);
        }
        self.pos += 1;
        check_arity(self, &b.domain.predicates[pred], args.len(), &tok)?;
        Ok(AtomSchema { pred, args })
    }

    fn term(
        &mut self,
        b: &DomainBuilder,
        action: &ActionSchema,
        pred: &str,
    ) -> Result<Term, ParseError> {
        let what = format!("an argument or ')' after '{pred}'");
        let Some(tok) = self.peek().cloned() else {
            return Err(self.expected(&what));
        };
        let TokenKind::Symbol(s) = &tok.kind else {
            return Err(self.expected(&what));
        };
        if s.starts_with(':') {
            return Err(self.expected(&what));
        }
        self.pos += 1;
        if let Some(var) = s.strip_prefix('?') {
            action
                .params
                .iter()
                .position(|p| p.name == var)
                .map(Term::Param)
                .ok_or_else(|| {
                    self.error_at(
                        Some(&tok),
                        ParseErrorKind::UnknownVariable {
                            variable: s.clone(),
                            action: action.name.clone(),
                        },
                    )
                })
        } else {
            b.constant_ids
                .get(s)
                .map(|&c| Term::Const(c))
                .ok_or_else(|| self.error_at(Some(&tok), ParseErrorKind::UnknownObject(s.clone())))
        }
    }

    // ---- problem ------------------------------------------------------------------------

    fn problem(&mut self, domain: &Domain) -> Result<Problem, ParseError> {
        self.open("to start the problem definition")?;
        self.keyword("define", "at the start of the problem")?;
        self.open("before 'problem'")?;
        self.keyword("problem", "after '(define ('")?;
        let (name, _) = self.name("a problem name")?;
        self.close("after the problem name")?;

        self.open("before ':domain'")?;
        self.keyword(":domain", "after the problem name")?;
        let (dname, dtok) = self.name("the domain name")?;
        if dname != domain.name {
            return Err(self.error_at(
                Some(&dtok),
                ParseErrorKind::DomainMismatch {
                    expected: domain.name.clone(),
                    found: dname,
                },
            ));
        }
        self.close("after the domain name")?;

        let mut objects = domain.constants.clone();
        let mut ids: HashMap<String, ObjId> = objects
            .iter()
            .enumerate()
            .map(|(i, o)| (o.name.clone(), i))
            .collect();
        let type_ids: HashMap<String, TypeId> = domain
            .types
            .iter()
            .enumerate()
            .map(|(i, t)| (t.name.clone(), i))
            .collect();

        self.open("before ':objects' or ':init'")?;
        if self.peek_symbol() == Some(":requirements") {
            self.pos += 1;
            self.requirements()?;
            self.open("before ':objects' or ':init'")?;
        }
        if self.peek_symbol() == Some(":objects") {
            self.pos += 1;
            for (name, tok, ty) in self.typed_list(false, "objects")? {
                let ty = self.resolve_type(&type_ids, ty)?;
                if ids.contains_key(&name) {
                    return Err(self.error_at(
                        Some(&tok),
                        ParseErrorKind::Duplicate {
                            what: "object",
                            name,
                        },
                    ));
                }
                ids.insert(name.clone(), objects.len());
                objects.push(TypedName { name, ty });
            }
            self.close("after the objects")?;
            self.open("before ':init'")?;
        }
        let ctx = ProblemCtx {
            domain,
            objects: &objects,
            ids: &ids,
        };

        self.keyword(":init", "(the initial state)")?;
        let mut init = Vec::new();
        while self.at_open() {
            self.pos += 1;
            let atom = self.ground_atom(&ctx)?;
            if !init.contains(&atom) {
                init.push(atom);
            }
        }
        self.close("after the initial state")?;

        self.open("before ':goal'")?;
        self.keyword(":goal", "after the initial state")?;
        let mut goal = Vec::new();
        self.goal(&ctx, &mut goal)?;
        self.close("after the goal")?;
        if self.at_open() {
            let next = self.tokens.get(self.pos + 1).cloned();
            if let Some(Token {
                kind: TokenKind::Symbol(s),
                ..
            }) = &next
            {
                let kind = ParseErrorKind::Unsupported(format!("problem section '{s}'"));
                return Err(self.error_at(next.as_ref(), kind));
            }
        }
        self.close("to end the problem definition")?;
        Ok(Problem {
            name,
            objects,
            init,
            goal,
        })
    }

    /// Parses a goal formula (a conjunction of atoms) into `out`.
    fn goal(&mut self, ctx: &ProblemCtx<'_>, out: &mut Vec<GroundAtom>) -> Result<(), ParseError> {
        self.open("to start a goal condition")?;
        match self.peek_symbol() {
            Some("and") => {
                self.pos += 1;
                while self.at_open() {
                    self.goal(ctx, out)?;
                }
                self.close("to end the goal conjunction")
            }
            Some(s @ ("not" | "or" | "imply" | "exists" | "forall" | "=")) => {
                let what = format!("'{s}' in the goal (only a conjunction of atoms is allowed)");
                Err(self.error_here(ParseErrorKind::Unsupported(what)))
            }
            _ => {
                let atom = self.ground_atom(ctx)?;
                if !out.contains(&atom) {
                    out.push(atom);
                }
                Ok(())
            }
        }
    }

    /// After the `(`: `pred object* )`, checking objects and their types.
    fn ground_atom(&mut self, ctx: &ProblemCtx<'_>) -> Result<GroundAtom, ParseError> {
        let (name, tok) = self.name("a predicate name")?;
        let pred = ctx
            .domain
            .predicates
            .iter()
            .position(|p| p.name == name)
            .ok_or_else(|| {
                self.error_at(
                    Some(&tok),
                    ParseErrorKind::UndeclaredPredicate(name.clone()),
                )
            })?;
        let decl = &ctx.domain.predicates[pred];
        let mut args = Vec::new();
        while !self.at_close() {
            let (obj, otok) = self.name(&format!("an object or ')' after '{name}'"))?;
            let id = *ctx.ids.get(&obj).ok_or_else(|| {
                self.error_at(Some(&otok), ParseErrorKind::UnknownObject(obj.clone()))
            })?;
            if let Some(&want) = decl.params.get(args.len()) {
                let have = ctx.objects[id].ty;
                if !ctx.domain.is_subtype(have, want) {
                    return Err(self.error_at(
                        Some(&otok),
                        ParseErrorKind::TypeMismatch {
                            object: obj,
                            actual: ctx.domain.types[have].name.clone(),
                            predicate: name,
                            index: args.len() + 1,
                            expected: ctx.domain.types[want].name.clone(),
                        },
                    ));
                }
            }
            args.push(id);
        }
        self.pos += 1;
        check_arity(self, decl, args.len(), &tok)?;
        Ok(GroundAtom { pred, args })
    }
}

fn check_arity(
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

/// Name tables built while parsing a domain.
struct DomainBuilder {
    domain: Domain,
    type_ids: HashMap<String, TypeId>,
    /// Types declared by name in `:types` (not only mentioned as a supertype).
    explicit_types: Vec<String>,
    constant_ids: HashMap<String, ObjId>,
    pred_ids: HashMap<String, usize>,
}

impl DomainBuilder {
    fn new(name: String) -> Self {
        let object = TypeDecl {
            name: "object".to_string(),
            parent: None,
        };
        DomainBuilder {
            domain: Domain {
                name,
                requirements: Vec::new(),
                types: vec![object],
                constants: Vec::new(),
                predicates: Vec::new(),
                actions: Vec::new(),
            },
            type_ids: HashMap::from([("object".to_string(), 0)]),
            explicit_types: Vec::new(),
            constant_ids: HashMap::new(),
            pred_ids: HashMap::new(),
        }
    }

    /// The id of type `name`, declaring it (as a subtype of `object`) if new.
    fn declare_type(&mut self, name: &str, explicit: bool) -> TypeId {
        if explicit {
            self.explicit_types.push(name.to_string());
        }
        if let Some(&id) = self.type_ids.get(name) {
            return id;
        }
        let id = self.domain.types.len();
        self.domain.types.push(TypeDecl {
            name: name.to_string(),
            parent: Some(0),
        });
        self.type_ids.insert(name.to_string(), id);
        id
    }
}

/// Lookup tables for parsing a problem's atoms.
struct ProblemCtx<'a> {
    domain: &'a Domain,
    objects: &'a [TypedName],
    ids: &'a HashMap<String, ObjId>,
}
