//! LSDEM: landmark-aligned spherical density-equalizing maps (Lyu, Lui & Choi, Algorithm 3.2).
//!
//! Minimises `E = α ∫|∇ρ|² + β ∫|∇f|² + γ Σ|f(p_i) − q_i|²` (3.26) by descent on the sphere:
//! 1. Initial map f₀: spherical conformal map with Möbius correction (§3.1.1).
//! 2. Repeat: rotate the map by the rotation best aligning the landmarks with their targets
//!    (§3.2.2; closed form by Horn's quaternion method instead of the paper's gradient descent
//!    over three Euler angles: both find the optimal rotation, the closed form exactly);
//!    descend `f ← f + δt dE` with `dE = α ṽ + β Δ̄f + γ (q − f)` at the landmarks, each term
//!    projected on the tangent planes (3.27)–(3.33); overlap correction (§3.1.3); recoupling
//!    (3.22) — until ‖f_n − f_{n−1}‖∞ < ε (the matrix ∞-norm of the n×3 difference: the
//!    largest sum of a vertex's absolute coordinate changes).
//!
//! ṽ is the velocity −∇ρ/ρ (3.12)–(3.13) of the current recoupled density. The descent step is
//! semi-implicit: the density term explicit, the harmonic and landmark terms implicit —
//! `f_new = argmin ½|f − f*|²_A + ½δtβ fᵀLf + ½δtγ Σ|f(p_i) − q_i|²` with `f* = f + δt α ṽ`
//! (A lumped mass, L cotangent Laplacian), then projected on the tangent planes. An explicit
//! step of the Laplace–Beltrami term (3.29) with δt = 0.01 is unstable on fine meshes, and the
//! implicit landmark term drags each landmark's neighbourhood along with it instead of pulling
//! a single vertex through its neighbours. A map whose change keeps hovering above ε (over the
//! last 20 iterations its smallest value fell by less than 5%) stops as stationary. The loop is
//! the shared one of [`crate::methods::iteration`], with a fixed step, returning the last map.

use super::density::SphereDiffusion;
use super::input::{check_sphere_input, initial_sphere_map};
use super::overlap::{OverlapCorrector, advance};
use crate::geometry::ellipsoid::Ellipsoid;
use crate::geometry::rotation::optimal_rotation;
use crate::geometry::sphere::{mat_vec, normalize};
use crate::geometry::{norm, sub};
use crate::linalg::VertexOrder;
use crate::methods::iteration::{Flow, Keep, Measured, Moved, Rules, check_parameters, iterate};
use crate::methods::{MapResult, ProgressFn};
use crate::{Error, Result, TriMesh};
use rayon::prelude::*;
use std::time::Instant;

/// LSDEM parameters; `Default` gives the paper's defaults.
#[derive(Debug, Clone, PartialEq)]
pub struct Config {
    /// Weight α of the density term.
    pub alpha: f64,
    /// Weight β of the harmonic (conformality) term.
    pub beta: f64,
    /// Weight γ of the landmark term.
    pub gamma: f64,
    /// Descent step δt (paper: 0.01).
    pub dt: f64,
    /// Time over which the density is diffused before its velocity is taken; 0 takes the
    /// velocity −∇ρ/ρ of the current (recoupled) density itself, as §3.2.1 states.
    pub diffusion_dt: f64,
    /// Stationary stop: over the last `window` iterations the smallest ‖f_n − f_{n−1}‖∞ met
    /// fell by less than the fraction `min_progress` (the map only jitters).
    pub window: usize,
    /// See `window`.
    pub min_progress: f64,
    /// Stop when ‖f_n − f_{n−1}‖∞ < ε (paper: 1e-3).
    pub epsilon: f64,
    /// Iteration limit (paper: 200).
    pub max_iter: usize,
}

impl Default for Config {
    fn default() -> Self {
        Self {
            alpha: 1.0,
            beta: 2.0,
            gamma: 5.0,
            dt: 0.01,
            diffusion_dt: 0.0,
            epsilon: 1e-3,
            max_iter: 200,
            window: 20,
            min_progress: 0.05,
        }
    }
}

/// Largest distance of a landmark target from the unit sphere.
const TARGET_TOLERANCE: f64 = 1e-4;

/// Checks the landmarks: indices in range, each vertex once (`methods::check_landmark_vertices`),
/// targets on the unit sphere.
pub fn check_landmarks(landmarks: &[(usize, [f64; 3])], n_vertices: usize) -> Result<()> {
    crate::methods::check_landmark_vertices(landmarks, n_vertices, "lsdem")?;
    for (k, &(v, q)) in landmarks.iter().enumerate() {
        let r = norm(q);
        if !((r - 1.0).abs() <= TARGET_TOLERANCE) {
            return Err(Error::Landmarks(format!(
                "landmark {} (vertex {v}): target ({}, {}, {}) is not on the unit sphere (|q| = {r})",
                k + 1,
                q[0],
                q[1],
                q[2]
            )));
        }
    }
    Ok(())
}

fn check_config(c: &Config) -> Result<()> {
    check_parameters(c.epsilon, Some(c.dt), c.max_iter)?;
    if !(c.diffusion_dt >= 0.0 && c.diffusion_dt.is_finite()) {
        return Err(Error::Argument(format!(
            "the diffusion time must be non-negative, got {}",
            c.diffusion_dt
        )));
    }
    for (name, w) in [("alpha", c.alpha), ("beta", c.beta), ("gamma", c.gamma)] {
        if !(w >= 0.0 && w.is_finite()) {
            return Err(Error::Argument(format!(
                "{name} must be non-negative, got {w}"
            )));
        }
    }
    Ok(())
}

/// Computes the LSDEM of `mesh` (a genus-0 closed surface) with one `population` value per
/// face and `landmarks` (vertex, target on the unit sphere).
pub fn run(
    mesh: &TriMesh,
    population: &[f64],
    landmarks: &[(usize, [f64; 3])],
    config: &Config,
    progress: ProgressFn,
) -> Result<MapResult> {
    check_config(config)?;
    check_sphere_input(mesh, population, "lsdem")?;
    check_landmarks(landmarks, mesh.n_vertices())?;
    let t0 = Instant::now();
    let mut notes = Vec::new();
    let order = VertexOrder::of_mesh(mesh.n_vertices(), &mesh.faces)?;
    let initial = initial_sphere_map(mesh, population, &order, &mut notes)?;
    let time_init = t0.elapsed().as_secs_f64();

    let t1 = Instant::now();
    let faces = &mesh.faces;
    let targets: Vec<[f64; 3]> = landmarks.iter().map(|l| normalize(l.1)).collect();
    let mut flow = LandmarkFlow {
        diffusion: SphereDiffusion::new(
            Ellipsoid::UNIT_SPHERE,
            initial.len(),
            faces,
            population,
            Some(&order),
        )?,
        corrector: OverlapCorrector::new(Ellipsoid::UNIT_SPHERE, &initial, faces),
        faces,
        landmarks,
        targets: &targets,
        landmark_penalty: landmarks
            .iter()
            .map(|&(v, _)| (v, config.dt * config.gamma))
            .collect(),
        config,
        change: f64::INFINITY,
    };
    let rules = Rules::fixed(
        config.epsilon,
        config.max_iter,
        config.dt,
        config.window,
        config.min_progress,
        Keep::Last,
    );
    let out = iterate(&mut flow, initial.clone(), &rules, progress)?;
    // The rotation that would start the next iteration: it only lowers the landmark energy.
    let positions = |x: Vec<[f64; 3]>| {
        let current: Vec<[f64; 3]> = landmarks.iter().map(|l| x[l.0]).collect();
        let r = optimal_rotation(&current, &targets);
        x.into_iter().map(|p| normalize(mat_vec(&r, p))).collect()
    };
    let mut result = out.into_result("lsdem", initial, positions, t1, notes);
    result.time_init = time_init;
    Ok(result)
}

/// LSDEM's descent (Alg. 3.2 lines 3–9) on the shared skeleton. Its stopping quantity is the
/// change the last move made, ‖f_n − f_{n−1}‖∞ (infinite before the first move).
struct LandmarkFlow<'a> {
    diffusion: SphereDiffusion<'a>,
    corrector: OverlapCorrector,
    faces: &'a [[u32; 3]],
    landmarks: &'a [(usize, [f64; 3])],
    /// The landmarks' targets, on the unit sphere.
    targets: &'a [[f64; 3]],
    /// (vertex, δt γ) of every landmark: the landmark term of the implicit system.
    landmark_penalty: Vec<(usize, f64)>,
    config: &'a Config,
    /// ‖f_n − f_{n−1}‖∞ of the last move.
    change: f64,
}

impl Flow for LandmarkFlow<'_> {
    type Map = Vec<[f64; 3]>;
    type Data = ();

    fn measure(&mut self, _x: &Vec<[f64; 3]>) -> Result<Measured<()>> {
        Ok(Measured {
            error: self.change,
            merit: self.change,
            data: (),
        })
    }

    /// The rotation (§3.2.2), the semi-implicit descent step of length `dt` (3.27)–(3.33) and
    /// the overlap correction.
    fn advance(
        &mut self,
        prev: &Vec<[f64; 3]>,
        _m: &Measured<()>,
        dt: f64,
    ) -> Result<Moved<Vec<[f64; 3]>>> {
        let config = self.config;
        // §3.2.2: the optimal rotation.
        let current: Vec<[f64; 3]> = self.landmarks.iter().map(|l| prev[l.0]).collect();
        let r = optimal_rotation(&current, self.targets);
        let mut x: Vec<[f64; 3]> = prev
            .par_iter()
            .map(|p| normalize(mat_vec(&r, *p)))
            .collect();
        // (3.27)–(3.32): the descent direction.
        let d = self.diffusion.measure(&x);
        let v = self.diffusion.velocity(&x, &d, config.diffusion_dt)?;
        // Semi-implicit step: the density term explicit, the harmonic and landmark terms
        // implicit, f_new = argmin ½|f − f*|²_A + ½δtβ fᵀLf + ½δtγ Σ|f(p_i) − q_i|², i.e.
        // (A + δtβ L + δtγ C) f_new = A f* + δtγ C q with f* = f + δt α ṽ.
        let mut system = self.diffusion.operator().factor(
            &x,
            &d.areas,
            dt * config.beta,
            &self.landmark_penalty,
        )?;
        let mass = &system.mass;
        let n = x.len();
        let mut rhs = vec![0.0; 3 * n];
        for i in 0..n {
            for k in 0..3 {
                rhs[k * n + i] = mass[i] * (x[i][k] + dt * config.alpha * v[i][k]);
            }
        }
        for (&(vtx, _), q) in self.landmarks.iter().zip(self.targets) {
            for k in 0..3 {
                rhs[k * n + vtx] += dt * config.gamma * q[k];
            }
        }
        system.solve_many_in_place(&mut rhs, 3)?;
        let step: Vec<[f64; 3]> = (0..n)
            .into_par_iter()
            .map(|i| {
                let target = [rhs[i], rhs[n + i], rhs[2 * n + i]];
                Ellipsoid::UNIT_SPHERE.tangential(sub(target, x[i]), x[i])
            })
            .collect();
        // (3.33), overlap correction, recoupling (the density is re-derived from the map at the
        // start of every iteration).
        let outcome = advance(&mut x, &step, self.faces, &self.corrector);
        self.change = x
            .par_iter()
            .zip(prev.par_iter())
            .map(|(a, b)| (0..3).map(|k| (a[k] - b[k]).abs()).sum::<f64>())
            .reduce(|| 0.0, f64::max);
        Ok(Moved {
            map: x,
            fraction: outcome.fraction,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::generate::icosphere;
    use crate::geometry::face_areas;
    use crate::metrics::{Domain, Metrics, compute};

    /// LSDEM's map of `mesh` with `landmarks` at the defaults: no flipped face, every landmark
    /// within 0.02 of its target; its metrics.
    fn mapped(mesh: &TriMesh, pop: &[f64], landmarks: &[(usize, [f64; 3])]) -> Metrics {
        let r = run(mesh, pop, landmarks, &Config::default(), &mut |_| {}).unwrap();
        let m = compute(
            mesh,
            pop,
            &r.initial,
            &r.positions,
            Domain::Sphere,
            Some(landmarks),
        );
        assert_eq!(m.flipped_triangles, 0);
        assert!(m.landmark_error.unwrap() < 0.02, "{m:?}");
        m
    }

    #[test]
    fn landmark_checks() {
        assert!(check_landmarks(&[(3, [0.0, 0.0, 1.0])], 10).is_ok());
        let e = check_landmarks(&[(3, [0.0, 0.0, 1.001])], 10).unwrap_err();
        assert!(e.to_string().contains("unit sphere"), "{e}");
        let e = check_landmarks(&[(10, [0.0, 0.0, 1.0])], 10).unwrap_err();
        assert!(e.to_string().contains("out of range"), "{e}");
        assert!(check_landmarks(&[], 10).is_err());
    }

    #[test]
    fn rotated_landmarks_are_matched() {
        // Targets: four vertices of the sphere after a rotation about a tilted axis. The optimal
        // rotation aligns them, the rest of the map stays nearly conformal and equal-area.
        let mesh = icosphere(3).unwrap();
        let pop = face_areas(&mesh.positions, &mesh.faces);
        let (s, c) = 0.7f64.sin_cos();
        let rot = |p: [f64; 3]| [c * p[0] - s * p[1], s * p[0] + c * p[1], p[2]];
        let landmarks: Vec<(usize, [f64; 3])> = [0usize, 5, 50, 300]
            .iter()
            .map(|&v| (v, rot(mesh.positions[v])))
            .collect();
        let m = mapped(&mesh, &pop, &landmarks);
        assert!(m.density_var_final < 1e-3, "{m:?}");
        assert!(m.mean_abs_mu < 0.1, "{m:?}");
    }

    #[test]
    fn displaced_landmark_is_pulled_to_its_target() {
        let mesh = icosphere(3).unwrap();
        let pop = face_areas(&mesh.positions, &mesh.faces);
        let p0 = mesh.positions[0];
        let p1 = mesh.positions[100];
        // Landmark 0 stays, landmark 100 moves a little towards landmark 0.
        let moved = normalize([
            0.9 * p1[0] + 0.1 * p0[0],
            0.9 * p1[1] + 0.1 * p0[1],
            0.9 * p1[2] + 0.1 * p0[2],
        ]);
        let landmarks = vec![(0, p0), (100, moved), (400, mesh.positions[400])];
        mapped(&mesh, &pop, &landmarks);
    }
}
