//! Shared by the budget benchmarks: the case runner that prints each case's time budget beside
//! its measured time, where the real meshes are, and the meshes the DEQ cases are built from.

#![allow(dead_code)]
use demkit::methods::MethodConfig;

use criterion::measurement::WallTime;
use criterion::{BenchmarkGroup, Criterion, SamplingMode};
use demkit::TriMesh;
use demkit::methods::deq;
use demkit::population::{PopulationSpec, face_populations};
use std::path::PathBuf;
use std::time::Duration;

#[path = "../../tests/common/cut.rs"]
pub mod cut;
#[path = "../../tests/common/domains.rs"]
pub mod domains;

/// A group for multi-second cases: ten samples, each one run (flat sampling), a short
/// measurement time (criterion extends it when one run takes longer).
pub fn slow_group<'a>(c: &'a mut Criterion, name: &str) -> BenchmarkGroup<'a, WallTime> {
    let mut g = c.benchmark_group(name);
    g.sample_size(10)
        .sampling_mode(SamplingMode::Flat)
        .warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_secs(2));
    g
}

/// Benchmarks `run` on what `setup` makes, as `name` with its time budget in the case's name
/// (so criterion prints it beside the measured time). `setup` runs once, and only when the
/// case is selected by criterion's filter.
pub fn case<S, T>(
    g: &mut BenchmarkGroup<'_, WallTime>,
    name: &str,
    budget_seconds: f64,
    setup: impl FnOnce() -> S,
    run: impl Fn(&S) -> T,
) {
    let mut setup = Some(setup);
    let mut state: Option<S> = None;
    g.bench_function(format!("{name} (budget {budget_seconds} s)"), |b| {
        if let Some(f) = setup.take() {
            state = Some(f());
        }
        let s = state.as_ref().expect("set up");
        b.iter(|| run(s))
    });
}

/// The folder of the real meshes (`DEMKIT_DATA`, default `../shared/data` beside the
/// checkout) if it exists; otherwise `None`, after saying which cases are skipped.
pub fn data_root(what: &str) -> Option<PathBuf> {
    let root = std::env::var_os("DEMKIT_DATA")
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../../shared/data"));
    if root.is_dir() {
        Some(root)
    } else {
        eprintln!(
            "skipping the {what} cases: no real meshes at {} (set DEMKIT_DATA)",
            root.display()
        );
        None
    }
}

/// Reads and validates a real mesh.
pub fn load(root: &std::path::Path, rel: &str) -> TriMesh {
    let mesh = demkit::io::read_mesh(&root.join(rel)).unwrap_or_else(|e| panic!("{rel}: {e}"));
    demkit::mesh::validate::validate(mesh)
        .unwrap_or_else(|e| panic!("{rel}: {e}"))
        .0
}

/// The face populations of `spec` (`area`, an expression or a file).
pub fn population(mesh: &TriMesh, spec: &str) -> Vec<f64> {
    face_populations(&PopulationSpec::parse(spec), mesh).unwrap()
}

/// DEQ with its defaults, as the DEQ tests run it.
pub fn run_deq(mesh: &TriMesh, pop: &[f64]) -> demkit::methods::MapResult {
    deq::Config::default().run(mesh, pop, &mut |_| {}).unwrap()
}

/// The landmarks of the LDEQ tests: `k` interior vertices away from the loops and from each
/// other on DEQ's map, each with a target `distance` from its DEQ position in its own
/// direction.
pub fn ldeq_landmarks(
    mesh: &TriMesh,
    pop: &[f64],
    k: usize,
    distance: f64,
) -> Vec<(usize, [f64; 3])> {
    domains::spread_landmarks(mesh, &run_deq(mesh, pop).positions, k, distance)
}
