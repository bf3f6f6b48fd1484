//! Typed PDDL parse errors carrying the file, line and column.

use thiserror::Error;

/// A PDDL syntax or consistency error at a place in a file.
///
/// Displays as `file:line:column: message`, e.g.
/// `domain.pddl:12:7: expected ')' after action parameters, found ':effect'`.
#[derive(Debug, Clone, PartialEq, Eq, Error)]
#[error("{file}:{line}:{column}: {kind}")]
pub struct ParseError {
    /// File name (or a label such as `domain`) the error is in.
    pub file: String,
    /// 1-based line.
    pub line: u32,
    /// 1-based column (in characters).
    pub column: u32,
    /// What went wrong (boxed to keep `Result<_, ParseError>` small).
    pub kind: Box<ParseErrorKind>,
}

/// What went wrong while reading PDDL.
#[derive(Debug, Clone, PartialEq, Eq, Error)]
pub enum ParseErrorKind {
    /// A token other than the one the grammar needs here.
    #[error("expected {expected}, found {found}")]
    Expected {
        /// What the grammar needs, e.g. `')' after action parameters`.
        expected: String,
        /// The token met instead, quoted, or `end of file`.
        found: String,
    },
    /// A `:requirements` flag beyond STRIPS with typing and equality.
    #[error("unsupported requirement '{0}' (supported: :strips, :typing, :equality)")]
    UnsupportedRequirement(String),
    /// A construct outside the supported STRIPS subset.
    #[error("unsupported: {0}")]
    Unsupported(String),
    /// A type that was never declared.
    #[error("unknown type '{0}'")]
    UnknownType(String),
    /// A type that is, through its supertypes, its own supertype.
    #[error("type '{0}' is its own supertype")]
    TypeCycle(String),
    /// A predicate used without a declaration in `:predicates`.
    #[error("undeclared predicate '{0}'")]
    UndeclaredPredicate(String),
    /// A predicate applied to the wrong number of arguments.
    #[error("predicate '{predicate}' takes {expected} argument(s), found {found}")]
    Arity {
        /// The predicate.
        predicate: String,
        /// Its declared arity.
        expected: usize,
        /// The number of arguments given.
        found: usize,
    },
    /// A `?variable` that is not a parameter of the action it appears in.
    #[error("unknown variable '{variable}' in action '{action}'")]
    UnknownVariable {
        /// The variable, with its `?`.
        variable: String,
        /// The action it appears in.
        action: String,
    },
    /// A name that is neither a constant nor a problem object.
    #[error("unknown object '{0}'")]
    UnknownObject(String),
    /// A name declared twice (`what` says which kind of name).
    #[error("duplicate {what} '{name}'")]
    Duplicate {
        /// `type`, `object`, `predicate`, `action`, `parameter`.
        what: &'static str,
        /// The repeated name.
        name: String,
    },
    /// An object whose type does not fit a predicate argument.
    #[error(
        "object '{object}' of type '{actual}' does not fit argument {index} of '{predicate}' (type '{expected}')"
    )]
    TypeMismatch {
        /// The object.
        object: String,
        /// Its declared type.
        actual: String,
        /// The predicate.
        predicate: String,
        /// 1-based argument position.
        index: usize,
        /// The argument's declared type.
        expected: String,
    },
    /// A problem written for another domain.
    #[error("problem is for domain '{found}', but the domain is '{expected}'")]
    DomainMismatch {
        /// The domain's name.
        expected: String,
        /// The name in the problem's `:domain`.
        found: String,
    },
}
