//! Compilation errors: what is wrong and in which column.

use std::fmt;

/// Why an expression could not be compiled.
#[derive(Debug, Clone, PartialEq)]
pub enum ExprErrorKind {
    /// The text is not a well-formed expression; the string says what was expected or found.
    Syntax(String),
    /// A name that is neither a variable nor a constant.
    UnknownVariable(String),
    /// A call to a function this language does not have.
    UnknownFunction(String),
    /// A known function called with the wrong number of arguments.
    Arity {
        /// The function's name.
        name: String,
        /// What it accepts, in words ("1", "2", "at least 2").
        expected: &'static str,
        /// How many arguments it was given.
        got: usize,
    },
}

impl fmt::Display for ExprErrorKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ExprErrorKind::Syntax(msg) => write!(f, "syntax error: {msg}"),
            ExprErrorKind::UnknownVariable(name) => write!(f, "unknown variable '{name}'"),
            ExprErrorKind::UnknownFunction(name) => write!(f, "unknown function '{name}'"),
            ExprErrorKind::Arity {
                name,
                expected,
                got,
            } => {
                let s = if *expected == "1" { "" } else { "s" };
                write!(
                    f,
                    "function '{name}' takes {expected} argument{s}, got {got}"
                )
            }
        }
    }
}

/// A compilation error: what is wrong and where (1-based character column in the source).
#[derive(Debug, Clone, PartialEq)]
pub struct ExprError {
    /// What is wrong.
    pub kind: ExprErrorKind,
    /// 1-based column (in characters) of the offending token; one past the end for "unexpected
    /// end of expression".
    pub column: usize,
}

impl fmt::Display for ExprError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{} at column {}", self.kind, self.column)
    }
}

impl std::error::Error for ExprError {}
