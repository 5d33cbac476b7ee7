//! DEM on the papers' real meshes (from `DEMKIT_DATA`, default `../shared/data` beside the
//! checkout). Ignored by default: run with `cargo test --release -- --ignored`.
//!
//! These assert what demkit guarantees today — convergence, zero flipped triangles, a large
//! reduction of the initial map's density error, the time budget — and record the accuracy
//! reached. The DEM issue's accuracy targets for these meshes (density_error_mean ≤ 0.12 on
//! human_face, ≤ 0.17 on chinese_lion) are not met yet; see README "Results".

use demkit::methods::dem;
use demkit::metrics::{Domain, compute, density_error, map_areas};
use demkit::population::{PopulationSpec, face_populations};
use std::path::PathBuf;
use std::sync::Mutex;
use std::time::Instant;

fn data(rel: &str) -> PathBuf {
    let root = std::env::var_os("DEMKIT_DATA")
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../../shared/data"));
    root.join(rel)
}

/// The timing checks need the machine to themselves: one real mesh at a time.
static SERIAL: Mutex<()> = Mutex::new(());

fn check(rel: &str, seconds: f64) {
    let _guard = SERIAL.lock().unwrap_or_else(|e| e.into_inner());
    let mesh = demkit::io::read_mesh(&data(rel)).unwrap();
    let (mesh, _) = demkit::mesh::validate::validate(mesh).unwrap();
    let pop = face_populations(&PopulationSpec::Area, &mesh).unwrap();
    let t = Instant::now();
    let r = dem::run(&mesh, &pop, &dem::Config::default(), &mut |_| {}).unwrap();
    let elapsed = t.elapsed().as_secs_f64();
    let m = compute(&mesh, &pop, &r.initial, &r.positions, Domain::Plane, None);
    let initial = density_error(&pop, &map_areas(&r.initial, &mesh.faces, Domain::Plane).0).0;
    eprintln!(
        "{rel}: {} iterations ({:?}), density_error_mean {:.4} (initial {:.4}), {} flipped, {:.2} s",
        r.iterations, r.stop_reason, m.density_error_mean, initial, m.flipped_triangles, elapsed
    );
    assert!(r.converged);
    assert_eq!(m.flipped_triangles, 0);
    assert_eq!(r.positions.len(), mesh.n_vertices());
    assert!(
        m.density_error_mean < initial,
        "no improvement over the initial map"
    );
    if !cfg!(debug_assertions) {
        assert!(elapsed <= seconds, "{rel}: {elapsed:.2} s > {seconds} s");
    }
}

#[test]
#[ignore = "needs real meshes (DEMKIT_DATA)"]
fn human_face() {
    check("open/human_face.obj", 3.0);
}

#[test]
#[ignore = "needs real meshes (DEMKIT_DATA)"]
fn chinese_lion() {
    check("open/chinese_lion.obj", 3.0);
}

#[test]
#[ignore = "needs real meshes (DEMKIT_DATA)"]
fn hand() {
    check("open/hand.obj", 15.0);
}

#[test]
#[ignore = "needs real meshes (DEMKIT_DATA)"]
fn human_brain() {
    check("open/human_brain.obj", 15.0);
}
