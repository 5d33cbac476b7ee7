//! Holes left by the clean-up, re-triangulated by ear clipping.

use super::clean_up::{Incidence, boundary_next, loop_area, loops, orient2};

/// Fills every hole (a clockwise boundary loop) of the alive faces by ear clipping. On failure
/// returns the reflected vertices (index ≥ `n_disk`) of the offending loop, to be removed
/// so that the hole grows and gets another chance.
pub(super) fn fill_holes(
    pos: &[[f64; 2]],
    inc: &Incidence,
    alive: &[bool],
    full: &[u32],
    n_disk: usize,
) -> std::result::Result<Vec<[u32; 3]>, Vec<u32>> {
    let reflected = |lp: &[u32]| -> Vec<u32> {
        lp.iter()
            .copied()
            .filter(|&v| v as usize >= n_disk)
            .collect()
    };
    let Some(next) = boundary_next(inc, alive, Some(full)) else {
        // Not a manifold: remove the reflected vertices on every boundary.
        let nv = inc.start.len() - 1;
        let on_boundary = (n_disk..nv)
            .map(|v| v as u32)
            .filter(|&v| inc.of(v, alive).any(|c| !inc.has_twin(v, c.next, alive)));
        return Err(on_boundary.collect());
    };
    let mut new_faces = Vec::new();
    for lp in loops(&next) {
        if loop_area(pos, &lp) > 0.0 {
            continue; // the outer boundary
        }
        let mut poly = lp.clone();
        poly.reverse();
        match ear_clip(pos, &poly) {
            Some(tris) => new_faces.extend(tris),
            None => return Err(reflected(&lp)),
        }
    }
    Ok(new_faces)
}

/// Triangulates a simple counter-clockwise polygon (vertex indices into `pos`) by ear clipping,
/// choosing the best-shaped ear; `None` if the polygon is not simple or an ear cannot be found.
pub(super) fn ear_clip(pos: &[[f64; 2]], poly: &[u32]) -> Option<Vec<[u32; 3]>> {
    let k = poly.len();
    if !(3..=4096).contains(&k) || !is_simple(pos, poly) {
        return None;
    }
    let p = |v: u32| pos[v as usize];
    let mut idx: Vec<u32> = poly.to_vec();
    let mut out = Vec::with_capacity(k - 2);
    while idx.len() > 3 {
        let m = idx.len();
        let mut best: Option<(f64, usize)> = None;
        for i in 0..m {
            let (a, b, c) = (idx[(i + m - 1) % m], idx[i], idx[(i + 1) % m]);
            let area = orient2(p(a), p(b), p(c));
            if area <= 0.0 {
                continue;
            }
            let blocked = idx.iter().any(|&o| {
                o != a && o != b && o != c && {
                    let q = p(o);
                    orient2(p(a), p(b), q) >= 0.0
                        && orient2(p(b), p(c), q) >= 0.0
                        && orient2(p(c), p(a), q) >= 0.0
                }
            });
            if blocked {
                continue;
            }
            let d2 = |u: [f64; 2], w: [f64; 2]| (u[0] - w[0]).powi(2) + (u[1] - w[1]).powi(2);
            let quality = area / (d2(p(a), p(b)) + d2(p(b), p(c)) + d2(p(c), p(a)));
            if best.is_none_or(|(q, _)| quality > q) {
                best = Some((quality, i));
            }
        }
        let (_, i) = best?;
        let m = idx.len();
        out.push([idx[(i + m - 1) % m], idx[i], idx[(i + 1) % m]]);
        idx.remove(i);
    }
    if orient2(p(idx[0]), p(idx[1]), p(idx[2])) <= 0.0 {
        return None;
    }
    out.push([idx[0], idx[1], idx[2]]);
    Some(out)
}

/// No two non-adjacent edges of the closed polygon touch or cross, and no vertex repeats.
pub(super) fn is_simple(pos: &[[f64; 2]], poly: &[u32]) -> bool {
    let k = poly.len();
    let p = |i: usize| pos[poly[i % k] as usize];
    for i in 0..k {
        for j in i + 1..k {
            if poly[i] == poly[j] {
                return false;
            }
            if j == i + 1 || (i == 0 && j == k - 1) {
                continue;
            }
            if segments_meet(p(i), p(i + 1), p(j), p(j + 1)) {
                return false;
            }
        }
    }
    true
}

pub(super) fn segments_meet(a: [f64; 2], b: [f64; 2], c: [f64; 2], d: [f64; 2]) -> bool {
    let (o1, o2) = (orient2(a, b, c), orient2(a, b, d));
    let (o3, o4) = (orient2(c, d, a), orient2(c, d, b));
    if o1 * o2 < 0.0 && o3 * o4 < 0.0 {
        return true;
    }
    let on = |p: [f64; 2], q: [f64; 2], r: [f64; 2], o: f64| {
        o == 0.0
            && r[0] >= p[0].min(q[0])
            && r[0] <= p[0].max(q[0])
            && r[1] >= p[1].min(q[1])
            && r[1] <= p[1].max(q[1])
    };
    on(a, b, c, o1) || on(a, b, d, o2) || on(c, d, a, o3) || on(c, d, b, o4)
}
