//! Benchmarks of the operators and of DEM on generated meshes (`cargo bench`).

use criterion::{Criterion, criterion_group, criterion_main};
use demkit::fem::cotangent_weights;
use demkit::generate::{peaks, square_grid};
use demkit::linalg::{SparseCholesky, StiffnessPattern};
use demkit::methods::dem;
use demkit::population::{PopulationSpec, face_populations};
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

fn dem_runs(c: &mut Criterion) {
    let mut g = c.benchmark_group("dem");
    g.sample_size(10);
    let p = peaks(45).unwrap();
    let pop = face_populations(&PopulationSpec::Area, &p).unwrap();
    g.bench_function("peaks 4050 faces, area", |b| {
        b.iter(|| dem::run(&p, &pop, &dem::Config::default(), &mut |_| {}).unwrap())
    });
    let grid = square_grid(99, 99, 99.0, 99.0).unwrap();
    let pop = face_populations(
        &PopulationSpec::parse("1+exp(-((x-49.5)^2+(y-49.5)^2)/1000)"),
        &grid,
    )
    .unwrap();
    g.bench_function("grid 100x100, Table 4 Gaussian population", |b| {
        b.iter(|| dem::run(&grid, &pop, &dem::Config::default(), &mut |_| {}).unwrap())
    });
    g.finish();
}

criterion_group!(benches, operators, dem_runs);
criterion_main!(benches);
