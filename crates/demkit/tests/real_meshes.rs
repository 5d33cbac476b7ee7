//! DEM on the papers' real meshes (from `DEMKIT_DATA`, default `../shared/data` beside the
//! checkout). Ignored by default: run with `cargo test --release -- --ignored`.
//!
//! Each test asserts convergence, zero flipped triangles, the input's vertex order, a bound on
//! the final `density_error_mean` (the DEM issue's targets where it gives one); it prints the
//! time, whose budget is a case of `benches/real_meshes.rs`.

use demkit::methods::MethodConfig;
use demkit::methods::{dem, dem_shape};
use demkit::metrics::{Domain, compute, density_error, map_areas};
use demkit::population::{PopulationSpec, face_populations};
use demkit::shape::Shape;
use std::time::Instant;

mod common;
use common::{SERIAL, data};

fn check(rel: &str, max_error: f64) {
    check_method(rel, None, max_error);
}

/// Runs DEM (or shape-prescribed DEM onto `shape`) with population area and checks it.
fn check_method(rel: &str, shape: Option<Shape>, max_error: f64) {
    let _guard = SERIAL.lock().unwrap_or_else(|e| e.into_inner());
    let mesh = demkit::io::read_mesh(&data(rel)).unwrap();
    let (mesh, _) = demkit::mesh::validate::validate(mesh).unwrap();
    let pop = face_populations(&PopulationSpec::Area, &mesh).unwrap();
    let t = Instant::now();
    let r = match shape {
        None => dem::Config::default()
            .run(&mesh, &pop, &mut |_| {})
            .unwrap(),
        Some(shape) => {
            let c = dem_shape::Config {
                shape,
                ..Default::default()
            };
            c.run(&mesh, &pop, &mut |_| {}).unwrap()
        }
    };
    let elapsed = t.elapsed().as_secs_f64();
    let m = compute(&mesh, &pop, &r.initial, &r.positions, Domain::Plane, None);
    let initial = density_error(&pop, &map_areas(&r.initial, &mesh.faces, Domain::Plane).0).0;
    eprintln!(
        "{rel} {shape:?}: {} iterations ({:?}), density_error_mean {:.4} (initial {:.4}), {} flipped, {:.2} s",
        r.iterations, r.stop_reason, m.density_error_mean, initial, m.flipped_triangles, elapsed
    );
    assert!(r.converged);
    assert_eq!(m.flipped_triangles, 0);
    assert_eq!(r.positions.len(), mesh.n_vertices());
    assert!(
        m.density_error_mean <= max_error,
        "{rel} {shape:?}: density_error_mean {} > {max_error}",
        m.density_error_mean
    );
    if let Some(shape) = shape {
        let topo = demkit::mesh::topology::topology(&mesh);
        for &v in &topo.boundary_loops[0] {
            let q = r.positions[v as usize];
            let p = shape.project([q[0], q[1]]);
            assert!(
                (p[0] - q[0]).hypot(p[1] - q[1]) <= 1e-9,
                "vertex {v} off the shape"
            );
        }
    }
}

// Targets from the DEM issue (face ≤ 0.12, lion ≤ 0.17; the time budgets, 3 s and 15 s for
// hand and brain, are benchmark cases); the measured figures are in the README. Hand and brain have no accuracy target in the issue:
// their bounds guard what demkit reaches today (0.055 and 0.65, from 4.9 and 2.1 initially).

#[test]
#[ignore = "needs real meshes (DEMKIT_DATA)"]
fn human_face() {
    check("open/human_face.obj", 0.12);
}

#[test]
#[ignore = "needs real meshes (DEMKIT_DATA)"]
fn chinese_lion() {
    check("open/chinese_lion.obj", 0.17);
}

#[test]
#[ignore = "needs real meshes (DEMKIT_DATA)"]
fn hand() {
    check("open/hand.obj", 0.1);
}

#[test]
#[ignore = "needs real meshes (DEMKIT_DATA)"]
fn human_brain() {
    check("open/human_brain.obj", 0.8);
}

#[test]
#[ignore = "needs real meshes (DEMKIT_DATA)"]
fn human_face_onto_shapes() {
    check_method("open/human_face.obj", Some(Shape::Disk), 0.2);
    let rectangle = Shape::Rectangle {
        width: 3.0,
        height: 2.0,
    };
    check_method("open/human_face.obj", Some(rectangle), 0.2);
    check_method(
        "open/human_face.obj",
        Some(Shape::Ellipse { a: 2.0, b: 1.0 }),
        0.2,
    );
}
