//! Registration (SDEM paper §5.1) of a real genus-0 mesh with smoothly deformed copies of
//! itself (from `DEMKIT_DATA`, default `../shared/data` beside the checkout). Ignored by
//! default: run with `cargo test --release -- --ignored`.
//!
//! The copy has the same vertices in the same order, so the registration's error is known at
//! every vertex: the distance from vertex i carried onto the copy to vertex i of the copy. Six
//! landmark pairs: the vertices extreme along ±x, ±y, ±z. Acceptance: the mean error is below
//! 2% of the copy's bounding-box diagonal.

use demkit::TriMesh;
use demkit::apps::register::{register, registration_config};
use demkit::geometry::{bounding_box, bounding_box_diagonal, face_areas, norm, sub};
use std::f64::consts::TAU;

mod common;
use common::{SERIAL, data};

/// Applies `warp` to the mesh's positions in the frame centred at its bounding-box centre and
/// scaled by its diagonal.
fn deformed(mesh: &TriMesh, warp: impl Fn([f64; 3]) -> [f64; 3]) -> TriMesh {
    let (lo, hi) = bounding_box(&mesh.positions);
    let c = [0, 1, 2].map(|d| 0.5 * (lo[d] + hi[d]));
    let diag = norm(sub(hi, lo));
    let positions = mesh
        .positions
        .iter()
        .map(|p| {
            let q = warp([0, 1, 2].map(|d| (p[d] - c[d]) / diag));
            [0, 1, 2].map(|d| q[d] * diag + c[d])
        })
        .collect();
    TriMesh::new(positions, mesh.faces.clone())
}

/// The vertices with the least and the largest x, y and z.
fn extreme_vertices(p: &[[f64; 3]]) -> Vec<usize> {
    let mut out = Vec::new();
    for d in 0..3 {
        let by = |i: &usize, j: &usize| p[*i][d].total_cmp(&p[*j][d]);
        out.push((0..p.len()).min_by(by).unwrap());
        out.push((0..p.len()).max_by(by).unwrap());
    }
    out
}

/// Registers maxplanck with its deformed copy; returns the mean error / diagonal.
fn mean_error(warp: impl Fn([f64; 3]) -> [f64; 3]) -> f64 {
    let _lock = SERIAL.lock().unwrap_or_else(|e| e.into_inner());
    let a = demkit::io::read_mesh(&data("genus0/maxplanck.obj")).unwrap();
    let b = deformed(&a, warp);
    let pairs: Vec<(usize, usize)> = extreme_vertices(&a.positions)
        .into_iter()
        .map(|v| (v, v))
        .collect();
    let pa = face_areas(&a.positions, &a.faces);
    let pb = face_areas(&b.positions, &b.faces);
    let r = register(
        &a,
        &b,
        &pairs,
        &pa,
        &pb,
        &registration_config(),
        &mut |_| {},
    )
    .unwrap();
    let diag = bounding_box_diagonal(&b.positions);
    let mean = r
        .positions
        .iter()
        .zip(&b.positions)
        .map(|(p, q)| norm(sub(*p, *q)))
        .sum::<f64>()
        / (b.n_vertices() as f64 * diag);
    println!("mean error {:.3}% of the diagonal", 100.0 * mean);
    mean
}

#[test]
#[ignore]
fn maxplanck_with_a_sinusoidal_warp_of_itself() {
    let e = mean_error(|[x, y, z]| {
        [
            1.1 * (x + 0.04 * (TAU * y).sin()),
            y + 0.04 * (TAU * z).sin(),
            0.9 * (z + 0.04 * (TAU * x).sin()),
        ]
    });
    assert!(e < 0.02, "{e}");
}

#[test]
#[ignore]
fn maxplanck_with_an_anisotropic_scaling_of_itself() {
    let e = mean_error(|[x, y, z]| [1.2 * x, y, 0.85 * z]);
    assert!(e < 0.02, "{e}");
}

#[test]
#[ignore]
fn maxplanck_with_a_bend_of_itself() {
    let e = mean_error(|[x, y, z]| [x, y + 0.3 * x * x, z * (1.0 + 0.2 * y)]);
    assert!(e < 0.02, "{e}");
}
