use super::cut_graph::{CutGraph, EdgeKind};
use super::*;
use crate::generate;
use std::collections::HashMap;
use std::f64::consts::PI;

fn target(major: f64, minor: f64) -> Torus {
    Torus::new(major, minor).unwrap()
}

/// Signed area of planar corners.
fn signed(c: [[f64; 3]; 3]) -> f64 {
    0.5 * ((c[1][0] - c[0][0]) * (c[2][1] - c[0][1]) - (c[1][1] - c[0][1]) * (c[2][0] - c[0][0]))
}

/// Per directed edge (v, w): a face containing it and the corners of v and w in that face.
fn directed_edges(faces: &[[u32; 3]]) -> HashMap<(u32, u32), (usize, usize, usize)> {
    let mut out = HashMap::new();
    for (f, t) in faces.iter().enumerate() {
        for k in 0..3 {
            let l = (k + 1) % 3;
            out.insert((t[k], t[l]), (f, k, l));
            out.insert((t[l], t[k]), (f, l, k));
        }
    }
    out
}

/// The image of the directed edge (v, w) in the face that `edges` names for it.
fn displacement(
    map: &FlatTorusMap,
    faces: &[[u32; 3]],
    period: [f64; 2],
    edges: &HashMap<(u32, u32), (usize, usize, usize)>,
    v: u32,
    w: u32,
) -> [f64; 2] {
    let (f, kv, kw) = edges[&(v, w)];
    let c = map.corners(faces, f, period);
    [c[kw][0] - c[kv][0], c[kw][1] - c[kv][1]]
}

/// The translation a closed vertex path picks up, in periods.
fn path_period(map: &FlatTorusMap, faces: &[[u32; 3]], period: [f64; 2], path: &[u32]) -> [f64; 2] {
    let edges = directed_edges(faces);
    let mut s = [0.0; 2];
    for i in 0..path.len() {
        let d = displacement(
            map,
            faces,
            period,
            &edges,
            path[i],
            path[(i + 1) % path.len()],
        );
        s[0] += d[0];
        s[1] += d[1];
    }
    [s[0] / period[0], s[1] / period[1]]
}

/// Every edge has the same image (up to sign) in its two faces: the map is a well-defined
/// map onto the flat torus, opposite sides of the rectangle identified.
fn assert_consistent(map: &FlatTorusMap, faces: &[[u32; 3]], period: [f64; 2]) {
    for (f, t) in faces.iter().enumerate() {
        let c = map.corners(faces, f, period);
        for k in 0..3 {
            let l = (k + 1) % 3;
            // The twin face, found by scanning (the test meshes are small).
            let (g, gk, gl) = faces
                .iter()
                .enumerate()
                .find_map(|(g, s)| {
                    let i = s.iter().position(|&x| x == t[l])?;
                    (s[(i + 1) % 3] == t[k]).then_some((g, i, (i + 1) % 3))
                })
                .unwrap();
            let d = map.corners(faces, g, period);
            for x in 0..2 {
                let mine = c[l][x] - c[k][x];
                let theirs = d[gk][x] - d[gl][x];
                assert!(
                    (mine - theirs).abs() < 1e-9,
                    "face {f} edge {k}: {mine} vs {theirs}"
                );
            }
        }
    }
}

fn total_planar_area(map: &FlatTorusMap, faces: &[[u32; 3]], period: [f64; 2]) -> f64 {
    (0..faces.len())
        .map(|f| signed(map.corners(faces, f, period)))
        .sum()
}

#[test]
fn cut_of_a_torus_has_two_generators_and_closed_dual_forms() {
    for (n, m) in [(3, 3), (4, 7), (24, 12)] {
        let mesh = generate::torus(2.0, 1.0, n, m).unwrap();
        let cut = CutGraph::new(mesh.n_vertices(), &mesh.faces).unwrap();
        assert_eq!(cut.generators.len(), 2);
        let count = |k| cut.kind.iter().filter(|&&x| x == k).count();
        assert_eq!(count(EdgeKind::PrimalTree), mesh.n_vertices() - 1);
        assert_eq!(count(EdgeKind::DualTree), mesh.n_faces() - 1);
        let eta = [cut.cohomology_form(0), cut.cohomology_form(1)];
        for (k, form) in eta.iter().enumerate() {
            for f in 0..mesh.n_faces() {
                assert_eq!(
                    form[3 * f] + form[3 * f + 1] + form[3 * f + 2],
                    0,
                    "face {f}"
                );
            }
            for h in 0..form.len() {
                assert_eq!(form[h], -form[cut.twin[h] as usize]);
                if cut.kind[cut.edge_of[h] as usize] == EdgeKind::PrimalTree {
                    assert_eq!(form[h], 0);
                }
            }
            // Dual bases: η_k on the loop of generator l is δ_kl.
            for l in 0..2 {
                let lp = cut.generator_loop(&mesh.faces, l);
                let s: i64 = lp.iter().map(|&h| form[h as usize]).sum();
                assert_eq!(s, i64::from(k == l), "η_{k} on loop {l}");
                // The loop is closed and starts and ends at the root.
                let (first, _) = crate::mesh::topology::half_edge(&mesh.faces, lp[0]);
                assert_eq!(first, cut.root);
                for w in lp.windows(2) {
                    let (_, a) = crate::mesh::topology::half_edge(&mesh.faces, w[0]);
                    let (b, _) = crate::mesh::topology::half_edge(&mesh.faces, w[1]);
                    assert_eq!(a, b);
                }
            }
        }
    }
}

#[test]
fn map_of_a_torus_has_the_target_periods_and_no_flips() {
    for (n, m) in [(3, 3), (30, 12)] {
        let mesh = generate::torus(3.0, 1.0, n, m).unwrap();
        for t in [target(2.0, 1.0), target(3.0, 1.0), target(10.0, 0.5)] {
            check_map_of_torus(&mesh, &t);
        }
    }
}

/// (a) and (c) for one mesh and target.
fn check_map_of_torus(mesh: &TriMesh, t: &Torus) {
    let (map, report) = flat_torus_map_with_report(mesh, t).unwrap();
    let period = t.periods();
    eprintln!("{} faces onto {t:?}: {report:?}", mesh.n_faces());
    assert_eq!(map.count_flipped(&mesh.faces, period), 0);
    assert_consistent(&map, &mesh.faces, period);
    // Points in the fundamental rectangle, first corners unshifted.
    for p in &map.points {
        assert!(p[0] >= 0.0 && p[0] < period[0], "{p:?}");
        assert!(p[1] >= -period[1] / 2.0 && p[1] < period[1] / 2.0, "{p:?}");
    }
    assert!(map.offsets.iter().all(|o| o[0] == [0, 0]));
    // The two generator loops pick up whole periods forming a basis of the lattice.
    let cut = CutGraph::new(mesh.n_vertices(), &mesh.faces).unwrap();
    let mut basis = [[0i64; 2]; 2];
    for (k, row) in basis.iter_mut().enumerate() {
        let lp = cut.generator_loop(&mesh.faces, k);
        let path: Vec<u32> = lp
            .iter()
            .map(|&h| crate::mesh::topology::half_edge(&mesh.faces, h).0)
            .collect();
        let q = path_period(&map, &mesh.faces, period, &path);
        for d in 0..2 {
            assert!((q[d] - q[d].round()).abs() < 1e-9, "{q:?}");
            row[d] = q[d].round() as i64;
        }
    }
    assert_eq!(
        (basis[0][0] * basis[1][1] - basis[0][1] * basis[1][0]).abs(),
        1
    );
    // (c) The image covers the rectangle exactly once.
    let area = total_planar_area(&map, &mesh.faces, period);
    assert!((area - period[0] * period[1]).abs() < 1e-9 * area, "{area}");
    assert!(report.conformal_distortion >= 1.0);
}

#[test]
fn wrong_topologies_and_bad_input_are_errors() {
    let t = target(2.0, 1.0);
    let topology_error = |mesh: &TriMesh| {
        let e = flat_torus_map(mesh, &t).unwrap_err();
        assert!(matches!(e, Error::Topology { .. }), "{e}");
        e.to_string()
    };
    let sphere = generate::icosphere(2).unwrap();
    let msg = topology_error(&sphere);
    assert!(msg.contains("genus 0"), "{msg}");
    let disk = generate::regular_polygon(6, 4).unwrap();
    let msg = topology_error(&disk);
    assert!(msg.contains("boundary"), "{msg}");
    // Two tori side by side.
    let one = generate::torus(2.0, 1.0, 8, 6).unwrap();
    let mut two = one.clone();
    let shift = one.n_vertices() as u32;
    two.positions
        .extend(one.positions.iter().map(|p| [p[0] + 10.0, p[1], p[2]]));
    two.faces
        .extend(one.faces.iter().map(|f| f.map(|v| v + shift)));
    let msg = topology_error(&two);
    assert!(msg.contains("2 separate pieces"), "{msg}");
    // A torus with a face removed is open.
    let mut open = one.clone();
    open.faces.pop();
    topology_error(&open);
    // A closed surface of genus 2.
    let double = double_torus();
    let msg = topology_error(&double);
    assert!(msg.contains("genus 2"), "{msg}");

    // Not a valid mesh: a vertex index out of range.
    let mut bad = one.clone();
    bad.faces[0][0] = 10_000;
    assert!(matches!(
        flat_torus_map(&bad, &t),
        Err(Error::InvalidMesh(_))
    ));
    // Inconsistent orientation.
    let mut flipped = one.clone();
    flipped.faces[3].swap(1, 2);
    assert!(matches!(
        flat_torus_map(&flipped, &t),
        Err(Error::InvalidMesh(_))
    ));
    // Radii without R > r > 0.
    let bad_torus = Torus {
        major: 1.0,
        minor: 2.0,
    };
    assert!(matches!(
        flat_torus_map(&one, &bad_torus),
        Err(Error::Argument(_))
    ));
    assert!(matches!(
        flat_torus_map(&TriMesh::default(), &t),
        Err(Error::InvalidMesh(_))
    ));
}

/// Two tori, each with one face removed, joined along the two triangular holes by a prism
/// (three quads): a closed surface of genus 2.
fn double_torus() -> TriMesh {
    let one = generate::torus(2.0, 1.0, 8, 6).unwrap();
    let mut mesh = one.clone();
    let shift = one.n_vertices() as u32;
    mesh.positions
        .extend(one.positions.iter().map(|p| [p[0] + 10.0, p[1], p[2]]));
    // Face 0 removed from both copies; the second copy mirrored (z → −z, faces reversed).
    let [a, b, c] = one.faces[0];
    let [a2, b2, c2] = [a + shift, b + shift, c + shift];
    mesh.faces.remove(0);
    mesh.faces
        .extend(one.faces.iter().skip(1).map(|f| f.map(|v| v + shift)));
    let first = one.faces.len() - 1;
    for f in mesh.faces.iter_mut().skip(first) {
        f.swap(1, 2);
    }
    for p in mesh.positions.iter_mut().skip(shift as usize) {
        p[2] = -p[2];
    }
    // The first hole's edges are now traversed y→x by the remaining faces, the mirrored
    // second's x2→y2: the tube's quads take x→y and y2→x2.
    for (x, y, x2, y2) in [(a, b, a2, b2), (b, c, b2, c2), (c, a, c2, a2)] {
        mesh.faces.push([x, y, y2]);
        mesh.faces.push([x, y2, x2]);
    }
    mesh
}

/// The harmonic map of the torus of revolution with periods (2πR, 0), (0, 2πr): `u = Rα`
/// and `v = r h(θ)` with `h' ∝ 1/(R + r cos θ)`, i.e.
/// `h(θ) = 2 atan(k tan(θ/2)) = θ − 2 atan((1 − k) sin θ / ((1 + k) + (1 − k) cos θ))`,
/// `k = √((R − r)/(R + r))`.
fn harmonic_of_revolution(big_r: f64, small_r: f64, alpha: f64, theta: f64) -> [f64; 3] {
    let k = ((big_r - small_r) / (big_r + small_r)).sqrt();
    let (s, c) = theta.sin_cos();
    let h = theta - 2.0 * ((1.0 - k) * s / ((1.0 + k) + (1.0 - k) * c)).atan();
    [big_r * alpha, small_r * h, 0.0]
}

#[test]
fn torus_of_revolution_maps_to_its_analytic_harmonic_map() {
    let (big_r, small_r, n, m) = (2.0, 1.0, 120, 60);
    let mesh = generate::torus(big_r, small_r, n, m).unwrap();
    let t = target(big_r, small_r);
    let period = t.periods();
    let (map, report) = flat_torus_map_with_report(&mesh, &t).unwrap();
    assert_eq!(map.count_flipped(&mesh.faces, period), 0);
    // In the conformal coordinates (α, ψ), dψ = r dθ / (R + r cos θ), the map is the linear
    // u = Rα, v = √(R² − r²) ψ: its distortion (K + 1/K)/2 with K = R/√(R² − r²).
    let k = big_r / (big_r * big_r - small_r * small_r).sqrt();
    let expect = (k + 1.0 / k) / 2.0;
    assert!(
        (report.conformal_distortion - expect).abs() < 1e-3,
        "{} vs {expect}",
        report.conformal_distortion
    );
    // Faces come in cell order: cell (i, j) gives [(i,j), (i+1,j), (i+1,j+1)] and
    // [(i,j), (i+1,j+1), (i,j+1)].
    let grid = |i: usize, j: usize| {
        let alpha = 2.0 * PI * i as f64 / n as f64;
        let theta = 2.0 * PI * j as f64 / m as f64;
        harmonic_of_revolution(big_r, small_r, alpha, theta)
    };
    let mut worst: f64 = 0.0;
    for i in 0..n {
        for j in 0..m {
            let cells = [
                [grid(i, j), grid(i + 1, j), grid(i + 1, j + 1)],
                [grid(i, j), grid(i + 1, j + 1), grid(i, j + 1)],
            ];
            for (s, cell) in cells.iter().enumerate() {
                let f = 2 * (i * m + j) + s;
                let got = signed(map.corners(&mesh.faces, f, period));
                let want = signed(*cell);
                worst = worst.max((got / want - 1.0).abs());
            }
        }
    }
    eprintln!("face areas off the analytic harmonic map by at most {worst:.2e}");
    assert!(
        worst < 0.02,
        "face areas off the analytic harmonic map by {worst}"
    );
    // The u coordinate is Rα up to sign and translation: every edge along α moves by ±2πR/n.
    let edges = directed_edges(&mesh.faces);
    let step = period[0] / n as f64;
    for i in 0..n {
        for j in 0..m {
            let (v, w) = ((i * m + j) as u32, (((i + 1) % n) * m + j) as u32);
            let d = displacement(&map, &mesh.faces, period, &edges, v, w);
            assert!(
                (d[0].abs() - step).abs() < 1e-9 * step && d[1].abs() < 1e-9,
                "{d:?}"
            );
        }
    }
}

#[test]
fn torus_of_revolution_differs_from_the_toroidal_projection_by_its_v_spacing() {
    // φ⁻¹ spaces the rings uniformly in θ; the harmonic map spaces them ∝ 1/(R + r cos θ), so
    // the inner faces are (R + r)/(R − r) = 3 times larger than the outer ones (R = 2, r = 1).
    let (big_r, small_r, n, m) = (2.0, 1.0, 40, 40);
    let mesh = generate::torus(big_r, small_r, n, m).unwrap();
    let t = target(big_r, small_r);
    let period = t.periods();
    let map = flat_torus_map(&mesh, &t).unwrap();
    let phi = FlatTorusMap::from_surface(&mesh.positions, &mesh.faces, &t);
    assert_eq!(phi.count_flipped(&mesh.faces, period), 0);
    let ratio = |f: usize| {
        signed(map.corners(&mesh.faces, f, period)) / signed(phi.corners(&mesh.faces, f, period))
    };
    // Cell (0, 0) is on the outer equator, cell (0, m/2) on the inner one.
    let outer = ratio(0);
    let inner = ratio(2 * (m / 2));
    let expect = (big_r + small_r) / (big_r - small_r);
    assert!(
        (inner / outer / expect - 1.0).abs() < 0.03,
        "{inner} / {outer}"
    );
}

#[test]
fn thick_torus_sends_the_meridian_along_the_long_side() {
    // R = 1.1, r = 1: the conformal period of the meridian, 2πr/√(R² − r²) ≈ 13.7, exceeds that
    // of the longitude, 2π; the least distorted assignment puts the meridian on the 2πR side.
    let (big_r, small_r, n, m) = (1.1, 1.0, 48, 48);
    let mesh = generate::torus(big_r, small_r, n, m).unwrap();
    let t = target(big_r, small_r);
    let period = t.periods();
    let map = flat_torus_map(&mesh, &t).unwrap();
    assert_eq!(map.count_flipped(&mesh.faces, period), 0);
    let meridian: Vec<u32> = (0..m as u32).collect();
    let longitude: Vec<u32> = (0..n as u32).map(|i| i * m as u32).collect();
    let q = path_period(&map, &mesh.faces, period, &meridian);
    assert!(
        (q[0].abs() - 1.0).abs() < 1e-9 && q[1].abs() < 1e-9,
        "meridian {q:?}"
    );
    let q = path_period(&map, &mesh.faces, period, &longitude);
    assert!(
        q[0].abs() < 1e-9 && (q[1].abs() - 1.0).abs() < 1e-9,
        "longitude {q:?}"
    );
    // And the slim torus keeps the longitude on the long side.
    let mesh = generate::torus(3.0, 1.0, n, m).unwrap();
    let map = flat_torus_map(&mesh, &target(3.0, 1.0)).unwrap();
    let q = path_period(&map, &mesh.faces, target(3.0, 1.0).periods(), &longitude);
    assert!(
        (q[0].abs() - 1.0).abs() < 1e-9 && q[1].abs() < 1e-9,
        "longitude {q:?}"
    );
}

/// A torus with its vertices renumbered, its faces shuffled and their corners rotated, and
/// its vertices moved off the surface of revolution.
fn scrambled_torus(n: usize, m: usize) -> TriMesh {
    let mesh = generate::torus(2.0, 0.7, n, m).unwrap();
    let nv = mesh.n_vertices();
    // A fixed permutation: multiply by a unit modulo nv.
    let mut unit = 7919 % nv;
    while gcd(unit, nv) != 1 {
        unit += 1;
    }
    let perm: Vec<u32> = (0..nv).map(|v| ((v * unit) % nv) as u32).collect();
    let mut positions = vec![[0.0; 3]; nv];
    for (v, p) in mesh.positions.iter().enumerate() {
        let s = (v as f64 * 12.9898).sin() * 0.08;
        let c = (v as f64 * 78.233).cos() * 0.08;
        positions[perm[v] as usize] = [p[0] * (1.0 + s), p[1] * (1.0 + c), p[2] + 0.5 * s * c];
    }
    let nf = mesh.n_faces();
    let mut faces: Vec<[u32; 3]> = (0..nf)
        .map(|f| {
            let t = mesh.faces[(f * 37) % nf].map(|v| perm[v as usize]);
            match f % 3 {
                0 => t,
                1 => [t[1], t[2], t[0]],
                _ => [t[2], t[0], t[1]],
            }
        })
        .collect();
    if gcd(37, nf) != 1 {
        faces = mesh
            .faces
            .iter()
            .map(|t| t.map(|v| perm[v as usize]))
            .collect();
    }
    TriMesh::new(positions, faces)
}

fn gcd(a: usize, b: usize) -> usize {
    if b == 0 { a } else { gcd(b, a % b) }
}

#[test]
fn scrambled_bumpy_torus_still_maps_bijectively() {
    let mesh = scrambled_torus(50, 23);
    let t = target(2.0, 1.0);
    let period = t.periods();
    let (map, report) = flat_torus_map_with_report(&mesh, &t).unwrap();
    assert_eq!(map.count_flipped(&mesh.faces, period), 0, "{report:?}");
    assert_consistent(&map, &mesh.faces, period);
    let area = total_planar_area(&map, &mesh.faces, period);
    assert!((area - period[0] * period[1]).abs() < 1e-9 * area);
}

#[test]
fn every_weight_choice_gives_a_valid_map() {
    let mesh = scrambled_torus(30, 17);
    let t = target(2.0, 1.0);
    let period = t.periods();
    let setup = Setup::new(&mesh).unwrap();
    let mut distortion = Vec::new();
    let mut region = vec![false; mesh.n_faces()];
    region[0] = true;
    let choices = [
        setup.cot.clone(),
        weights::raised_cotangent(&setup.cot, &setup.cut.twin, Some(&region)),
        weights::raised_cotangent(&setup.cot, &setup.cut.twin, None),
        weights::uniform(mesh.n_faces()),
    ];
    for (kind, w) in choices.iter().enumerate() {
        let a = setup.attempt(&mesh, &t, w).unwrap();
        assert!(a.flipped.is_empty(), "weights {kind}");
        assert_consistent(&a.map, &mesh.faces, period);
        let area = total_planar_area(&a.map, &mesh.faces, period);
        assert!((area - period[0] * period[1]).abs() < 1e-9 * area);
        distortion.push(a.conformal_distortion);
    }
    // The cotangent map is the least distorted (it minimises the Dirichlet energy).
    for d in &distortion[1..] {
        assert!(distortion[0] <= d + 1e-12, "{distortion:?}");
    }
}

#[test]
fn positive_weights_are_positive_and_keep_positive_edges() {
    let mesh = scrambled_torus(20, 11);
    let cut = CutGraph::new(mesh.n_vertices(), &mesh.faces).unwrap();
    let mut cot = cotangent_weights(&mesh.positions, &mesh.faces);
    // Make one edge strongly negative.
    cot[0][0] = -5.0;
    cot[1][1] = -5.0;
    let facing = |w: &[[f64; 3]], h: usize| w[h / 3][(h % 3 + 2) % 3];
    let pos = weights::raised_cotangent(&cot, &cut.twin, None);
    for h in 0..3 * mesh.n_faces() {
        let t = cut.twin[h] as usize;
        let before = facing(&cot, h) + facing(&cot, t);
        let after = facing(&pos, h) + facing(&pos, t);
        assert!(after > 0.0);
        if before > 1e-2 {
            assert!((after - before).abs() < 1e-12 * before);
        }
    }
    // Raised only around face 0: face 1's negative edge (corner 1 faces half-edge 3 + 2)
    // keeps its weight unless it touches face 0.
    let mut region = vec![false; mesh.n_faces()];
    region[0] = true;
    let local = weights::raised_cotangent(&cot, &cut.twin, Some(&region));
    for h in 0..3 * mesh.n_faces() {
        let t = cut.twin[h] as usize;
        let after = facing(&local, h) + facing(&local, t);
        if h / 3 == 0 || t / 3 == 0 {
            assert!(after > 0.0);
        } else {
            assert_eq!(after, facing(&cot, h) + facing(&cot, t));
        }
    }
    let grown = weights::grow(&mesh.faces, mesh.n_vertices(), &region);
    let ring = grown.iter().filter(|&&g| g).count();
    // The faces around the three corners of face 0 (6 each on this grid, shared ones once).
    assert!((4..=18).contains(&ring), "{ring}");
}

#[test]
fn unused_vertices_are_allowed() {
    let mut mesh = generate::torus(2.0, 1.0, 12, 8).unwrap();
    mesh.positions.push([100.0, 0.0, 0.0]);
    let t = target(2.0, 1.0);
    let map = flat_torus_map(&mesh, &t).unwrap();
    assert_eq!(map.points.len(), mesh.n_vertices());
    assert_eq!(map.count_flipped(&mesh.faces, t.periods()), 0);
}

#[test]
fn torus_of_revolution_is_translated_onto_its_own_equators() {
    // φ shrinks faces near v = ±πr and stretches them near v = 0: the area-balancing shift puts
    // the outer equator (θ = 0) at v = 0 and the inner one (θ = π) at v = ±πr, as φ⁻¹ does.
    let (big_r, small_r, n, m) = (2.0, 1.0, 60, 40);
    let mut mesh = generate::torus(big_r, small_r, n, m).unwrap();
    // Start the faces at cell (0, m/4): the pinned vertex (the first corner of face 0) is then
    // on the top of the tube, θ = π/2.
    mesh.faces.rotate_left(2 * (m / 4));
    let t = target(big_r, small_r);
    let (map, report) = flat_torus_map_with_report(&mesh, &t).unwrap();
    assert!(report.v_shift > 0.1, "{report:?}");
    let tolerance = 0.01 * small_r;
    for i in 0..n {
        let outer = map.points[i * m][1];
        let inner = map.points[i * m + m / 2][1];
        assert!(outer.abs() < tolerance, "outer equator at v = {outer}");
        assert!(
            (inner.abs() - PI * small_r).abs() < tolerance,
            "inner at v = {inner}"
        );
    }
    // φ⁻¹ itself has no area distortion on this mesh; the harmonic map's comes from its v
    // spacing: source over torus area ∝ (R + r cos θ)² / (R + r cos(v/r)), 3 times larger on
    // the outer equator than on the inner one.
    assert!(
        report.area_distortion > 0.2 && report.area_distortion < 0.6,
        "{report:?}"
    );
    assert_eq!(
        translation::area_balanced_shift(&map, &mesh.faces, &t, &[1.0]),
        0.0,
        "a target of the wrong length is ignored"
    );
}

/// The torus of revolution R = 2, r = 1 on an n × m grid whose (u, v) parameters are moved by
/// up to `amp` cells (a fixed pseudo-random pattern): many obtuse triangles.
fn jittered_torus(n: usize, m: usize, amp: f64) -> TriMesh {
    let mut mesh = generate::torus(2.0, 1.0, n, m).unwrap();
    let noise = |x: f64| x - x.floor() - 0.5;
    for i in 0..n {
        for j in 0..m {
            let du = noise(((i * 31 + j * 17) as f64 * 12.9898).sin() * 43758.5453) * 2.0 * amp;
            let dv = noise(((i * 13 + j * 7) as f64 * 78.233).sin() * 12345.678) * 2.0 * amp;
            let u = 2.0 * PI * (i as f64 + du) / n as f64;
            let v = 2.0 * PI * (j as f64 + dv) / m as f64;
            let rho = 2.0 + v.cos();
            mesh.positions[i * m + j] = [rho * u.cos(), rho * u.sin(), v.sin()];
        }
    }
    mesh
}

#[test]
fn folded_cotangent_map_is_repaired_with_positive_weights_around_the_folds() {
    let mesh = jittered_torus(80, 40, 0.45);
    let t = target(2.0, 1.0);
    let period = t.periods();
    let setup = Setup::new(&mesh).unwrap();
    let cotangent = setup.attempt(&mesh, &t, &setup.cot).unwrap();
    let folds = cotangent.flipped.len();
    assert!(folds > 0, "this mesh should fold the cotangent map");
    let (map, report) = flat_torus_map_with_report(&mesh, &t).unwrap();
    assert_eq!(report.rejected[0], (HarmonicWeights::Cotangent, folds));
    assert_eq!(
        report.weights,
        HarmonicWeights::LocallyPositive,
        "{report:?}"
    );
    assert_eq!(map.count_flipped(&mesh.faces, period), 0);
    assert_consistent(&map, &mesh.faces, period);
    let area = total_planar_area(&map, &mesh.faces, period);
    assert!((area - period[0] * period[1]).abs() < 1e-9 * area);
    // Still nearly conformal: only the edges around the folds were changed.
    eprintln!(
        "distortion {} (cotangent map {}), {report:?}",
        report.conformal_distortion, cotangent.conformal_distortion
    );
    assert!(report.conformal_distortion < cotangent.conformal_distortion * 1.01);
    // The globally positive weights are an embedding too, but further from conformal.
    let all = weights::raised_cotangent(&setup.cot, &setup.cut.twin, None);
    let positive = setup.attempt(&mesh, &t, &all).unwrap();
    assert!(positive.flipped.is_empty());
    eprintln!(
        "all weights positive: distortion {}",
        positive.conformal_distortion
    );
}
