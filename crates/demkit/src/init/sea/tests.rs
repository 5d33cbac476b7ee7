//! Tests of the sea construction.

use super::*;
use crate::mesh::triangulate::constrained_delaunay;
use clean_up::{boundary_next, loops};
use holes::ear_clip;
use std::collections::HashMap;
use std::f64::consts::PI;

/// A disk of `k` concentric rings (6j points on ring j, interior radii jittered),
/// triangulated ring by ring: 6k² faces. Returns positions, faces and the boundary loop
/// (the outer ring, CCW).
fn disk(k: usize, center: [f64; 2], radius: f64) -> (Vec<[f64; 2]>, Vec<[u32; 3]>, Vec<u32>) {
    let mut pos = vec![center];
    let mut rings: Vec<Vec<u32>> = vec![vec![0]];
    for j in 1..=k {
        let count = 6 * j;
        let mut ring = Vec::new();
        for i in 0..count {
            let t = 2.0 * PI * i as f64 / count as f64;
            let jitter = if j < k {
                0.2 * (7.0 * i as f64 + j as f64).sin()
            } else {
                0.0
            };
            let r = radius * (j as f64 + jitter) / k as f64;
            ring.push(pos.len() as u32);
            pos.push([center[0] + r * t.cos(), center[1] + r * t.sin()]);
        }
        rings.push(ring);
    }
    let mut faces = Vec::new();
    for j in 1..=k {
        let (inner, outer) = (&rings[j - 1], &rings[j]);
        let (ni, no) = (inner.len(), outer.len());
        if ni == 1 {
            for o in 0..no {
                faces.push([inner[0], outer[o], outer[(o + 1) % no]]);
            }
            continue;
        }
        // Merge the two rings by angle; both start at angle 0.
        let (mut i, mut o) = (0usize, 0usize);
        while i < ni || o < no {
            let next_in = (i + 1) as f64 / ni as f64;
            let next_out = (o + 1) as f64 / no as f64;
            if o < no && (i == ni || next_out <= next_in) {
                faces.push([inner[i % ni], outer[o], outer[(o + 1) % no]]);
                o += 1;
            } else {
                faces.push([inner[i], outer[o % no], inner[(i + 1) % ni]]);
                i += 1;
            }
        }
    }
    let boundary = rings[k].clone();
    (pos, faces, boundary)
}

/// A grid ROI from a mask of unit cells (row-major, `w` wide), each cell split in two.
fn grid_roi(mask: &[&str], cell: f64) -> (Vec<[f64; 2]>, Vec<[u32; 3]>, Vec<u32>) {
    let h = mask.len();
    let w = mask[0].len();
    let mut id: HashMap<(usize, usize), u32> = HashMap::new();
    let mut pos = Vec::new();
    let mut vid = |x: usize, y: usize, pos: &mut Vec<[f64; 2]>| -> u32 {
        *id.entry((x, y)).or_insert_with(|| {
            pos.push([x as f64 * cell + 0.3, y as f64 * cell - 1.1]);
            (pos.len() - 1) as u32
        })
    };
    let mut faces = Vec::new();
    for (row, line) in mask.iter().enumerate() {
        let y = h - 1 - row;
        for (x, ch) in line.chars().enumerate().take(w) {
            if ch == '#' {
                let a = vid(x, y, &mut pos);
                let b = vid(x + 1, y, &mut pos);
                let c = vid(x + 1, y + 1, &mut pos);
                let d = vid(x, y + 1, &mut pos);
                faces.push([a, b, c]);
                faces.push([a, c, d]);
            }
        }
    }
    let boundary = boundary_of(&faces, pos.len());
    (pos, faces, boundary)
}

/// The single boundary loop of a disk mesh, in face orientation (CCW).
fn boundary_of(faces: &[[u32; 3]], nv: usize) -> Vec<u32> {
    let alive = vec![true; faces.len()];
    let inc = Incidence::new(faces, nv);
    let next = boundary_next(&inc, &alive, None).unwrap();
    let lps = loops(&next);
    assert_eq!(lps.len(), 1);
    lps[0].clone()
}

fn area(p: &[[f64; 2]], f: [u32; 3]) -> f64 {
    0.5 * orient(p, f)
}

/// The checks every sea must pass.
fn check_sea(pos: &[[f64; 2]], faces: &[[u32; 3]], boundary: &[u32], eta: f64) -> SeaMesh {
    let sea = build_sea(pos, faces, boundary, eta).unwrap();
    let n = pos.len();
    assert_eq!(sea.n_roi_vertices, n);
    assert_eq!(sea.n_roi_faces, faces.len());
    assert_eq!(&sea.positions[..n], pos);
    assert_eq!(&sea.faces[..faces.len()], faces);
    assert!(sea.faces.len() > 2 * faces.len());

    // Positive areas.
    for (k, f) in sea.faces.iter().enumerate() {
        assert!(area(&sea.positions, *f) > 0.0, "face {k} {f:?}");
    }
    // Edge use counts.
    let mut uses: HashMap<(u32, u32), usize> = HashMap::new();
    for f in &sea.faces {
        for e in 0..3 {
            let (a, b) = (f[e], f[(e + 1) % 3]);
            *uses.entry((a.min(b), a.max(b))).or_default() += 1;
        }
    }
    assert!(uses.values().all(|&u| u <= 2));
    let b = boundary.len();
    for k in 0..b {
        let (a, c) = (boundary[k], boundary[(k + 1) % b]);
        assert_eq!(uses[&(a.min(c), a.max(c))], 2, "ROI boundary edge {a}-{c}");
    }
    // Euler characteristic of a disk; every vertex used.
    let mut used = vec![false; sea.positions.len()];
    for f in &sea.faces {
        for &v in f {
            used[v as usize] = true;
        }
    }
    assert!(used.iter().all(|&u| u));
    let chi = sea.positions.len() as i64 - uses.len() as i64 + sea.faces.len() as i64;
    assert_eq!(chi, 1);

    // The scaled frame: area centroid at 0, farthest ROI vertex at 0.5.
    let frame = Similarity::fit(pos, faces, 0.5).unwrap();
    let z: Vec<[f64; 2]> = sea.positions.iter().map(|&p| frame.apply(p)).collect();
    let rmax = z.iter().map(|q| q[0].hypot(q[1])).fold(0.0, f64::max);
    assert!(rmax <= eta * (1.0 + 1e-12), "{rmax}");
    assert!(rmax >= 0.8 * eta.min(2.0), "{rmax}");

    // Sea faces around the ROI boundary have areas comparable to l².
    let l = mean_edge_length(&z[..n], faces, boundary);
    let on_boundary: std::collections::HashSet<u32> = boundary.iter().copied().collect();
    let mut count = 0;
    for f in &sea.faces[faces.len()..] {
        if f.iter().any(|v| on_boundary.contains(v)) {
            let a = area(&z, *f);
            assert!(
                a > l * l / 10.0 && a < 10.0 * l * l,
                "{a} vs l² = {}",
                l * l
            );
            count += 1;
        }
    }
    assert!(count >= b);
    sea
}

#[test]
fn disk_roi_gets_a_sea() {
    let (pos, faces, boundary) = disk(6, [3.0, -2.0], 2.5);
    assert_eq!(faces.len(), 6 * 36);
    let sea = check_sea(&pos, &faces, &boundary, 5.0);
    // The sea extends well beyond the unit circle (reflection), up to eta.
    assert!(sea.positions.len() > 4 * pos.len());
}

#[test]
fn the_far_sea_is_a_graded_fill_not_a_reflected_copy_of_the_roi() {
    // A fine ROI (38 400 faces) at DEM's radius 0.85: reflecting it would put most of its
    // vertices into the sea; the graded fill beyond the reflected ring costs a fraction of
    // them, and the sea still reaches the truncation radius.
    let (pos, faces, boundary) = disk(80, [1.0, 2.0], 3.0);
    let n = pos.len();
    let sea = build_sea_with_radius(&pos, &faces, &boundary, 5.0, 0.85).unwrap();
    assert_eq!(&sea.positions[..n], &pos[..]);
    assert_eq!(&sea.faces[..faces.len()], &faces[..]);
    assert!(sea.faces.iter().all(|f| area(&sea.positions, *f) > 0.0));
    let sea_vertices = sea.positions.len() - n;
    assert!(
        2 * sea_vertices < n,
        "{sea_vertices} sea vertices for {n} ROI vertices"
    );
    let frame = Similarity::fit(&pos, &faces, 0.85).unwrap();
    let rmax = sea
        .positions
        .iter()
        .map(|&p| {
            let z = frame.apply(p);
            z[0].hypot(z[1])
        })
        .fold(0.0, f64::max);
    assert!(rmax > 0.99 * 5.0 && rmax < 5.0 * (1.0 + 1e-12), "{rmax}");
}

#[test]
fn disk_roi_with_other_eta() {
    let (pos, faces, boundary) = disk(8, [0.0, 0.0], 1.0);
    check_sea(&pos, &faces, &boundary, 2.0);
    check_sea(&pos, &faces, &boundary, 1.3);
    check_sea(&pos, &faces, &boundary, 20.0);
}

#[test]
fn square_grid_roi() {
    let mask = ["########"; 8];
    let (pos, faces, boundary) = grid_roi(&mask, 0.25);
    check_sea(&pos, &faces, &boundary, 5.0);
}

#[test]
fn nonconvex_roi_with_centroid_outside() {
    // A U shape: the area centroid is in the notch, outside the ROI.
    let mask = [
        "###....###",
        "###....###",
        "###....###",
        "###....###",
        "##########",
        "##########",
    ];
    let (pos, faces, boundary) = grid_roi(&mask, 0.1);
    check_sea(&pos, &faces, &boundary, 5.0);
    // A spiral-ish shape with pockets.
    let mask = [
        "##########",
        "#........#",
        "#.######.#",
        "#.#....#.#",
        "#.#.##.#.#",
        "#.#..#.#.#",
        "#.####.#.#",
        "#......#.#",
        "########.#",
    ];
    let (pos, faces, boundary) = grid_roi(&mask, 1.0);
    check_sea(&pos, &faces, &boundary, 5.0);
}

#[test]
fn inverted_reflections_are_repaired() {
    // A regular hexagon fan-triangulated from one corner: every triangle's circumcircle is
    // the hexagon's, which contains the origin, so every reflected ROI face is inverted.
    let pos: Vec<[f64; 2]> = (0..6)
        .map(|k| {
            let t = PI / 3.0 * k as f64;
            [t.cos(), t.sin()]
        })
        .collect();
    let faces = vec![[0, 1, 2], [0, 2, 3], [0, 3, 4], [0, 4, 5]];
    let boundary = vec![0, 1, 2, 3, 4, 5];
    let sea = build_sea(&pos, &faces, &boundary, 5.0).unwrap();
    for f in &sea.faces {
        assert!(area(&sea.positions, *f) > 0.0);
    }
    assert_eq!(&sea.positions[..6], &pos[..]);
    // Also with a fan of thin triangles (a 40-gon fanned from one corner).
    let pos: Vec<[f64; 2]> = (0..40)
        .map(|k| {
            let t = PI / 20.0 * k as f64;
            [2.0 * t.cos(), 1.5 * t.sin()]
        })
        .collect();
    let faces: Vec<[u32; 3]> = (1..39).map(|k| [0, k, k + 1]).collect();
    let boundary: Vec<u32> = (0..40).collect();
    let sea = build_sea(&pos, &faces, &boundary, 5.0).unwrap();
    for f in &sea.faces {
        assert!(area(&sea.positions, *f) > 0.0);
    }
}

#[test]
fn bad_input_is_rejected() {
    let (pos, faces, boundary) = disk(3, [0.0, 0.0], 1.0);
    for eta in [1.0, 0.5, f64::NAN, f64::INFINITY] {
        assert!(matches!(
            build_sea(&pos, &faces, &boundary, eta),
            Err(Error::Argument(_))
        ));
    }
    let rev: Vec<u32> = boundary.iter().rev().copied().collect();
    assert!(matches!(
        build_sea(&pos, &faces, &rev, 5.0),
        Err(Error::InvalidMesh(_))
    ));
    assert!(matches!(
        build_sea(&pos, &faces, &boundary[..2], 5.0),
        Err(Error::InvalidMesh(_))
    ));
    let mut bad = faces.clone();
    bad[3][1] = 10_000;
    assert!(matches!(
        build_sea(&pos, &bad, &boundary, 5.0),
        Err(Error::InvalidMesh(_))
    ));
    let mut p2 = pos.clone();
    p2[4][0] = f64::NAN;
    assert!(matches!(
        build_sea(&p2, &faces, &boundary, 5.0),
        Err(Error::InvalidMesh(_))
    ));
}

#[test]
fn ear_clipping_and_simplicity() {
    let pos = vec![[0.0, 0.0], [2.0, 0.0], [2.0, 2.0], [1.0, 0.5], [0.0, 2.0]];
    let tris = ear_clip(&pos, &[0, 1, 2, 3, 4]).unwrap();
    assert_eq!(tris.len(), 3);
    let total: f64 = tris.iter().map(|t| area(&pos, *t)).sum();
    assert!((total - (4.0 - 1.5)).abs() < 1e-12);
    assert!(tris.iter().all(|t| area(&pos, *t) > 0.0));
    // A bow tie is not simple.
    let pos = vec![[0.0, 0.0], [1.0, 1.0], [1.0, 0.0], [0.0, 1.0]];
    assert!(ear_clip(&pos, &[0, 1, 2, 3]).is_none());
    // Clockwise is refused.
    let pos = vec![[0.0, 0.0], [0.0, 1.0], [1.0, 0.0]];
    assert!(ear_clip(&pos, &[0, 1, 2]).is_none());
}

#[test]
fn point_in_polygon_index() {
    let poly: Vec<[f64; 2]> = vec![
        [0.0, 0.0],
        [3.0, 0.0],
        [3.0, 3.0],
        [2.0, 3.0],
        [2.0, 1.0],
        [1.0, 1.0],
        [1.0, 3.0],
        [0.0, 3.0],
    ];
    let idx = BoundaryIndex::new(&poly, 0.2);
    assert!(idx.contains([0.5, 2.0]));
    assert!(idx.contains([1.5, 0.5]));
    assert!(!idx.contains([1.5, 2.0]));
    assert!(!idx.contains([-1.0, 1.0]));
    assert!(!idx.contains([1.0, 5.0]));
    assert!(idx.far_from_boundary([1.5, 2.0]));
    assert!(!idx.far_from_boundary([1.5, 1.1]));
    assert!(!idx.far_from_boundary([3.1, 1.5]));
    assert!(idx.far_from_boundary([3.3, 1.5]));
    assert!(idx.far_from_boundary([30.0, 1.5]));
}

/// A small deterministic generator (64-bit LCG), uniform in [0, 1).
struct Lcg(u64);
impl Lcg {
    fn next(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// A random ROI: a noisy star-shaped polygon of `nb` vertices (stretched by `aspect`) with
/// `ni` random interior points, triangulated by a constrained Delaunay triangulation.
/// `noise` < 1 keeps the radius positive, so the polygon is simple.
fn random_roi(
    seed: u64,
    nb: usize,
    ni: usize,
    aspect: f64,
    noise: f64,
) -> (Vec<[f64; 2]>, Vec<[u32; 3]>, Vec<u32>) {
    let mut rng = Lcg(seed);
    let harmonics: Vec<(f64, f64)> = (1..6).map(|k| (k as f64, rng.next() * 2.0 * PI)).collect();
    let mut pos: Vec<[f64; 2]> = (0..nb)
        .map(|k| {
            let t = 2.0 * PI * (k as f64 + 0.4 * rng.next()) / nb as f64;
            let wave: f64 = harmonics.iter().map(|(h, ph)| (h * t + ph).sin() / h).sum();
            let r = 1.0 + noise * wave / 2.3;
            [aspect * r * t.cos() + 7.0, r * t.sin() - 3.0]
        })
        .collect();
    let bpoly = pos.clone();
    let index = BoundaryIndex::new(&bpoly, 0.02);
    while pos.len() < nb + ni {
        let p = [
            7.0 + aspect * 3.0 * (2.0 * rng.next() - 1.0),
            -3.0 + 3.0 * (2.0 * rng.next() - 1.0),
        ];
        if index.contains(p) && index.far_from_boundary(p) {
            pos.push(p);
        }
    }
    let edges: Vec<[usize; 2]> = (0..nb).map(|k| [k, (k + 1) % nb]).collect();
    let cdt = constrained_delaunay(&pos, &edges).unwrap();
    let faces: Vec<[u32; 3]> = cdt
        .faces
        .into_iter()
        .filter(|f| {
            let c = [0, 1].map(|d| f.iter().map(|&v| pos[v as usize][d]).sum::<f64>() / 3.0);
            index.contains(c)
        })
        .collect();
    (pos, faces, (0..nb as u32).collect())
}

#[test]
fn random_rois_give_valid_seas() {
    let mut seed = 1;
    for (nb, ni, aspect, noise) in [
        (40, 100, 1.0, 0.3),
        (60, 0, 1.0, 0.2),
        (25, 10, 3.0, 0.9),
        (120, 400, 1.0, 0.95),
        (80, 50, 8.0, 0.1),
        (200, 30, 1.5, 0.7),
        (12, 0, 1.0, 0.0),
        (30, 300, 0.2, 0.3),
    ] {
        for _ in 0..4 {
            seed += 1;
            let (pos, faces, boundary) = random_roi(seed, nb, ni, aspect, noise);
            for eta in [5.0, 1.5, 30.0] {
                let sea = build_sea(&pos, &faces, &boundary, eta)
                    .unwrap_or_else(|e| panic!("seed {seed} eta {eta}: {e}"));
                assert_eq!(&sea.positions[..pos.len()], &pos[..]);
                assert_eq!(&sea.faces[..faces.len()], &faces[..]);
                for f in &sea.faces {
                    assert!(area(&sea.positions, *f) > 0.0, "seed {seed}");
                }
            }
        }
    }
}

/// CPU time of this thread in seconds (Linux), to time on a busy machine.
fn thread_cpu_seconds() -> Option<f64> {
    let s = std::fs::read_to_string("/proc/thread-self/schedstat").ok()?;
    Some(s.split_whitespace().next()?.parse::<f64>().ok()? * 1e-9)
}

/// Run with `cargo test --release -p demkit --lib init::sea -- --ignored --nocapture`.
#[test]
#[ignore = "timing; run in release"]
fn timing_35k_faces() {
    for k in [76, 130] {
        let (pos, faces, boundary) = disk(k, [0.0, 0.0], 1.0);
        let mut best = (f64::INFINITY, f64::INFINITY);
        let mut sea = None;
        for _ in 0..5 {
            let (t, c) = (std::time::Instant::now(), thread_cpu_seconds());
            sea = Some(build_sea(&pos, &faces, &boundary, 5.0).unwrap());
            let wall = t.elapsed().as_secs_f64();
            let cpu = c
                .and_then(|c| Some(thread_cpu_seconds()? - c))
                .unwrap_or(wall);
            best = (best.0.min(wall), best.1.min(cpu));
        }
        let sea = sea.unwrap();
        println!(
            "build_sea: ROI {} faces / {} vertices -> {} faces / {} vertices: \
             best of 5 {:.3} s wall, {:.3} s CPU",
            faces.len(),
            pos.len(),
            sea.faces.len(),
            sea.positions.len(),
            best.0,
            best.1
        );
    }
}
