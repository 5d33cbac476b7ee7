//! Benchmarks of the finite-element operators and the sparse Cholesky factorization on a
//! generated grid. They reach the library's internals, so they need its `internals` feature:
//! `cargo bench -p demkit --features internals --bench operators`. With `DEMKIT_DATA` set, the
//! refactorization of SDEM's diffusion operator on `genus0/brain.obj` too: the unit that SDEM's
//! time per iteration is compared with (README, *Performance*).

use criterion::{Criterion, criterion_group, criterion_main};
use demkit::fem::{DiffusionOperator, cotangent_weights};
use demkit::generate::square_grid;
use demkit::linalg::{SparseCholesky, StiffnessPattern};
use std::hint::black_box;

fn operators(c: &mut Criterion) {
    let grid = square_grid(299, 299, 1.0, 1.0).unwrap(); // 90k vertices, 179k faces
    let n = grid.n_vertices();
    let pattern = StiffnessPattern::new(n, &grid.faces, None);
    let mass = vec![1e-5; n];
    let mut values = vec![0.0; pattern.nnz()];
    c.bench_function("cotangent weights 179k faces", |b| {
        b.iter(|| black_box(cotangent_weights(&grid.positions, &grid.faces)))
    });
    let w = cotangent_weights(&grid.positions, &grid.faces);
    c.bench_function("assemble A + L 90k vertices", |b| {
        b.iter(|| pattern.assemble(black_box(&w), &mass, &mut values))
    });
    let mut chol = SparseCholesky::for_stiffness(&pattern).unwrap();
    pattern.assemble(&w, &mass, &mut values);
    c.bench_function("numeric Cholesky 90k vertices", |b| {
        b.iter(|| chol.factor(black_box(&values)).unwrap())
    });
    brain_refactorization(c);
}

/// One numeric refactorization of `A + 4π L` (SDEM's first step) on the brain's spherical
/// conformal map, when `DEMKIT_DATA` holds `genus0/brain.obj`.
fn brain_refactorization(c: &mut Criterion) {
    let Some(root) = std::env::var_os("DEMKIT_DATA") else {
        return;
    };
    let path = std::path::Path::new(&root).join("genus0/brain.obj");
    let Ok(mesh) = demkit::io::read_mesh(&path) else {
        return;
    };
    let mut notes = Vec::new();
    let sphere = demkit::init::spherical_conformal::spherical_conformal_map(
        &mesh.positions,
        &mesh.faces,
        &mut notes,
    )
    .unwrap();
    let areas = demkit::geometry::face_areas(&sphere, &mesh.faces);
    let op = DiffusionOperator::new(sphere.len(), &mesh.faces).unwrap();
    c.bench_function("refactor A + 4πL, brain (48k vertices)", |b| {
        b.iter(|| {
            drop(
                op.factor(black_box(&sphere), &areas, 4.0 * std::f64::consts::PI, &[])
                    .unwrap(),
            );
        })
    });
}

criterion_group!(benches, operators);
criterion_main!(benches);
