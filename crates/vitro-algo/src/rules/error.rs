//! Errors of rule programs: where (file, line, column) and what.

use serde::{Deserialize, Serialize};
use thiserror::Error;

/// A 1-based line and column (in characters).
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Default, Serialize, Deserialize,
)]
pub struct Pos {
    /// Line.
    pub line: u32,
    /// Column.
    pub column: u32,
}

/// An error in a rule program, at a place in its file.
///
/// Displays as `file:line:column: message`, e.g.
/// `guard.jz:4:17: expected 'then' after query, found '{'`.
#[derive(Debug, Clone, PartialEq, Eq, Error)]
#[error("{file}:{}:{}: {kind}", .pos.line, .pos.column)]
pub struct RuleError {
    /// The program's name (usually its file).
    pub file: String,
    /// Where.
    pub pos: Pos,
    /// What (boxed to keep results small).
    pub kind: Box<ErrorKind>,
}

impl RuleError {
    pub(crate) fn new(file: &str, pos: Pos, kind: ErrorKind) -> Self {
        RuleError {
            file: file.to_string(),
            pos,
            kind: Box::new(kind),
        }
    }
}

/// What is wrong with a rule program.
#[derive(Debug, Clone, PartialEq, Eq, Error)]
pub enum ErrorKind {
    /// A character that starts no token.
    #[error("unexpected character '{0}'")]
    Character(char),
    /// A string without its closing quote on the same line.
    #[error("unterminated string")]
    UnterminatedString,
    /// An unknown escape in a string.
    #[error("unknown escape '\\{0}' in string")]
    Escape(char),
    /// A `/*` without `*/`.
    #[error("unterminated comment")]
    UnterminatedComment,
    /// An integer beyond 64 bits.
    #[error("integer {0} out of range")]
    IntegerRange(String),
    /// A token other than the one the grammar needs here.
    #[error("expected {expected}, found {found}")]
    Expected {
        /// What the grammar needs, e.g. `'then' after query`.
        expected: String,
        /// The token met instead, e.g. `'{'` or `end of input`.
        found: String,
    },
    /// A macro defined twice.
    #[error("macro '{name}' is already defined at {}:{}", .first.line, .first.column)]
    DuplicateMacro {
        /// Its name.
        name: String,
        /// Where it was defined first.
        first: Pos,
    },
    /// A macro parameter listed twice.
    #[error("parameter '{0}' appears twice")]
    DuplicateParameter(String),
    /// A call of a macro that is not defined.
    #[error("unknown macro '{0}'")]
    UnknownMacro(String),
    /// A macro called with the wrong number of arguments.
    #[error("macro '{name}' takes {expected} argument(s), found {found}")]
    MacroArity {
        /// The macro.
        name: String,
        /// Its parameters.
        expected: usize,
        /// Arguments given.
        found: usize,
    },
    /// A macro that expands into itself.
    #[error("recursive macro: {}", .0.join(" -> "))]
    RecursiveMacro(Vec<String>),
    /// Macro expansion produced too many statements.
    #[error("macro expansion exceeds {0} statements")]
    ExpansionTooLarge(usize),
    /// A variable used in an update that no enclosing query binds.
    #[error("variable '{0}' is not bound by an enclosing query")]
    Unbound(String),
    /// A module the agent does not have.
    #[error("unknown module '{0}'")]
    UnknownModule(String),
    /// An update operation a module does not offer.
    #[error("module '{module}' has no operation '{op}'")]
    UnknownOperation {
        /// The module.
        module: String,
        /// The operation.
        op: String,
    },
}
