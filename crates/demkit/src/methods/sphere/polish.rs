//! Local area matching on the sphere or an ellipsoid: the last stage of EDEM and EDEQ.
//!
//! The density flow follows the vertex density ρ_V, an average of the face densities around
//! each vertex, so it cannot see a misfit that alternates from one triangle to the next; such a
//! misfit is what remains of the face density's variance when ρ_V is flat. Each sweep here
//! moves every vertex, in the tangent plane of the domain, by the least-squares step that
//! brings the areas of its faces (linear in its position) towards their targets
//! `P(T) ΣA / ΣP`, relative errors weighted equally:
//!
//! min over δ of Σ_T ((A_T + ∇A_T · δ − A*_T) / A*_T)², with ∇A_T = ½ n̂_T × (c − b)
//!
//! for the face (v, b, c) with unit normal n̂_T. The steps of all vertices are taken at once,
//! halved (from half their length) until no face flips and the face misfit
//! mean |log((A/ΣA)/(P/ΣP))| falls; the sweeps stop when it falls by less than
//! [`MIN_GAIN`] or after [`MAX_SWEEPS`].

use crate::fem::VertexFaces;
use crate::geometry::ellipsoid::Ellipsoid;
use crate::geometry::sphere::spherical_flipped;
use crate::geometry::{add, cross, dot, face_areas, norm, scale, sub};
use crate::metrics::log_area_misfit;
use rayon::prelude::*;

/// At most this many sweeps.
pub(crate) const MAX_SWEEPS: usize = 50;

/// The sweeps stop when one lowers the face misfit by less than this share.
pub(crate) const MIN_GAIN: f64 = 0.002;

/// The share of the least-squares step tried first (the steps of neighbours interact).
const FIRST_TRY: f64 = 0.5;

/// Halvings of a sweep's steps before it is given up.
const HALVINGS: usize = 6;

/// What a run of sweeps did.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Matched {
    /// Sweeps kept.
    pub sweeps: usize,
    /// The merit before and after (the face misfit for [`match_areas`]).
    pub misfit: [f64; 2],
}

/// Sweeps of local area matching (module docs) on the flip-free map `map` of `faces` onto
/// `domain`, towards `population`; the map stays flip-free and on the domain.
pub(crate) fn match_areas(
    domain: &Ellipsoid,
    faces: &[[u32; 3]],
    population: &[f64],
    map: &mut Vec<[f64; 3]>,
) -> Matched {
    let incidence = VertexFaces::new(map.len(), faces);
    let total_p: f64 = population.iter().sum();
    sweeps(
        domain,
        faces,
        map,
        |x: &[[f64; 3]]| log_area_misfit(population, &face_areas(x, faces)),
        |x: &[[f64; 3]]| {
            let scale_to_area = face_areas(x, faces).iter().sum::<f64>() / total_p;
            (0..x.len())
                .into_par_iter()
                .map(|v| vertex_step(domain, faces, &incidence, x, v, population, scale_to_area))
                .collect()
        },
    )
}

/// The sweep skeleton: every vertex's step from `steps` taken at once, halved (from
/// [`FIRST_TRY`] of its length) until no face flips and `merit` falls; until a sweep gains
/// less than [`MIN_GAIN`] or after [`MAX_SWEEPS`].
fn sweeps(
    domain: &Ellipsoid,
    faces: &[[u32; 3]],
    map: &mut Vec<[f64; 3]>,
    merit: impl Fn(&[[f64; 3]]) -> f64,
    steps: impl Fn(&[[f64; 3]]) -> Vec<[f64; 3]>,
) -> Matched {
    let before = merit(map);
    let mut current = before;
    let mut done = 0;
    let mut moved = map.clone();
    while done < MAX_SWEEPS {
        let step = steps(map);
        let mut tau = FIRST_TRY;
        let mut kept = None;
        for _ in 0..HALVINGS {
            moved
                .par_iter_mut()
                .zip(map.par_iter().zip(&step))
                .for_each(|(m, (&x, &s))| *m = domain.project(add(x, scale(s, tau))));
            if !faces.par_iter().any(|&f| spherical_flipped(&moved, f)) {
                let m = merit(&moved);
                if m < current {
                    kept = Some(m);
                    break;
                }
            }
            tau *= 0.5;
        }
        let Some(m) = kept else {
            break;
        };
        std::mem::swap(map, &mut moved);
        done += 1;
        let gain = (current - m) / current;
        current = m;
        if !(gain >= MIN_GAIN) {
            break;
        }
    }
    Matched {
        sweeps: done,
        misfit: [before, current],
    }
}

/// An orthonormal basis of the tangent plane of `domain` at `x`.
fn tangent_basis(domain: &Ellipsoid, x: [f64; 3]) -> ([f64; 3], [f64; 3]) {
    let n = domain.normal(x);
    let axis = if n[0].abs() < 0.6 {
        [1.0, 0.0, 0.0]
    } else {
        [0.0, 1.0, 0.0]
    };
    let t = cross(n, axis);
    let t1 = scale(t, 1.0 / norm(t));
    (t1, cross(n, t1))
}

/// The least-squares step of vertex `v` (module docs) in the tangent plane of `domain` at its
/// point, the targets being `population × scale_to_area`; zero where it is not defined.
fn vertex_step(
    domain: &Ellipsoid,
    faces: &[[u32; 3]],
    incidence: &VertexFaces,
    map: &[[f64; 3]],
    v: usize,
    population: &[f64],
    scale_to_area: f64,
) -> [f64; 3] {
    let x = map[v];
    let (t1, t2) = tangent_basis(domain, x);
    // Normal equations M c = r of the 2×2 least-squares problem.
    let (mut m11, mut m12, mut m22, mut r1, mut r2) = (0.0, 0.0, 0.0, 0.0, 0.0);
    for &f in incidence.faces_of(v) {
        let tri = faces[f as usize];
        let k = tri.iter().position(|&u| u as usize == v).unwrap_or(0);
        let (b, c) = (
            map[tri[(k + 1) % 3] as usize],
            map[tri[(k + 2) % 3] as usize],
        );
        let normal = cross(sub(b, x), sub(c, x));
        let twice_area = norm(normal);
        let target = population[f as usize] * scale_to_area;
        if !(twice_area > 0.0 && target > 0.0) {
            continue;
        }
        let g = scale(cross(scale(normal, 1.0 / twice_area), sub(c, b)), 0.5);
        let h = [dot(g, t1) / target, dot(g, t2) / target];
        let e = (target - 0.5 * twice_area) / target;
        m11 += h[0] * h[0];
        m12 += h[0] * h[1];
        m22 += h[1] * h[1];
        r1 += h[0] * e;
        r2 += h[1] * e;
    }
    // A little damping keeps the step finite where the faces' gradients are nearly parallel.
    let damping = 1e-3 * (m11 + m22);
    let (m11, m22) = (m11 + damping, m22 + damping);
    let det = m11 * m22 - m12 * m12;
    if !(det > 0.0) {
        return [0.0; 3];
    }
    let c1 = (m22 * r1 - m12 * r2) / det;
    let c2 = (m11 * r2 - m12 * r1) / det;
    add(scale(t1, c1), scale(t2, c2))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::generate::icosphere;

    #[test]
    fn the_area_gradient_is_exact_for_a_planar_move() {
        // A(x + δ) = A(x) + ∇A · δ exactly for moves in the face's plane (A is linear in the
        // corner there).
        let (x, b, c) = ([0.2, 0.9, 0.0], [0.0, 0.0, 0.0], [1.0, 0.1, 0.0]);
        let area = |p: [f64; 3]| 0.5 * norm(cross(sub(b, p), sub(c, p)));
        let normal = cross(sub(b, x), sub(c, x));
        let g = scale(cross(scale(normal, 1.0 / norm(normal)), sub(c, b)), 0.5);
        let d = [0.03, -0.05, 0.0];
        assert!((area(add(x, d)) - area(x) - dot(g, d)).abs() < 1e-15);
    }

    #[test]
    fn alternating_misfits_are_matched() {
        // The icosphere's faces with a population alternating by ±30% around their areas: the
        // map is the icosphere itself, whose vertex density is nearly flat while every face is
        // off. The sweeps bring the misfit down and flip nothing.
        let mesh = icosphere(4).unwrap();
        let areas = face_areas(&mesh.positions, &mesh.faces);
        let population: Vec<f64> = areas
            .iter()
            .enumerate()
            .map(|(i, a)| a * if i % 2 == 0 { 1.3 } else { 0.7 })
            .collect();
        let mut map = mesh.positions.clone();
        let m = match_areas(&Ellipsoid::UNIT_SPHERE, &mesh.faces, &population, &mut map);
        assert!(m.sweeps > 0);
        assert!(m.misfit[1] < 0.5 * m.misfit[0], "{m:?}");
        assert!(!mesh.faces.iter().any(|&f| spherical_flipped(&map, f)));
        for p in &map {
            assert!((norm(*p) - 1.0).abs() < 1e-12);
        }
    }

    #[test]
    fn an_equalized_map_is_left_alone() {
        let mesh = icosphere(3).unwrap();
        let areas = face_areas(&mesh.positions, &mesh.faces);
        let mut map = mesh.positions.clone();
        let m = match_areas(&Ellipsoid::UNIT_SPHERE, &mesh.faces, &areas, &mut map);
        assert_eq!(m.sweeps, 0);
        assert_eq!(map, mesh.positions);
    }
}
