//! A small `f64` expression language: compiled once, evaluated many times without allocation.
//!
//! Used for populations given as expressions (`--population "2.2-abs(x)-abs(y)"`), evaluated
//! once per face with the face's centroid and area as variables.
//!
//! # Why not a crate
//!
//! DESIGN.md names `fasteval` and `exmex`. Both were tried (fasteval 0.2.4, exmex 0.21.0) on the
//! syntax the project documents, and neither covers it:
//! - `fasteval` has no `exp`, `sqrt` or `atan2`, spells the constants `pi()` and `e()`, reads
//!   `log(x)` as the base-10 logarithm, and parses `-2^2` as `(-2)^2 = 4`;
//! - `exmex` has no comparison operators at all (`x>0` is a parse error), treats `pi` as an
//!   unknown variable (its constant is `PI`), and evaluates `2^3^2` as `(2^3)^2 = 64` and
//!   `-2^2` as `4`.
//!
//! So this module is a small recursive-descent parser emitting a postfix program with constant
//! folding; evaluation walks the program with a fixed stack on the machine stack.
//!
//! # Syntax
//!
//! From the loosest to the tightest binding:
//!
//! | syntax | meaning |
//! | --- | --- |
//! | `a < b`, `a > b`, `a <= b`, `a >= b`, `a == b`, `a != b` | 1 if true, 0 if false; not chainable (`a<b<c` is an error) |
//! | `a + b`, `a - b` | left-associative |
//! | `a * b`, `a / b` | left-associative |
//! | `-a`, `+a` | unary sign: `-2^2 = -4` |
//! | `a ^ b` (also `a ** b`) | power, right-associative: `2^3^2 = 512`; the exponent may carry a sign: `2^-1 = 0.5` |
//! | `f(a, ...)`, `(a)`, numbers, names | calls, grouping, literals (`1`, `2.5`, `.5`, `1e-3`), variables and constants |
//!
//! Constants: `pi`, `e`, `tau` (variables of the same name take precedence).
//!
//! Functions: `abs`, `sqrt`, `cbrt`, `exp`, `ln` and `log` (both the natural logarithm),
//! `log10`, `log2`, `sin`, `cos`, `tan`, `asin`, `acos`, `atan`, `sinh`, `cosh`, `tanh`,
//! `floor`, `ceil`, `round`, `sign` (−1, 0 or 1), `atan2(y, x)`, `pow(a, b)`, `hypot(a, b)`,
//! `min(a, b, ...)` and `max(a, b, ...)` (two or more arguments), and `if(c, a, b)` (`a` where
//! `c != 0`, otherwise `b`; both branches are evaluated).
//!
//! Arithmetic is IEEE: `1/0` is `inf`, `sqrt(-1)` is NaN; callers decide what to refuse.

mod error;
mod lexer;
mod parser;
mod program;
#[cfg(test)]
mod tests;

pub use error::{ExprError, ExprErrorKind};

use program::{Op, stack_depth};

/// Evaluation stacks up to this depth live on the machine stack; deeper ones (absurdly nested
/// expressions) fall back to one heap allocation per evaluation.
const INLINE_STACK: usize = 32;

/// A compiled expression over a fixed, ordered list of variables.
///
/// ```
/// use demkit::expr::Expr;
/// let e = Expr::compile("area*(1+3*(x>0))", &["x", "area"]).unwrap();
/// assert_eq!(e.eval(&[2.0, 0.5]), 2.0);
/// assert_eq!(e.eval(&[-2.0, 0.5]), 0.5);
/// ```
#[derive(Debug, Clone)]
pub struct Expr {
    program: Vec<Op>,
    max_depth: usize,
    n_vars: usize,
}

impl Expr {
    /// Compiles `source`; a name in `variables` refers to the value at the same index of the
    /// slice later given to [`Expr::eval`].
    pub fn compile(source: &str, variables: &[&str]) -> Result<Expr, ExprError> {
        let program = parser::parse(source, variables)?;
        let max_depth = stack_depth(&program);
        Ok(Expr {
            program,
            max_depth,
            n_vars: variables.len(),
        })
    }

    /// Evaluates the expression with `values[i]` for the i-th compile-time variable.
    ///
    /// Does not allocate (unless the expression nests more than 32 levels deep).
    ///
    /// # Panics
    /// If `values` is shorter than the variable list given to [`Expr::compile`].
    pub fn eval(&self, values: &[f64]) -> f64 {
        assert!(
            values.len() >= self.n_vars,
            "Expr::eval: {} values for {} variables",
            values.len(),
            self.n_vars
        );
        if self.max_depth <= INLINE_STACK {
            self.run(values, &mut [0.0; INLINE_STACK])
        } else {
            self.run(values, &mut vec![0.0; self.max_depth])
        }
    }

    /// The value of the expression if it does not depend on any variable.
    pub fn as_constant(&self) -> Option<f64> {
        match self.program.as_slice() {
            [Op::Const(c)] => Some(*c),
            _ => None,
        }
    }

    fn run(&self, values: &[f64], stack: &mut [f64]) -> f64 {
        let mut sp = 0;
        for op in &self.program {
            match *op {
                Op::Const(c) => {
                    stack[sp] = c;
                    sp += 1;
                }
                Op::Var(i) => {
                    stack[sp] = values[i];
                    sp += 1;
                }
                Op::Neg => stack[sp - 1] = -stack[sp - 1],
                Op::Fn1(f) => stack[sp - 1] = f(stack[sp - 1]),
                Op::Bin(b) => {
                    sp -= 1;
                    stack[sp - 1] = b.apply(stack[sp - 1], stack[sp]);
                }
                Op::Fn2(f) => {
                    sp -= 1;
                    stack[sp - 1] = f(stack[sp - 1], stack[sp]);
                }
                Op::Select => {
                    sp -= 2;
                    let (c, a, b) = (stack[sp - 1], stack[sp], stack[sp + 1]);
                    stack[sp - 1] = if c != 0.0 { a } else { b };
                }
            }
        }
        debug_assert_eq!(sp, 1);
        stack[0]
    }
}
