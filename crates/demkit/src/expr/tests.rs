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
