//! The compiled form: a postfix program of [`Op`]s over an evaluation stack.

/// One instruction of the postfix program.
#[derive(Debug, Clone, Copy)]
pub(super) enum Op {
    Const(f64),
    Var(usize),
    Neg,
    Bin(BinOp),
    Fn1(fn(f64) -> f64),
    Fn2(fn(f64, f64) -> f64),
    /// Pops else, then, condition; pushes `then` if condition != 0.
    Select,
}

/// A binary operator; comparisons give 1 for true and 0 for false.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum BinOp {
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
    pub(super) fn apply(self, a: f64, b: f64) -> f64 {
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

/// The deepest the evaluation stack gets while running `program`.
pub(super) fn stack_depth(program: &[Op]) -> usize {
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
