//! The problem grammar: objects, initial state and goal, checked against the domain.

use std::collections::HashMap;

use super::error::{ParseError, ParseErrorKind};
use super::lexer::{Token, TokenKind};
use super::parser::{Parser, check_arity};
use super::{Domain, GroundAtom, ObjId, Problem, TypeId, TypedName};

impl Parser<'_> {
    /// `(define (problem NAME) (:domain NAME) [(:requirements ...)] [(:objects ...)]
    /// (:init ATOM*) (:goal GOAL))`.
    pub(super) fn problem(&mut self, domain: &Domain) -> Result<Problem, ParseError> {
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

/// Lookup tables for parsing a problem's atoms.
struct ProblemCtx<'a> {
    domain: &'a Domain,
    objects: &'a [TypedName],
    ids: &'a HashMap<String, ObjId>,
}
