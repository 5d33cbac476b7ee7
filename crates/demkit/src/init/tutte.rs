//! Fixed-boundary initial maps of a disk: Tutte's embedding (DEM paper Alg. 2, (4.11)–(4.13))
//! and the locally authalic map of Desbrun, Meyer and Alliez (Alg. 3, (4.14)–(4.17)), with
//! the fallback to Tutte when the authalic map overlaps.

use crate::fem::{DirichletSystem, uniform_weights};
use crate::geometry::{corner_cotangents, count_nonpositive, dot, sub};
use crate::linalg::solve_lu;
use crate::{Error, Result};

/// Which interior weights the fixed-boundary map uses.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum InteriorWeights {
    /// Tutte's uniform weights (4.13): always bijective for a convex boundary.
    Tutte,
    /// `λ M^χ + (1 − λ) M^cot` (Alg. 3 with the blend of §4.1.3); λ = 1 is the pure locally
    /// authalic Chi energy (4.15).
    Authalic {
        /// The blend parameter λ ∈ [0, 1].
        lambda: f64,
    },
    /// Floater's mean value weights `w_ij = (tan(α/2) + tan(β/2)) / |x_i − x_j|`, with α, β the
    /// angles at `x_i` of the two triangles on edge `ij`: positive, so bijective for a convex
    /// boundary like Tutte's, and reproducing planar meshes (closer to conformal).
    MeanValue,
}

/// Solves `Σ_j w_ij (φ_j − φ_i) = 0` at every interior vertex with `φ = boundary_positions`
/// on the boundary loop `boundary` (4.12)/(4.16). Positions are 3D (the input surface);
/// the result is planar (z = 0).
pub fn fixed_boundary_map(
    positions: &[[f64; 3]],
    faces: &[[u32; 3]],
    boundary: &[u32],
    boundary_positions: &[[f64; 2]],
    weights: InteriorWeights,
) -> Result<Vec<[f64; 3]>> {
    let n = positions.len();
    if weights == InteriorWeights::Tutte {
        return tutte_map(n, faces, boundary, boundary_positions);
    }
    let mut fixed: Vec<Option<[f64; 2]>> = vec![None; n];
    for (&v, &p) in boundary.iter().zip(boundary_positions) {
        fixed[v as usize] = Some(p);
    }
    let mut unknown = vec![usize::MAX; n];
    let mut n_free = 0;
    for v in 0..n {
        if fixed[v].is_none() {
            unknown[v] = n_free;
            n_free += 1;
        }
    }
    // Mean squared edge length makes M^χ dimensionless so that the λ blend does not depend on
    // the mesh's scale (the paper leaves the units of the blend implicit).
    let mut mean_sq = 0.0;
    for f in faces {
        for k in 0..3 {
            let e = sub(positions[f[(k + 1) % 3] as usize], positions[f[k] as usize]);
            mean_sq += dot(e, e);
        }
    }
    mean_sq /= (3 * faces.len().max(1)) as f64;

    let mut triplets: Vec<(usize, usize, f64)> = Vec::with_capacity(faces.len() * 9);
    let mut rhs = vec![0.0; 2 * n_free];
    for f in faces {
        let p = f.map(|v| positions[v as usize]);
        let cot = corner_cotangents(p);
        for a in 0..3 {
            let i = f[a] as usize;
            let ui = unknown[i];
            if ui == usize::MAX {
                continue;
            }
            for b in [(a + 1) % 3, (a + 2) % 3] {
                let j = f[b] as usize;
                let c = 3 - a - b; // the third corner
                let w = match weights {
                    InteriorWeights::Tutte => 0.5,
                    InteriorWeights::MeanValue => mean_value_weight(p, a, b),
                    InteriorWeights::Authalic { lambda } => {
                        let e = sub(p[b], p[a]);
                        // Chi weight (4.15): cot of the angle at x_j in this face over |x_i − x_j|².
                        let chi = cot[b] / dot(e, e) * mean_sq;
                        let cotan = 0.5 * cot[c];
                        lambda * chi + (1.0 - lambda) * cotan
                    }
                };
                triplets.push((ui, ui, w));
                match fixed[j] {
                    Some(q) => {
                        rhs[ui] += w * q[0];
                        rhs[n_free + ui] += w * q[1];
                    }
                    None => triplets.push((ui, unknown[j], -w)),
                }
            }
        }
    }
    if n_free > 0 {
        solve_lu(n_free, &triplets, &mut rhs, 2)?;
    }
    Ok((0..n)
        .map(|v| match fixed[v] {
            Some(q) => [q[0], q[1], 0.0],
            None => [rhs[unknown[v]], rhs[n_free + unknown[v]], 0.0],
        })
        .collect())
}

/// Tutte's map: its weights are symmetric, so the system is a Dirichlet problem of the
/// uniform-weight Laplacian, solved by a sparse Cholesky factorization instead of the LU the
/// other weights need (the hand, 53 000 unknowns: 0.03 s instead of 0.4 s).
fn tutte_map(
    n: usize,
    faces: &[[u32; 3]],
    boundary: &[u32],
    boundary_positions: &[[f64; 2]],
) -> Result<Vec<[f64; 3]>> {
    let mut fixed = vec![false; n];
    let mut values = vec![[0.0; 3]; n];
    for (&v, &p) in boundary.iter().zip(boundary_positions) {
        fixed[v as usize] = true;
        values[v as usize] = [p[0], p[1], 0.0];
    }
    if fixed.iter().all(|&f| f) {
        return Ok(values);
    }
    DirichletSystem::new(n, faces, &fixed)?.solve(&uniform_weights(faces.len()), &values)
}

/// The share of triangle `p` in the mean value weight of the edge from corner `a` to corner
/// `b`: `tan(θ_a / 2) / |p_b − p_a|` with θ_a the angle at `a` (clamped away from 0 and π, so a
/// degenerate triangle gives a small positive weight instead of 0 or ∞).
fn mean_value_weight(p: [[f64; 3]; 3], a: usize, b: usize) -> f64 {
    let c = 3 - a - b;
    let (u, v) = (sub(p[b], p[a]), sub(p[c], p[a]));
    let (lu, lv) = (dot(u, u).sqrt(), dot(v, v).sqrt());
    if !(lu > 0.0 && lv > 0.0) {
        return 0.0;
    }
    let cos = (dot(u, v) / (lu * lv)).clamp(-1.0, 1.0);
    let theta = cos.acos().clamp(1e-6, std::f64::consts::PI - 1e-6);
    (0.5 * theta).tan() / lu
}

/// The initial flattening of Alg. 2 / Alg. 3: the locally authalic map if requested and free of
/// overlaps, otherwise Tutte's map (step 4 of Alg. 3). Returns the map and the weights used.
pub fn flatten_with_fallback(
    positions: &[[f64; 3]],
    faces: &[[u32; 3]],
    boundary: &[u32],
    boundary_positions: &[[f64; 2]],
    weights: InteriorWeights,
) -> Result<(Vec<[f64; 3]>, InteriorWeights)> {
    if let InteriorWeights::Authalic { lambda } = weights {
        if !(0.0..=1.0).contains(&lambda) {
            return Err(Error::Argument(format!(
                "authalic blend λ = {lambda} must lie in [0, 1]"
            )));
        }
        if let Ok(map) = fixed_boundary_map(positions, faces, boundary, boundary_positions, weights)
            && map.iter().all(|p| p[0].is_finite() && p[1].is_finite())
            && count_nonpositive(&map, faces) == 0
        {
            {
                return Ok((map, weights));
            }
        }
    }
    let map = fixed_boundary_map(
        positions,
        faces,
        boundary,
        boundary_positions,
        InteriorWeights::Tutte,
    )?;
    Ok((map, InteriorWeights::Tutte))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::generate_fixtures::grid;

    fn boundary_loop(n: usize) -> Vec<u32> {
        // Counter-clockwise boundary of the (n+1)x(n+1) grid.
        let m = n + 1;
        let mut b = Vec::new();
        for i in 0..n {
            b.push(i as u32);
        }
        for j in 0..n {
            b.push((j * m + n) as u32);
        }
        for i in (1..=n).rev() {
            b.push((n * m + i) as u32);
        }
        for j in (1..=n).rev() {
            b.push((j * m) as u32);
        }
        b
    }

    #[test]
    fn planar_mesh_with_its_own_boundary_is_reproduced_by_cotan_weights() {
        // A planar jittered grid with its boundary fixed in place: the cotangent (harmonic) map
        // reproduces the identity, as linear functions are harmonic.
        let (pos, faces, _) = grid(6, 0.2);
        let b = boundary_loop(6);
        let bp: Vec<[f64; 2]> = b
            .iter()
            .map(|&v| [pos[v as usize][0], pos[v as usize][1]])
            .collect();
        let map = fixed_boundary_map(
            &pos,
            &faces,
            &b,
            &bp,
            InteriorWeights::Authalic { lambda: 0.0 },
        )
        .unwrap();
        for (p, q) in pos.iter().zip(&map) {
            assert!((p[0] - q[0]).abs() < 1e-12 && (p[1] - q[1]).abs() < 1e-12);
        }
    }

    #[test]
    fn tutte_is_barycentric_and_flip_free() {
        let (pos, faces, _) = grid(5, 0.2);
        let b = boundary_loop(5);
        // Map the boundary onto a circle.
        let bp: Vec<[f64; 2]> = (0..b.len())
            .map(|k| {
                let t = std::f64::consts::TAU * k as f64 / b.len() as f64;
                [t.cos(), t.sin()]
            })
            .collect();
        let map = fixed_boundary_map(&pos, &faces, &b, &bp, InteriorWeights::Tutte).unwrap();
        assert_eq!(count_nonpositive(&map, &faces), 0);
        // Each interior vertex is the average of its neighbours (weights: one per edge).
        let v = 2 * 6 + 2; // an interior vertex of the 6x6-point grid
        let nb: Vec<usize> = vec![v - 1, v + 1, v - 6, v + 6, v + 7, v - 7];
        let avg = nb.iter().fold([0.0, 0.0], |s, &u| {
            [s[0] + map[u][0] / 6.0, s[1] + map[u][1] / 6.0]
        });
        assert!((avg[0] - map[v][0]).abs() < 1e-12 && (avg[1] - map[v][1]).abs() < 1e-12);
    }

    #[test]
    fn authalic_map_of_flat_mesh_is_identity_and_fallback_reports_weights() {
        let (pos, faces, _) = grid(4, 0.1);
        let b = boundary_loop(4);
        let bp: Vec<[f64; 2]> = b
            .iter()
            .map(|&v| [pos[v as usize][0], pos[v as usize][1]])
            .collect();
        let (map, used) = flatten_with_fallback(
            &pos,
            &faces,
            &b,
            &bp,
            InteriorWeights::Authalic { lambda: 1.0 },
        )
        .unwrap();
        assert_eq!(used, InteriorWeights::Authalic { lambda: 1.0 });
        for (p, q) in pos.iter().zip(&map) {
            assert!((p[0] - q[0]).abs() < 1e-10 && (p[1] - q[1]).abs() < 1e-10);
        }
        assert!(
            flatten_with_fallback(
                &pos,
                &faces,
                &b,
                &bp,
                InteriorWeights::Authalic { lambda: 2.0 }
            )
            .is_err()
        );
    }
}
