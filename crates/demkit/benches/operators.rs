//! Benchmarks of the finite-element operators and the sparse Cholesky factorization on a
//! generated grid. They reach the library's internals, so they need its `internals` feature:
//! `cargo bench -p demkit --features internals --bench operators`.

use criterion::{Criterion, criterion_group, criterion_main};
use demkit::fem::cotangent_weights;
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
}

criterion_group!(benches, operators);
criterion_main!(benches);
