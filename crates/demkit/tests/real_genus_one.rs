//! The initial map of the toroidal parameterization (TDEM paper §4, Algorithm 2 line 1) on the
//! paper's genus-one meshes (from `DEMKIT_DATA`, default `../shared/data` beside the checkout).
//! Ignored by default: run with `cargo test --release -- --ignored`.
//!
//! Each test asserts that the map exists, flips no triangle and covers the flat torus once (its
//! budget, a second, is a case of `benches/real_meshes.rs`); it prints the mean |log area ratio| of the
//! normalized face areas (the paper's (27), Table 3 "mean(d_area(h))") on the target torus
//! and on its flat rectangle.

use demkit::TriMesh;
use demkit::geometry::face_areas;
use demkit::geometry::torus::Torus;
use demkit::init::genus_one::flat_torus_map_with_report;
use std::time::Instant;

mod common;
use common::{SERIAL, data};

/// The radii of `NAME.torus.txt`: lines `R value` and `r value`.
fn target(name: &str) -> Torus {
    let path = data(&format!("genus1/{name}.torus.txt"));
    let text = std::fs::read_to_string(&path).unwrap();
    let mut radii = [None, None];
    for line in text.lines() {
        let mut words = line.split_whitespace();
        let (Some(key), Some(value)) = (words.next(), words.next()) else {
            continue;
        };
        let slot = match key {
            "R" => 0,
            "r" => 1,
            _ => continue,
        };
        radii[slot] = value.parse::<f64>().ok();
    }
    Torus::new(radii[0].unwrap(), radii[1].unwrap()).unwrap()
}

/// Mean of |log((a_i / Σa) / (b_i / Σb))|.
fn mean_log_area_ratio(a: &[f64], b: &[f64]) -> f64 {
    let (sa, sb) = (a.iter().sum::<f64>(), b.iter().sum::<f64>());
    a.iter()
        .zip(b)
        .map(|(x, y)| ((x / sa) / (y / sb)).ln().abs())
        .sum::<f64>()
        / a.len() as f64
}

fn check(name: &str) {
    let _guard = SERIAL.lock().unwrap_or_else(|e| e.into_inner());
    let mesh = demkit::io::read_mesh(&data(&format!("genus1/{name}.obj"))).unwrap();
    let (mesh, _) = demkit::mesh::validate::validate(mesh).unwrap();
    let torus = target(name);
    let t = Instant::now();
    let (map, report) = flat_torus_map_with_report(&mesh, &torus).unwrap();
    let elapsed = t.elapsed().as_secs_f64();
    let period = torus.periods();
    let flips = map.count_flipped(&mesh.faces, period);

    let (flat, on_torus) = image_areas(&mesh, &map, &torus);
    let source = face_areas(&mesh.positions, &mesh.faces);
    let covered: f64 = flat.iter().sum();
    eprintln!(
        "{name}: {} vertices, {} faces, R = {}, r = {}: {flips} flipped, {elapsed:.3} s, \
         mean |d_area| {:.4} on the torus ({:.4} flat), weights {:?} (rejected {:?}), \
         lattice {:?}, conformal distortion {:.4}, v shift {:.4}, generators {:?}",
        mesh.n_vertices(),
        mesh.n_faces(),
        torus.major,
        torus.minor,
        mean_log_area_ratio(&source, &on_torus),
        mean_log_area_ratio(&source, &flat),
        report.weights,
        report.rejected,
        report.lattice,
        report.conformal_distortion,
        report.v_shift,
        report.generators,
    );
    assert_eq!(flips, 0);
    let d = mean_log_area_ratio(&source, &on_torus);
    assert!(
        (report.area_distortion - d).abs() < 1e-9,
        "{d} vs {report:?}"
    );
    assert_eq!(map.points.len(), mesh.n_vertices());
    let expect = period[0] * period[1];
    assert!(
        (covered - expect).abs() < 1e-9 * expect,
        "{covered} vs {expect}"
    );
}

/// Per face: the signed planar area on the flat torus and the area of the triangle through
/// the φ-images of its corners on the target torus.
fn image_areas(
    mesh: &TriMesh,
    map: &demkit::geometry::torus::FlatTorusMap,
    torus: &Torus,
) -> (Vec<f64>, Vec<f64>) {
    let period = torus.periods();
    let mut flat = Vec::with_capacity(mesh.n_faces());
    let mut on_torus = Vec::with_capacity(mesh.n_faces());
    for f in 0..mesh.n_faces() {
        let c = map.corners(&mesh.faces, f, period);
        flat.push(demkit::geometry::signed_area_2d(c[0], c[1], c[2]));
        let p = c.map(|q| torus.project([q[0], q[1]]));
        on_torus.push(demkit::geometry::triangle_area(p[0], p[1], p[2]));
    }
    (flat, on_torus)
}

#[test]
#[ignore = "needs real meshes (DEMKIT_DATA)"]
fn bob() {
    check("bob");
}

#[test]
#[ignore = "needs real meshes (DEMKIT_DATA)"]
fn bracelet() {
    check("bracelet");
}

#[test]
#[ignore = "needs real meshes (DEMKIT_DATA)"]
fn rocker_arm() {
    check("rocker_arm");
}

#[test]
#[ignore = "needs real meshes (DEMKIT_DATA)"]
fn twisted() {
    check("twisted");
}

#[test]
#[ignore = "needs real meshes (DEMKIT_DATA)"]
fn vertebra() {
    check("vertebra");
}
