//! Exit 0 and `converged: true` only for a map that is what was asked for: a run that barely
//! moved, stopped improving under a fixed step, or missed a landmark ends with exit 3 and says
//! why in the report's notes; a huge population is computed, not overflowed.

mod common;

use common::{Scratch, json_file};
use serde_json::Value;

fn report(s: &Scratch) -> Value {
    json_file(&s.path("r.json"))
}

fn notes(r: &Value) -> String {
    r["notes"].to_string()
}

#[test]
fn a_time_step_too_small_to_move_the_map_is_exit_3() {
    let s = Scratch::new("tiny-dt");
    s.generate(&["peaks", "--n", "20", "--out", "p.obj"]);
    let out = s.run(&[
        "map", "p.obj", "--out", "o.obj", "--dt", "1e-6", "--report", "r.json", "--quiet",
    ]);
    out.assert_code(3);
    let r = report(&s);
    assert_eq!(r["converged"], Value::Bool(false));
    assert_eq!(r["stop_reason"], "max_iter");
    assert!(notes(&r).contains("fixed time step 1e-6"), "{}", notes(&r));

    s.generate(&["icosphere", "--subdivisions", "3", "--out", "s.obj"]);
    let out = s.run(&[
        "map",
        "s.obj",
        "--out",
        "o.obj",
        "--population",
        "area*(1+x*x)",
        "--dt",
        "1e-6",
        "--report",
        "r.json",
        "--quiet",
    ]);
    out.assert_code(3);
    assert!(
        notes(&report(&s)).contains("barely moved"),
        "{}",
        notes(&report(&s))
    );
}

#[test]
fn a_huge_population_is_computed_with_finite_metrics() {
    let s = Scratch::new("huge-pop");
    s.generate(&["peaks", "--n", "20", "--out", "p.obj"]);
    s.ok(&[
        "map",
        "p.obj",
        "--out",
        "o.obj",
        "--population",
        "area*1e306",
        "--report",
        "r.json",
        "--quiet",
    ]);
    let r = report(&s);
    let v = r["metrics"]["face_density_var_final"].as_f64().unwrap();
    assert!(v.is_finite() && v < 0.1, "{r:#}");
    assert!(
        r["metrics"]["mean_abs_mu"]
            .as_f64()
            .is_some_and(f64::is_finite),
        "{r:#}"
    );
}

#[test]
fn a_landmark_in_a_hole_that_stays_is_exit_3_and_named() {
    let s = Scratch::new("ldeq-hole");
    s.generate(&[
        "annulus",
        "--inner",
        "0.4",
        "--outer",
        "1",
        "--radial",
        "8",
        "--angular",
        "48",
        "--out",
        "a.obj",
    ]);
    // Vertex 100 is on the annulus; its target is the hole's centre.
    s.write("l.txt", "100 0 0\n");
    let out = s.run(&[
        "map",
        "a.obj",
        "--out",
        "o.obj",
        "--method",
        "ldeq",
        "--no-geometry-update",
        "--landmarks",
        "l.txt",
        "--report",
        "r.json",
        "--quiet",
    ]);
    out.assert_code(3);
    let r = report(&s);
    assert_eq!(r["converged"], Value::Bool(false));
    assert!(notes(&r).contains("1 (vertex 100)"), "{}", notes(&r));
    assert_eq!(r["metrics"]["flipped_triangles"], 0);
}
