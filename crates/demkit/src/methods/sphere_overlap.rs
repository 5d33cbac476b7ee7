//! Bijectivity on the sphere: the north–south overlap correction of the SDEM paper (§3.1.3)
//! and a step that never returns a flipped map.
//!
//! A pass of the correction, for a pole face `F`: rotate the initial map S₀ and the current map
//! Sₙ so that `F`'s centroid is the north pole, project both stereographically (the pole face
//! becomes the outer face, its neighbourhood the outermost region), compute the Beltrami
//! coefficient μ of the planar map D₀ → Dₙ, truncate it where |μ| ≥ 1 (3.19), and rebuild the
//! map with the linear Beltrami solver from D₀ with the outermost vertices fixed at their place
//! in Dₙ (3.20). Two passes run with antipodal pole faces, each the face with the most regular
//! 1-ring (3.15)–(3.18) in its hemisphere, so that each pass corrects the other's fixed cap.

use crate::geometry::sphere::{
    mat_t_vec, mat_vec, normalize, project_from_north, rotation_to_north, spherical_orientation,
    unproject_from_north,
};
use crate::geometry::{add, dot, scale};
use crate::init::spherical_conformal::face_regularity;
use crate::qc::{LinearBeltramiSolver, beltrami_coefficient, truncate};
use rayon::prelude::*;
use std::cell::OnceCell;

/// The truncation parameter δ of (3.19).
const DELTA: f64 = 0.1;

/// One pass of the correction (module docs).
struct Pass {
    pole: usize,
    fixed: Vec<bool>,
    inner_faces: Vec<[u32; 3]>,
    /// D₀: the initial map seen from the pole face, projected.
    d0: Vec<[f64; 3]>,
    lbs: OnceCell<Option<LinearBeltramiSolver>>,
}

/// The north–south overlap correction for one mesh and one initial map.
pub(crate) struct OverlapCorrector {
    faces: Vec<[u32; 3]>,
    passes: [Pass; 2],
}

fn centroid_direction(map: &[[f64; 3]], f: [u32; 3]) -> [f64; 3] {
    normalize(add(add(map[f[0] as usize], map[f[1] as usize]), map[f[2] as usize]))
}

/// The 1-ring regularity R̄ (3.18) of every face of `map`.
pub(crate) fn one_ring_regularity(map: &[[f64; 3]], faces: &[[u32; 3]]) -> Vec<f64> {
    let rf = face_regularity(map, faces);
    // (3.16)–(3.17): R_V = H^FV R_F with H_ij = 1/3 for incident faces.
    let mut rv = vec![0.0; map.len()];
    for (f, r) in faces.iter().zip(&rf) {
        for &v in f {
            rv[v as usize] += r / 3.0;
        }
    }
    faces
        .iter()
        .map(|f| f.iter().map(|&v| rv[v as usize]).sum::<f64>() / 3.0)
        .collect()
}

impl Pass {
    fn new(initial: &[[f64; 3]], faces: &[[u32; 3]], pole: usize) -> Self {
        let n = initial.len();
        let r0 = rotation_to_north(centroid_direction(initial, faces[pole]));
        let d0: Vec<[f64; 3]> = initial
            .par_iter()
            .map(|&p| project_from_north(mat_vec(&r0, p)))
            .collect();
        // The outermost region: the pole face's corners and their neighbours.
        let mut fixed = vec![false; n];
        let corners = faces[pole];
        for f in faces {
            if f.iter().any(|v| corners.contains(v)) {
                for &v in f {
                    fixed[v as usize] = true;
                }
            }
        }
        let inner_faces = faces
            .iter()
            .enumerate()
            .filter(|&(i, _)| i != pole)
            .map(|(_, f)| *f)
            .collect();
        Self {
            pole,
            fixed,
            inner_faces,
            d0,
            lbs: OnceCell::new(),
        }
    }

    /// Applies the pass to `map` in place. Returns false if the solver failed (map unchanged).
    fn apply(&self, faces: &[[u32; 3]], map: &mut [[f64; 3]]) -> bool {
        let rn = rotation_to_north(centroid_direction(map, faces[self.pole]));
        let dn: Vec<[f64; 3]> = map
            .par_iter()
            .map(|&p| project_from_north(mat_vec(&rn, p)))
            .collect();
        let mu = beltrami_coefficient(&self.d0, &dn, &self.inner_faces);
        let needs = self.inner_faces.iter().zip(&mu).any(|(f, m)| {
            !(m.norm() < 1.0) && !f.iter().all(|&v| self.fixed[v as usize])
        });
        if !needs {
            return true;
        }
        let mu: Vec<_> = mu.into_iter().map(|m| truncate(m, DELTA)).collect();
        let lbs = self.lbs.get_or_init(|| {
            LinearBeltramiSolver::new(self.d0.len(), &self.inner_faces, &self.fixed).ok()
        });
        let Some(lbs) = lbs else { return false };
        let Ok(out) = lbs.solve(&self.d0, &mu, &dn) else {
            return false;
        };
        if out.iter().any(|p| !p[0].is_finite() || !p[1].is_finite()) {
            return false;
        }
        map.par_iter_mut()
            .zip(out.par_iter())
            .for_each(|(m, &w)| *m = mat_t_vec(&rn, unproject_from_north(w)));
        true
    }
}

impl OverlapCorrector {
    /// Chooses the two pole faces on the initial (flip-free) map.
    pub(crate) fn new(initial: &[[f64; 3]], faces: &[[u32; 3]]) -> Self {
        let reg = one_ring_regularity(initial, faces);
        let best = |keep: &dyn Fn(usize) -> bool| {
            (0..faces.len())
                .filter(|&f| keep(f))
                .min_by(|&a, &b| reg[a].total_cmp(&reg[b]))
        };
        let north = best(&|_| true).unwrap_or(0);
        let cn = centroid_direction(initial, faces[north]);
        let south = best(&|f| dot(centroid_direction(initial, faces[f]), cn) < -0.5)
            .unwrap_or_else(|| {
                (0..faces.len())
                    .min_by(|&a, &b| {
                        let d = |f: usize| dot(centroid_direction(initial, faces[f]), cn);
                        d(a).total_cmp(&d(b))
                    })
                    .unwrap_or(0)
            });
        Self {
            faces: faces.to_vec(),
            passes: [
                Pass::new(initial, faces, north),
                Pass::new(initial, faces, south),
            ],
        }
    }

    /// Runs the north pass then the south pass on `map`.
    pub(crate) fn correct(&self, map: &mut [[f64; 3]]) {
        for p in &self.passes {
            if !p.apply(&self.faces, map) {
                return;
            }
        }
    }
}

/// True when some face of `map` is not counter-clockwise seen from outside.
pub(crate) fn has_spherical_flip(map: &[[f64; 3]], faces: &[[u32; 3]]) -> bool {
    faces.par_iter().any(|f| {
        !(spherical_orientation(map[f[0] as usize], map[f[1] as usize], map[f[2] as usize]) > 0.0)
    })
}

/// The first `t ∈ (0, 2]` at which the face with corners `p + t s` has a non-positive
/// orientation det(a, b, c) (a cubic in t), or +∞; sampled on a grid and refined by bisection.
fn collapse_time(p: [[f64; 3]; 3], s: [[f64; 3]; 3]) -> f64 {
    let det = |t: f64| {
        let q = [0, 1, 2].map(|k| add(p[k], scale(s[k], t)));
        spherical_orientation(q[0], q[1], q[2])
    };
    if !(det(0.0) > 0.0) {
        return 0.0;
    }
    const STEPS: usize = 32;
    let mut lo = 0.0;
    for k in 1..=STEPS {
        let t = 2.0 * k as f64 / STEPS as f64;
        if !(det(t) > 0.0) {
            let mut hi = t;
            for _ in 0..30 {
                let mid = 0.5 * (lo + hi);
                if det(mid) > 0.0 {
                    lo = mid;
                } else {
                    hi = mid;
                }
            }
            return lo;
        }
        lo = t;
    }
    f64::INFINITY
}

/// How a step was taken.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct StepOutcome {
    /// The fraction of the step taken (1 = full step).
    pub fraction: f64,
    /// True when the overlap correction was used.
    pub corrected: bool,
}

/// Moves the flip-free spherical map `map` by the tangent `step` (then back onto the sphere)
/// without ever leaving a flipped face: the full step; if faces flip, the overlap correction;
/// if faces still flip, the step halved and tried again (§3.1.3). After 6 halvings the step is
/// scaled to half the earliest collapse time of any face, which cannot flip; if even that
/// fails the map stays put (fraction 0).
pub(crate) fn advance(
    map: &mut Vec<[f64; 3]>,
    step: &[[f64; 3]],
    faces: &[[u32; 3]],
    corrector: &OverlapCorrector,
) -> StepOutcome {
    let propose = |tau: f64| -> Vec<[f64; 3]> {
        map.par_iter()
            .zip(step.par_iter())
            .map(|(&p, &s)| normalize(add(p, scale(s, tau))))
            .collect()
    };
    let mut tau = 1.0;
    for _ in 0..=6 {
        let mut prop = propose(tau);
        if !has_spherical_flip(&prop, faces) {
            *map = prop;
            return StepOutcome {
                fraction: tau,
                corrected: false,
            };
        }
        corrector.correct(&mut prop);
        if prop.iter().all(|p| p.iter().all(|x| x.is_finite())) {
            for p in prop.iter_mut() {
                *p = normalize(*p);
            }
            if !has_spherical_flip(&prop, faces) {
                *map = prop;
                return StepOutcome {
                    fraction: tau,
                    corrected: true,
                };
            }
        }
        tau *= 0.5;
    }
    let t_min = faces
        .par_iter()
        .map(|f| collapse_time(f.map(|v| map[v as usize]), f.map(|v| step[v as usize])))
        .reduce(|| f64::INFINITY, f64::min);
    let mut tau = (0.5 * t_min).min(1.0);
    for _ in 0..8 {
        let prop = propose(tau);
        if !has_spherical_flip(&prop, faces) {
            *map = prop;
            return StepOutcome {
                fraction: tau,
                corrected: false,
            };
        }
        tau *= 0.5;
    }
    StepOutcome {
        fraction: 0.0,
        corrected: false,
    }
}

/// Projects `v` onto the tangent plane of the unit sphere at `p` (3.13).
#[inline]
pub(crate) fn tangential(v: [f64; 3], p: [f64; 3]) -> [f64; 3] {
    let n = normalize(p);
    add(v, scale(n, -dot(v, n)))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::generate::icosphere;

    #[test]
    fn correction_unfolds_a_local_fold() {
        let mesh = icosphere(3).unwrap();
        let faces = &mesh.faces;
        let corrector = OverlapCorrector::new(&mesh.positions, faces);
        // Push one vertex across its neighbours: a local fold-over.
        let mut map = mesh.positions.clone();
        let v = 100;
        let nb = faces.iter().find(|f| f.contains(&(v as u32))).unwrap();
        let w = nb.iter().map(|&u| u as usize).find(|&u| u != v).unwrap();
        map[v] = normalize(add(map[w], scale(crate::geometry::sub(map[w], map[v]), 0.8)));
        assert!(has_spherical_flip(&map, faces));
        corrector.correct(&mut map);
        assert!(!has_spherical_flip(&map, faces));
    }

    #[test]
    fn advance_never_flips() {
        let mesh = icosphere(3).unwrap();
        let faces = &mesh.faces;
        let corrector = OverlapCorrector::new(&mesh.positions, faces);
        let mut map = mesh.positions.clone();
        // A wild tangent field.
        let step: Vec<[f64; 3]> = map
            .iter()
            .enumerate()
            .map(|(i, &p)| {
                let t = i as f64 * 2.399;
                tangential([0.3 * t.cos(), 0.3 * t.sin(), 0.3 * (3.0 * t).cos()], p)
            })
            .collect();
        let out = advance(&mut map, &step, faces, &corrector);
        assert!(!has_spherical_flip(&map, faces));
        assert!(out.fraction > 0.0);
    }

    #[test]
    fn collapse_time_of_a_vertex_crossing_the_great_circle() {
        // Face around the north pole; vertex c moves towards and across edge ab.
        let p = [
            normalize([0.1, 0.0, 1.0]),
            normalize([-0.05, 0.08, 1.0]),
            normalize([-0.05, -0.08, 1.0]),
        ];
        assert!(spherical_orientation(p[0], p[1], p[2]) > 0.0);
        let s = [[-0.3, 0.0, 0.0], [0.0; 3], [0.0; 3]];
        let t = collapse_time(p, s);
        // det is linear here: the corner reaches x = −0.05/1.0-ish plane at t ≈ 0.5.
        assert!(t > 0.4 && t < 0.6, "t = {t}");
        assert_eq!(collapse_time(p, [[0.0; 3]; 3]), f64::INFINITY);
    }
}
