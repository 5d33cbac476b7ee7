//! Curvature-based flattening of a surface boundary onto a planar convex polygon
//! (DEM paper, section 4.1.1, Algorithm 1, with the convexity proof of Appendix A).
//!
//! The boundary loop γ of a disk-like surface is a closed space curve. Its unsigned curvature κ
//! (4.2)–(4.3) is rescaled to total 2π (4.5), integrated once to edge directions θ (4.7) and
//! once more, with the edge lengths, to a plane curve φ (4.6). The small gap φ(l) − φ(0) is then
//! distributed along the arclength (4.10), which keeps the curve convex and makes it closed and
//! simple (Proposition A.1).

use std::f64::consts::PI;

/// Flattens the closed boundary loop `boundary` (vertex indices into `positions`, ordered
/// counter-clockwise with respect to the face orientation; the closing edge last → first is
/// implicit) into a planar closed convex polygon: DEM paper, Algorithm 1, eqs. (4.2)–(4.10).
///
/// Discretisation:
/// - edge `j` goes from loop vertex `j` to `j + 1` (cyclically), with its 3D length `L_j`;
/// - the discrete curvature at loop vertex `i` (4.3) is the unsigned turning angle in `[0, π]`
///   between the incoming and the outgoing edge directions in 3D (zero-length edges are skipped:
///   the turn is measured between the nearest edges of positive length);
/// - the turning angles are rescaled to sum to 2π (4.5) (equal angles `2π/b` if they all vanish);
/// - the direction of edge `j` is `θ_j = Σ_{i=1..j} κ_i` (4.7), and `φ_{j+1} = φ_j + L_j (cos θ_j,
///   sin θ_j)` with `φ_0 = 0` (4.6), so every edge keeps its 3D length;
/// - the closing adjustment (4.10) `φ(s) ← φ(s) − (s/l)(φ(l) − φ(0))`, with `s` the arclength of
///   the vertex along the loop and `l` the total length.
///
/// The result has one point per loop vertex, in loop order; loop vertex 0 sits at the origin and
/// the polygon is counter-clockwise (positive signed area), convex and simple (Appendix A):
/// its edge vectors `L_j (u_j − g)`, with `u_j` unit vectors turning monotonically once around
/// and `|g| < 1`, also turn monotonically once around. A planar convex loop is reproduced up to
/// a rigid motion (its turning angles already sum to 2π, so nothing is rescaled or adjusted).
///
/// Loops with fewer than three vertices give a degenerate (but finite) result: no points, the
/// origin, or a segment along the x axis.
pub fn curvature_flatten_boundary(positions: &[[f64; 3]], boundary: &[u32]) -> Vec<[f64; 2]> {
    let b = boundary.len();
    if b == 0 {
        return Vec::new();
    }
    let p = |k: usize| positions[boundary[k % b] as usize];

    // Edge vectors and lengths (edge j: vertex j -> vertex j+1, cyclically).
    let edges: Vec<[f64; 3]> = (0..b).map(|j| sub3(p(j + 1), p(j))).collect();
    let lengths: Vec<f64> = edges.iter().map(|e| norm3(*e)).collect();
    let total: f64 = lengths.iter().sum();
    if b < 3 || total <= 0.0 || !total.is_finite() {
        let mut out = vec![[0.0, 0.0]; b];
        if b == 2 {
            out[1] = [lengths[0], 0.0];
        }
        return out;
    }
    // Edges shorter than this carry no direction.
    let tiny = total * 1e-15;
    let is_real = |j: usize| lengths[j] > tiny;

    // (4.2)-(4.3): discrete curvature = turning angle at each vertex, in [0, pi].
    // The turn at vertex i is between the last real edge before i and edge i (if edge i is real).
    let mut turn = vec![0.0; b];
    if let Some(last_real) = (0..b).rev().find(|&j| is_real(j)) {
        let mut incoming = last_real;
        for (i, t) in turn.iter_mut().enumerate() {
            if !is_real(i) {
                continue;
            }
            if incoming != i {
                *t = turning_angle(edges[incoming], edges[i]);
            }
            incoming = i;
        }
    }
    // (4.5): rescale so that the total signed curvature of the plane curve is 2π.
    let sum: f64 = turn.iter().sum();
    if sum > 0.0 && sum.is_finite() {
        for t in &mut turn {
            *t *= 2.0 * PI / sum;
        }
    } else {
        turn.iter_mut().for_each(|t| *t = 2.0 * PI / b as f64);
    }

    // (4.6)-(4.7): integrate the curvature to directions, the directions to positions.
    let mut phi = Vec::with_capacity(b + 1);
    let mut arclength = Vec::with_capacity(b + 1);
    let (mut x, mut y, mut s, mut theta) = (0.0, 0.0, 0.0, 0.0);
    phi.push([x, y]);
    arclength.push(0.0);
    for j in 0..b {
        if j > 0 {
            theta += turn[j];
        }
        x += lengths[j] * theta.cos();
        y += lengths[j] * theta.sin();
        s += lengths[j];
        phi.push([x, y]);
        arclength.push(s);
    }

    // (4.10): close the curve by distributing the gap along the arclength.
    let gap = [phi[b][0] - phi[0][0], phi[b][1] - phi[0][1]];
    (0..b)
        .map(|j| {
            let f = arclength[j] / total;
            [phi[j][0] - f * gap[0], phi[j][1] - f * gap[1]]
        })
        .collect()
}

/// Unsigned angle in `[0, π]` between two nonzero 3D vectors.
fn turning_angle(u: [f64; 3], w: [f64; 3]) -> f64 {
    let c = cross3(u, w);
    norm3(c).atan2(dot3(u, w))
}

fn sub3(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn dot3(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn cross3(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

fn norm3(a: [f64; 3]) -> f64 {
    dot3(a, a).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn signed_area(p: &[[f64; 2]]) -> f64 {
        let n = p.len();
        (0..n)
            .map(|i| {
                let (a, b) = (p[i], p[(i + 1) % n]);
                a[0] * b[1] - a[1] * b[0]
            })
            .sum::<f64>()
            / 2.0
    }

    fn perimeter2(p: &[[f64; 2]]) -> f64 {
        let n = p.len();
        (0..n)
            .map(|i| {
                let (a, b) = (p[i], p[(i + 1) % n]);
                ((b[0] - a[0]).powi(2) + (b[1] - a[1]).powi(2)).sqrt()
            })
            .sum()
    }

    /// Convex, counter-clockwise and turning exactly once (hence simple).
    fn assert_convex_ccw_simple(p: &[[f64; 2]]) {
        let n = p.len();
        assert!(signed_area(p) > 0.0, "not counter-clockwise");
        let scale = perimeter2(p);
        let mut total_turn = 0.0;
        for i in 0..n {
            let (a, b, c) = (p[(i + n - 1) % n], p[i], p[(i + 1) % n]);
            let u = [b[0] - a[0], b[1] - a[1]];
            let w = [c[0] - b[0], c[1] - b[1]];
            let cr = u[0] * w[1] - u[1] * w[0];
            assert!(cr >= -1e-12 * scale * scale, "reflex vertex {i}: {cr}");
            total_turn += cr.atan2(u[0] * w[0] + u[1] * w[1]);
        }
        assert!((total_turn - 2.0 * PI).abs() < 1e-9, "turning {total_turn}");
    }

    /// Embeds planar points in a tilted plane of R^3 (a rotation plus a translation).
    fn tilt(p: &[[f64; 2]]) -> Vec<[f64; 3]> {
        let e1 = [0.6, 0.0, 0.8];
        let e2 = [0.48, 0.8, -0.36];
        p.iter()
            .map(|q| {
                [
                    1.0 + q[0] * e1[0] + q[1] * e2[0],
                    -2.0 + q[0] * e1[1] + q[1] * e2[1],
                    0.5 + q[0] * e1[2] + q[1] * e2[2],
                ]
            })
            .collect()
    }

    /// All pairwise distances agree: congruent up to a rigid motion.
    fn assert_congruent(p: &[[f64; 2]], q: &[[f64; 2]], tol: f64) {
        assert_eq!(p.len(), q.len());
        let d = |a: [f64; 2], b: [f64; 2]| ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2)).sqrt();
        for i in 0..p.len() {
            for j in 0..p.len() {
                let (dp, dq) = (d(p[i], p[j]), d(q[i], q[j]));
                assert!((dp - dq).abs() < tol, "pair ({i},{j}): {dp} vs {dq}");
            }
        }
    }

    fn check_reproduces(poly: &[[f64; 2]]) {
        let pos = tilt(poly);
        let loop_: Vec<u32> = (0..poly.len() as u32).collect();
        let out = curvature_flatten_boundary(&pos, &loop_);
        assert_convex_ccw_simple(&out);
        assert_congruent(&out, poly, 1e-12);
        // The clockwise traversal of the same loop gives the mirror image, still CCW.
        let rev: Vec<u32> = loop_.iter().rev().copied().collect();
        let out_rev = curvature_flatten_boundary(&pos, &rev);
        assert_convex_ccw_simple(&out_rev);
        let poly_rev: Vec<[f64; 2]> = poly.iter().rev().copied().collect();
        assert_congruent(&out_rev, &poly_rev, 1e-12);
        assert_eq!(out[0], [0.0, 0.0]);
    }

    #[test]
    fn regular_hexagon_in_tilted_plane_is_reproduced() {
        let hex: Vec<[f64; 2]> = (0..6)
            .map(|k| {
                let t = PI / 3.0 * k as f64;
                [1.7 * t.cos(), 1.7 * t.sin()]
            })
            .collect();
        check_reproduces(&hex);
    }

    #[test]
    fn irregular_convex_polygon_in_tilted_plane_is_reproduced() {
        let poly = [
            [0.0, 0.0],
            [3.0, -0.5],
            [4.0, 1.0],
            [3.5, 2.5],
            [1.0, 3.0],
            [-0.7, 1.2],
        ];
        check_reproduces(&poly);
    }

    #[test]
    fn collinear_points_on_edges_are_kept_on_straight_edges() {
        // A 2x1 rectangle with extra points in the middle of its sides.
        let poly = [
            [0.0, 0.0],
            [0.5, 0.0],
            [1.0, 0.0],
            [2.0, 0.0],
            [2.0, 1.0],
            [1.0, 1.0],
            [0.0, 1.0],
            [0.0, 0.5],
        ];
        check_reproduces(&poly);
    }

    #[test]
    fn saddle_boundary_gives_convex_ccw_polygon_with_similar_perimeter() {
        let n = 96;
        let pos: Vec<[f64; 3]> = (0..n)
            .map(|k| {
                let t = 2.0 * PI * k as f64 / n as f64;
                let (x, y) = (2.0 * t.cos(), 1.3 * t.sin());
                [x, y, 0.3 * (x * x - y * y)]
            })
            .collect();
        let loop_: Vec<u32> = (0..n as u32).collect();
        let length3: f64 = (0..n).map(|k| norm3(sub3(pos[(k + 1) % n], pos[k]))).sum();
        let out = curvature_flatten_boundary(&pos, &loop_);
        assert_eq!(out.len(), n);
        assert_convex_ccw_simple(&out);
        let per = perimeter2(&out);
        assert!(per <= length3 * (1.0 + 1e-12));
        assert!(per > 0.97 * length3, "{per} vs {length3}");
    }

    #[test]
    fn twisted_nonconvex_space_curve_gives_convex_polygon() {
        // A star-shaped loop lifted out of the plane: turning angles sum to more than 2π.
        let n = 40;
        let pos: Vec<[f64; 3]> = (0..n)
            .map(|k| {
                let t = 2.0 * PI * k as f64 / n as f64;
                let r = 1.0 + 0.4 * (5.0 * t).cos();
                [r * t.cos(), r * t.sin(), 0.5 * (3.0 * t).sin()]
            })
            .collect();
        let loop_: Vec<u32> = (0..n as u32).rev().collect();
        let out = curvature_flatten_boundary(&pos, &loop_);
        assert_convex_ccw_simple(&out);
        assert!(out.iter().all(|p| p[0].is_finite() && p[1].is_finite()));
    }

    #[test]
    fn degenerate_loops_stay_finite() {
        // All points on one line (a back-and-forth loop).
        let pos = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [2.0, 0.0, 0.0]];
        let out = curvature_flatten_boundary(&pos, &[0, 1, 2]);
        assert_eq!(out.len(), 3);
        assert!(out.iter().all(|p| p[0].is_finite() && p[1].is_finite()));
        assert!((out[2][0] - 2.0).abs() < 1e-12 && out[2][1].abs() < 1e-12);

        // A repeated vertex (zero-length edge) inside a square.
        let pos = [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [1.0, 1.0, 0.0],
            [0.0, 1.0, 0.0],
        ];
        let out = curvature_flatten_boundary(&pos, &[0, 1, 2, 3, 4]);
        let sq = [[0.0, 0.0], [1.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]];
        assert_congruent(&out, &sq, 1e-12);
        assert!(signed_area(&out) > 0.0);

        // All points equal, and short loops.
        let pos = [[1.0, 2.0, 3.0]; 4];
        let out = curvature_flatten_boundary(&pos, &[0, 1, 2, 3]);
        assert!(out.iter().all(|p| *p == [0.0, 0.0]));
        assert!(curvature_flatten_boundary(&pos, &[]).is_empty());
        let pos = [[0.0, 0.0, 0.0], [0.0, 3.0, 4.0]];
        assert_eq!(curvature_flatten_boundary(&pos, &[0]), vec![[0.0, 0.0]]);
        assert_eq!(
            curvature_flatten_boundary(&pos, &[0, 1]),
            vec![[0.0, 0.0], [5.0, 0.0]]
        );
    }
}
