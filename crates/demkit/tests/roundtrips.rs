//! Round-trip properties: what is written and read back, or printed and compiled, must come
//! back unchanged — exactly where the format can hold it, to the format's precision where not.
//!
//! - Mesh files. The library writes OBJ (shortest decimal text that reads back to the same
//!   `f64`) and binary little-endian PLY (`double` coordinates); the test writers of
//!   `support::formats` produce the other inputs (ascii and big-endian PLY with `double` or
//!   `float` coordinates, OFF, ascii and binary STL). A random mesh with awkward coordinates
//!   (zeros of both signs, subnormals, the extremes, values with 17 significant digits) is
//!   written and read back:
//!   - OBJ, OFF, ascii STL and `double` PLY of every encoding give the same faces and the same
//!     positions bit for bit (`-0.0` stays `-0.0`);
//!   - binary STL and binary `float` PLY store `f32`: the positions read back are the written
//!     coordinates rounded to `f32`, exactly;
//!   - ascii `float` PLY stores the `f32`'s shortest decimal text, which the reader parses as
//!     an `f64` (it does not round it to `f32`): rounded to `f32`, the value read is exactly
//!     the `f32` written;
//!   - STL keeps no shared vertices: the reader welds equal corners, so the faces come back
//!     with the same corner positions, the vertices numbered in the order faces first use them
//!     and unused vertices gone (the meshes are drawn with positions distinct as stored).
//! - Expressions. A random expression tree over `x`, `y`, `z`, `area`, numbers and constants,
//!   with every operator and function of [`demkit::expr`], is printed as text (with only the
//!   parentheses precedence needs, or more, and `^` or `**`), compiled, and evaluated at random
//!   points. The compiled program applies the same `f64` operations in the same order as the
//!   tree (constant folding included), so the value must equal the tree's value evaluated
//!   directly in Rust bit for bit, NaN matching any NaN.
//!
//! The case counts keep the file to a few seconds in release mode;
//! `DEMKIT_PROPTEST_SCALE=20` runs twenty times as many.

mod support;

use demkit::TriMesh;
use demkit::expr::Expr;
use demkit::io::obj::{self, TextureCoordinates};
use demkit::io::{off, ply, read_mesh, stl, write_mesh};
use proptest::prelude::*;
use std::collections::HashSet;
use support::formats::{self, Format, PlyStyle};

/// A configuration running `n` cases, times `DEMKIT_PROPTEST_SCALE` when it is set.
fn cases(n: u32) -> ProptestConfig {
    let scale = std::env::var("DEMKIT_PROPTEST_SCALE")
        .ok()
        .and_then(|s| s.parse::<f64>().ok())
        .filter(|s| *s > 0.0)
        .unwrap_or(1.0);
    ProptestConfig::with_cases(((n as f64 * scale).ceil() as u32).max(1))
}

// ---------------------------------------------------------------------------------------------
// Mesh files

/// Finite `f64` values that are hard to print and read: both zeros, subnormals, the extremes,
/// the edges of the OBJ writer's switch to exponent notation, values with many digits, and
/// arbitrary finite bit patterns.
fn awkward_f64() -> BoxedStrategy<f64> {
    use prop::num::f64 as f;
    prop_oneof![
        3 => f::POSITIVE | f::NEGATIVE | f::NORMAL | f::SUBNORMAL | f::ZERO,
        2 => prop::sample::select(vec![
            0.0,
            -0.0,
            5e-324,
            -5e-324,
            f64::MIN_POSITIVE,
            -f64::MIN_POSITIVE,
            f64::MAX,
            f64::MIN,
            f64::EPSILON,
            1e-5,
            9.999999999999999e-6,
            1e16,
            9999999999999998.0,
            0.1,
            1.0 / 3.0,
            -2.0 / 3.0,
            123456789.12345679,
            -0.30000000000000004,
            4.35e-310,
        ]),
        2 => -1e3..1e3f64,
        1 => (-300i32..300, -1.0..1.0f64).prop_map(|(e, m)| m * 10f64.powi(e)),
    ]
    .boxed()
}

/// Finite `f64` values whose `f32` rounding is finite: exact `f32` values of every kind, `f64`
/// values between them, values that round to a subnormal or to zero, and the largest `f32`.
fn awkward_f32_range() -> BoxedStrategy<f64> {
    use prop::num::f32 as f;
    prop_oneof![
        3 => (f::POSITIVE | f::NEGATIVE | f::NORMAL | f::SUBNORMAL | f::ZERO).prop_map(f64::from),
        2 => prop::sample::select(vec![
            0.0,
            -0.0,
            1e-46,
            -1e-50,
            1.4e-45,
            f32::MIN_POSITIVE as f64,
            f32::MAX as f64,
            f32::MIN as f64,
            0.1,
            1.0 / 3.0,
            16777217.0,
            -0.30000000000000004,
        ]),
        2 => -1e3..1e3f64,
        1 => (-40i32..38, -1.0..1.0f64).prop_map(|(e, m)| m * 10f64.powi(e)),
    ]
    .prop_filter("f32 rounding is finite", |x| (*x as f32).is_finite())
    .boxed()
}

/// A mesh over `coordinate`: 3 to 24 vertices whose positions are distinct under `key`, and 1
/// to 32 faces of three distinct vertices each (some vertices may be unused).
fn mesh_over(
    coordinate: fn() -> BoxedStrategy<f64>,
    key: fn(&[f64; 3]) -> [u64; 3],
) -> impl Strategy<Value = TriMesh> {
    prop::collection::vec([coordinate(), coordinate(), coordinate()], 3..24)
        .prop_map(move |positions| {
            let mut seen = HashSet::new();
            positions
                .into_iter()
                .filter(|p| seen.insert(key(p)))
                .collect::<Vec<_>>()
        })
        .prop_filter("three distinct positions", |p| p.len() >= 3)
        .prop_flat_map(|positions| {
            let n = positions.len() as u32;
            let face = prop::sample::subsequence((0..n).collect::<Vec<_>>(), 3)
                .prop_shuffle()
                .prop_map(|v| [v[0], v[1], v[2]]);
            (Just(positions), prop::collection::vec(face, 1..32))
        })
        .prop_map(|(positions, faces)| TriMesh::new(positions, faces))
}

/// Positions compared as stored: the bits, zeros of both signs apart.
fn f64_bits(p: &[f64; 3]) -> [u64; 3] {
    p.map(f64::to_bits)
}

/// Positions as a welding reader compares them in `f64`: `0.0` and `-0.0` alike.
fn f64_weld_key(p: &[f64; 3]) -> [u64; 3] {
    p.map(|x| (x + 0.0).to_bits())
}

/// Positions as a welding reader compares them after rounding to `f32`.
fn f32_weld_key(p: &[f64; 3]) -> [u64; 3] {
    p.map(|x| f64::from(x as f32 + 0.0).to_bits())
}

/// Any mesh with awkward `f64` coordinates.
fn f64_mesh() -> impl Strategy<Value = TriMesh> {
    mesh_over(awkward_f64, f64_bits)
}

/// The bits of every coordinate, for exact comparisons that tell `-0.0` from `0.0`.
fn bits(m: &TriMesh) -> Vec<[u64; 3]> {
    m.positions.iter().map(f64_bits).collect()
}

/// `mesh` with every coordinate rounded to `f32` and widened back.
fn rounded_to_f32(mesh: &TriMesh) -> TriMesh {
    let positions = mesh
        .positions
        .iter()
        .map(|p| p.map(|x| f64::from(x as f32)))
        .collect();
    TriMesh::new(positions, mesh.faces.clone())
}

/// What reading an STL file of `mesh` must give when its used positions are distinct: the same
/// faces with the same corner positions, the vertices renumbered in the order the faces first
/// use them, unused vertices dropped.
fn as_stl_reads_it(mesh: &TriMesh) -> TriMesh {
    let mut index = vec![u32::MAX; mesh.n_vertices()];
    let mut positions = Vec::new();
    let faces = mesh
        .faces
        .iter()
        .map(|f| {
            f.map(|v| {
                if index[v as usize] == u32::MAX {
                    index[v as usize] = positions.len() as u32;
                    positions.push(mesh.positions[v as usize]);
                }
                index[v as usize]
            })
        })
        .collect();
    TriMesh::new(positions, faces)
}

/// Asserts that `back` equals `expected` face for face and bit for bit.
fn assert_same(back: &TriMesh, expected: &TriMesh) -> Result<(), TestCaseError> {
    prop_assert_eq!(&back.faces, &expected.faces);
    prop_assert_eq!(bits(back), bits(expected), "{:?}", back.positions);
    Ok(())
}

/// The PLY styles with `double` coordinates.
fn double_ply_style() -> impl Strategy<Value = PlyStyle> {
    (0u8..4, any::<bool>()).prop_map(|(index_type, extras)| PlyStyle {
        double: true,
        index_type,
        extras,
    })
}

/// Random texture coordinates for `mesh`: up to one point per face corner.
fn texture_for(mesh: &TriMesh) -> impl Strategy<Value = TextureCoordinates> + use<> {
    let corners = mesh.faces.len();
    prop::collection::vec([awkward_f64(), awkward_f64()], 1..8).prop_flat_map(move |points| {
        let n = points.len() as u32;
        let corner = [0..n, 0..n, 0..n];
        (Just(points), prop::collection::vec(corner, corners))
            .prop_map(|(points, corners)| TextureCoordinates { points, corners })
    })
}

proptest! {
    #![proptest_config(cases(1000))]

    /// The library's OBJ writer and reader: the same mesh, bit for bit.
    #[test]
    fn obj_round_trips_exactly(mesh in f64_mesh()) {
        let mut text = Vec::new();
        obj::write_obj(&mut text, &mesh).unwrap();
        assert_same(&obj::parse_obj(&text, "m.obj").unwrap(), &mesh)?;
    }

    /// Texture coordinates in the OBJ (`vt` lines, `f a/ta ...`) change nothing the reader
    /// returns.
    #[test]
    fn textured_obj_round_trips_exactly(
        (mesh, texture) in f64_mesh().prop_flat_map(|m| {
            let t = texture_for(&m);
            (Just(m), t)
        })
    ) {
        let mut text = Vec::new();
        obj::write_obj_textured(&mut text, &mesh, Some(&texture)).unwrap();
        assert_same(&obj::parse_obj(&text, "m.obj").unwrap(), &mesh)?;
    }

    /// The library's PLY writer (binary little-endian, `double`) and reader: bit for bit.
    #[test]
    fn library_ply_round_trips_exactly(mesh in f64_mesh()) {
        let mut data = Vec::new();
        ply::write_ply(&mut data, &mesh).unwrap();
        assert_same(&ply::parse_ply(&data, "m.ply").unwrap(), &mesh)?;
    }

    /// PLY with `double` coordinates in every encoding, index type and with extra properties
    /// and elements: bit for bit.
    #[test]
    fn double_ply_round_trips_exactly(
        mesh in f64_mesh(),
        encoding in prop::sample::select(vec![None, Some(false), Some(true)]),
        style in double_ply_style(),
    ) {
        let data = formats::ply(&mesh, encoding, style);
        assert_same(&ply::parse_ply(&data, "m.ply").unwrap(), &mesh)?;
    }

    /// Binary PLY with `float` coordinates: the coordinates come back rounded to `f32`,
    /// exactly.
    #[test]
    fn binary_float_ply_round_trips_to_f32(
        mesh in mesh_over(awkward_f32_range, f64_bits),
        big_endian in any::<bool>(),
        index_type in 0u8..4,
    ) {
        let style = PlyStyle { double: false, index_type, extras: false };
        let data = formats::ply(&mesh, Some(big_endian), style);
        assert_same(&ply::parse_ply(&data, "m.ply").unwrap(), &rounded_to_f32(&mesh))?;
    }

    /// Ascii PLY with `float` coordinates: each value read, rounded to `f32`, is exactly the
    /// `f32` written (the reader keeps the decimal text's `f64` value).
    #[test]
    fn ascii_float_ply_round_trips_to_f32(mesh in mesh_over(awkward_f32_range, f64_bits)) {
        let style = PlyStyle { double: false, index_type: 0, extras: false };
        let data = formats::ply(&mesh, None, style);
        let back = ply::parse_ply(&data, "m.ply").unwrap();
        prop_assert_eq!(&back.faces, &mesh.faces);
        let as_f32 = |m: &TriMesh| -> Vec<[u32; 3]> {
            m.positions.iter().map(|p| p.map(|x| (x as f32).to_bits())).collect()
        };
        prop_assert_eq!(as_f32(&back), as_f32(&mesh));
    }

    /// OFF: bit for bit.
    #[test]
    fn off_round_trips_exactly(mesh in f64_mesh()) {
        let data = formats::write(&mesh, Format::Off);
        assert_same(&off::parse_off(&data, "m.off").unwrap(), &mesh)?;
    }

    /// Ascii STL: the same faces with the same corner positions bit for bit, vertices welded
    /// and numbered in order of first use.
    #[test]
    fn ascii_stl_round_trips_exactly(mesh in mesh_over(awkward_f64, f64_weld_key)) {
        let data = formats::write(&mesh, Format::StlAscii);
        assert_same(&stl::parse_stl(&data, "m.stl").unwrap(), &as_stl_reads_it(&mesh))?;
    }

    /// Binary STL: as ascii STL, with the coordinates rounded to `f32`.
    #[test]
    fn binary_stl_round_trips_to_f32(mesh in mesh_over(awkward_f32_range, f32_weld_key)) {
        let data = formats::write(&mesh, Format::StlBinary);
        let expected = as_stl_reads_it(&rounded_to_f32(&mesh));
        assert_same(&stl::parse_stl(&data, "m.stl").unwrap(), &expected)?;
    }
}

proptest! {
    #![proptest_config(cases(100))]

    /// Through files: `write_mesh` then `read_mesh` (the format chosen by the extension, in
    /// either case) give back the mesh bit for bit.
    #[test]
    fn files_round_trip_exactly(
        mesh in f64_mesh(),
        name in prop::sample::select(vec!["m.obj", "m.ply", "M.OBJ", "M.PLY"]),
    ) {
        let dir = std::env::temp_dir().join(format!("demkit-roundtrips-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join(name);
        write_mesh(&path, &mesh).unwrap();
        let back = read_mesh(&path).unwrap();
        std::fs::remove_file(&path).unwrap();
        assert_same(&back, &mesh)?;
    }
}

// ---------------------------------------------------------------------------------------------
// Expressions

/// The variables the expressions are compiled with, in the order of the values.
const VARIABLES: [&str; 4] = ["x", "y", "z", "area"];

/// Binary operators, comparisons included.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Op {
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

/// An expression tree.
#[derive(Debug, Clone)]
enum Node {
    /// A literal; never negative (a minus sign is a [`Node::Neg`]).
    Num(f64),
    /// The variable of that index in [`VARIABLES`].
    Var(usize),
    /// `pi`, `e` or `tau`.
    Constant(&'static str),
    Neg(Box<Node>),
    /// Unary plus.
    Plus(Box<Node>),
    Binary(Op, Box<Node>, Box<Node>),
    /// A one-argument function by name.
    Call1(&'static str, Box<Node>),
    /// `atan2`, `pow` or `hypot`.
    Call2(&'static str, Box<Node>, Box<Node>),
    /// `min` (false) or `max` (true) of two or more arguments.
    Extremum(bool, Vec<Node>),
    /// `if(c, a, b)`.
    If(Box<Node>, Box<Node>, Box<Node>),
}

const FUNCTIONS_1: [&str; 21] = [
    "abs", "sqrt", "cbrt", "exp", "ln", "log", "log10", "log2", "sin", "cos", "tan", "asin",
    "acos", "atan", "sinh", "cosh", "tanh", "floor", "ceil", "round", "sign",
];

const OPERATORS: [Op; 11] = [
    Op::Add,
    Op::Sub,
    Op::Mul,
    Op::Div,
    Op::Pow,
    Op::Lt,
    Op::Gt,
    Op::Le,
    Op::Ge,
    Op::Eq,
    Op::Ne,
];

/// Non-negative literals: small and simple, awkward (subnormal, huge, many digits) and any
/// non-negative finite value.
fn literal() -> impl Strategy<Value = f64> {
    use prop::num::f64 as f;
    prop_oneof![
        2 => prop::sample::select(vec![0.0, 0.5, 1.0, 2.0, 3.0, 10.0]),
        1 => prop::sample::select(vec![5e-324, 1e-300, 1e300, f64::MAX, 0.1, 1.0 / 3.0, 1e-7]),
        2 => 0.0..10.0f64,
        1 => f::POSITIVE | f::NORMAL | f::SUBNORMAL | f::ZERO,
    ]
}

/// Expression trees up to a few levels deep using every operator and function.
fn node() -> impl Strategy<Value = Node> {
    let leaf = prop_oneof![
        2 => literal().prop_map(Node::Num),
        3 => (0..VARIABLES.len()).prop_map(Node::Var),
        1 => prop::sample::select(vec!["pi", "e", "tau"]).prop_map(Node::Constant),
    ];
    leaf.prop_recursive(5, 40, 3, |inner| {
        let boxed = inner.clone().prop_map(Box::new);
        prop_oneof![
            4 => (prop::sample::select(OPERATORS.to_vec()), boxed.clone(), boxed.clone())
                .prop_map(|(op, a, b)| Node::Binary(op, a, b)),
            1 => boxed.clone().prop_map(Node::Neg),
            1 => boxed.clone().prop_map(Node::Plus),
            2 => (prop::sample::select(FUNCTIONS_1.to_vec()), boxed.clone())
                .prop_map(|(f, a)| Node::Call1(f, a)),
            1 => (
                prop::sample::select(vec!["atan2", "pow", "hypot"]),
                boxed.clone(),
                boxed.clone()
            )
                .prop_map(|(f, a, b)| Node::Call2(f, a, b)),
            1 => (any::<bool>(), prop::collection::vec(inner, 2..4))
                .prop_map(|(max, args)| Node::Extremum(max, args)),
            1 => (boxed.clone(), boxed.clone(), boxed)
                .prop_map(|(c, a, b)| Node::If(c, a, b)),
        ]
    })
}

impl Node {
    /// The tree's value at `v` (x, y, z, area), computed directly.
    fn eval(&self, v: &[f64; 4]) -> f64 {
        let truth = |b: bool| if b { 1.0 } else { 0.0 };
        match self {
            Node::Num(c) => *c,
            Node::Var(i) => v[*i],
            Node::Constant(name) => match *name {
                "pi" => std::f64::consts::PI,
                "e" => std::f64::consts::E,
                _ => std::f64::consts::TAU,
            },
            Node::Neg(a) => -a.eval(v),
            Node::Plus(a) => a.eval(v),
            Node::Binary(op, a, b) => {
                let (a, b) = (a.eval(v), b.eval(v));
                match op {
                    Op::Add => a + b,
                    Op::Sub => a - b,
                    Op::Mul => a * b,
                    Op::Div => a / b,
                    Op::Pow => a.powf(b),
                    Op::Lt => truth(a < b),
                    Op::Gt => truth(a > b),
                    Op::Le => truth(a <= b),
                    Op::Ge => truth(a >= b),
                    Op::Eq => truth(a == b),
                    Op::Ne => truth(a != b),
                }
            }
            Node::Call1(f, a) => {
                let a = a.eval(v);
                match *f {
                    "abs" => a.abs(),
                    "sqrt" => a.sqrt(),
                    "cbrt" => a.cbrt(),
                    "exp" => a.exp(),
                    "ln" | "log" => a.ln(),
                    "log10" => a.log10(),
                    "log2" => a.log2(),
                    "sin" => a.sin(),
                    "cos" => a.cos(),
                    "tan" => a.tan(),
                    "asin" => a.asin(),
                    "acos" => a.acos(),
                    "atan" => a.atan(),
                    "sinh" => a.sinh(),
                    "cosh" => a.cosh(),
                    "tanh" => a.tanh(),
                    "floor" => a.floor(),
                    "ceil" => a.ceil(),
                    "round" => a.round(),
                    "sign" if a == 0.0 => 0.0,
                    "sign" => a.signum(),
                    other => unreachable!("{other}"),
                }
            }
            Node::Call2(f, a, b) => {
                let (a, b) = (a.eval(v), b.eval(v));
                match *f {
                    "atan2" => a.atan2(b),
                    "pow" => a.powf(b),
                    _ => a.hypot(b),
                }
            }
            Node::Extremum(max, args) => {
                let mut values = args.iter().map(|a| a.eval(v));
                let first = values.next().expect("two or more arguments");
                values.fold(first, |m, x| if *max { m.max(x) } else { m.min(x) })
            }
            Node::If(c, a, b) => {
                let (c, a, b) = (c.eval(v), a.eval(v), b.eval(v));
                if c != 0.0 { a } else { b }
            }
        }
    }

    /// The binding level of the node's own syntax: 0 comparison, 1 sum, 2 product, 3 sign,
    /// 4 power, 5 an operand that never needs parentheses.
    fn level(&self) -> u8 {
        match self {
            Node::Binary(op, ..) => match op {
                Op::Add | Op::Sub => 1,
                Op::Mul | Op::Div => 2,
                Op::Pow => 4,
                _ => 0,
            },
            Node::Neg(_) | Node::Plus(_) => 3,
            _ => 5,
        }
    }

    /// Appends the node as source text where the grammar asks for level `need` or tighter:
    /// parentheses when the node binds looser, and also where `style` says so at random.
    fn print(&self, out: &mut String, need: u8, style: &mut Style) {
        let paren = self.level() < need || style.extra_parentheses();
        if paren {
            out.push('(');
        }
        let sp = if style.spaced { " " } else { "" };
        match self {
            Node::Num(c) => out.push_str(&style.number(*c)),
            Node::Var(i) => out.push_str(VARIABLES[*i]),
            Node::Constant(name) => out.push_str(name),
            Node::Neg(a) | Node::Plus(a) => {
                out.push(if matches!(self, Node::Neg(_)) {
                    '-'
                } else {
                    '+'
                });
                a.print(out, 3, style);
            }
            Node::Binary(op, a, b) => {
                let (symbol, left, right) = match op {
                    Op::Add => ("+", 1, 2),
                    Op::Sub => ("-", 1, 2),
                    Op::Mul => ("*", 2, 3),
                    Op::Div => ("/", 2, 3),
                    Op::Pow if style.flip() => ("**", 5, 3),
                    Op::Pow => ("^", 5, 3),
                    Op::Lt => ("<", 1, 1),
                    Op::Gt => (">", 1, 1),
                    Op::Le => ("<=", 1, 1),
                    Op::Ge => (">=", 1, 1),
                    Op::Eq => ("==", 1, 1),
                    Op::Ne => ("!=", 1, 1),
                };
                a.print(out, left, style);
                out.push_str(&format!("{sp}{symbol}{sp}"));
                b.print(out, right, style);
            }
            Node::Call1(f, a) => Node::call(out, f, &[a], style),
            Node::Call2(f, a, b) => Node::call(out, f, &[a, b], style),
            Node::Extremum(max, args) => {
                let args: Vec<&Node> = args.iter().collect();
                Node::call(out, if *max { "max" } else { "min" }, &args, style)
            }
            Node::If(c, a, b) => Node::call(out, "if", &[c, a, b], style),
        }
        if paren {
            out.push(')');
        }
    }

    /// Appends `name(arg, ...)`.
    fn call(out: &mut String, name: &str, args: &[&Node], style: &mut Style) {
        out.push_str(name);
        out.push('(');
        for (k, a) in args.iter().enumerate() {
            if k > 0 {
                out.push(',');
                if style.spaced {
                    out.push(' ');
                }
            }
            a.print(out, 0, style);
        }
        out.push(')');
    }
}

/// How a tree is printed: spaces around operators or not, and a stream of coin flips for
/// redundant parentheses, `**` for `^` and exponent notation for numbers.
struct Style {
    spaced: bool,
    redundant: bool,
    state: u64,
}

impl Style {
    /// A coin flip from a xorshift stream.
    fn flip(&mut self) -> bool {
        self.state ^= self.state << 13;
        self.state ^= self.state >> 7;
        self.state ^= self.state << 17;
        self.state & 1 == 1
    }

    /// Whether to wrap a node that does not need parentheses.
    fn extra_parentheses(&mut self) -> bool {
        self.redundant && self.flip() && self.flip()
    }

    /// A literal as shortest round-trip text, positional (`0.001`) or with an exponent
    /// (`1e-3`).
    fn number(&mut self, c: f64) -> String {
        if self.flip() {
            format!("{c:e}")
        } else {
            format!("{c}")
        }
    }
}

/// Values of the variables: ordinary, awkward and any finite value.
fn point() -> impl Strategy<Value = [f64; 4]> {
    let value = || {
        prop_oneof![
            3 => -10.0..10.0f64,
            1 => prop::sample::select(vec![0.0, -0.0, 1.0, -1.0, 0.5, 1e-300, -1e300, 5e-324]),
            1 => awkward_f64(),
        ]
    };
    [value(), value(), value(), value()]
}

/// Equal bit for bit, or both NaN.
fn same(a: f64, b: f64) -> bool {
    a.to_bits() == b.to_bits() || (a.is_nan() && b.is_nan())
}

proptest! {
    #![proptest_config(cases(6000))]

    /// A printed tree compiles, and its compiled value equals the tree's own value at every
    /// point, bit for bit.
    #[test]
    fn expressions_evaluate_as_their_trees(
        tree in node(),
        spaced in any::<bool>(),
        redundant in any::<bool>(),
        seed in 1u64..,
        points in prop::collection::vec(point(), 1..8),
    ) {
        let mut style = Style { spaced, redundant, state: seed };
        let mut text = String::new();
        tree.print(&mut text, 0, &mut style);
        let compiled = Expr::compile(&text, &VARIABLES);
        prop_assert!(compiled.is_ok(), "{text}: {:?}", compiled.err());
        let compiled = compiled.unwrap();
        for v in &points {
            let (got, want) = (compiled.eval(v), tree.eval(v));
            prop_assert!(same(got, want), "{text} at {v:?}: compiled {got:e}, tree {want:e}");
        }
    }
}
