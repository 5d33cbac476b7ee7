//! End-to-end tests of `demkit register` (SDEM paper §5.1): a genus-0 surface carried onto a
//! deformed copy of itself through landmark-aligned spherical maps, and the refusals.

mod common;

use common::{Scratch, parse_obj};

/// Writes `a.obj` (an icosphere stretched into an ellipsoid) and `b.obj` (the same mesh bent
/// and scaled), plus six landmark files on the vertices extreme along ±x, ±y, ±z.
fn pair(s: &Scratch) -> (Vec<[f64; 3]>, Vec<[f64; 3]>) {
    s.generate(&["icosphere", "--subdivisions", "3", "--out", "ico.obj"]);
    let (ico, _) = parse_obj(&s.read("ico.obj"));
    let text = s.read("ico.obj");
    let faces: Vec<&str> = text.lines().filter(|l| l.starts_with("f ")).collect();
    let a: Vec<[f64; 3]> = ico
        .positions
        .iter()
        .map(|p| [1.4 * p[0], p[1], 0.8 * p[2]])
        .collect();
    let b: Vec<[f64; 3]> = a
        .iter()
        .map(|&[x, y, z]| [1.1 * x, y + 0.15 * x * x, z * (1.0 + 0.1 * y)])
        .collect();
    for (name, p) in [("a.obj", &a), ("b.obj", &b)] {
        let mut out = String::new();
        for q in p {
            out += &format!("v {} {} {}\n", q[0], q[1], q[2]);
        }
        out += &faces.join("\n");
        out.push('\n');
        s.write(name, out);
    }
    let mut extreme = Vec::new();
    for d in 0..3 {
        let by = |i: &usize, j: &usize| a[*i][d].total_cmp(&a[*j][d]);
        extreme.push((0..a.len()).min_by(by).unwrap());
        extreme.push((0..a.len()).max_by(by).unwrap());
    }
    let lines: Vec<String> = extreme.iter().map(|v| v.to_string()).collect();
    s.write("la.txt", lines.join("\n") + "\n");
    s.write("lb.txt", lines.join("\n") + "\n");
    (a, b)
}

fn dist(p: [f64; 3], q: [f64; 3]) -> f64 {
    (0..3).map(|d| (p[d] - q[d]).powi(2)).sum::<f64>().sqrt()
}

#[test]
fn register_carries_a_onto_its_deformed_copy() {
    let s = Scratch::new("register");
    let (a, b) = pair(&s);
    s.ok(&[
        "register",
        "a.obj",
        "b.obj",
        "--landmarks-a",
        "la.txt",
        "--landmarks-b",
        "lb.txt",
        "--out",
        "out.obj",
        "--report",
        "r.json",
        "--quiet",
    ]);
    let (out, _) = parse_obj(&s.read("out.obj"));
    assert_eq!(out.positions.len(), a.len());
    assert_eq!(
        s.read("out.obj")
            .lines()
            .filter(|l| l.starts_with("f "))
            .count(),
        1280
    );
    // Vertex i of A lands near vertex i of B (the copy has the same vertex order).
    let mean = out
        .positions
        .iter()
        .zip(&b)
        .map(|(p, q)| dist(*p, *q))
        .sum::<f64>()
        / b.len() as f64;
    // B's bounding-box diagonal is about 3.3.
    assert!(mean < 0.02 * 3.3, "mean error {mean}");
    let report: serde_json::Value = serde_json::from_str(&s.read("r.json")).unwrap();
    assert_eq!(report["method"], "register");
    assert_eq!(report["landmarks"], 6);
    assert_eq!(report["map_a"]["flipped_triangles"], 0);
    assert_eq!(report["map_b"]["flipped_triangles"], 0);
    assert!(report["landmark_error_relative"].as_f64().unwrap() < 0.01);
}

#[test]
fn register_refuses_bad_landmarks_and_surfaces() {
    let s = Scratch::new("register_bad");
    pair(&s);
    let run = |la: &str, lb: &str, a: &str| {
        s.run(&[
            "register",
            a,
            "b.obj",
            "--landmarks-a",
            la,
            "--landmarks-b",
            lb,
            "--out",
            "out.obj",
            "--quiet",
        ])
        .input_error()
    };
    s.write("five.txt", "0\n1\n2\n3\n4\n");
    assert!(run("five.txt", "lb.txt", "a.obj").contains("must correspond"));
    s.write("far.txt", "0\n1\n2\n3\n4\n100000\n");
    assert!(run("far.txt", "lb.txt", "a.obj").contains("100000"));
    s.write("two.txt", "0\n1\n");
    assert!(run("two.txt", "two.txt", "a.obj").contains("at least 3"));
    assert!(run("missing.txt", "lb.txt", "a.obj").contains("missing.txt"));
    s.generate(&["polygon", "--out", "disk.obj"]);
    s.write("three.txt", "0\n1\n2\n");
    let e = run("three.txt", "three.txt", "disk.obj");
    assert!(
        e.contains("surface A") && e.contains("boundary loop"),
        "{e}"
    );
    s.generate(&["torus", "--out", "torus.obj"]);
    let e = s
        .run(&[
            "register",
            "a.obj",
            "torus.obj",
            "--landmarks-a",
            "three.txt",
            "--landmarks-b",
            "three.txt",
            "--out",
            "out.obj",
            "--quiet",
        ])
        .input_error();
    assert!(e.contains("surface B") && e.contains("genus 1"), "{e}");
}
