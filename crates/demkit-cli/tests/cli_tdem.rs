//! End-to-end tests of `demkit map --method tdem` (TDEM paper, Alg. 1) on tori the binary
//! generates itself: the map, its report, and the refusals of wrong input.

mod common;

use common::{Scratch, assert_density_improved, json_file, parse_obj};

/// `demkit generate torus` with radii 3 and 1 into `t.obj`.
fn torus(s: &Scratch) {
    s.generate(&[
        "torus", "--R", "3", "--r", "1", "--major", "48", "--minor", "16", "--out", "t.obj",
    ]);
}

#[test]
fn smooth_population_is_equalized_on_the_torus() {
    // The paper's Fig. 5 population 2 − cos u, u the angle around the axis.
    let s = Scratch::new("tdem_fig5");
    torus(&s);
    s.ok(&[
        "map",
        "t.obj",
        "--out",
        "o.obj",
        "--torus",
        "3:1",
        "--population",
        "area*(2-cos(atan2(y,x)))",
        "--report",
        "r.json",
        "--quiet",
    ]);
    let r = json_file(&s.path("r.json"));
    assert_eq!(r["method"], "tdem");
    assert_eq!(r["converged"], true);
    assert_eq!(r["input"]["genus"], 1);
    assert_density_improved(&r, None);
    let m = &r["metrics"];
    assert_eq!(m["flipped_triangles"], 0);
    assert!(m["density_var_initial"].as_f64().unwrap() > 0.05);
    assert!(m["density_var_final"].as_f64().unwrap() < 1e-4);
    // Same faces, every vertex on the torus.
    let (input, in_faces) = parse_obj(&s.read("t.obj"));
    let (output, out_faces) = parse_obj(&s.read("o.obj"));
    assert_eq!(in_faces, out_faces);
    assert_eq!(input.positions.len(), output.positions.len());
    for p in &output.positions {
        let d = ((p[0].hypot(p[1]) - 3.0).hypot(p[2]) - 1.0).abs();
        assert!(d < 1e-9, "{p:?} is {d} off the torus");
    }
}

#[test]
fn auto_picks_tdem_for_a_torus_and_needs_the_target() {
    let s = Scratch::new("tdem_auto");
    torus(&s);
    s.run(&["map", "t.obj", "--out", "o.obj"])
        .input_error_naming(&["--torus"]);
    s.ok(&[
        "map", "t.obj", "--out", "o.obj", "--torus", "3:1", "--quiet",
    ]);
}

#[test]
fn impossible_radii_are_refused() {
    let s = Scratch::new("tdem_radii");
    torus(&s);
    for bad in ["1:2", "2:2", "3", "a:b", "3:-1", "3:1:1"] {
        s.run(&["map", "t.obj", "--out", "o.obj", "--torus", bad])
            .input_error_naming(&["--torus"]);
    }
}

#[test]
fn a_sphere_or_a_disk_is_not_a_torus() {
    let s = Scratch::new("tdem_topology");
    s.generate(&["icosphere", "--out", "s.obj"]);
    s.generate(&["peaks", "--n", "8", "--out", "p.obj"]);
    for mesh in ["s.obj", "p.obj"] {
        s.run(&[
            "map", mesh, "--out", "o.obj", "--method", "tdem", "--torus", "3:1",
        ])
        .input_error_naming(&["tdem", "genus one"]);
    }
}

#[test]
fn a_surface_off_the_target_torus_is_parameterized_onto_it() {
    // Alg. 2: the generated (3, 1) torus mapped area-preservingly onto the (2, 1) torus through
    // demkit's own cut and periodic harmonic map.
    let s = Scratch::new("tdem_param");
    torus(&s);
    s.ok(&[
        "map", "t.obj", "--out", "o.obj", "--torus", "2:1", "--report", "r.json", "--quiet",
    ]);
    let r = json_file(&s.path("r.json"));
    assert_eq!(r["converged"], true);
    assert_density_improved(&r, None);
    let m = &r["metrics"];
    assert_eq!(m["flipped_triangles"], 0);
    assert!(m["density_error_mean"].as_f64().unwrap() < 0.05);
    let (output, _) = parse_obj(&s.read("o.obj"));
    for p in &output.positions {
        let d = ((p[0].hypot(p[1]) - 2.0).hypot(p[2]) - 1.0).abs();
        assert!(d < 1e-9, "{p:?} is {d} off the (2, 1) torus");
    }
}
