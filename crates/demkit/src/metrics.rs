//! The report metrics of DESIGN.md, one definition each, shared by every method.
//!
//! Notation: P(T) population of face T, A0(T) its area on the initial map, A(T) its area on the
//! final map; sums run over the faces of the input (a sea never counts).

use crate::TriMesh;
use crate::fem::VertexFaces;
use crate::geometry::{face_areas, signed_areas_2d};
use crate::qc::{beltrami_coefficient_surface, beltrami_coefficient_surfaces};
use rayon::prelude::*;

/// The target domain of a map, which decides how flips and areas are measured.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Domain {
    /// A planar map (x, y; z ignored).
    Plane,
    /// A map onto the unit sphere: a face is flipped when ((b−a)×(c−a))·(a+b+c) ≤ 0; areas are
    /// those of the flat triangles between the mapped corners.
    Sphere,
    /// A map onto a torus: areas are those of the flat triangles between the mapped corners;
    /// flips are counted on the map's periodic planar image by the method, which passes the
    /// count here.
    Torus {
        /// Faces whose periodic planar image has signed area ≤ 0.
        flipped: usize,
    },
}

/// The report metrics (DESIGN.md, "Report"); serialized with exactly these field names.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Metrics {
    /// Faces whose signed area has the sign opposite to the majority, or is zero.
    pub flipped_triangles: usize,
    /// Var(ρ_V / mean ρ_V) on the initial map (population variance).
    pub density_var_initial: f64,
    /// Var(ρ_V / mean ρ_V) on the final map.
    pub density_var_final: f64,
    /// Var(ρ_F / mean ρ_F) on the initial map.
    pub face_density_var_initial: f64,
    /// Var(ρ_F / mean ρ_F) on the final map.
    pub face_density_var_final: f64,
    /// Mean of |d(T)|, d(T) = log((A(T)/ΣA) / (P(T)/ΣP)).
    pub density_error_mean: f64,
    /// Standard deviation of |d(T)|.
    pub density_error_sd: f64,
    /// Median of (P/ΣP)/(A/ΣA).
    pub density_median: f64,
    /// Interquartile range of (P/ΣP)/(A/ΣA).
    pub density_iqr: f64,
    /// Mean of |(A/ΣA)/(P/ΣP) − 1| (the E_A of the DEM paper's Table 5 when P = area).
    pub area_ratio_error_mean: f64,
    /// Mean |μ| of the map from the input surface to the output.
    pub mean_abs_mu: f64,
    /// Max |μ| of the map from the input surface to the output.
    pub max_abs_mu: f64,
    /// sqrt(Σ |f(p_i) − q_i|²) over the landmarks; `None` without landmarks.
    pub landmark_error: Option<f64>,
}

/// Face areas of a map on `domain` (absolute values), and the number of flipped faces.
pub fn map_areas(map: &[[f64; 3]], faces: &[[u32; 3]], domain: Domain) -> (Vec<f64>, usize) {
    match domain {
        Domain::Plane => {
            let s = signed_areas_2d(map, faces);
            let pos = s.iter().filter(|&&a| a > 0.0).count();
            let neg = s.iter().filter(|&&a| a < 0.0).count();
            let majority_positive = pos >= neg;
            let flipped = s
                .iter()
                .filter(|&&a| a == 0.0 || (a > 0.0) != majority_positive)
                .count();
            (s.iter().map(|a| a.abs()).collect(), flipped)
        }
        Domain::Torus { flipped } => (face_areas(map, faces), flipped),
        Domain::Sphere => {
            let flipped = faces
                .iter()
                .filter(|&&f| crate::geometry::sphere::spherical_flipped(map, f))
                .count();
            (face_areas(map, faces), flipped)
        }
    }
}

/// A run counts as having equalized nothing when its face-density variance fell by less than
/// this share of the initial one ...
pub const MIN_PROGRESS: f64 = 0.1;

/// ... unless the initial variance was already below this (nothing to equalize).
pub const ALREADY_EQUAL: f64 = 1e-2;

/// Why a map that its method reports as converged did not equalize the density: the
/// face-density variance fell by less than [`MIN_PROGRESS`] of the way to zero from an initial
/// variance above [`ALREADY_EQUAL`]. `None` when the map moved.
pub fn barely_moved(m: &Metrics) -> Option<String> {
    let (v0, v1) = (m.face_density_var_initial, m.face_density_var_final);
    if !(v0 > ALREADY_EQUAL) || v0 - v1 >= MIN_PROGRESS * v0 {
        return None;
    }
    Some(if v1 > v0 {
        format!(
            "the map did not equalize the density: the face density variance rose from \
             {v0:.4} to {v1:.4}"
        )
    } else {
        format!("the map barely moved: the face density variance went only from {v0:.4} to {v1:.4}")
    })
}

/// Why a map that its method reports as converged did not do what the method is for, judged
/// on the method's own objective (DEQ's energy, which weighs the density against the
/// distortion): it fell by less than [`MIN_PROGRESS`] of the way to zero from an initial value
/// above [`ALREADY_EQUAL`]. `None` when the map moved.
pub fn barely_lowered(before: f64, after: f64) -> Option<String> {
    if !(before > ALREADY_EQUAL) || before - after >= MIN_PROGRESS * before {
        return None;
    }
    Some(format!(
        "the map barely moved: its energy (density misfit and distortion) went only from \
         {before:.4} to {after:.4}"
    ))
}

/// Above this final Var(ρ̃) a map that trades the density against the distortion (DEQ) has not
/// equalized the density at all: for comparison, the DEQ paper's Table 1 reaches 0.01–0.1, and
/// its α = 10 on human_face gives 0.13.
pub const NOT_EQUALIZED: f64 = 0.25;

/// Why a DEQ map that met its energy's tolerance is still not density-equalizing: its final
/// Var(ρ̃) is above [`NOT_EQUALIZED`] (a surface too long and narrow for its share of the
/// disk, whose triangles would have to degenerate). `None` otherwise.
pub fn not_equalized(m: &Metrics) -> Option<String> {
    let v = m.face_density_var_final;
    if v <= NOT_EQUALIZED {
        return None;
    }
    Some(format!(
        "the density was not equalized: Var(ρ̃) is {v:.3} (above {NOT_EQUALIZED}) at mean |μ| \
         {:.3}; the surface needs more shear than its triangles can take without degenerating",
        m.mean_abs_mu
    ))
}

/// Population variance of `x / mean(x)`.
pub fn normalized_variance(x: &[f64]) -> f64 {
    if x.is_empty() {
        return 0.0;
    }
    let n = x.len() as f64;
    let mean = x.iter().sum::<f64>() / n;
    if mean == 0.0 {
        return 0.0;
    }
    x.iter().map(|v| (v / mean - 1.0).powi(2)).sum::<f64>() / n
}

/// The `q`-quantile (0 ≤ q ≤ 1) of `sorted` by linear interpolation between order statistics.
pub fn quantile(sorted: &[f64], q: f64) -> f64 {
    if sorted.is_empty() {
        return f64::NAN;
    }
    let h = q * (sorted.len() - 1) as f64;
    let lo = h.floor() as usize;
    let hi = (lo + 1).min(sorted.len() - 1);
    sorted[lo] + (h - lo as f64) * (sorted[hi] - sorted[lo])
}

/// Vertex density ρ_V = W^FV ρ_F (4.31) for `ρ_F = P / A`, and ρ_F itself.
pub fn densities(
    faces: &[[u32; 3]],
    n_vertices: usize,
    population: &[f64],
    areas: &[f64],
) -> (Vec<f64>, Vec<f64>) {
    let rho_f: Vec<f64> = population.iter().zip(areas).map(|(p, a)| p / a).collect();
    let w = VertexFaces::new(n_vertices, faces);
    (w.apply(areas, &rho_f), rho_f)
}

/// The population's and the areas' totals, and |d(T)| of one face, d(T) = log((A/ΣA)/(P/ΣP)):
/// how far the face's share of the area is from its share of the population.
fn log_area_ratio(p: f64, a: f64, sp: f64, sa: f64) -> f64 {
    ((a / sa) / (p / sp)).ln().abs()
}

/// Faces per block of the face misfit's sum: blocks are summed in parallel, each in face order,
/// and the block sums in block order, so the result does not depend on the threads.
const MISFIT_BLOCK: usize = 4096;

/// The face misfit, the mean of |d(T)|, d(T) = log((A/ΣA)/(P/ΣP)), without storing the |d(T)|
/// (it is measured after every move of SDEM's flow).
pub fn log_area_misfit(population: &[f64], areas: &[f64]) -> f64 {
    let sp: f64 = population.iter().sum();
    let sa: f64 = areas.iter().sum();
    let blocks: Vec<f64> = population
        .par_chunks(MISFIT_BLOCK)
        .zip(areas.par_chunks(MISFIT_BLOCK))
        .map(|(p, a)| {
            p.iter()
                .zip(a)
                .map(|(&p, &a)| log_area_ratio(p, a, sp, sa))
                .sum::<f64>()
        })
        .collect();
    blocks.iter().sum::<f64>() / areas.len() as f64
}

/// Mean and standard deviation of |d(T)|, d(T) = log((A/ΣA)/(P/ΣP)).
pub fn density_error(population: &[f64], areas: &[f64]) -> (f64, f64) {
    let sp: f64 = population.iter().sum();
    let sa: f64 = areas.iter().sum();
    let d: Vec<f64> = population
        .par_iter()
        .zip(areas.par_iter())
        .map(|(&p, &a)| log_area_ratio(p, a, sp, sa))
        .collect();
    let n = areas.len() as f64;
    // Summed in the blocks of [`log_area_misfit`], which it then equals bit for bit.
    let blocks: Vec<f64> = d
        .par_chunks(MISFIT_BLOCK)
        .map(|c| c.iter().sum::<f64>())
        .collect();
    let mean = blocks.iter().sum::<f64>() / n;
    let sd = (d.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / n).sqrt();
    (mean, sd)
}

/// Computes every metric for the map `initial → final` of `input` with face `population`.
/// `landmarks` are (vertex, target) pairs.
pub fn compute(
    input: &TriMesh,
    population: &[f64],
    initial: &[[f64; 3]],
    final_map: &[[f64; 3]],
    domain: Domain,
    landmarks: Option<&[(usize, [f64; 3])]>,
) -> Metrics {
    let faces = &input.faces;
    let n = input.n_vertices();
    let (a0, _) = map_areas(initial, faces, domain);
    let (a1, flipped) = map_areas(final_map, faces, domain);
    let (rv0, rf0) = densities(faces, n, population, &a0);
    let (rv1, rf1) = densities(faces, n, population, &a1);
    let (density_error_mean, density_error_sd) = density_error(population, &a1);
    let sp: f64 = population.iter().sum();
    let sa: f64 = a1.iter().sum();
    let mut ratio: Vec<f64> = population
        .iter()
        .zip(&a1)
        .map(|(p, a)| (p / sp) / (a / sa))
        .collect();
    let area_ratio_error_mean = population
        .iter()
        .zip(&a1)
        .map(|(p, a)| ((a / sa) / (p / sp) - 1.0).abs())
        .sum::<f64>()
        / a1.len() as f64;
    ratio.sort_by(f64::total_cmp);
    let mu = match domain {
        Domain::Plane => beltrami_coefficient_surface(&input.positions, final_map, faces),
        Domain::Sphere | Domain::Torus { .. } => {
            beltrami_coefficient_surfaces(&input.positions, final_map, faces)
        }
    };
    let abs_mu: Vec<f64> = mu.iter().map(|m| m.norm()).collect();
    let landmark_error = landmarks.map(|l| {
        l.iter()
            .map(|&(v, q)| {
                let p = final_map[v];
                (p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2) + (p[2] - q[2]).powi(2)
            })
            .sum::<f64>()
            .sqrt()
    });
    Metrics {
        flipped_triangles: flipped,
        density_var_initial: normalized_variance(&rv0),
        density_var_final: normalized_variance(&rv1),
        face_density_var_initial: normalized_variance(&rf0),
        face_density_var_final: normalized_variance(&rf1),
        density_error_mean,
        density_error_sd,
        density_median: quantile(&ratio, 0.5),
        density_iqr: quantile(&ratio, 0.75) - quantile(&ratio, 0.25),
        area_ratio_error_mean,
        mean_abs_mu: abs_mu.iter().sum::<f64>() / abs_mu.len().max(1) as f64,
        max_abs_mu: abs_mu.iter().cloned().fold(0.0, f64::max),
        landmark_error,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    use crate::generate_fixtures::unit_square as two_triangles;

    #[test]
    fn identity_map_with_area_population_is_perfect() {
        let m = two_triangles();
        let pop = vec![0.5, 0.5];
        let r = compute(&m, &pop, &m.positions, &m.positions, Domain::Plane, None);
        assert_eq!(r.flipped_triangles, 0);
        assert!(r.density_error_mean.abs() < 1e-15);
        assert!((r.density_median - 1.0).abs() < 1e-15);
        assert!(r.density_iqr.abs() < 1e-15);
        assert!(r.mean_abs_mu < 1e-15);
        assert_eq!(r.landmark_error, None);
    }

    #[test]
    fn a_map_that_did_not_equalize_is_named_for_what_it_did() {
        let m = two_triangles();
        let pop = vec![0.5, 0.5];
        let mut r = compute(&m, &pop, &m.positions, &m.positions, Domain::Plane, None);
        (r.face_density_var_initial, r.face_density_var_final) = (0.5, 0.3);
        assert_eq!(barely_moved(&r), None);
        r.face_density_var_final = 0.48;
        assert!(barely_moved(&r).unwrap().contains("barely moved"));
        r.face_density_var_final = 0.7;
        assert!(
            barely_moved(&r)
                .unwrap()
                .contains("rose from 0.5000 to 0.7000")
        );
        (r.face_density_var_initial, r.face_density_var_final) = (0.005, 0.7);
        assert_eq!(barely_moved(&r), None);
        // The face misfit is the mean |log| of the area shares over the population shares.
        let areas = [1.0, 4.0];
        let expect = ((0.2f64 / 0.5).ln().abs() + (0.8f64 / 0.5).ln().abs()) / 2.0;
        assert!((log_area_misfit(&pop, &areas) - expect).abs() < 1e-15);
        assert_eq!(density_error(&pop, &areas).0, log_area_misfit(&pop, &areas));
    }

    #[test]
    fn known_density_errors() {
        let m = two_triangles();
        // Populations 1 and 3: normalized P = 1/4, 3/4; areas 1/2, 1/2.
        let pop = vec![1.0, 3.0];
        let r = compute(
            &m,
            &pop,
            &m.positions,
            &m.positions,
            Domain::Plane,
            Some(&[(2, [1.0, 2.0, 0.0])]),
        );
        let d0 = (0.5f64 / 0.25).ln().abs();
        let d1 = (0.5f64 / 0.75).ln().abs();
        assert!((r.density_error_mean - (d0 + d1) / 2.0).abs() < 1e-14);
        assert!((r.area_ratio_error_mean - (1.0 + 1.0 / 3.0) / 2.0).abs() < 1e-14);
        // Face densities 2 and 6: normalized 0.5 and 1.5 → variance 0.25.
        assert!((r.face_density_var_final - 0.25).abs() < 1e-14);
        assert_eq!(r.landmark_error, Some(1.0));
    }

    #[test]
    fn flips_are_counted_against_majority() {
        let faces = vec![[0u32, 1, 2], [0, 2, 3], [0, 3, 1]];
        let map = vec![
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [-1.0, 0.0, 0.0],
        ];
        let (_, flipped) = map_areas(&map, &faces, Domain::Plane);
        // Signed areas: +, +, − → one flip.
        assert_eq!(flipped, 1);
    }

    #[test]
    fn spherical_flips_use_the_outward_test() {
        // A tetrahedron inscribed in the sphere, outward faces; then one vertex pushed through.
        let s = 1.0 / 3f64.sqrt();
        let mut p = vec![[s, s, s], [s, -s, -s], [-s, s, -s], [-s, -s, s]];
        let faces = vec![[0u32, 1, 2], [0, 3, 1], [0, 2, 3], [1, 3, 2]];
        let (areas, flipped) = map_areas(&p, &faces, Domain::Sphere);
        assert_eq!(flipped, 0);
        let a = 2.0 * 3f64.sqrt() * s * s;
        assert!((areas[0] - a).abs() < 1e-12);
        // The identity map of the tetrahedron onto itself has μ = 0.
        let mesh = TriMesh::new(p.clone(), faces.clone());
        let r = compute(&mesh, &areas, &p, &p, Domain::Sphere, None);
        assert!(r.max_abs_mu < 1e-12 && r.flipped_triangles == 0);
        p[0] = [-s, -s, -s];
        assert!(map_areas(&p, &faces, Domain::Sphere).1 > 0);
    }

    #[test]
    fn quantiles_interpolate() {
        let s = [1.0, 2.0, 3.0, 4.0];
        assert_eq!(quantile(&s, 0.5), 2.5);
        assert_eq!(quantile(&s, 0.25), 1.75);
    }

    /// Densities 1 : 4 in the map (Var(ρ̃) 0.36) are not equalized; 1 : 1.5 (0.04) are.
    #[test]
    fn a_density_far_from_equal_is_named() {
        let m = two_triangles();
        let var = |pop: &[f64]| compute(&m, pop, &m.positions, &m.positions, Domain::Plane, None);
        let far = var(&[1.0, 4.0]);
        assert!((far.face_density_var_final - 0.36).abs() < 1e-12);
        let why = not_equalized(&far).expect("Var 0.36 is not equalized");
        assert!(why.contains("0.360"), "{why}");
        let near = var(&[1.0, 1.5]);
        assert!((near.face_density_var_final - 0.04).abs() < 1e-12);
        assert_eq!(not_equalized(&near), None);
    }
}
