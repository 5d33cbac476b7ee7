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

/// One instruction of the postfix program.
#[derive(Debug, Clone, Copy)]
enum Op {
    Const(f64),
    Var(usize),
    Neg,
    Bin(BinOp),
    Fn1(fn(f64) -> f64),
    Fn2(fn(f64, f64) -> f64),
    /// Pops else, then, condition; pushes `then` if condition != 0.
    Select,
}

#[derive(Debug, Clone, Copy, PartialEq)]
enum BinOp {
    Add,
    Sub,
    Mul,
    Div,
    Pow,
    Lt,
    Gt,
    Le,
    Ge,
    Eq,
    Ne,
}

impl BinOp {
    #[inline]
    fn apply(self, a: f64, b: f64) -> f64 {
        let t = |c: bool| if c { 1.0 } else { 0.0 };
        match self {
            BinOp::Add => a + b,
            BinOp::Sub => a - b,
            BinOp::Mul => a * b,
            BinOp::Div => a / b,
            BinOp::Pow => a.powf(b),
            BinOp::Lt => t(a < b),
            BinOp::Gt => t(a > b),
            BinOp::Le => t(a <= b),
            BinOp::Ge => t(a >= b),
            BinOp::Eq => t(a == b),
            BinOp::Ne => t(a != b),
        }
    }
}

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
        let tokens = lex(source)?;
        let mut parser = Parser {
            tokens: &tokens,
            pos: 0,
            variables,
            program: Vec::new(),
            end_column: source.chars().count() + 1,
        };
        parser.comparison()?;
        if let Some(tok) = parser.peek() {
            return Err(ExprError {
                kind: ExprErrorKind::Syntax(format!("unexpected {}", tok.kind.describe())),
                column: tok.column,
            });
        }
        let program = parser.program;
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

/// The deepest the evaluation stack gets while running `program`.
fn stack_depth(program: &[Op]) -> usize {
    let (mut depth, mut max) = (0usize, 0usize);
    for op in program {
        match op {
            Op::Const(_) | Op::Var(_) => depth += 1,
            Op::Neg | Op::Fn1(_) => {}
            Op::Bin(_) | Op::Fn2(_) => depth -= 1,
            Op::Select => depth -= 2,
        }
        max = max.max(depth);
    }
    max
}

// ---------------------------------------------------------------------------------------------
// Lexer

#[derive(Debug, Clone, PartialEq)]
enum TokKind {
    Num(f64),
    Ident(String),
    /// Operators and punctuation: `+ - * / ^ ( ) ,` and the comparisons; `**` becomes `^`.
    Sym(&'static str),
}

impl TokKind {
    fn describe(&self) -> String {
        match self {
            TokKind::Num(v) => format!("number {v}"),
            TokKind::Ident(s) => format!("name '{s}'"),
            TokKind::Sym(s) => format!("'{s}'"),
        }
    }
}

#[derive(Debug, Clone)]
struct Token {
    kind: TokKind,
    column: usize,
}

fn lex(source: &str) -> Result<Vec<Token>, ExprError> {
    let chars: Vec<char> = source.chars().collect();
    let mut tokens = Vec::new();
    let mut i = 0;
    while i < chars.len() {
        let c = chars[i];
        let column = i + 1;
        if c.is_whitespace() {
            i += 1;
            continue;
        }
        if c.is_ascii_digit() || (c == '.' && chars.get(i + 1).is_some_and(|d| d.is_ascii_digit()))
        {
            let start = i;
            while i < chars.len() && chars[i].is_ascii_digit() {
                i += 1;
            }
            if i < chars.len() && chars[i] == '.' {
                i += 1;
                while i < chars.len() && chars[i].is_ascii_digit() {
                    i += 1;
                }
            }
            // An exponent only if digits follow (`2e` is the number 2 then the name `e`).
            if i < chars.len() && (chars[i] == 'e' || chars[i] == 'E') {
                let mut j = i + 1;
                if j < chars.len() && (chars[j] == '+' || chars[j] == '-') {
                    j += 1;
                }
                if j < chars.len() && chars[j].is_ascii_digit() {
                    while j < chars.len() && chars[j].is_ascii_digit() {
                        j += 1;
                    }
                    i = j;
                }
            }
            let text: String = chars[start..i].iter().collect();
            let value = text.parse::<f64>().map_err(|_| ExprError {
                kind: ExprErrorKind::Syntax(format!("bad number '{text}'")),
                column,
            })?;
            tokens.push(Token {
                kind: TokKind::Num(value),
                column,
            });
            continue;
        }
        if c.is_alphabetic() || c == '_' {
            let start = i;
            while i < chars.len() && (chars[i].is_alphanumeric() || chars[i] == '_') {
                i += 1;
            }
            tokens.push(Token {
                kind: TokKind::Ident(chars[start..i].iter().collect()),
                column,
            });
            continue;
        }
        let next = chars.get(i + 1).copied();
        let (sym, len): (&'static str, usize) = match (c, next) {
            ('<', Some('=')) => ("<=", 2),
            ('>', Some('=')) => (">=", 2),
            ('=', Some('=')) => ("==", 2),
            ('!', Some('=')) => ("!=", 2),
            ('*', Some('*')) => ("^", 2),
            ('<', _) => ("<", 1),
            ('>', _) => (">", 1),
            ('+', _) => ("+", 1),
            ('-', _) => ("-", 1),
            ('*', _) => ("*", 1),
            ('/', _) => ("/", 1),
            ('^', _) => ("^", 1),
            ('(', _) => ("(", 1),
            (')', _) => (")", 1),
            (',', _) => (",", 1),
            ('=', _) => {
                return Err(ExprError {
                    kind: ExprErrorKind::Syntax("'=' is not an operator (use '==')".into()),
                    column,
                });
            }
            _ => {
                return Err(ExprError {
                    kind: ExprErrorKind::Syntax(format!("unexpected character '{c}'")),
                    column,
                });
            }
        };
        tokens.push(Token {
            kind: TokKind::Sym(sym),
            column,
        });
        i += len;
    }
    Ok(tokens)
}

// ---------------------------------------------------------------------------------------------
// Parser: recursive descent, emitting postfix code with constant folding.

struct Parser<'a> {
    tokens: &'a [Token],
    pos: usize,
    variables: &'a [&'a str],
    program: Vec<Op>,
    end_column: usize,
}

/// Nesting deeper than this is refused, so that hostile input cannot overflow the parser's stack.
const MAX_NESTING: usize = 200;

impl Parser<'_> {
    fn peek(&self) -> Option<&Token> {
        self.tokens.get(self.pos)
    }

    fn peek_sym(&self) -> Option<&'static str> {
        match self.peek() {
            Some(Token {
                kind: TokKind::Sym(s),
                ..
            }) => Some(s),
            _ => None,
        }
    }

    fn column(&self) -> usize {
        self.peek().map_or(self.end_column, |t| t.column)
    }

    fn syntax<T>(&self, expected: &str) -> Result<T, ExprError> {
        let found = match self.peek() {
            Some(t) => t.kind.describe(),
            None => "the end of the expression".to_string(),
        };
        Err(ExprError {
            kind: ExprErrorKind::Syntax(format!("expected {expected}, found {found}")),
            column: self.column(),
        })
    }

    fn expect(&mut self, sym: &'static str) -> Result<(), ExprError> {
        if self.peek_sym() == Some(sym) {
            self.pos += 1;
            Ok(())
        } else {
            self.syntax(&format!("'{sym}'"))
        }
    }

    /// Appends `op`, folding it into a constant when all its operands are constants.
    fn emit(&mut self, op: Op) {
        let arity = match op {
            Op::Const(_) | Op::Var(_) => 0,
            Op::Neg | Op::Fn1(_) => 1,
            Op::Bin(_) | Op::Fn2(_) => 2,
            Op::Select => 3,
        };
        let n = self.program.len();
        if arity > 0
            && n >= arity
            && self.program[n - arity..]
                .iter()
                .all(|o| matches!(o, Op::Const(_)))
        {
            let mut stack = [0.0; 3];
            for (slot, o) in stack.iter_mut().zip(&self.program[n - arity..]) {
                if let Op::Const(c) = o {
                    *slot = *c;
                }
            }
            let value = match op {
                Op::Neg => -stack[0],
                Op::Fn1(f) => f(stack[0]),
                Op::Bin(b) => b.apply(stack[0], stack[1]),
                Op::Fn2(f) => f(stack[0], stack[1]),
                Op::Select => {
                    if stack[0] != 0.0 {
                        stack[1]
                    } else {
                        stack[2]
                    }
                }
                Op::Const(_) | Op::Var(_) => unreachable!(),
            };
            self.program.truncate(n - arity);
            self.program.push(Op::Const(value));
        } else {
            self.program.push(op);
        }
    }

    fn enter(&self, depth: usize) -> Result<(), ExprError> {
        if depth > MAX_NESTING {
            Err(ExprError {
                kind: ExprErrorKind::Syntax("expression nested too deeply".into()),
                column: self.column(),
            })
        } else {
            Ok(())
        }
    }

    /// comparison := additive (cmp additive)?
    fn comparison(&mut self) -> Result<(), ExprError> {
        self.comparison_at(0)
    }

    fn comparison_at(&mut self, depth: usize) -> Result<(), ExprError> {
        self.enter(depth)?;
        self.additive(depth)?;
        if let Some(op) = self.peek_sym().and_then(comparison_op) {
            self.pos += 1;
            self.additive(depth)?;
            self.emit(Op::Bin(op));
            if self.peek_sym().and_then(comparison_op).is_some() {
                return Err(ExprError {
                    kind: ExprErrorKind::Syntax(
                        "comparisons cannot be chained; use parentheses".into(),
                    ),
                    column: self.column(),
                });
            }
        }
        Ok(())
    }

    /// additive := term (('+' | '-') term)*
    fn additive(&mut self, depth: usize) -> Result<(), ExprError> {
        self.term(depth)?;
        while let Some(sym @ ("+" | "-")) = self.peek_sym() {
            self.pos += 1;
            self.term(depth)?;
            self.emit(Op::Bin(if sym == "+" { BinOp::Add } else { BinOp::Sub }));
        }
        Ok(())
    }

    /// term := unary (('*' | '/') unary)*
    fn term(&mut self, depth: usize) -> Result<(), ExprError> {
        self.unary(depth)?;
        while let Some(sym @ ("*" | "/")) = self.peek_sym() {
            self.pos += 1;
            self.unary(depth)?;
            self.emit(Op::Bin(if sym == "*" { BinOp::Mul } else { BinOp::Div }));
        }
        Ok(())
    }

    /// unary := ('-' | '+') unary | power
    fn unary(&mut self, depth: usize) -> Result<(), ExprError> {
        self.enter(depth)?;
        match self.peek_sym() {
            Some("-") => {
                self.pos += 1;
                self.unary(depth + 1)?;
                self.emit(Op::Neg);
                Ok(())
            }
            Some("+") => {
                self.pos += 1;
                self.unary(depth + 1)
            }
            _ => self.power(depth),
        }
    }

    /// power := primary ('^' unary)?   (right-associative through `unary`)
    fn power(&mut self, depth: usize) -> Result<(), ExprError> {
        self.primary(depth)?;
        if self.peek_sym() == Some("^") {
            self.pos += 1;
            self.unary(depth + 1)?;
            self.emit(Op::Bin(BinOp::Pow));
        }
        Ok(())
    }

    /// primary := number | name | name '(' args ')' | '(' comparison ')'
    fn primary(&mut self, depth: usize) -> Result<(), ExprError> {
        let Some(tok) = self.peek().cloned() else {
            return self.syntax("a number, a name or '('");
        };
        match tok.kind {
            TokKind::Num(v) => {
                self.pos += 1;
                self.emit(Op::Const(v));
                Ok(())
            }
            TokKind::Sym("(") => {
                self.pos += 1;
                self.comparison_at(depth + 1)?;
                self.expect(")")
            }
            TokKind::Ident(name) => {
                self.pos += 1;
                if self.peek_sym() == Some("(") {
                    self.pos += 1;
                    self.call(&name, tok.column, depth)
                } else {
                    self.name(&name, tok.column)
                }
            }
            TokKind::Sym(_) => self.syntax("a number, a name or '('"),
        }
    }

    fn name(&mut self, name: &str, column: usize) -> Result<(), ExprError> {
        if let Some(i) = self.variables.iter().position(|v| *v == name) {
            self.emit(Op::Var(i));
            return Ok(());
        }
        let value = match name {
            "pi" => std::f64::consts::PI,
            "e" => std::f64::consts::E,
            "tau" => std::f64::consts::TAU,
            _ => {
                return Err(ExprError {
                    kind: ExprErrorKind::UnknownVariable(name.to_string()),
                    column,
                });
            }
        };
        self.emit(Op::Const(value));
        Ok(())
    }

    /// Parses the arguments after `name(` and the closing `)`, then emits the call.
    fn call(&mut self, name: &str, column: usize, depth: usize) -> Result<(), ExprError> {
        let Some(kind) = function(name) else {
            return Err(ExprError {
                kind: ExprErrorKind::UnknownFunction(name.to_string()),
                column,
            });
        };
        let mut n_args = 0;
        if self.peek_sym() != Some(")") {
            loop {
                self.comparison_at(depth + 1)?;
                n_args += 1;
                // min/max fold pairwise as the arguments arrive: min(a,b,c) = min(min(a,b),c).
                if let Func::Variadic(f) = kind
                    && n_args >= 2
                {
                    self.emit(Op::Fn2(f));
                }
                match self.peek_sym() {
                    Some(",") => self.pos += 1,
                    Some(")") => break,
                    _ => return self.syntax("',' or ')'"),
                }
            }
        }
        self.expect(")")?;
        let arity_error = |expected| {
            Err(ExprError {
                kind: ExprErrorKind::Arity {
                    name: name.to_string(),
                    expected,
                    got: n_args,
                },
                column,
            })
        };
        match kind {
            Func::Unary(f) if n_args == 1 => self.emit(Op::Fn1(f)),
            Func::Unary(_) => return arity_error("1"),
            Func::Binary(f) if n_args == 2 => self.emit(Op::Fn2(f)),
            Func::Binary(_) => return arity_error("2"),
            Func::Variadic(_) if n_args >= 2 => {}
            Func::Variadic(_) => return arity_error("at least 2"),
            Func::Select if n_args == 3 => self.emit(Op::Select),
            Func::Select => return arity_error("3"),
        }
        Ok(())
    }
}

fn comparison_op(sym: &str) -> Option<BinOp> {
    Some(match sym {
        "<" => BinOp::Lt,
        ">" => BinOp::Gt,
        "<=" => BinOp::Le,
        ">=" => BinOp::Ge,
        "==" => BinOp::Eq,
        "!=" => BinOp::Ne,
        _ => return None,
    })
}

#[derive(Clone, Copy)]
enum Func {
    Unary(fn(f64) -> f64),
    Binary(fn(f64, f64) -> f64),
    Variadic(fn(f64, f64) -> f64),
    Select,
}

fn function(name: &str) -> Option<Func> {
    use Func::*;
    Some(match name {
        "abs" => Unary(f64::abs),
        "sqrt" => Unary(f64::sqrt),
        "cbrt" => Unary(f64::cbrt),
        "exp" => Unary(f64::exp),
        "ln" | "log" => Unary(f64::ln),
        "log10" => Unary(f64::log10),
        "log2" => Unary(f64::log2),
        "sin" => Unary(f64::sin),
        "cos" => Unary(f64::cos),
        "tan" => Unary(f64::tan),
        "asin" => Unary(f64::asin),
        "acos" => Unary(f64::acos),
        "atan" => Unary(f64::atan),
        "sinh" => Unary(f64::sinh),
        "cosh" => Unary(f64::cosh),
        "tanh" => Unary(f64::tanh),
        "floor" => Unary(f64::floor),
        "ceil" => Unary(f64::ceil),
        "round" => Unary(f64::round),
        "sign" => Unary(|v| if v == 0.0 { 0.0 } else { v.signum() }),
        "atan2" => Binary(f64::atan2),
        "pow" => Binary(f64::powf),
        "hypot" => Binary(f64::hypot),
        "min" => Variadic(f64::min),
        "max" => Variadic(f64::max),
        "if" => Select,
        _ => return None,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::{E, PI};

    const VARS: [&str; 4] = ["x", "y", "z", "area"];

    fn ev(src: &str, x: f64, y: f64) -> f64 {
        Expr::compile(src, &VARS)
            .unwrap_or_else(|e| panic!("{src}: {e}"))
            .eval(&[x, y, 0.0, 0.5])
    }

    fn err(src: &str) -> ExprError {
        Expr::compile(src, &VARS).expect_err(src)
    }

    fn close(a: f64, b: f64) {
        assert!((a - b).abs() <= 1e-12 * b.abs().max(1.0), "{a} != {b}");
    }

    #[test]
    fn design_examples() {
        close(ev("2.2-abs(x)-abs(y)", -0.5, 1.25), 2.2 - 0.5 - 1.25);
        assert_eq!(ev("area*(1+3*(x>0))", 0.1, 0.0), 2.0);
        assert_eq!(ev("area*(1+3*(x>0))", 0.0, 0.0), 0.5);
        assert_eq!(ev("area*(1+3*(x>0))", -3.0, 0.0), 0.5);
        close(
            ev("5+((x-49.5)+(y-49.5))/50", 99.0, 99.0),
            5.0 + 99.0 / 50.0,
        );
        close(ev("5+((x-49.5)+(y-49.5))/50", 0.0, 24.5), 5.0 - 74.5 / 50.0);
        assert_eq!(ev("1+exp(-((x-49.5)^2+(y-49.5)^2)/1000)", 49.5, 49.5), 2.0);
        close(
            ev("1+exp(-((x-49.5)^2+(y-49.5)^2)/1000)", 59.5, 29.5),
            1.0 + (-0.5f64).exp(),
        );
        close(ev("2.5+sin(pi*(x-49.5)/25)", 62.0, 0.0), 3.5);
        close(ev("2.5+sin(pi*(x-49.5)/25)", 37.0, 0.0), 1.5);
        close(
            ev("1.5+sin(pi*(x-49.5)/25)*sin(pi*(y-49.5)/25)", 62.0, 37.0),
            0.5,
        );
        close(
            ev("1.5+sin(pi*(x-49.5)/25)*sin(pi*(y-49.5)/25)", 62.0, 62.0),
            2.5,
        );
        close(ev("atan2(y,x)", -1.0, 1.0), 0.75 * PI);
        close(ev("atan2(y,x)", 0.0, -2.0), -0.5 * PI);
        assert_eq!(ev("sqrt(x^2+y^2)", 3.0, 4.0), 5.0);
    }

    #[test]
    fn comparisons_give_one_or_zero() {
        let cases = [
            ("x<y", [1.0, 0.0, 0.0]),
            ("x>y", [0.0, 0.0, 1.0]),
            ("x<=y", [1.0, 1.0, 0.0]),
            ("x>=y", [0.0, 1.0, 1.0]),
            ("x==y", [0.0, 1.0, 0.0]),
            ("x!=y", [1.0, 0.0, 1.0]),
        ];
        for (src, want) in cases {
            for (x, w) in [1.0, 2.0, 3.0].into_iter().zip(want) {
                assert_eq!(ev(src, x, 2.0), w, "{src} with x={x}");
            }
        }
        // Comparisons bind looser than arithmetic.
        assert_eq!(ev("x+1>y*2", 3.0, 1.9), 1.0);
        assert_eq!(ev("x+1>y*2", 3.0, 2.0), 0.0);
    }

    #[test]
    fn precedence_and_associativity() {
        assert_eq!(ev("2^3^2", 0.0, 0.0), 512.0);
        assert_eq!(ev("2**3**2", 0.0, 0.0), 512.0);
        assert_eq!(ev("-2^2", 0.0, 0.0), -4.0);
        assert_eq!(ev("(-2)^2", 0.0, 0.0), 4.0);
        assert_eq!(ev("2^-1", 0.0, 0.0), 0.5);
        assert_eq!(ev("-x", 3.0, 0.0), -3.0);
        assert_eq!(ev("--x", 3.0, 0.0), 3.0);
        assert_eq!(ev("+x", 3.0, 0.0), 3.0);
        assert_eq!(ev("x-y-1", 10.0, 3.0), 6.0);
        assert_eq!(ev("x/y/2", 12.0, 3.0), 2.0);
        assert_eq!(ev("1+2*3", 0.0, 0.0), 7.0);
        assert_eq!(ev("2*x^2", 3.0, 0.0), 18.0);
        assert_eq!(ev("-x^2", 3.0, 0.0), -9.0);
        assert_eq!(ev("1 - -1", 0.0, 0.0), 2.0);
        assert_eq!(ev("2*-x", 3.0, 0.0), -6.0);
    }

    #[test]
    fn constants_functions_and_numbers() {
        assert_eq!(ev("pi", 0.0, 0.0), PI);
        assert_eq!(ev("e", 0.0, 0.0), E);
        assert_eq!(ev("min(x,y)", 1.0, 2.0), 1.0);
        assert_eq!(ev("max(x,y)", 1.0, 2.0), 2.0);
        assert_eq!(ev("min(3,x,y,0.5)", 1.0, 2.0), 0.5);
        assert_eq!(ev("max(x, y, 7)", 1.0, 2.0), 7.0);
        assert_eq!(ev("log(e)", 0.0, 0.0), 1.0);
        close(ev("log(x)", 10.0, 0.0), 10f64.ln());
        assert_eq!(ev("log10(1000)", 0.0, 0.0), 3.0);
        assert_eq!(ev("log2(8)", 0.0, 0.0), 3.0);
        assert_eq!(ev("cos(0)+abs(-2)", 0.0, 0.0), 3.0);
        assert_eq!(ev("if(x>0, 2, 3)", 1.0, 0.0), 2.0);
        assert_eq!(ev("if(x>0, 2, 3)", -1.0, 0.0), 3.0);
        assert_eq!(ev("hypot(x,y)", 3.0, 4.0), 5.0);
        assert_eq!(ev("sign(x)", -7.0, 0.0), -1.0);
        assert_eq!(ev("1e-3*1E3 + .5 + 2.", 0.0, 0.0), 3.5);
        assert_eq!(ev("z+area", 0.0, 0.0), 0.5);
        assert!(ev("sqrt(-1)", 0.0, 0.0).is_nan());
        assert_eq!(ev("1/x", 0.0, 0.0), f64::INFINITY);
    }

    #[test]
    fn constant_folding_and_depth() {
        let e = Expr::compile("2*pi*(1+1)", &VARS).unwrap();
        assert_eq!(e.as_constant(), Some(4.0 * PI));
        let e = Expr::compile("x*(1+2)", &VARS).unwrap();
        assert_eq!(e.program.len(), 3);
        assert_eq!(e.as_constant(), None);
        // A right-leaning chain needs a deep stack: exercise the heap fallback.
        let src = format!("{}1{}", "x+(".repeat(40), ")".repeat(40));
        let e = Expr::compile(&src, &VARS).unwrap();
        assert!(e.max_depth > INLINE_STACK);
        assert_eq!(e.eval(&[1.0, 0.0, 0.0, 0.0]), 41.0);
    }

    #[test]
    fn errors_name_the_problem_and_column() {
        let e = err("q+1");
        assert_eq!(e.kind, ExprErrorKind::UnknownVariable("q".into()));
        assert_eq!(e.column, 1);
        let e = err("x + foo(2)");
        assert_eq!(e.kind, ExprErrorKind::UnknownFunction("foo".into()));
        assert_eq!(e.column, 5);
        let e = err("atan2(y)");
        assert_eq!(
            e.to_string(),
            "function 'atan2' takes 2 arguments, got 1 at column 1"
        );
        assert!(matches!(
            err("min(x)").kind,
            ExprErrorKind::Arity { got: 1, .. }
        ));
        assert!(matches!(
            err("sin()").kind,
            ExprErrorKind::Arity { got: 0, .. }
        ));
        let e = err("(x+1");
        assert_eq!(e.column, 5);
        assert!(e.to_string().contains("expected ')'"), "{e}");
        let e = err("x+*2");
        assert_eq!(e.column, 3);
        assert_eq!(err("").column, 1);
        assert_eq!(err("x y").column, 3);
        assert_eq!(err("2e").column, 2); // the number 2, then an unexpected name
        assert_eq!(err("x = 1").column, 3);
        assert_eq!(err("x # 1").column, 3);
        assert!(err("x<y<1").to_string().contains("chained"));
        assert!(
            err(&"(".repeat(1000))
                .to_string()
                .contains("nested too deeply")
        );
        assert!(
            err(&"-".repeat(1000))
                .to_string()
                .contains("nested too deeply")
        );
    }
}
