//! Planar domains with holes and LDEQ landmarks, made the same way by the DEQ tests
//! (tests/real_deq.rs) and the DEQ benchmarks (benches/budgets.rs, benches/real_meshes.rs).

use super::cut::cut_holes;
use demkit::TriMesh;
use demkit::generate::square_grid;

/// A planar domain: the `width × height` grid of `cells` squares per unit with the faces
/// whose centroid `keep` rejects removed, then holes cut into it (jagged loops).
pub fn planar_domain(
    width: f64,
    height: f64,
    cells: usize,
    keep: impl Fn([f64; 2]) -> bool,
    holes: &[([f64; 3], f64)],
) -> TriMesh {
    let size = |l: f64| (cells as f64 * l).round() as usize;
    let mut grid = square_grid(size(width), size(height), width, height).unwrap();
    let positions = grid.positions.clone();
    grid.faces.retain(|f| {
        let c = f.iter().fold([0.0; 2], |s, &v| {
            let p = positions[v as usize];
            [s[0] + p[0] / 3.0, s[1] + p[1] / 3.0]
        });
        keep(c)
    });
    cut_holes(&grid, holes, true)
}

/// A square spiral corridor 5 cells wide (its wall a polyline 0.5 cells thick through the
/// centres of a 96 × 96 grid) with four small holes in its inner turns.
pub fn square_spiral() -> TriMesh {
    let (n, step) = (96.0, 6.0);
    let mut lengths = vec![n - step];
    let mut a = n - 2.0 * step;
    while a > step {
        lengths.extend([a, a]);
        a -= step;
    }
    let mut wall = vec![[step - 0.5, 0.5]];
    for (turn, length) in lengths.iter().enumerate() {
        let [x, y] = wall[wall.len() - 1];
        let (dx, dy) = [(0.0, 1.0), (1.0, 0.0), (0.0, -1.0), (-1.0, 0.0)][turn % 4];
        wall.push([x + dx * length, y + dy * length]);
    }
    let to_wall = |p: [f64; 2]| {
        wall.windows(2)
            .map(|s| demkit::geometry::segment::segment_distance(p, s[0], s[1]).0)
            .fold(f64::INFINITY, f64::min)
    };
    let mut centres: Vec<f64> = Vec::new();
    for i in 0..(n as usize) {
        let x = n / 2.0 + i as f64 * 0.25;
        if to_wall([x, n / 2.0]) >= 2.4 && centres.last().is_none_or(|&c| x - c >= step) {
            centres.push(x);
        }
    }
    let holes: Vec<([f64; 3], f64)> = centres
        .iter()
        .take(4)
        .map(|&x| ([x / n, 0.5, 0.0], 1.0 / n))
        .collect();
    planar_domain(
        1.0,
        1.0,
        n as usize,
        |c| to_wall([c[0] * n, c[1] * n]) > 0.5,
        &holes,
    )
}

/// `k` LDEQ landmarks on the DEQ map `x` of `mesh`: interior vertices away from the loops and
/// from each other (drawn by a fixed linear congruential sequence), each with a target
/// `distance` from its DEQ position in its own direction (golden-angle turns).
pub fn spread_landmarks(
    mesh: &TriMesh,
    x: &[[f64; 3]],
    k: usize,
    distance: f64,
) -> Vec<(usize, [f64; 3])> {
    let loops = demkit::mesh::topology::topology(mesh).boundary_loops;
    let on_loop: Vec<[f64; 3]> = loops.iter().flatten().map(|&v| x[v as usize]).collect();
    let d = |a: [f64; 3], b: [f64; 3]| (a[0] - b[0]).hypot(a[1] - b[1]);
    let mut landmarks: Vec<(usize, [f64; 3])> = Vec::new();
    let mut state: u64 = 12345;
    while landmarks.len() < k {
        state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        let v = (state >> 33) as usize % mesh.n_vertices();
        let p = x[v];
        if on_loop.iter().all(|&q| d(p, q) > 2.5 * distance)
            && landmarks.iter().all(|l| d(p, x[l.0]) > 0.15)
        {
            let t = 2.399963 * landmarks.len() as f64;
            landmarks.push((
                v,
                [p[0] + distance * t.cos(), p[1] + distance * t.sin(), 0.0],
            ));
        }
    }
    landmarks
}

/// An Archimedean spiral corridor in a disk: the disk of radius 0.98 about (1, 1) on a grid of
/// `cells` squares per unit, less the faces within `wall / 2` of a pitch (a fraction of the
/// distance between turns) of the spiral `r = bθ` of `turns` turns out to radius 0.9. The
/// spiral's wall is one hole; the corridor between its turns is wound `turns` times.
pub fn archimedean_spiral(cells: usize, turns: f64, wall: f64) -> TriMesh {
    use std::f64::consts::{PI, TAU};
    let theta_max = turns * TAU;
    let b = 0.9 / theta_max;
    let half = 0.5 * wall * TAU * b;
    let samples = 4000;
    let points: Vec<[f64; 2]> = (0..samples)
        .map(|k| {
            let t = PI + (theta_max - PI) * k as f64 / (samples - 1) as f64;
            [1.0 + b * t * t.cos(), 1.0 + b * t * t.sin()]
        })
        .collect();
    let to_wall = |p: [f64; 2]| {
        points
            .windows(2)
            .map(|s| demkit::geometry::segment::segment_distance(p, s[0], s[1]).0)
            .fold(f64::INFINITY, f64::min)
    };
    planar_domain(
        2.0,
        2.0,
        cells,
        |c| (c[0] - 1.0).hypot(c[1] - 1.0) < 0.98 && to_wall(c) > half,
        &[],
    )
}
