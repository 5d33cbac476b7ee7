//! The disk automorphism that best balances the areas of a circle-domain map: the circle
//! domain of a multiply connected surface is unique only up to the Möbius transformations of
//! the unit disk, `φ_a(z) = (z − a) / (1 − ā z)` (|a| < 1) and rotations, which keep it a circle
//! domain and keep the map conformal. As for the sphere (`init::mobius`), we take the one whose
//! face areas are closest to the population: the density-equalizing iteration then starts
//! from the least distorted of the equivalent conformal maps (a planar annulus stays where it
//! is, instead of having its middle pulled to the centre).

use super::circle_domain::CircleDomain;
use crate::geometry::signed_area_2d;
use num_complex::Complex64;
use rayon::prelude::*;

/// `φ_a(z) = (z − a) / (1 − ā z)`.
pub fn disk_automorphism(a: Complex64, z: Complex64) -> Complex64 {
    (z - a) / (Complex64::new(1.0, 0.0) - a.conj() * z)
}

/// The circle through three points (centre, radius); `None` when they are collinear.
fn circumcircle(p: [Complex64; 3]) -> Option<([f64; 2], f64)> {
    let (a, b, c) = (p[0], p[1], p[2]);
    let d = 2.0 * (a.re * (b.im - c.im) + b.re * (c.im - a.im) + c.re * (a.im - b.im));
    if d == 0.0 || !d.is_finite() {
        return None;
    }
    let (aa, bb, cc) = (a.norm_sqr(), b.norm_sqr(), c.norm_sqr());
    let ux = (aa * (b.im - c.im) + bb * (c.im - a.im) + cc * (a.im - b.im)) / d;
    let uy = (aa * (c.re - b.re) + bb * (a.re - c.re) + cc * (b.re - a.re)) / d;
    let r = (a - Complex64::new(ux, uy)).norm();
    Some(([ux, uy], r))
}

/// Mean |log((A/ΣA) / (w/Σw))| over the faces of the planar map `z`.
fn imbalance(z: &[Complex64], faces: &[[u32; 3]], log_weight: &[f64]) -> f64 {
    let areas: Vec<f64> = faces
        .par_iter()
        .map(|f| {
            let p = f.map(|v| [z[v as usize].re, z[v as usize].im, 0.0]);
            signed_area_2d(p[0], p[1], p[2])
        })
        .collect();
    if areas.iter().any(|a| !(*a > 0.0)) {
        return f64::INFINITY;
    }
    let log_sum = areas.iter().sum::<f64>().ln();
    // Terms computed in parallel, summed in face order: the same result whatever the threads.
    let terms: Vec<f64> = areas
        .par_iter()
        .zip(log_weight.par_iter())
        .map(|(a, w)| (a.ln() - log_sum - w).abs())
        .collect();
    terms.iter().sum::<f64>() / faces.len().max(1) as f64
}

/// Composes `domain` with the disk automorphism `φ_a` minimising the mean |log area ratio|
/// against the face `weights` (a population, or the input's face areas), found by a
/// Nelder–Mead search over `a` in the disk |a| ≤ 0.95. Circles are mapped to circles (each
/// through the images of three of its points) and the boundary vertices put back exactly
/// on them. Returns the domain unchanged when no `a` does better than the identity.
pub fn balance_areas(domain: &CircleDomain, faces: &[[u32; 3]], weights: &[f64]) -> CircleDomain {
    let z: Vec<Complex64> = domain
        .positions
        .iter()
        .map(|p| Complex64::new(p[0], p[1]))
        .collect();
    let total: f64 = weights.iter().sum();
    let log_weight: Vec<f64> = weights.iter().map(|w| (w / total).ln()).collect();
    let cost = |a: [f64; 2]| {
        let a = Complex64::new(a[0], a[1]);
        if a.norm() > 0.95 {
            return f64::INFINITY;
        }
        let w: Vec<Complex64> = z.par_iter().map(|&p| disk_automorphism(a, p)).collect();
        imbalance(&w, faces, &log_weight)
    };
    let start = cost([0.0, 0.0]);
    let (best, value) = crate::optimize::nelder_mead(cost, [0.0, 0.0], 0.1, 80, 0.0);
    if !(value < start) {
        return domain.clone();
    }
    let a = Complex64::new(best[0], best[1]);
    let mut positions: Vec<[f64; 3]> = z
        .iter()
        .map(|&p| {
            let w = disk_automorphism(a, p);
            [w.re, w.im, 0.0]
        })
        .collect();
    let mut centers = domain.centers.clone();
    let mut radii = domain.radii.clone();
    for (l, (c, r)) in domain.centers.iter().zip(&domain.radii).enumerate().skip(1) {
        let c = Complex64::new(c[0], c[1]);
        let pts: [Complex64; 3] = std::array::from_fn(|k| {
            let t = std::f64::consts::TAU * k as f64 / 3.0;
            disk_automorphism(a, c + Complex64::from_polar(*r, t))
        });
        if let Some((center, radius)) = circumcircle(pts) {
            centers[l] = center;
            radii[l] = radius;
        }
    }
    for (l, lp) in domain.loops.iter().enumerate() {
        let (c, r) = (centers[l], radii[l]);
        for &v in lp {
            let p = positions[v as usize];
            let (dx, dy) = (p[0] - c[0], p[1] - c[1]);
            let d = dx.hypot(dy);
            if d > 0.0 {
                positions[v as usize] = [c[0] + r * dx / d, c[1] + r * dy / d, 0.0];
            }
        }
    }
    CircleDomain {
        positions,
        loops: domain.loops.clone(),
        centers,
        radii,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::generate::annulus;

    #[test]
    fn automorphism_keeps_the_unit_circle_and_sends_a_to_the_centre() {
        let a = Complex64::new(0.3, -0.2);
        assert!(disk_automorphism(a, a).norm() < 1e-15);
        for k in 0..8 {
            let z = Complex64::from_polar(1.0, k as f64);
            assert!((disk_automorphism(a, z).norm() - 1.0).abs() < 1e-14);
        }
    }

    #[test]
    fn circles_map_to_circles() {
        let a = Complex64::new(-0.4, 0.25);
        let (c, r) = (Complex64::new(0.2, 0.1), 0.3);
        let pts: [Complex64; 3] = std::array::from_fn(|k| {
            disk_automorphism(a, c + Complex64::from_polar(r, k as f64 * 2.0))
        });
        let (center, radius) = circumcircle(pts).unwrap();
        for k in 0..10 {
            let w = disk_automorphism(a, c + Complex64::from_polar(r, 0.37 * k as f64));
            assert!(((w - Complex64::new(center[0], center[1])).norm() - radius).abs() < 1e-12);
        }
    }

    #[test]
    fn a_pulled_annulus_is_put_back_concentric() {
        // An annulus moved by φ_b is balanced back (its areas match the original's best at a
        // concentric position).
        let m = annulus(0.4, 1.0, 10, 64).unwrap();
        let b = Complex64::new(0.3, 0.1);
        let moved: Vec<[f64; 3]> = m
            .positions
            .iter()
            .map(|p| {
                let w = disk_automorphism(b, Complex64::new(p[0], p[1]));
                [w.re, w.im, 0.0]
            })
            .collect();
        let topo = crate::mesh::topology::topology(&m);
        let mut loops = topo.boundary_loops.clone();
        let r = |l: &Vec<u32>| m.positions[l[0] as usize][0].hypot(m.positions[l[0] as usize][1]);
        loops.sort_by(|x, y| r(y).total_cmp(&r(x)));
        let pts: [Complex64; 3] = std::array::from_fn(|k| {
            disk_automorphism(b, Complex64::from_polar(0.4, k as f64 * 2.0))
        });
        let (c, rad) = circumcircle(pts).unwrap();
        let domain = CircleDomain {
            positions: moved,
            loops,
            centers: vec![[0.0, 0.0], c],
            radii: vec![1.0, rad],
        };
        let areas = crate::geometry::face_areas(&m.positions, &m.faces);
        let out = balance_areas(&domain, &m.faces, &areas);
        assert!(
            out.centers[1][0].hypot(out.centers[1][1]) < 1e-3,
            "{:?}",
            out.centers[1]
        );
        assert!((out.radii[1] - 0.4).abs() < 1e-3, "{}", out.radii[1]);
    }
}
