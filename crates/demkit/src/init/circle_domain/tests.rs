//! Tests of the circle-domain map.

use super::*;
use crate::generate;
use crate::qc::beltrami_coefficient_surface;

fn mean_mu(mesh: &TriMesh, d: &CircleDomain) -> (f64, f64) {
    let mu = beltrami_coefficient_surface(&mesh.positions, &d.positions, &mesh.faces);
    let mean = mu.iter().map(|m| m.norm()).sum::<f64>() / mu.len() as f64;
    let max = mu.iter().map(|m| m.norm()).fold(0.0, f64::max);
    (mean, max)
}

fn run(mesh: &TriMesh) -> (CircleDomain, CircleDomainReport) {
    let loops = topology(mesh).boundary_loops;
    circle_domain_map_with_report(mesh, &loops).unwrap()
}

/// Zero flips and every boundary vertex on its circle to 1e-12 relative.
fn check_domain(d: &CircleDomain, faces: &[[u32; 3]]) {
    let flips = crate::geometry::count_nonpositive(&d.positions, faces);
    assert_eq!(flips, 0);
    assert_eq!(d.centers[0], [0.0, 0.0]);
    assert_eq!(d.radii[0], 1.0);
    for (l, lp) in d.loops.iter().enumerate() {
        let (c, r) = (d.centers[l], d.radii[l]);
        for &v in lp {
            let p = d.positions[v as usize];
            let off = ((p[0] - c[0]).hypot(p[1] - c[1]) - r).abs();
            assert!(
                off <= 1e-12 * r,
                "loop {l} vertex {v} off its circle by {off}"
            );
        }
    }
}

/// Inversive distance of two circles, invariant under Möbius maps:
/// `|r₁² + r₂² − |c₁ − c₂|²| / (2 r₁ r₂)`.
fn inversive(c1: [f64; 2], r1: f64, c2: [f64; 2], r2: f64) -> f64 {
    let d2 = (c1[0] - c2[0]).powi(2) + (c1[1] - c2[1]).powi(2);
    (r1 * r1 + r2 * r2 - d2).abs() / (2.0 * r1 * r2)
}

fn lifted(holes: &[(f64, f64, f64)], resolution: usize) -> TriMesh {
    let mut mesh = generate::disk_with_holes(holes, resolution).unwrap();
    for p in &mut mesh.positions {
        p[2] = 0.3 * (p[0] * p[0] - p[1] * p[1]);
    }
    mesh
}

#[test]
fn energy_is_zero_for_similarities_and_its_gradient_is_exact() {
    let flat = generate::disk_with_holes(&[(0.3, 0.1, 0.2)], 24).unwrap();
    let g = Geometry::new(&flat);
    let sim: Vec<C64> = complex_positions(&flat.positions)
        .iter()
        .map(|&z| C64::new(0.5, 2.0) * z + 3.0)
        .collect();
    assert!(g.conformal_energy(&sim, None) < 1e-24);
    // Central differences of the (quadratic) energy are exact up to rounding.
    let mesh = lifted(&[(0.3, 0.1, 0.2)], 24);
    let geo = Geometry::new(&mesh);
    let weights: Vec<f64> = (0..mesh.faces.len())
        .map(|t| 1.0 + (t % 3) as f64)
        .collect();
    let z: Vec<C64> = complex_positions(&mesh.positions)
        .iter()
        .map(|&z| z + 0.2 * z * z)
        .collect();
    let y = geo.gradient(&z, &weights);
    for v in [0, 7, 30, mesh.n_vertices() - 1] {
        for dir in [C64::new(1.0, 0.0), C64::new(0.0, 1.0)] {
            let h = 1e-4;
            let mut zp = z.clone();
            zp[v] += h * dir;
            let mut zm = z.clone();
            zm[v] -= h * dir;
            let fd = (geo.conformal_energy(&zp, Some(&weights))
                - geo.conformal_energy(&zm, Some(&weights)))
                / (2.0 * h);
            assert!(
                (fd - dot2(dir, y[v])).abs() < 1e-8 * (1.0 + fd.abs()),
                "vertex {v}: {fd} vs {}",
                dot2(dir, y[v])
            );
        }
    }
}

#[test]
fn normal_matrix_is_the_energy_curvature() {
    // E_C is quadratic: along any δ of the unknowns, δᵀ (Pᵀ H P) δ = 2 E_C(P δ).
    let mesh = lifted(&[(0.3, 0.1, 0.2), (-0.4, -0.2, 0.15)], 20);
    let loops = ordered_loops(&mesh, &topology(&mesh).boundary_loops).unwrap();
    let geo = Geometry::new(&mesh);
    let pin = farthest_from_boundary(&geo, &loops);
    let layout = Layout::new(geo.n, &loops, pin, &[loops[0][0]], Holes::OnCircles);
    let order = geo.vertex_order().unwrap();
    let mut sys = NormalSystem::new(&geo, layout, &order).unwrap();
    let state = State {
        z: complex_positions(&mesh.positions),
        centers: vec![C64::new(0.0, 0.0), C64::new(0.3, 0.1), C64::new(-0.4, -0.2)],
        radii: vec![1.0, 0.2, 0.15],
    };
    let lin = circle_constraints(&state, &loops);
    let weights: Vec<f64> = (0..mesh.faces.len())
        .map(|t| 1.0 + (t % 2) as f64)
        .collect();
    sys.factor(&geo, &weights, &lin.u, 0.0, None).unwrap();
    let delta: Vec<f64> = (0..sys.layout.n_unknowns)
        .map(|k| ((k * 7919) % 13) as f64 / 13.0 - 0.5)
        .collect();
    let pd: Vec<C64> = (0..geo.n)
        .map(|v| {
            let (basis, len) = sys.layout.basis(v, lin.u[v]);
            basis[..len]
                .iter()
                .map(|&(id, m)| delta[id as usize] * m)
                .sum()
        })
        .collect();
    let kd = sys.pattern.mul(&sys.values, &delta);
    let quad: f64 = kd.iter().zip(&delta).map(|(a, b)| a * b).sum();
    let e = geo.conformal_energy(&pd, Some(&weights));
    assert!((quad - 2.0 * e).abs() < 1e-10 * e, "{quad} vs {}", 2.0 * e);
    // The step solves the normal equations K δ = −Pᵀ y.
    let y = geo.gradient(&state.z, &weights);
    let g = sys.gradient(&y, &lin.u, &state, 0.0);
    let step = sys.solve(g.clone()).unwrap();
    let ks = sys.pattern.mul(&sys.values, &step);
    for (a, b) in ks.iter().zip(&g) {
        assert!((a + b).abs() < 1e-8 * (1.0 + b.abs()));
    }
}

/// The disk automorphism of the planar points `p` (scaled by `1 / scale`) sending the
/// pinned vertex to the origin and the first outer vertex to angle 0: the exact map when
/// the input already is a circle domain (up to scale).
fn exact_map(p: &[[f64; 3]], scale: f64, d: &CircleDomain, pin: u32) -> Vec<[f64; 3]> {
    let w: Vec<C64> = p.iter().map(|q| C64::new(q[0], q[1]) / scale).collect();
    let mut m = Mobius {
        a: w[pin as usize],
        rotation: C64::new(1.0, 0.0),
    };
    let first = m.apply(w[d.loops[0][0] as usize]);
    m.rotation = first.conj() / first.norm();
    w.iter()
        .map(|&z| {
            let q = m.apply(z);
            [q.re, q.im, 0.0]
        })
        .collect()
}

/// The mean |μ| of the map is within 5% (+0.001) of that of the exact map's piecewise-linear
/// interpolation, which is not zero on a coarse mesh.
fn assert_close_to_exact_mu(mesh: &TriMesh, d: &CircleDomain, exact: Vec<[f64; 3]>) {
    let (mean, _) = mean_mu(mesh, d);
    let exact = CircleDomain {
        positions: exact,
        ..d.clone()
    };
    let (base, _) = mean_mu(mesh, &exact);
    assert!(
        mean <= 1.05 * base + 1e-3,
        "mean |mu| {mean}, exact map's {base}"
    );
}

/// Largest distance between the discrete map and the [`exact_map`].
fn deviation(d: &CircleDomain, exact: &[[f64; 3]]) -> f64 {
    exact
        .iter()
        .zip(&d.positions)
        .map(|(e, q)| (e[0] - q[0]).hypot(e[1] - q[1]))
        .fold(0.0, f64::max)
}

/// The input hole each output loop is (nearest centre), for loops of `disk_with_holes`.
fn hole_of_loop(mesh: &TriMesh, lp: &[u32], holes: &[(f64, f64, f64)]) -> usize {
    let c = lp.iter().fold(C64::new(0.0, 0.0), |s, &v| {
        s + C64::new(mesh.positions[v as usize][0], mesh.positions[v as usize][1])
    }) / lp.len() as f64;
    (0..holes.len())
        .min_by(|&i, &j| {
            let d = |k: usize| (c - C64::new(holes[k].0, holes[k].1)).norm();
            d(i).total_cmp(&d(j))
        })
        .unwrap_or(0)
}

#[test]
fn annulus_keeps_its_conformal_modulus() {
    // The annulus r ≤ |z| ≤ R is a circle domain once scaled by 1/R: the map is the disk
    // automorphism of the normalisation, and the inversive distance (1 + q²) / (2q) of its
    // two circles, q = r / R (Möbius-invariant), is kept.
    let (r, big_r) = (0.4, 1.3);
    let mesh = generate::annulus(r, big_r, 12, 96).unwrap();
    let (d, report) = run(&mesh);
    check_domain(&d, &mesh.faces);
    assert!(report.converged, "{report:?}");
    let inv = inversive(d.centers[0], d.radii[0], d.centers[1], d.radii[1]);
    let q = inv - (inv * inv - 1.0).sqrt();
    assert!((q - r / big_r).abs() < 1e-3, "modulus {q} vs {}", r / big_r);
    let pin = report.pinned_vertex.unwrap();
    assert_eq!(d.positions[pin as usize], [0.0, 0.0, 0.0]);
    let first = d.positions[d.loops[0][0] as usize];
    assert!((first[0] - 1.0).abs() < 1e-15 && first[1].abs() < 1e-15);
    let exact = exact_map(&mesh.positions, big_r, &d, pin);
    let dev = deviation(&d, &exact);
    assert!(dev < 0.02, "deviation from the exact map {dev}");
    assert_close_to_exact_mu(&mesh, &d, exact);
    // Second-order convergence to the exact map under refinement.
    let fine = generate::annulus(r, big_r, 24, 192).unwrap();
    let (df, rf) = run(&fine);
    let exact = exact_map(&fine.positions, big_r, &df, rf.pinned_vertex.unwrap());
    let dev_fine = deviation(&df, &exact);
    assert!(dev_fine < dev / 3.0, "deviation {dev} then {dev_fine}");
}

#[test]
fn circle_domain_maps_to_a_mobius_image_of_itself() {
    // A disk with round holes is already a circle domain: the map is a disk automorphism,
    // which keeps every pair of circles' inversive distance. Lifted onto the unit sphere by
    // the inverse stereographic projection (conformal, circles to circles) it has the same
    // map.
    let holes = [(0.35, 0.2, 0.2), (-0.4, -0.1, 0.25), (0.1, -0.55, 0.15)];
    let flat = generate::disk_with_holes(&holes, 128).unwrap();
    let mut sphere = flat.clone();
    for p in &mut sphere.positions {
        let s = 1.0 + p[0] * p[0] + p[1] * p[1];
        *p = [2.0 * p[0] / s, 2.0 * p[1] / s, (s - 2.0) / s];
    }
    for mesh in [&flat, &sphere] {
        let (d, report) = run(mesh);
        check_domain(&d, &mesh.faces);
        assert!(report.converged, "{report:?}");
        let exact = exact_map(&flat.positions, 1.0, &d, report.pinned_vertex.unwrap());
        let dev = deviation(&d, &exact);
        assert!(dev < 0.01, "deviation from the exact map {dev}");
        assert_close_to_exact_mu(mesh, &d, exact);
        let circle = |l: usize| match l {
            0 => ([0.0, 0.0], 1.0),
            _ => {
                let h = holes[hole_of_loop(&flat, &d.loops[l], &holes)];
                ([h.0, h.1], h.2)
            }
        };
        for i in 0..d.loops.len() {
            for j in 0..i {
                let ((ci, ri), (cj, rj)) = (circle(i), circle(j));
                let want = inversive(ci, ri, cj, rj);
                let got = inversive(d.centers[i], d.radii[i], d.centers[j], d.radii[j]);
                assert!(
                    (got - want).abs() < 0.01 * want,
                    "circles {i},{j}: {got} vs {want}"
                );
            }
        }
    }
}

#[test]
fn disk_maps_onto_the_unit_disk() {
    // The unit disk lifted onto the sphere by the inverse stereographic projection: its
    // conformal map is the projection back, up to a disk automorphism.
    let flat = generate::disk_with_holes(&[], 64).unwrap();
    let mut cap = flat.clone();
    for p in &mut cap.positions {
        let s = 1.0 + p[0] * p[0] + p[1] * p[1];
        *p = [2.0 * p[0] / s, 2.0 * p[1] / s, (s - 2.0) / s];
    }
    let (d, report) = run(&cap);
    check_domain(&d, &cap.faces);
    assert_eq!(d.loops.len(), 1);
    assert!(report.converged, "{report:?}");
    let exact = exact_map(&flat.positions, 1.0, &d, report.pinned_vertex.unwrap());
    let dev = deviation(&d, &exact);
    assert!(dev < 5e-3, "deviation from the exact map {dev}");
    assert_close_to_exact_mu(&cap, &d, exact);
    // A rectangle: its corners are singular points of the map onto the disk (angle π/2
    // opened to π), where the coarse grid cannot be conformal.
    let mesh = generate::square_grid(24, 16, 1.5, 1.0).unwrap();
    let (d, report) = run(&mesh);
    check_domain(&d, &mesh.faces);
    assert!(report.converged, "{report:?}");
    let (mean, _) = mean_mu(&mesh, &d);
    assert!(mean < 0.07, "mean |mu| {mean}");
}

#[test]
fn curved_surface_with_holes() {
    let mesh = lifted(&[(0.3, 0.25, 0.2), (-0.35, -0.2, 0.2)], 96);
    let (d, report) = run(&mesh);
    check_domain(&d, &mesh.faces);
    assert!(report.converged, "{report:?}");
    assert!(report.conformal_energy <= report.initial_energy);
    let (mean, _) = mean_mu(&mesh, &d);
    assert!(mean < 0.02, "mean |mu| {mean}");
    // The outer loop is the one spanning the largest area, whatever the input order.
    let mut loops = topology(&mesh).boundary_loops;
    loops.reverse();
    let d2 = circle_domain_map(&mesh, &loops).unwrap();
    assert_eq!(d2.loops[0], d.loops[0]);
    assert_eq!(d2.loops[1], loops[0]);
}

/// A unit square minus the square `[0.35, 0.65]²`, on an `n × n` grid.
fn square_frame(n: usize) -> TriMesh {
    let grid = generate::square_grid(n, n, 1.0, 1.0).unwrap();
    let inside = |x: f64| (0.35..=0.65).contains(&x);
    let faces = grid
        .faces
        .iter()
        .copied()
        .filter(|f| {
            let c = f.iter().fold([0.0, 0.0], |c, &v| {
                let p = grid.positions[v as usize];
                [c[0] + p[0] / 3.0, c[1] + p[1] / 3.0]
            });
            !(inside(c[0]) && inside(c[1]))
        })
        .collect();
    crate::mesh::validate::validate(TriMesh::new(grid.positions, faces))
        .unwrap()
        .0
}

/// The radius ratio of the concentric annulus conformal to the circle domain `d` (two
/// loops): from the inversive distance `I`, `q = I − √(I² − 1)`.
fn modulus(d: &CircleDomain) -> f64 {
    let inv = inversive(d.centers[0], d.radii[0], d.centers[1], d.radii[1]);
    inv - (inv * inv - 1.0).sqrt()
}

#[test]
fn polygonal_hole_becomes_a_circle() {
    // Square boundaries: the hole starts as a square around its fan vertex and is pulled
    // onto a circle. The conformal modulus of the frame converges under refinement.
    let coarse = square_frame(40);
    let (d, report) = run(&coarse);
    check_domain(&d, &coarse.faces);
    assert!(report.converged, "{report:?}");
    let fine = square_frame(80);
    let (df, _) = run(&fine);
    check_domain(&df, &fine.faces);
    let (q, qf) = (modulus(&d), modulus(&df));
    assert!((q - qf).abs() < 5e-3 * qf, "modulus {q} then {qf}");
    let (mean, _) = mean_mu(&fine, &df);
    assert!(mean < 0.05, "mean |mu| {mean}");
}

#[test]
fn mesh_without_interior_vertices() {
    // One ring of faces: every vertex is on a boundary; three outer vertices are pinned.
    let mesh = generate::annulus(0.5, 1.0, 1, 16).unwrap();
    let (d, _) = run(&mesh);
    check_domain(&d, &mesh.faces);
    let tri = TriMesh::new(
        vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
        vec![[0, 1, 2]],
    );
    let (d, _) = run(&tri);
    check_domain(&d, &tri.faces);
}

#[test]
fn bad_input_is_an_error() {
    let closed = generate::icosphere(1).unwrap();
    assert!(matches!(
        circle_domain_map(&closed, &[]),
        Err(Error::Topology { .. })
    ));
    let mesh = generate::annulus(0.5, 1.0, 2, 16).unwrap();
    let loops = topology(&mesh).boundary_loops;
    assert!(circle_domain_map(&mesh, &loops[..1]).is_err());
    assert!(circle_domain_map(&mesh, &[vec![0, 1]]).is_err());
    assert!(circle_domain_map(&mesh, &[vec![0, 1, 999]]).is_err());
    let torus = generate::torus(2.0, 1.0, 12, 8).unwrap();
    assert!(circle_domain_map(&torus, &[vec![0, 1, 2]]).is_err());
    // Reversed loops: the Tutte map is inside out.
    let rev: Vec<Vec<u32>> = loops
        .iter()
        .map(|l| l.iter().rev().copied().collect())
        .collect();
    assert!(matches!(
        circle_domain_map(&mesh, &rev),
        Err(Error::Numerical(_))
    ));
}
