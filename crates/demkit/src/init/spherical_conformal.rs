//! Spherical conformal parameterization of a genus-0 closed surface (SDEM paper §3.1.1): the
//! linear FLASH-type method of Choi, Lam & Lui.
//!
//! 1. Puncture the most regular face (3.15) and solve the cotangent Laplace equation on the
//!    plane with that face's corners fixed as the boundary triangle: a discrete conformal map
//!    of the punctured surface onto a triangle.
//! 2. Scale the plane so that the punctured face and the face at the origin end up with similar
//!    sizes, and map it onto the sphere by inverse stereographic projection (the punctured face
//!    covers the north pole).
//! 3. South-pole correction: project from the south pole (the distorted north becomes the
//!    middle of the plane), and compose with the quasi-conformal map whose Beltrami coefficient
//!    is that of the projected map back to the surface (linear Beltrami solver, the southern
//!    tenth of the vertices fixed); this cancels the conformality distortion near the north pole.
//!
//! The Möbius area correction that follows is in [`super::mobius`].

use crate::fem::cotangent_weights;
use crate::geometry::sphere::{project_from_south, unproject_from_north, unproject_from_south};
use crate::geometry::{local_frame, norm, sub};
use crate::linalg::{SparseCholesky, StiffnessPattern, VertexOrder};
use crate::qc::{LinearBeltramiSolver, triangle_beltrami, truncate};
use crate::{Error, Result};
use rayon::prelude::*;

/// Face regularity (3.15): `Σ_j |e_j / (e_1 + e_2 + e_3) − 1/3|`, 0 for an equilateral face.
pub fn face_regularity(positions: &[[f64; 3]], faces: &[[u32; 3]]) -> Vec<f64> {
    faces
        .par_iter()
        .map(|f| {
            let p = f.map(|v| positions[v as usize]);
            let e = [
                norm(sub(p[1], p[2])),
                norm(sub(p[2], p[0])),
                norm(sub(p[0], p[1])),
            ];
            let s = e[0] + e[1] + e[2];
            if !(s > 0.0) {
                return f64::INFINITY;
            }
            e.iter().map(|x| (x / s - 1.0 / 3.0).abs()).sum()
        })
        .collect()
}

/// The number of faces whose spherical orientation is not positive (DESIGN.md's test).
pub fn count_spherical_flips(map: &[[f64; 3]], faces: &[[u32; 3]]) -> usize {
    faces
        .par_iter()
        .filter(|&&f| crate::geometry::sphere::spherical_flipped(map, f))
        .count()
}

/// A spherical conformal map of the genus-0 closed mesh (`positions`, `faces`): one point of
/// the unit sphere per vertex, faces counter-clockwise seen from outside. `notes` receives
/// remarks (fallbacks taken).
pub fn spherical_conformal_map(
    positions: &[[f64; 3]],
    faces: &[[u32; 3]],
    notes: &mut Vec<String>,
) -> Result<Vec<[f64; 3]>> {
    check_size(positions.len(), faces.len())?;
    let order = VertexOrder::of_mesh(positions.len(), faces)?;
    spherical_conformal_map_in_order(positions, faces, &order, notes)
}

/// The smallest closed surface has 4 vertices and 4 faces.
fn check_size(n_vertices: usize, n_faces: usize) -> Result<()> {
    if n_vertices < 4 || n_faces < 4 {
        return Err(Error::InvalidMesh(
            "a closed surface needs at least 4 vertices and 4 faces".into(),
        ));
    }
    Ok(())
}

/// [`spherical_conformal_map`] with the connectivity's elimination `order` computed by the
/// caller, who solves other systems on the same connectivity ([`VertexOrder`]).
pub(crate) fn spherical_conformal_map_in_order(
    positions: &[[f64; 3]],
    faces: &[[u32; 3]],
    order: &VertexOrder,
    notes: &mut Vec<String>,
) -> Result<Vec<[f64; 3]>> {
    check_size(positions.len(), faces.len())?;
    // Step 1: puncture the most regular face.
    let reg = face_regularity(positions, faces);
    let big = (0..faces.len())
        .min_by(|&a, &b| reg[a].total_cmp(&reg[b]))
        .unwrap_or(0);
    for positive in [false, true] {
        let Some(plane) = punctured_plane_map(positions, faces, big, positive, order)? else {
            continue;
        };
        if positive {
            notes.push(
                "the cotangent map of the punctured surface folded over; used positive weights"
                    .into(),
            );
        }
        // Step 2: onto the sphere. A large face next to the puncture can come out flipped
        // (its corners' chord triangle faces inwards although the planar face does not); the
        // south-pole step, which sees that region in the middle of its plane, repairs it.
        let sphere = plane_to_sphere(&plane, faces, big);
        // Step 3: south-pole quasi-conformal correction.
        if let Ok(s) = south_pole_correction(positions, faces, &sphere, order)
            && count_spherical_flips(&s, faces) == 0
        {
            return Ok(s);
        }
        if count_spherical_flips(&sphere, faces) == 0 {
            notes.push("the south-pole correction of the spherical map was skipped".into());
            return Ok(sphere);
        }
    }
    Err(Error::Numerical(
        "the spherical conformal map has flipped triangles".into(),
    ))
}

/// Harmonic map of the surface without face `big` onto the plane, `big`'s corners fixed at the
/// face's own shape (mirrored, so the other faces come out counter-clockwise). `positive`
/// clamps the cotangent weights to positive values (a Tutte-type map, always an embedding).
/// `None` if the map folds over.
fn punctured_plane_map(
    positions: &[[f64; 3]],
    faces: &[[u32; 3]],
    big: usize,
    positive: bool,
    order: &VertexOrder,
) -> Result<Option<Vec<[f64; 3]>>> {
    let n = positions.len();
    let bf = faces[big];
    let mut fixed = vec![false; n];
    for &v in &bf {
        fixed[v as usize] = true;
    }
    let corner = local_frame(bf.map(|v| positions[v as usize]));
    let mut boundary = vec![[0.0; 3]; n];
    for (k, &v) in bf.iter().enumerate() {
        boundary[v as usize] = [corner[k][0], -corner[k][1], 0.0];
    }
    let mut w = cotangent_weights(positions, faces);
    if positive {
        let mean = w.iter().flatten().map(|x| x.abs()).sum::<f64>() / (3 * w.len()) as f64;
        for x in w.iter_mut().flatten() {
            *x = x.max(1e-3 * mean);
        }
    }
    let pattern = StiffnessPattern::new(n, faces, Some(&fixed));
    let mut chol = SparseCholesky::for_stiffness_in(&pattern, Some(order))?;
    let mut values = vec![0.0; pattern.nnz()];
    pattern.assemble(&w, &[], &mut values);
    if let Err(e) = chol.factor(&values) {
        return if positive { Err(e) } else { Ok(None) };
    }
    let bx: Vec<f64> = boundary.iter().map(|p| p[0]).collect();
    let by: Vec<f64> = boundary.iter().map(|p| p[1]).collect();
    let m = pattern.n_unknowns();
    let mut rhs = pattern.fixed_rhs(&w, &bx);
    rhs.extend(pattern.fixed_rhs(&w, &by));
    chol.solve_many_in_place(&mut rhs, 2)?;
    let map = pattern.unknown_map();
    let z: Vec<[f64; 3]> = (0..n)
        .map(|v| {
            if fixed[v] {
                boundary[v]
            } else {
                let u = map[v] as usize;
                [rhs[u], rhs[m + u], 0.0]
            }
        })
        .collect();
    let folded = faces.par_iter().enumerate().any(|(f, t)| {
        f != big
            && !(crate::geometry::signed_area_2d(
                z[t[0] as usize],
                z[t[1] as usize],
                z[t[2] as usize],
            ) > 0.0)
    });
    if folded || z.iter().any(|p| !p[0].is_finite() || !p[1].is_finite()) {
        return Ok(None);
    }
    Ok(Some(z))
}

/// Centres the planar map at the punctured face's centroid, scales it so that the punctured
/// face (near the north pole) and the face at the origin (near the south pole) get similar
/// sizes on the sphere, and maps it onto the sphere.
fn plane_to_sphere(z: &[[f64; 3]], faces: &[[u32; 3]], big: usize) -> Vec<[f64; 3]> {
    let bf = faces[big].map(|v| z[v as usize]);
    let c = [
        (bf[0][0] + bf[1][0] + bf[2][0]) / 3.0,
        (bf[0][1] + bf[1][1] + bf[2][1]) / 3.0,
    ];
    let z: Vec<[f64; 3]> = z.iter().map(|p| [p[0] - c[0], p[1] - c[1], 0.0]).collect();
    let r = |p: [f64; 3]| (p[0] * p[0] + p[1] * p[1]).sqrt();
    let d = |a: [f64; 3], b: [f64; 3]| ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2)).sqrt();
    // The face closest to the origin and its mean side.
    let south = (0..faces.len())
        .filter(|&f| f != big)
        .min_by(|&a, &b| {
            let s = |f: usize| faces[f].iter().map(|&v| r(z[v as usize])).sum::<f64>();
            s(a).total_cmp(&s(b))
        })
        .unwrap_or(0);
    let side = |p: [[f64; 3]; 3]| (d(p[0], p[1]) + d(p[1], p[2]) + d(p[2], p[0])) / 3.0;
    let sigma_s = side(faces[south].map(|v| z[v as usize]));
    // The punctured face's mean side after inversion w ↦ 1/w.
    let inv = |p: [f64; 3]| {
        let r2 = p[0] * p[0] + p[1] * p[1];
        [p[0] / r2, -p[1] / r2, 0.0]
    };
    let sigma_n = side(faces[big].map(|v| inv(z[v as usize])));
    let s = if sigma_s > 0.0 && sigma_n > 0.0 && (sigma_n / sigma_s).is_finite() {
        (sigma_n / sigma_s).sqrt()
    } else {
        1.0
    };
    z.iter()
        .map(|p| unproject_from_north([s * p[0], s * p[1], 0.0]))
        .collect()
}

/// The south-pole step of FLASH: project from the south pole and compose with the LBS map
/// whose Beltrami coefficient is that of the projection back to the surface, the southern
/// tenth of the vertices fixed.
fn south_pole_correction(
    positions: &[[f64; 3]],
    faces: &[[u32; 3]],
    sphere: &[[f64; 3]],
    order: &VertexOrder,
) -> Result<Vec<[f64; 3]>> {
    let n = sphere.len();
    let p: Vec<[f64; 3]> = sphere.iter().map(|&x| project_from_south(x)).collect();
    let mut by_height: Vec<usize> = (0..n).collect();
    by_height.sort_by(|&a, &b| sphere[a][2].total_cmp(&sphere[b][2]));
    let n_fixed = (n / 10).max(3).min(n - 1);
    let mut fixed = vec![false; n];
    for &v in &by_height[..n_fixed] {
        fixed[v] = true;
    }
    // μ of the map from the projected sphere to the surface, per face.
    let mu: Vec<_> = faces
        .par_iter()
        .map(|f| {
            let s = f.map(|v| [p[v as usize][0], p[v as usize][1]]);
            let t = local_frame(f.map(|v| positions[v as usize]));
            truncate(triangle_beltrami(s, t), 0.1)
        })
        .collect();
    let lbs = LinearBeltramiSolver::in_order(n, faces, &fixed, Some(order))?;
    let q = lbs.solve(&p, &mu, &p)?;
    if q.iter().any(|x| !x[0].is_finite() || !x[1].is_finite()) {
        return Err(Error::Numerical("south-pole correction diverged".into()));
    }
    Ok(q.into_iter().map(unproject_from_south).collect())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::generate::icosphere;

    #[test]
    fn regularity_of_equilateral_face_is_zero() {
        let p = [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.5, 3f64.sqrt() / 2.0, 0.0],
        ];
        let r = face_regularity(&p, &[[0, 1, 2]]);
        assert!(r[0] < 1e-15);
    }

    #[test]
    fn map_of_icosphere_is_a_mobius_image_of_the_identity() {
        // The sphere's own conformal map is a Möbius transformation: every face keeps its
        // angles, so the Beltrami coefficient of the map is small everywhere, and no face flips.
        let mesh = icosphere(3).unwrap();
        let mut notes = Vec::new();
        let s = spherical_conformal_map(&mesh.positions, &mesh.faces, &mut notes).unwrap();
        assert!(notes.is_empty(), "{notes:?}");
        assert_eq!(count_spherical_flips(&s, &mesh.faces), 0);
        for x in &s {
            assert!((norm(*x) - 1.0).abs() < 1e-12);
        }
        let mu = crate::qc::beltrami_coefficient_surfaces(&mesh.positions, &s, &mesh.faces);
        let mean = mu.iter().map(|m| m.norm()).sum::<f64>() / mu.len() as f64;
        let max = mu.iter().map(|m| m.norm()).fold(0.0, f64::max);
        assert!(mean < 0.02 && max < 0.1, "mean |mu| {mean}, max {max}");
    }
}
