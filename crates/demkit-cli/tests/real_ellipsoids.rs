//! EDEM and EDEQ through the command line on the ellipsoidal paper's examples and meshes (from
//! `DEMKIT_DATA`, default `../shared/data` beside the checkout). Ignored by default: run with
//! `cargo test --release -- --ignored`.
//!
//! The limits are the authors' code's figures on the same inputs, measured under Octave by
//! `bench/reference/compare_ellipsoid.sh` (face density variance Var(P/A / mean), mean |μ|):
//! each case asserts exit 0, no flipped triangle, every point on its ellipsoid, and a variance
//! at most the reference's; EDEQ also a mean |μ| at most the reference's and the radii it
//! reports.

mod common;

use common::{Scratch, json_file, parse_obj};
use std::path::PathBuf;
use std::sync::Mutex;
use std::time::Instant;

/// One case at a time: the times printed are then those of a run alone.
static SERIAL: Mutex<()> = Mutex::new(());

fn data(rel: &str) -> String {
    let root = std::env::var_os("DEMKIT_DATA")
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../../shared/data"));
    root.join(rel).to_string_lossy().into_owned()
}

/// The radii in an example's `.ellipsoid.txt` / `.ellipsoid-guess.txt`, as `A:B:C`.
fn radii_file(rel: &str) -> String {
    let text = std::fs::read_to_string(data(rel)).unwrap();
    text.split_whitespace().collect::<Vec<_>>().join(":")
}

/// Runs `demkit map MESH --method METHOD --ellipsoid RADII --population POP` and checks the
/// common lines; returns the report.
fn run(method: &str, mesh: &str, population: &str, radii: &str) -> serde_json::Value {
    let _guard = SERIAL.lock().unwrap_or_else(|e| e.into_inner());
    let s = Scratch::new(method);
    let t = Instant::now();
    s.ok(&[
        "map",
        mesh,
        "--method",
        method,
        "--ellipsoid",
        radii,
        "--population",
        population,
        "--out",
        "o.obj",
        "--report",
        "r.json",
        "--quiet",
    ]);
    let seconds = t.elapsed().as_secs_f64();
    let r = json_file(&s.path("r.json"));
    let m = &r["metrics"];
    eprintln!(
        "{method} {mesh}: {} iterations, Var {}, mean |mu| {}, radii {}, {seconds:.2} s",
        r["iterations"], m["face_density_var_final"], m["mean_abs_mu"], r["radii"]
    );
    assert_eq!(r["converged"], true);
    assert_eq!(r["domain"], "ellipsoid");
    assert_eq!(m["flipped_triangles"], 0);
    let e: Vec<f64> = r["radii"]
        .as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_f64().unwrap())
        .collect();
    let (out, _) = parse_obj(&s.read("o.obj"));
    for p in &out.positions {
        let q = (p[0] / e[0]).powi(2) + (p[1] / e[1]).powi(2) + (p[2] / e[2]).powi(2);
        assert!((q - 1.0).abs() <= 1e-9, "{p:?} is off the ellipsoid {e:?}");
    }
    r
}

fn var(r: &serde_json::Value) -> f64 {
    r["metrics"]["face_density_var_final"].as_f64().unwrap()
}

fn mu(r: &serde_json::Value) -> f64 {
    r["metrics"]["mean_abs_mu"].as_f64().unwrap()
}

/// EDEM on one of the paper's examples (its own population and radii; the surface lies on the
/// ellipsoid and is its own initial map).
fn example(name: &str, reference_var: f64) {
    let r = run(
        "edem",
        &data(&format!("ellipsoidal/{name}.obj")),
        &data(&format!("ellipsoidal/{name}.population.txt")),
        &radii_file(&format!("ellipsoidal/{name}.ellipsoid.txt")),
    );
    assert!(
        var(&r) <= reference_var,
        "{name}: Var {} > {reference_var}",
        var(&r)
    );
}

/// EDEM by area onto the paper's radii for a mesh.
fn by_area(rel: &str, radii: &str, reference_var: f64) {
    let r = run("edem", &data(rel), "area", radii);
    assert!(
        var(&r) <= reference_var,
        "{rel}: Var {} > {reference_var}",
        var(&r)
    );
}

/// EDEQ from a guess, against the reference's variance and mean |μ|.
fn edeq(mesh: &str, population: &str, guess: &str, reference: [f64; 2]) {
    let r = run("edeq", mesh, population, guess);
    assert!(
        var(&r) <= reference[0],
        "{mesh}: Var {} > {}",
        var(&r),
        reference[0]
    );
    assert!(
        mu(&r) <= reference[1],
        "{mesh}: mean |mu| {} > {}",
        mu(&r),
        reference[1]
    );
}

fn edeq_example(name: &str, reference: [f64; 2]) {
    edeq(
        &data(&format!("ellipsoidal/{name}_edeq.obj")),
        &data(&format!("ellipsoidal/{name}_edeq.population.txt")),
        &radii_file(&format!("ellipsoidal/{name}_edeq.ellipsoid-guess.txt")),
        reference,
    );
}

#[test]
#[ignore]
fn edem_ellipsoid1() {
    example("ellipsoid1", 0.0136612);
}

#[test]
#[ignore]
fn edem_ellipsoid2() {
    example("ellipsoid2", 0.00547498);
}

#[test]
#[ignore]
fn edem_ellipsoid3() {
    example("ellipsoid3", 0.00103333);
}

#[test]
#[ignore]
fn edem_ellipsoid_cts() {
    example("ellipsoid_cts", 0.00283122);
}

#[test]
#[ignore]
fn edem_ellipsoid_discts() {
    example("ellipsoid_discts", 0.00320981);
}

#[test]
#[ignore]
fn edem_sphere() {
    example("sphere", 0.00676558);
}

#[test]
#[ignore]
fn edem_david1() {
    by_area("genus0/david1.obj", "1:1.2:1.4", 0.000360711);
}

#[test]
#[ignore]
fn edem_buddha() {
    by_area("ellipsoidal/buddha.obj", "1:1:1.4", 0.121573);
}

#[test]
#[ignore]
fn edem_hippocampus() {
    by_area("ellipsoidal/hippocampus.obj", "1:1:2.2", 0.0499585);
}

#[test]
#[ignore]
fn edem_twistedball() {
    by_area("genus0/twistedball.obj", "1:0.8:1.4", 0.00150008);
}

#[test]
#[ignore]
fn edeq_ellipsoid1() {
    edeq_example("ellipsoid1", [0.0153466, 0.185187]);
}

#[test]
#[ignore]
fn edeq_ellipsoid2() {
    edeq_example("ellipsoid2", [0.00816184, 0.228531]);
}

#[test]
#[ignore]
fn edeq_ellipsoid3() {
    edeq_example("ellipsoid3", [0.0010855, 0.167893]);
}

#[test]
#[ignore]
fn edeq_ellipsoid_discts() {
    edeq_example("ellipsoid_discts", [0.00487782, 0.14343]);
}

#[test]
#[ignore]
fn edeq_sphere() {
    edeq_example("sphere", [0.0072451, 0.226746]);
}

#[test]
#[ignore]
fn edeq_hippocampus() {
    edeq(
        &data("ellipsoidal/hippocampus.obj"),
        "area",
        "1:1:1.5",
        [0.254821, 0.25492],
    );
}

#[test]
#[ignore]
fn edeq_vaselion() {
    edeq(
        &data("ellipsoidal/vaselion.obj"),
        "area",
        "1:1:1.4",
        [221.654, 0.225428],
    );
}

/// The two cases where demkit's EDEQ trades less distortion than the reference for a flatter
/// density (docs/deviations.md): the variance is asserted against the reference's, mean |μ|
/// against demkit's own measured figure, so that it does not grow.
#[test]
#[ignore]
fn edeq_ellipsoid_cts_and_duck() {
    edeq_example("ellipsoid_cts", [0.00286035, 0.1975]);
    edeq(
        &data("genus0/duck.obj"),
        "area",
        "1:1:1.2",
        [0.00215151, 0.2390],
    );
}
