//! The domain grammar: requirements, types, constants, predicates and action schemas.

use std::collections::HashMap;

use super::error::{ParseError, ParseErrorKind};
use super::lexer::{Token, TokenKind};
use super::parser::{Parser, check_arity};
use super::{
    ActionSchema, AtomSchema, Condition, Domain, ObjId, Predicate, Term, TypeDecl, TypeId,
    TypedName,
};

impl Parser<'_> {
    /// `(define (domain NAME) SECTION*)`.
    pub(super) fn domain(&mut self) -> Result<Domain, ParseError> {
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
