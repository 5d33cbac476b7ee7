//! The issues' time budgets on generated inputs, one criterion case each, on the input and
//! settings of the test that used to assert it (the tests now only print their times). Each
//! case's name carries its budget, printed beside the measured time; a budget is a figure for
//! an idle 2-core machine, not a pass/fail check. Run one case with, e.g.,
//! `cargo bench -p demkit --bench budgets -- --sample-size 10 "write 1M vertices"`.

mod budget;

use budget::domains::{planar_domain, square_spiral};
use budget::{case, ldeq_landmarks, population, run_deq, slow_group};
use criterion::{Criterion, criterion_group, criterion_main};
use demkit::TriMesh;
use demkit::apps::cartogram::{self, Positions, planar, values::ValueSource};
use demkit::generate::{annulus, disk_with_holes, rectangle_with_holes};
use demkit::methods::ldeq;
use std::path::PathBuf;

/// A fresh path in this process's temporary folder.
fn temp_path(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("demkit-bench-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

/// The 1000 × 1000-vertex sheet of the writer test (`io::tests`).
fn million_vertices() -> TriMesh {
    let n = 1000u32;
    let mut positions = Vec::with_capacity((n * n) as usize);
    for i in 0..n {
        for j in 0..n {
            positions.push([i as f64 / 7.0, j as f64 / 3.0, 0.1 * (i + j) as f64]);
        }
    }
    let mut faces = Vec::new();
    for i in 0..n - 1 {
        for j in 0..n - 1 {
            faces.push([i * n + j, (i + 1) * n + j, (i + 1) * n + j + 1]);
        }
    }
    TriMesh::new(positions, faces)
}

/// Writing a million vertices as PLY and as OBJ: 2 s each.
fn writing(c: &mut Criterion) {
    let mut g = slow_group(c, "write");
    for ext in ["ply", "obj"] {
        let path = temp_path(&format!("big.{ext}"));
        let name = format!("write 1M vertices as .{ext}");
        case(&mut g, &name, 2.0, million_vertices, |m| {
            demkit::io::write_mesh(&path, m).unwrap()
        });
        let _ = std::fs::remove_file(&path);
    }
    g.finish();
}

/// The four-quadrant annulus of the DEQ paper and its population.
fn quadrant_annulus() -> (TriMesh, Vec<f64>) {
    let mesh = annulus(0.4, 1.0, 12, 96).unwrap();
    let pop = population(&mesh, "area*(1+3*(x>0)*(y>0)+(x<0)*(y<0)+2*(x>0)*(y<0))");
    (mesh, pop)
}

/// DEQ and LDEQ on the generated surfaces with holes of tests/real_deq.rs: 15 s each.
fn deq_budgets(c: &mut Criterion) {
    let mut g = slow_group(c, "deq");
    type Make = fn() -> (TriMesh, &'static str);
    let made: [(&str, Make); 8] = [
        ("rectangle with two holes", || {
            let holes = [(-0.75, 0.0, 0.3), (0.75, 0.0, 0.3)];
            let mesh = rectangle_with_holes(3.0, 1.5, &holes, 40).unwrap();
            (mesh, "area*(1+(abs(x)<0.5))")
        }),
        ("four-quadrant annulus", || {
            let mesh = annulus(0.4, 1.0, 12, 96).unwrap();
            (mesh, "area*(1+3*(x>0)*(y>0)+(x<0)*(y<0)+2*(x>0)*(y<0))")
        }),
        ("L-shape, 1 hole", || {
            let l = |c: [f64; 2]| !(c[0] > 1.0 && c[1] > 1.0);
            let mesh = planar_domain(2.0, 2.0, 30, l, &[([0.5, 0.5, 0.0], 0.25)]);
            (mesh, "area*(1+2*exp(-((x-1.5)^2+(y-0.5)^2)/0.1))")
        }),
        ("L-shape, 3 holes", || {
            let holes = [
                ([0.5, 0.5, 0.0], 0.2),
                ([1.5, 0.5, 0.0], 0.2),
                ([0.5, 1.5, 0.0], 0.2),
            ];
            let l = |c: [f64; 2]| !(c[0] > 1.0 && c[1] > 1.0);
            (planar_domain(2.0, 2.0, 30, l, &holes), "area*(1+x)")
        }),
        ("disk with 6 holes", || {
            let holes: Vec<(f64, f64, f64)> = (0..6)
                .map(|k| {
                    let t = std::f64::consts::TAU * k as f64 / 6.0;
                    (0.55 * t.cos(), 0.55 * t.sin(), 0.08 + 0.02 * k as f64)
                })
                .collect();
            (disk_with_holes(&holes, 50).unwrap(), "area*(1+2*(x>0)+y*y)")
        }),
        ("C-shape, 2 holes", || {
            let keep = |c: [f64; 2]| !(c[0] > 1.0 && c[1] > 0.6 && c[1] < 1.4);
            let holes = [([2.2, 0.3, 0.0], 0.15), ([2.2, 1.7, 0.0], 0.15)];
            let mesh = planar_domain(3.0, 2.0, 40, keep, &holes);
            (mesh, "area*(1+2*exp(-((x-1.5)^2+(y-1)^2)/0.2))")
        }),
        ("U-shape, 3 holes", || {
            let keep = |c: [f64; 2]| !(c[0] > 0.8 && c[0] < 2.2 && c[1] > 0.8);
            let holes = [
                ([0.4, 2.2, 0.0], 0.2),
                ([2.6, 2.2, 0.0], 0.2),
                ([1.5, 0.4, 0.0], 0.2),
            ];
            (planar_domain(3.0, 3.0, 40, keep, &holes), "area*(1+x*y)")
        }),
        ("square spiral, flat holes", || (square_spiral(), "area")),
    ];
    for (name, make) in made {
        let setup = || {
            let (mesh, spec) = make();
            let pop = population(&mesh, spec);
            (mesh, pop)
        };
        case(&mut g, name, 15.0, setup, |(mesh, pop)| run_deq(mesh, pop));
    }
    let setup = || {
        let (mesh, pop) = quadrant_annulus();
        let landmarks = ldeq_landmarks(&mesh, &pop, 4, 0.05);
        (mesh, pop, landmarks)
    };
    case(&mut g, "LDEQ annulus", 15.0, setup, |(mesh, pop, l)| {
        ldeq::run(mesh, pop, l, &ldeq::Config::default(), &mut |_| {}).unwrap()
    });
    g.finish();
}

/// The GeoJSON of the CLI cartogram test: an `nx × ny` grid of unit squares with values
/// spread log-uniformly over 1..10 (the same generator and seed).
fn many_squares(nx: usize, ny: usize) -> String {
    let mut state: u64 = 11;
    let mut next = || {
        state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (state >> 11) as f64 / (1u64 << 53) as f64
    };
    let mut features = Vec::with_capacity(nx * ny);
    for i in 0..nx {
        for j in 0..ny {
            let (x, y) = (i as f64, j as f64);
            let ring = [
                [x, y],
                [x + 1.0, y],
                [x + 1.0, y + 1.0],
                [x, y + 1.0],
                [x, y],
            ];
            let ring: Vec<String> = ring
                .iter()
                .map(|p| format!("[{},{}]", p[0], p[1]))
                .collect();
            features.push(format!(
                r#"{{"type":"Feature","properties":{{"name":"s{i}_{j}","pop":{}}},"geometry":{{"type":"Polygon","coordinates":[[{}]]}}}}"#,
                10f64.powf(next()),
                ring.join(",")
            ));
        }
    }
    format!(
        r#"{{"type":"FeatureCollection","features":[{}]}}"#,
        features.join(",")
    )
}

/// The planar cartogram of 400 and of 10 000 squares with the CLI's defaults (tests
/// cli_cartogram.rs): 20 s and 60 s for the whole command; the cases time reading the
/// GeoJSON and the flow, not writing the outputs.
fn cartogram_budgets(c: &mut Criterion) {
    let mut g = slow_group(c, "cartogram");
    for (n, budget) in [(20, 20.0), (100, 60.0)] {
        let path = temp_path(&format!("squares-{n}.geojson"));
        let name = format!("{} squares", n * n);
        let setup = || std::fs::write(&path, many_squares(n, n)).unwrap();
        case(&mut g, &name, budget, setup, |_| {
            let source = ValueSource::Property("pop");
            let (_, set) = cartogram::load(&path, &source, Positions::Plane).unwrap();
            let config = cartogram::Config::default();
            planar::run(&set, &config, "squares", &mut |_| {}).unwrap()
        });
        let _ = std::fs::remove_file(&path);
    }
    g.finish();
}

criterion_group!(benches, writing, deq_budgets, cartogram_budgets);
criterion_main!(benches);
