//! Any finite valid mesh is mapped, whatever its size: coordinates of 1e300 or 1e-200 (whose
//! areas overflow or vanish) are scaled by a power of two inside, and results in input units
//! (a torus map, a remesh) are scaled back.

mod common;

use common::{Scratch, assert_density_improved, json_file, parse_obj};

/// Writes `name` as the mesh `source` with every coordinate multiplied by `factor`.
fn scaled_copy(s: &Scratch, source: &str, name: &str, factor: f64) {
    let mut out = String::new();
    for line in s.read(source).lines() {
        match line.strip_prefix("v ") {
            Some(rest) => {
                let p: Vec<f64> = rest
                    .split_whitespace()
                    .map(|x| x.parse::<f64>().unwrap() * factor)
                    .collect();
                out.push_str(&format!("v {:e} {:e} {:e}\n", p[0], p[1], p[2]));
            }
            None => {
                out.push_str(line);
                out.push('\n');
            }
        }
    }
    s.write(name, out);
}

/// Maps `mesh` with `extra` arguments; checks exit 0, no flip, a density equalized.
fn maps_cleanly(s: &Scratch, mesh: &str, extra: &[&str]) -> serde_json::Value {
    let mut args = vec![
        "map", mesh, "--out", "o.obj", "--report", "r.json", "--quiet",
    ];
    args.extend_from_slice(extra);
    s.ok(&args);
    let r = json_file(&s.path("r.json"));
    let m = &r["metrics"];
    assert_eq!(m["flipped_triangles"].as_u64(), Some(0), "{mesh}: {r:#}");
    let (before, after) = (
        m["face_density_var_initial"].as_f64().unwrap(),
        m["face_density_var_final"].as_f64().unwrap(),
    );
    assert!(after < 0.5 * before, "{mesh}: {before} -> {after}");
    assert_density_improved(&r, None);
    assert!(m["mean_abs_mu"].as_f64().is_some(), "{mesh}: {r:#}");
    r
}

#[test]
fn huge_and_tiny_meshes_of_every_topology_are_mapped() {
    let s = Scratch::new("scale");
    s.generate(&["grid", "--nx", "12", "--ny", "8", "--out", "grid.obj"]);
    s.generate(&["icosphere", "--out", "sphere.obj"]);
    s.generate(&["disk-holes", "--hole", "0.3:0:0.2", "--out", "holes.obj"]);
    for factor in [1e300, 1e-200] {
        // DEQ runs at α = 0.3 here: at its default α = 2 the population-weighted initial map
        // already does most of the equalizing on this mild step (Var 0.033 -> 0.022), and what
        // is checked is the scale, so the run must move the density well away from the start.
        for (mesh, population, extra) in [
            ("grid.obj", "1+(x>y)", &[][..]),
            ("sphere.obj", "area*(1+(z>0))", &[][..]),
            ("holes.obj", "area*(1+(x>0))", &["--alpha", "0.3"][..]),
        ] {
            let name = format!("{factor:e}-{mesh}");
            scaled_copy(&s, mesh, &name, factor);
            // The expression's x, y, z are in input units (its comparisons hold at any scale).
            let mut args = vec!["--population", population];
            args.extend_from_slice(extra);
            maps_cleanly(&s, &name, &args);
        }
    }
}

#[test]
fn a_torus_of_radii_1e300_is_mapped_onto_its_torus_in_input_units() {
    let s = Scratch::new("scale-torus");
    s.generate(&[
        "torus", "--R", "3", "--r", "1", "--major", "32", "--minor", "16", "--out", "t.obj",
    ]);
    for (factor, torus) in [(1e300, "3e300:1e300"), (1e-200, "3e-200:1e-200")] {
        scaled_copy(&s, "t.obj", "big.obj", factor);
        maps_cleanly(
            &s,
            "big.obj",
            &[
                "--method",
                "tdem",
                "--torus",
                torus,
                "--population",
                "area*(1+(z>0))",
            ],
        );
        let (out, _) = parse_obj(&s.read("o.obj"));
        for p in &out.positions {
            // On the torus of radii 3·factor and 1·factor about the z axis.
            let ring = p[0].hypot(p[1]) / factor - 3.0;
            let d = ring.hypot(p[2] / factor);
            assert!((d - 1.0).abs() < 1e-9, "{factor:e}: {d}");
        }
    }
}

#[test]
fn a_tiny_surface_is_remeshed_in_its_own_units() {
    let s = Scratch::new("scale-remesh");
    s.generate(&[
        "grid", "--nx", "10", "--ny", "10", "--width", "1", "--height", "1", "--out", "g.obj",
    ]);
    scaled_copy(&s, "g.obj", "tiny.obj", 1e-200);
    s.ok(&[
        "remesh",
        "tiny.obj",
        "--vertices",
        "200",
        "--out",
        "r.obj",
        "--quiet",
    ]);
    let (out, _) = parse_obj(&s.read("r.obj"));
    let largest = out
        .positions
        .iter()
        .flatten()
        .fold(0.0f64, |m, x| m.max(x.abs()));
    assert!(largest > 0.5e-200 && largest < 2e-200, "{largest:e}");
}

#[test]
fn a_shape_too_thin_to_map_onto_is_refused() {
    let s = Scratch::new("scale-shape");
    s.generate(&["polygon", "--out", "d.obj"]);
    let e = s
        .run(&[
            "map",
            "d.obj",
            "--method",
            "dem-shape",
            "--shape",
            "ellipse:1e300:1",
            "--out",
            "o.obj",
        ])
        .input_error_naming(&["ellipse:1e300:1", "too thin"]);
    assert!(e.contains("1000"), "{e}");
}
