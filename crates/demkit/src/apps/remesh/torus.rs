//! Remeshing through a map onto the flat torus (TDEM paper §5): TDEM equalizes density with
//! respect to the area of the torus of revolution with radii (R, r), so the points are laid out
//! uniformly on that torus — rings of constant tube angle, equally spaced along the tube, each
//! ring with as many points as its circumference holds — and consecutive rings are joined by
//! strips of triangles, which closes the mesh into a torus by construction. Every point is then
//! pulled back onto the input surface through the inverse map.

use super::Layout;
use super::sampling::{fit_spacing, hex_spacing};
use crate::geometry::torus::Torus;
use std::f64::consts::PI;

/// About `n` points uniformly spread over the torus of revolution, in flat coordinates `(u, v) =
/// (Rφ, rθ)` (z = 0), joined
/// into a closed genus-one triangulation: an even number (≥ 4) of rings of constant θ, `h√3/2`
/// apart along the tube, each with `max(3, round(2π(R + r cos θ)/h))` points `h` apart
/// (alternate rings shifted by half a step), so that triangles are close to equilateral on the
/// torus; `h` is adjusted until the count is within 1 % of `n` (or the steps run out).
pub fn layout_torus(torus: &Torus, n: usize) -> Layout {
    let (big, small) = (torus.major, torus.minor);
    let area = 4.0 * PI * PI * big * small;
    let rings = fit_spacing(
        hex_spacing(area, n),
        n,
        |h| ring_sizes(big, small, h),
        |r| r.iter().sum(),
    );
    join_rings(torus, &rings)
}

/// Points per ring for spacing `h`.
fn ring_sizes(big: f64, small: f64, h: f64) -> Vec<usize> {
    let m = 2 * ((PI * small / (h * 3f64.sqrt() / 2.0)).round() as usize).max(2);
    (0..m)
        .map(|j| {
            let theta = ring_angle(j, m);
            ((2.0 * PI * (big + small * theta.cos()) / h).round() as usize).max(3)
        })
        .collect()
}

/// The tube angle of ring `j` of `m`, in [−π, π).
fn ring_angle(j: usize, m: usize) -> f64 {
    -PI + 2.0 * PI * j as f64 / m as f64
}

/// The points of every ring and the strips of triangles between consecutive rings (the last
/// ring joined to the first across the period).
fn join_rings(torus: &Torus, rings: &[usize]) -> Layout {
    let [a, b] = torus.periods();
    let m = rings.len();
    let mut first = Vec::with_capacity(m + 1);
    let mut points = Vec::new();
    for (j, &k) in rings.iter().enumerate() {
        first.push(points.len());
        let v = b * ring_angle(j, m) / (2.0 * PI);
        let shift = if j % 2 == 1 { 0.5 } else { 0.0 };
        points.extend((0..k).map(|i| [a * (i as f64 + shift) / k as f64, v]));
    }
    first.push(points.len());
    let mut faces = Vec::with_capacity(2 * points.len());
    for j in 0..m {
        let next = (j + 1) % m;
        // The ring above, lifted by one period in v when it wraps.
        let lift = if next == 0 { b } else { 0.0 };
        strip(
            torus,
            &points,
            (first[j], rings[j]),
            (first[next], rings[next]),
            lift,
            &mut faces,
        );
    }
    Layout {
        fixed: vec![None; points.len()],
        domain: points.iter().map(|p| [p[0], p[1], 0.0]).collect(),
        faces,
    }
}

/// Triangulates the band between ring `lower` and ring `upper` (each `(first index, size)`):
/// walking both rings together in u, each step closes a triangle with the next point of one
/// ring, the one giving the shorter diagonal on the torus.
fn strip(
    torus: &Torus,
    points: &[[f64; 2]],
    lower: (usize, usize),
    upper: (usize, usize),
    lift: f64,
    faces: &mut Vec<[u32; 3]>,
) {
    let a = torus.periods()[0];
    // Point i of a ring, unwrapped: index i ≥ size means one period further in u.
    let at = |(first, size): (usize, usize), i: usize, dv: f64| -> ([f64; 2], u32) {
        let p = points[first + i % size];
        (
            [p[0] + a * (i / size) as f64, p[1] + dv],
            (first + i % size) as u32,
        )
    };
    // Start the upper ring at its point nearest (in u, modulo the period) to the lower ring's
    // first point, and unwrap it so that it lies within half a step of it.
    let u0 = points[lower.0][0];
    let start = (0..upper.1)
        .min_by(|&x, &y| {
            let d = |i: usize| {
                let du = (points[upper.0 + i][0] - u0).rem_euclid(a);
                du.min(a - du)
            };
            d(x).total_cmp(&d(y))
        })
        .unwrap_or(0);
    let (mut i, mut l) = (0usize, 0usize);
    let upper_at = |l: usize| {
        let (mut p, v) = at(upper, start + l, lift);
        let base = points[upper.0 + start][0];
        let ubase = if (base - u0) > 0.5 * a {
            base - a
        } else if (u0 - base) > 0.5 * a {
            base + a
        } else {
            base
        };
        p[0] += ubase - base;
        (p, v)
    };
    while i < lower.1 || l < upper.1 {
        let (pa, va) = at(lower, i, 0.0);
        let (pb, vb) = upper_at(l);
        let advance_lower = if i == lower.1 {
            false
        } else if l == upper.1 {
            true
        } else {
            let (qa, _) = at(lower, i + 1, 0.0);
            let (qb, _) = upper_at(l + 1);
            dist3(torus, qa, pb) < dist3(torus, pa, qb)
        };
        if advance_lower {
            let (_, wa) = at(lower, i + 1, 0.0);
            faces.push([va, wa, vb]);
            i += 1;
        } else {
            let (_, wb) = upper_at(l + 1);
            faces.push([va, wb, vb]);
            l += 1;
        }
    }
}

/// The distance in space between the points of the torus at flat coordinates `p` and `q`.
fn dist3(torus: &Torus, p: [f64; 2], q: [f64; 2]) -> f64 {
    let (x, y) = (torus.project(p), torus.project(q));
    (0..3).map(|d| (x[d] - y[d]).powi(2)).sum::<f64>().sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::TriMesh;
    use crate::geometry::torus::FlatTorusMap;
    use crate::mesh::topology::topology;

    #[test]
    fn the_layout_is_a_closed_torus_with_the_asked_count() {
        let t = Torus::new(2.0, 1.0).unwrap();
        for n in [16, 100, 1000, 5000] {
            let l = layout_torus(&t, n);
            let mesh = TriMesh::new(
                l.domain.iter().map(|p| t.project([p[0], p[1]])).collect(),
                l.faces,
            );
            let topo = topology(&mesh);
            assert_eq!(topo.boundary_loops.len(), 0, "n = {n}");
            assert_eq!(topo.genus, 1, "n = {n}");
            assert_eq!(topo.components, 1);
            assert_eq!(mesh.faces.len(), 2 * mesh.positions.len());
            let off = (mesh.n_vertices() as f64 - n as f64).abs() / n as f64;
            assert!(off <= 0.1, "n = {n}: {}", mesh.n_vertices());
            assert!(crate::mesh::check(&mesh).is_valid(), "n = {n}");
            // Outward normals: the face normal points away from the tube's centre line.
            for f in &mesh.faces {
                let [a, b, c] = f.map(|v| mesh.positions[v as usize]);
                let nrm =
                    crate::geometry::cross(crate::geometry::sub(b, a), crate::geometry::sub(c, a));
                let g = [0, 1, 2].map(|d| (a[d] + b[d] + c[d]) / 3.0);
                let rho = g[0].hypot(g[1]);
                let centre = [2.0 * g[0] / rho, 2.0 * g[1] / rho, 0.0];
                let out = crate::geometry::sub(g, centre);
                assert!(crate::geometry::dot(nrm, out) > 0.0);
            }
        }
    }

    #[test]
    fn a_torus_remeshed_through_its_own_map_stays_on_it() {
        let t = Torus::new(3.0, 1.0).unwrap();
        let input = crate::generate::torus(3.0, 1.0, 60, 20).unwrap();
        let map = FlatTorusMap::from_surface(&input.positions, &input.faces, &t);
        assert_eq!(map.count_flipped(&input.faces, t.periods()), 0);
        let area = crate::geometry::face_areas(&input.positions, &input.faces);
        let target = super::super::Target::Torus {
            map: &map,
            torus: &t,
        };
        let out = super::super::remesh(&input, &area, &input.positions, target, 800).unwrap();
        let topo = topology(&out);
        assert_eq!((topo.boundary_loops.len(), topo.genus), (0, 1));
        // On the input's chords: inside the torus by at most the sagitta of its cells.
        for p in &out.positions {
            assert!(t.distance(*p) < 0.02, "{}", t.distance(*p));
        }
    }
}
