//! Bijectivity on the sphere: the overlap correction of the SDEM paper (§3.1.3) and a step
//! that never returns a flipped map. The same serves maps onto an ellipsoid (EDEM paper §3.3):
//! the orientation test is the sphere's ([`crate::geometry::ellipsoid`]), and the correction
//! works on the map's image on the unit sphere through `M⁻¹ = diag(1/a, 1/b, 1/c)`, as the
//! paper's does.
//!
//! The correction works on a patch around the flipped faces (their corners and a few rings of
//! neighbours): rotate the initial map S₀ and the current map Sₙ so that the patch sits at the
//! south pole, project both stereographically from the north pole (the patch lands around the
//! origin, where the projection distorts least, and everything else is the outer region),
//! compute the Beltrami coefficient μ of the planar map D₀ → Dₙ, truncate it where |μ| ≥ 1
//! (3.19, δ = 0.1), and rebuild the map with the linear Beltrami solver from D₀ with the outer
//! region fixed at its place in Dₙ (3.20); then back onto the sphere. Since the outer region is
//! the rest of the sphere, the correction cannot disturb the map away from the overlaps, and
//! one pass replaces the paper's north and south passes (whose fixed polar caps exist only
//! because the paper corrects the whole sphere at once). A patch that does not unfold is grown
//! and tried again.

use crate::fem::VertexFaces;
use crate::geometry::ellipsoid::Ellipsoid;
use crate::geometry::sphere::{
    mat_t_vec, mat_vec, normalize, project_from_north, rotation_to_north, spherical_flipped,
    spherical_orientation, unproject_from_north,
};
use crate::geometry::{add, scale};
use crate::qc::{LinearBeltramiSolver, beltrami_coefficient, truncate};
use rayon::prelude::*;

/// The truncation parameter δ of (3.19).
const DELTA: f64 = 0.1;

/// The overlap correction for one mesh and one (flip-free) initial map onto one domain.
pub(crate) struct OverlapCorrector {
    faces: Vec<[u32; 3]>,
    /// The initial map's image on the unit sphere.
    initial: Vec<[f64; 3]>,
    incidence: VertexFaces,
    /// Where the maps lie: the unit sphere or an ellipsoid.
    domain: Ellipsoid,
}

fn flipped_faces(map: &[[f64; 3]], faces: &[[u32; 3]]) -> Vec<usize> {
    faces
        .par_iter()
        .enumerate()
        .filter(|&(_, &f)| spherical_flipped(map, f))
        .map(|(i, _)| i)
        .collect()
}

impl OverlapCorrector {
    /// The correction of maps of `faces` onto `domain` from the flip-free map `initial` (on
    /// `domain`).
    pub(crate) fn new(domain: Ellipsoid, initial: &[[f64; 3]], faces: &[[u32; 3]]) -> Self {
        Self {
            faces: faces.to_vec(),
            initial: initial.iter().map(|&p| domain.to_sphere(p)).collect(),
            incidence: VertexFaces::new(initial.len(), faces),
            domain,
        }
    }

    /// Per-vertex factors shortening every step to at most half the vertex's shortest edge.
    pub(crate) fn clamp_factors(&self, map: &[[f64; 3]], step: &[[f64; 3]]) -> Vec<f64> {
        (0..map.len())
            .into_par_iter()
            .map(|v| {
                let mut h = f64::INFINITY;
                for &f in self.incidence.faces_of(v) {
                    for &u in &self.faces[f as usize] {
                        if u as usize != v {
                            h = h.min(crate::geometry::norm(crate::geometry::sub(
                                map[u as usize],
                                map[v],
                            )));
                        }
                    }
                }
                let len = crate::geometry::norm(step[v]);
                if len > 0.5 * h { 0.5 * h / len } else { 1.0 }
            })
            .collect()
    }

    /// Corrects the flipped faces of `map` (module docs); patches of 3, 6 and 12 rings.
    /// A correction that does not reduce the number of flipped faces is undone. Only the
    /// first count looks at the whole map: a correction moves only its patch's vertices, so
    /// the flips after it are counted on the faces around them.
    pub(crate) fn correct(&self, map: &mut [[f64; 3]]) {
        let mut flipped = flipped_faces(map, &self.faces);
        for rings in [3, 6, 12] {
            if flipped.is_empty() {
                return;
            }
            let free = self.patch(&flipped, rings);
            let saved: Vec<[f64; 3]> = free.iter().map(|&v| map[v]).collect();
            if !self.correct_patch(map, &free) {
                continue;
            }
            // Every face that was flipped has its corners in the patch, so the flips now are
            // those among the faces touching it.
            let touched = self.faces_around(&free);
            let now: Vec<usize> = touched
                .into_iter()
                .filter(|&f| spherical_flipped(map, self.faces[f]))
                .collect();
            if now.len() < flipped.len() {
                flipped = now;
            } else {
                for (&v, &p) in free.iter().zip(&saved) {
                    map[v] = p;
                }
            }
        }
    }

    /// The vertices within `rings` rings of the corners of the faces `flipped`.
    fn patch(&self, flipped: &[usize], rings: usize) -> Vec<usize> {
        let mut seen = std::collections::HashSet::new();
        let mut free: Vec<usize> = Vec::new();
        for &f in flipped {
            for &v in &self.faces[f] {
                if seen.insert(v as usize) {
                    free.push(v as usize);
                }
            }
        }
        let mut start = 0;
        for _ in 0..rings {
            let end = free.len();
            for k in start..end {
                for &f in self.incidence.faces_of(free[k]) {
                    for &u in &self.faces[f as usize] {
                        if seen.insert(u as usize) {
                            free.push(u as usize);
                        }
                    }
                }
            }
            start = end;
        }
        free
    }

    /// The faces with a corner among the vertices `verts`, each once, in increasing order.
    fn faces_around(&self, verts: &[usize]) -> Vec<usize> {
        let mut out: Vec<usize> = verts
            .iter()
            .flat_map(|&v| self.incidence.faces_of(v).iter().map(|&f| f as usize))
            .collect();
        out.sort_unstable();
        out.dedup();
        out
    }

    /// One LBS correction of the patch whose free vertices are `free` (connected pieces are
    /// corrected one at a time, each around its own centre); true if anything moved.
    fn correct_patch(&self, map: &mut [[f64; 3]], free: &[usize]) -> bool {
        let faces = &self.faces;
        let in_patch: std::collections::HashSet<usize> = free.iter().copied().collect();
        let mut label: std::collections::HashMap<usize, usize> = std::collections::HashMap::new();
        let mut components: Vec<Vec<usize>> = Vec::new();
        for &start in free {
            if label.contains_key(&start) {
                continue;
            }
            let id = components.len();
            let mut comp = vec![start];
            label.insert(start, id);
            let mut k = 0;
            while k < comp.len() {
                let v = comp[k];
                k += 1;
                for &f in self.incidence.faces_of(v) {
                    for &u in &faces[f as usize] {
                        let u = u as usize;
                        if in_patch.contains(&u) && !label.contains_key(&u) {
                            label.insert(u, id);
                            comp.push(u);
                        }
                    }
                }
            }
            components.push(comp);
        }
        let mut changed = false;
        for comp in &components {
            changed |= self.correct_component(map, comp, &in_patch);
        }
        changed
    }

    /// LBS correction of one connected patch: `comp` are its free vertices, `free` those of
    /// the whole patch.
    fn correct_component(
        &self,
        map: &mut [[f64; 3]],
        comp: &[usize],
        free: &std::collections::HashSet<usize>,
    ) -> bool {
        let faces = &self.faces;
        // The patch's faces (those touching a free vertex) and their corners, re-indexed.
        let mut local: std::collections::HashMap<usize, u32> = std::collections::HashMap::new();
        let mut verts: Vec<usize> = Vec::new();
        let mut patch: Vec<[u32; 3]> = Vec::new();
        let mut seen_face = std::collections::HashSet::new();
        for &v in comp {
            for &f in self.incidence.faces_of(v) {
                if !seen_face.insert(f) {
                    continue;
                }
                patch.push(faces[f as usize].map(|u| {
                    let u = u as usize;
                    *local.entry(u).or_insert_with(|| {
                        verts.push(u);
                        (verts.len() - 1) as u32
                    })
                }));
            }
        }
        let fixed: Vec<bool> = verts.iter().map(|&v| !free.contains(&v)).collect();
        if !fixed.iter().any(|&x| x) {
            return false;
        }
        // The current map's patch on the unit sphere.
        let sphere: Vec<[f64; 3]> = verts
            .iter()
            .map(|&v| self.domain.to_sphere(map[v]))
            .collect();
        let centre = |m: &dyn Fn(usize) -> [f64; 3]| {
            let mut c = [0.0; 3];
            for (k, &fx) in fixed.iter().enumerate() {
                if !fx {
                    c = add(c, m(k));
                }
            }
            normalize(scale(c, -1.0))
        };
        // Rotations sending the patch's centre to the south pole.
        let r0 = rotation_to_north(centre(&|k| self.initial[verts[k]]));
        let rn = rotation_to_north(centre(&|k| sphere[k]));
        let d0: Vec<[f64; 3]> = verts
            .iter()
            .map(|&v| mat_vec(&r0, self.initial[v]))
            .collect();
        let dn: Vec<[f64; 3]> = sphere.iter().map(|&p| mat_vec(&rn, p)).collect();
        // The patch must stay well away from the projection's pole.
        if d0.iter().chain(&dn).any(|p| p[2] > 0.5) {
            return false;
        }
        let d0: Vec<[f64; 3]> = d0.into_iter().map(project_from_north).collect();
        let dn: Vec<[f64; 3]> = dn.into_iter().map(project_from_north).collect();
        let mu: Vec<_> = beltrami_coefficient(&d0, &dn, &patch)
            .into_iter()
            .map(|m| truncate(m, DELTA))
            .collect();
        let Ok(lbs) = LinearBeltramiSolver::new(verts.len(), &patch, &fixed) else {
            return false;
        };
        let Ok(out) = lbs.solve(&d0, &mu, &dn) else {
            return false;
        };
        if out.iter().any(|p| !p[0].is_finite() || !p[1].is_finite()) {
            return false;
        }
        for (k, &v) in verts.iter().enumerate() {
            if !fixed[k] {
                map[v] = self
                    .domain
                    .from_sphere(mat_t_vec(&rn, unproject_from_north(out[k])));
            }
        }
        true
    }
}

/// True when some face of `map` is not counter-clockwise seen from outside.
pub(crate) fn has_spherical_flip(map: &[[f64; 3]], faces: &[[u32; 3]]) -> bool {
    faces.par_iter().any(|&f| spherical_flipped(map, f))
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
    /// The fraction of the step taken (1 = full step; with local damping, the mean fraction
    /// over the vertices).
    pub fraction: f64,
    /// True when the overlap correction was used.
    pub corrected: bool,
}

/// Moves the flip-free map `map` onto the corrector's domain by the tangent `step` (then back
/// onto the domain)
/// without ever leaving a flipped face: the step; if faces flip, the overlap correction;
/// if faces still flip, the step halved and tried again (§3.1.3), down to 1/64. If that fails,
/// every vertex's step is limited to half its shortest edge (then corrected likewise); if that
/// fails, the limited step is damped locally: the vertices of every face that would collapse
/// have their step shortened (a face whose corners all stop cannot flip), so that a face being
/// crushed does not stop the rest of the map. Last resort: the step scaled uniformly to half
/// the earliest collapse time of any face. If nothing works the map stays put (fraction 0).
pub(crate) fn advance(
    map: &mut Vec<[f64; 3]>,
    step: &[[f64; 3]],
    faces: &[[u32; 3]],
    corrector: &OverlapCorrector,
) -> StepOutcome {
    let domain = corrector.domain;
    let propose = |scale_of: &(dyn Fn(usize) -> f64 + Sync)| propose(&domain, map, step, scale_of);
    let mut tau = 1.0;
    for _ in 0..7 {
        let mut prop = propose(&|_| tau);
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
                *p = domain.project(*p);
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
    // A step longer than half the vertex's shortest edge is shortened to that length.
    let limit = corrector.clamp_factors(map, step);
    let mut prop = propose(&|i| limit[i]);
    let mean_limit = limit.iter().sum::<f64>() / limit.len().max(1) as f64;
    if has_spherical_flip(&prop, faces) {
        corrector.correct(&mut prop);
        for p in prop.iter_mut() {
            *p = domain.project(*p);
        }
    }
    if prop.iter().all(|p| p.iter().all(|x| x.is_finite())) && !has_spherical_flip(&prop, faces) {
        *map = prop;
        return StepOutcome {
            fraction: mean_limit,
            corrected: true,
        };
    }
    // Local damping of the limited step: the rest of the map moves on.
    let limited: Vec<[f64; 3]> = step
        .iter()
        .zip(&limit)
        .map(|(s, &l)| scale(*s, l))
        .collect();
    let damp = local_damping(map, &limited, faces, &corrector.incidence);
    let prop = propose(&|i| limit[i] * damp[i]);
    if !has_spherical_flip(&prop, faces) {
        *map = prop;
        return StepOutcome {
            fraction: limit.iter().zip(&damp).map(|(a, b)| a * b).sum::<f64>()
                / limit.len().max(1) as f64,
            corrected: false,
        };
    }
    let t_min = faces
        .par_iter()
        .map(|f| collapse_time(f.map(|v| map[v as usize]), f.map(|v| step[v as usize])))
        .reduce(|| f64::INFINITY, f64::min);
    let tau = (0.5 * t_min).min(1.0);
    let prop = propose(&|_| tau);
    if tau > 0.0 && !has_spherical_flip(&prop, faces) {
        *map = prop;
        return StepOutcome {
            fraction: tau,
            corrected: false,
        };
    }
    StepOutcome {
        fraction: 0.0,
        corrected: false,
    }
}

/// `map` moved by `step`, vertex `i`'s step scaled by `scale_of(i)`, back onto `domain`.
fn propose(
    domain: &Ellipsoid,
    map: &[[f64; 3]],
    step: &[[f64; 3]],
    scale_of: &(dyn Fn(usize) -> f64 + Sync),
) -> Vec<[f64; 3]> {
    map.par_iter()
        .zip(step.par_iter())
        .enumerate()
        .map(|(i, (&p, &s))| domain.project(add(p, scale(s, scale_of(i)))))
        .collect()
}

/// Per-vertex step factors in [0, 1] such that no face collapses before twice the damped step
/// (see [`advance`]). After the first round only the faces around damped vertices are
/// re-examined.
fn local_damping(
    map: &[[f64; 3]],
    step: &[[f64; 3]],
    faces: &[[u32; 3]],
    incidence: &VertexFaces,
) -> Vec<f64> {
    let mut s = vec![1.0f64; map.len()];
    let mut candidates: Vec<usize> = (0..faces.len()).collect();
    let mut mark = vec![false; faces.len()];
    for round in 0..500 {
        let hits: Vec<(usize, f64)> = candidates
            .par_iter()
            .filter_map(|&i| {
                let f = &faces[i];
                let t = collapse_time(
                    f.map(|v| map[v as usize]),
                    f.map(|v| scale(step[v as usize], s[v as usize])),
                );
                (t < 2.0).then_some((i, t))
            })
            .collect();
        if hits.is_empty() {
            break;
        }
        let mut next = Vec::new();
        for (i, t) in hits {
            // The last rounds stop the corners outright: a face whose corners all stay put
            // cannot collapse, so the loop ends.
            let k = if round >= 30 { 0.0 } else { 0.5 * t.min(1.0) };
            for &v in &faces[i] {
                s[v as usize] *= k;
                for &g in incidence.faces_of(v as usize) {
                    if !mark[g as usize] {
                        mark[g as usize] = true;
                        next.push(g as usize);
                    }
                }
            }
        }
        for &g in &next {
            mark[g] = false;
        }
        candidates = next;
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::generate::icosphere;

    #[test]
    fn correction_unfolds_a_local_fold() {
        let mesh = icosphere(3).unwrap();
        let faces = &mesh.faces;
        let corrector = OverlapCorrector::new(Ellipsoid::UNIT_SPHERE, &mesh.positions, faces);
        // Push one vertex just across the far edge of one of its faces: a local fold-over.
        let mut map = mesh.positions.clone();
        let v = 100u32;
        let f = faces.iter().find(|f| f.contains(&v)).unwrap();
        let others: Vec<usize> = f.iter().filter(|&&u| u != v).map(|&u| u as usize).collect();
        let mid = scale(add(map[others[0]], map[others[1]]), 0.5);
        let p = map[v as usize];
        map[v as usize] = normalize(add(mid, scale(crate::geometry::sub(mid, p), 0.05)));
        assert!(has_spherical_flip(&map, faces));
        corrector.correct(&mut map);
        assert!(!has_spherical_flip(&map, faces));
    }

    #[test]
    fn advance_never_flips() {
        let mesh = icosphere(3).unwrap();
        let faces = &mesh.faces;
        let corrector = OverlapCorrector::new(Ellipsoid::UNIT_SPHERE, &mesh.positions, faces);
        let mut map = mesh.positions.clone();
        // A wild tangent field.
        let step: Vec<[f64; 3]> = map
            .iter()
            .enumerate()
            .map(|(i, &p)| {
                let t = i as f64 * 2.399;
                Ellipsoid::UNIT_SPHERE
                    .tangential([0.3 * t.cos(), 0.3 * t.sin(), 0.3 * (3.0 * t).cos()], p)
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
