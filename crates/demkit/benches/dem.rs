//! Benchmarks of DEM on generated meshes (`cargo bench -p demkit --bench dem`).

use criterion::{Criterion, criterion_group, criterion_main};
use demkit::generate::{peaks, square_grid};
use demkit::methods::MethodConfig;
use demkit::methods::dem;
use demkit::population::{PopulationSpec, face_populations};

fn dem_runs(c: &mut Criterion) {
    let mut g = c.benchmark_group("dem");
    g.sample_size(10);
    let p = peaks(45).unwrap();
    let pop = face_populations(&PopulationSpec::Area, &p).unwrap();
    g.bench_function("peaks 4050 faces, area", |b| {
        b.iter(|| dem::Config::default().run(&p, &pop, &mut |_| {}).unwrap())
    });
    let grid = square_grid(99, 99, 99.0, 99.0).unwrap();
    let pop = face_populations(
        &PopulationSpec::parse("1+exp(-((x-49.5)^2+(y-49.5)^2)/1000)"),
        &grid,
    )
    .unwrap();
    g.bench_function("grid 100x100, Table 4 Gaussian population", |b| {
        b.iter(|| {
            dem::Config::default()
                .run(&grid, &pop, &mut |_| {})
                .unwrap()
        })
    });
    g.finish();
}

criterion_group!(benches, dem_runs);
criterion_main!(benches);
