//! The parser: recursive descent over the tokens, emitting postfix code with constant folding.

use super::lexer::{TokKind, Token, lex};
use super::program::{BinOp, Op};
use super::{ExprError, ExprErrorKind};

/// Parses `source` into a postfix program; a name in `variables` becomes [`Op::Var`] of its index.
pub(super) fn parse(source: &str, variables: &[&str]) -> Result<Vec<Op>, ExprError> {
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
    Ok(parser.program)
}

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
        self.left_assoc(depth, &[("+", BinOp::Add), ("-", BinOp::Sub)], Self::term)
    }

    /// term := unary (('*' | '/') unary)*
    fn term(&mut self, depth: usize) -> Result<(), ExprError> {
        self.left_assoc(depth, &[("*", BinOp::Mul), ("/", BinOp::Div)], Self::unary)
    }

    /// A left-associative chain `operand (op operand)*` over the operators `ops`.
    fn left_assoc(
        &mut self,
        depth: usize,
        ops: &[(&str, BinOp)],
        operand: fn(&mut Self, usize) -> Result<(), ExprError>,
    ) -> Result<(), ExprError> {
        operand(self, depth)?;
        while let Some(&(_, op)) = self
            .peek_sym()
            .and_then(|s| ops.iter().find(|(sym, _)| *sym == s))
        {
            self.pos += 1;
            operand(self, depth)?;
            self.emit(Op::Bin(op));
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
