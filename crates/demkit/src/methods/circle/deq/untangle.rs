//! Untangling a planar map that folds a few triangles, with chosen vertices held: the
//! foldover-free maps of Garanzha, Kaporin, Kudryavtseva, Protais, Ray and Sokolov
//! ("Foldover-free maps in 50 lines of code", ACM TOG 40(4), 2021).
//!
//! Each face's Jacobian `J` is measured against its reference triangle — the face on the
//! surface, scaled to the area it should have — and the energy
//!
//! `F_ε = Σ_T A_T [ (tr JᵀJ + λ (det² J + 1)) / χ(det J, ε) ]`, `χ(D, ε) = (D + √(ε² + D²)) / 2`,
//!
//! is finite for folded faces too (χ > 0) and becomes a barrier against folding as ε → 0. It is
//! minimised by Newton's method (the Hessian made positive semi-definite face by face,
//! [`energy::lift`]) while ε shrinks with the smallest determinant by the paper's rule; the map
//! is untangled once every determinant is positive.

use super::energy::{self, Face};
use super::layout::Layout;
use crate::geometry::{face_areas, signed_area_2d};
use crate::linalg::{ElementPattern, SparseCholesky, packed_index};
use crate::mesh::topology::{ring_distances, vertex_neighbours};
use crate::{Result, TriMesh};
use rayon::prelude::*;

/// The weight λ of the area term (the paper's 2D choice).
const LAMBDA: f64 = 1.0;

/// Outer iterations (each with a new ε) at most, and Newton iterations per ε.
const MAX_OUTER: usize = 60;
const INNER: usize = 3;

/// `χ(D, ε)` and its first two derivatives in `D`.
fn chi(d: f64, eps: f64) -> [f64; 3] {
    let r = (eps * eps + d * d).sqrt();
    [
        0.5 * (d + r),
        0.5 * (1.0 + d / r),
        0.5 * eps * eps / (r * r * r),
    ]
}

/// The untangling energy of one face as a function of `p = |f_z|²`, `q = |f_z̄|²` (of the map
/// from the reference triangle): `[E, E_p, E_q, E_pp, E_pq, E_qq]`.
fn g(p: f64, q: f64, eps: f64) -> [f64; 6] {
    let d = p - q;
    // Numerator N = tr JᵀJ + λ(D² + 1) = 2(p + q) + λ(D² + 1), and its derivatives.
    let n = 2.0 * (p + q) + LAMBDA * (d * d + 1.0);
    let (n_p, n_q) = (2.0 + 2.0 * LAMBDA * d, 2.0 - 2.0 * LAMBDA * d);
    let (n_pp, n_pq, n_qq) = (2.0 * LAMBDA, -2.0 * LAMBDA, 2.0 * LAMBDA);
    // Denominator χ(D): χ_p = χ', χ_q = −χ', χ_pp = χ'', χ_pq = −χ'', χ_qq = χ''.
    let [c, c1, c2] = chi(d, eps);
    let (c_p, c_q) = (c1, -c1);
    let (c_pp, c_pq, c_qq) = (c2, -c2, c2);
    let second = |n_xy: f64, n_x: f64, n_y: f64, c_x: f64, c_y: f64, c_xy: f64| {
        n_xy / c - (n_x * c_y + n_y * c_x) / (c * c) - n * c_xy / (c * c)
            + 2.0 * n * c_x * c_y / (c * c * c)
    };
    [
        n / c,
        n_p / c - n * c_p / (c * c),
        n_q / c - n * c_q / (c * c),
        second(n_pp, n_p, n_p, c_p, c_p, c_pp),
        second(n_pq, n_p, n_q, c_p, c_q, c_pq),
        second(n_qq, n_q, n_q, c_q, c_q, c_qq),
    ]
}

/// Untangles the planar map `x` of `faces` (surface positions `surface`; `area_ratio[f]`, the
/// area face `f` should have in the map over its area on the surface), moving only vertices
/// where `movable` holds and, at each stage, only those within `rings` edges of a folded
/// face (the region shrinks as the folds go). Returns true, with `x` untangled, when no face
/// folds any more; false, with `x` unchanged, otherwise.
pub(crate) fn untangle(
    surface: &[[f64; 3]],
    faces: &[[u32; 3]],
    area_ratio: &[f64],
    movable: &[bool],
    rings: usize,
    x: &mut [[f64; 3]],
) -> Result<bool> {
    let neighbours = vertex_neighbours(x.len(), faces);
    let start = x.to_vec();
    let mut eps = 1.0f64;
    let mut region: Option<(Vec<bool>, Region)> = None;
    for _ in 0..MAX_OUTER {
        let folded: Vec<usize> = (0..faces.len())
            .into_par_iter()
            .filter(|&f| !positive(x, faces[f]))
            .collect();
        if folded.is_empty() {
            return Ok(true);
        }
        let distance = ring_distances(&neighbours, folded.iter().flat_map(|&f| faces[f]), rings);
        let free: Vec<bool> = distance
            .iter()
            .zip(movable)
            .map(|(&d, &m)| m && d != usize::MAX)
            .collect();
        if region.as_ref().is_none_or(|(f, _)| *f != free) {
            let r = Region::new(surface, faces, area_ratio, &free)?;
            region = Some((free, r));
        }
        let Some((_, r)) = region.as_mut() else {
            break;
        };
        if r.n == 0 {
            break;
        }
        let previous = r.energy(x, eps);
        for _ in 0..INNER {
            if !r.newton_step(x, eps)? {
                break;
            }
        }
        // The paper's ε update: shrink with the energy's relative decrease, and keep ε above
        // what the smallest determinant needs.
        let e = r.energy(x, eps);
        let d = r.min_det(x);
        let sigma = (1.0 - e / previous).max(0.1);
        let mu = (1.0 - sigma) * chi(d, eps)[0];
        eps = if d < mu {
            2.0 * (mu * (mu - d)).sqrt()
        } else {
            1e-13
        };
    }
    x.copy_from_slice(&start);
    Ok(false)
}

/// For every face, the area it should have in the planar map `x` (its share of the
/// population, of the map's total area) over its area on the surface.
pub(crate) fn area_ratios(mesh: &TriMesh, population: &[f64], x: &[[f64; 3]]) -> Vec<f64> {
    let total_area: f64 = mesh
        .faces
        .iter()
        .map(|f| signed_area_2d(x[f[0] as usize], x[f[1] as usize], x[f[2] as usize]))
        .sum();
    let total_population: f64 = population.iter().sum();
    population
        .iter()
        .zip(face_areas(&mesh.positions, &mesh.faces))
        .map(|(p, a)| p / total_population * total_area / a)
        .collect()
}

/// Untangles the circle domain map `x` of `mesh` ([`untangle`]) with every loop of `layout`
/// held, towards faces whose areas follow the population ([`area_ratios`]), trying each
/// region radius of `rings` in turn. Returns false, with `x` unchanged, when none untangles.
pub(crate) fn untangle_within_loops(
    mesh: &TriMesh,
    population: &[f64],
    layout: &Layout,
    x: &mut [[f64; 3]],
    rings: &[usize],
) -> Result<bool> {
    let movable: Vec<bool> = layout.on_loops(x.len()).iter().map(|&l| !l).collect();
    let ratio = area_ratios(mesh, population, x);
    for &r in rings {
        if untangle(&mesh.positions, &mesh.faces, &ratio, &movable, r, x)? {
            return Ok(true);
        }
    }
    Ok(false)
}

/// The untangling problem on the faces around a set of free vertices.
struct Region<'a> {
    faces: &'a [[u32; 3]],
    /// The faces with a free corner, each with its reference (the surface triangle, its
    /// area ratio `k`) and weight (its reference area).
    moving: Vec<usize>,
    reference: Vec<(Face, f64, f64)>,
    total_weight: f64,
    /// Every vertex's first unknown (x; y is the next), or `u32::MAX` when it is held.
    unknown: Vec<u32>,
    n: usize,
    pattern: ElementPattern,
    solver: SparseCholesky,
    element_values: Vec<f64>,
    values: Vec<f64>,
}

impl<'a> Region<'a> {
    fn new(
        surface: &[[f64; 3]],
        faces: &'a [[u32; 3]],
        area_ratio: &[f64],
        free: &[bool],
    ) -> Result<Self> {
        let moving: Vec<usize> = (0..faces.len())
            .filter(|&f| faces[f].iter().any(|&v| free[v as usize]))
            .collect();
        let mut unknown = vec![u32::MAX; free.len()];
        let mut n = 0u32;
        for &f in &moving {
            for &v in &faces[f] {
                if free[v as usize] && unknown[v as usize] == u32::MAX {
                    unknown[v as usize] = n;
                    n += 2;
                }
            }
        }
        let reference: Vec<(Face, f64, f64)> = moving
            .iter()
            .map(|&f| {
                let face = Face::new(faces[f].map(|v| surface[v as usize]));
                let k = area_ratio[f];
                let weight = face.source_area * k;
                (face, k, weight)
            })
            .collect();
        let total_weight = reference
            .iter()
            .map(|r| r.2)
            .sum::<f64>()
            .max(f64::MIN_POSITIVE);
        let elements: Vec<Vec<u32>> = moving
            .iter()
            .map(|&f| {
                faces[f]
                    .iter()
                    .filter(|&&v| unknown[v as usize] != u32::MAX)
                    .flat_map(|&v| [unknown[v as usize], unknown[v as usize] + 1])
                    .collect()
            })
            .collect();
        let n = n as usize;
        let pattern = ElementPattern::new(n, elements.iter().map(|e| e.as_slice()))?;
        let solver = SparseCholesky::for_pattern(&pattern)?;
        Ok(Self {
            faces,
            moving,
            reference,
            total_weight,
            unknown,
            n,
            element_values: vec![0.0; pattern.n_element_values()],
            values: vec![0.0; pattern.nnz()],
            pattern,
            solver,
        })
    }

    fn image(&self, x: &[[f64; 3]], j: usize) -> [[f64; 2]; 3] {
        self.faces[self.moving[j]].map(|v| [x[v as usize][0], x[v as usize][1]])
    }

    /// The moving faces' energy at `eps`, per unit reference area.
    fn energy(&self, x: &[[f64; 3]], eps: f64) -> f64 {
        (0..self.moving.len())
            .into_par_iter()
            .map(|j| {
                let (face, k, w) = &self.reference[j];
                let (fz, fzb) = face.derivatives(self.image(x, j));
                w * g(fz.norm_sqr() / k, fzb.norm_sqr() / k, eps)[0]
            })
            // Summed in order: the same result whatever the threads.
            .collect::<Vec<f64>>()
            .iter()
            .sum::<f64>()
            / self.total_weight
    }

    /// The smallest determinant of a moving face's Jacobian (against its reference).
    fn min_det(&self, x: &[[f64; 3]]) -> f64 {
        (0..self.moving.len())
            .into_par_iter()
            .map(|j| {
                let (face, k, _) = &self.reference[j];
                let (fz, fzb) = face.derivatives(self.image(x, j));
                (fz.norm_sqr() - fzb.norm_sqr()) / k
            })
            .reduce(|| f64::INFINITY, f64::min)
    }

    /// One damped Newton step at `eps` with a backtracking line search; false when no step
    /// lowers the energy.
    fn newton_step(&mut self, x: &mut [[f64; 3]], eps: f64) -> Result<bool> {
        let derivatives: Vec<(f64, [f64; 6], [[f64; 6]; 6])> = (0..self.moving.len())
            .into_par_iter()
            .map(|j| {
                let (face, k, w) = &self.reference[j];
                let (fz, fzb) = face.derivatives(self.image(x, j));
                let [e, gp, gq, gpp, gpq, gqq] = g(fz.norm_sqr() / k, fzb.norm_sqr() / k, eps);
                let (s1, s2) = (w / k, w / (k * k));
                energy::lift(
                    face,
                    fz,
                    fzb,
                    [e * w, gp * s1, gq * s1, gpp * s2, gpq * s2, gqq * s2],
                )
            })
            .collect();
        let n = self.n;
        let scale = 1.0 / self.total_weight;
        let mut grad = vec![0.0; n];
        let (faces, moving, unknown) = (self.faces, &self.moving, &self.unknown);
        for (slot, (j, (_, gc, hc))) in self
            .pattern
            .element_slices(&mut self.element_values)
            .into_iter()
            .zip(derivatives.iter().enumerate())
        {
            slot.fill(0.0);
            // The element's unknowns: its free corners in face order, (x, y) each.
            let f = faces[moving[j]];
            let corners: Vec<usize> = (0..3)
                .filter(|&c| unknown[f[c] as usize] != u32::MAX)
                .collect();
            for (a, &ca) in corners.iter().enumerate() {
                let u = unknown[f[ca] as usize] as usize;
                grad[u] += gc[2 * ca] * scale;
                grad[u + 1] += gc[2 * ca + 1] * scale;
                for (b, &cb) in corners.iter().enumerate().take(a + 1) {
                    for da in 0..2 {
                        for db in 0..2 {
                            let (la, lb) = (2 * a + da, 2 * b + db);
                            if lb <= la {
                                slot[packed_index(la, lb)] += hc[2 * ca + da][2 * cb + db] * scale;
                            }
                        }
                    }
                }
            }
        }
        self.pattern
            .assemble(&self.element_values, &mut self.values);
        let col_ptr = self.pattern.col_ptr();
        let diag_mean = col_ptr[..n].iter().map(|&k| self.values[k]).sum::<f64>() / n as f64;
        for &k in &col_ptr[..n] {
            self.values[k] += (DAMPING * diag_mean).max(f64::MIN_POSITIVE);
        }
        if self.solver.factor(&self.values).is_err() {
            return Ok(false);
        }
        let mut step: Vec<f64> = grad.iter().map(|g| -g).collect();
        if self.solver.solve_finite_in_place(&mut step).is_err() {
            return Ok(false);
        }
        let slope: f64 = step.iter().zip(&grad).map(|(s, g)| s * g).sum();
        let current = self.energy(x, eps);
        let mut trial = x.to_vec();
        let mut t = 1.0;
        for _ in 0..30 {
            for (v, &u) in self.unknown.iter().enumerate() {
                if u != u32::MAX {
                    trial[v][0] = x[v][0] + t * step[u as usize];
                    trial[v][1] = x[v][1] + t * step[u as usize + 1];
                }
            }
            if self.energy(&trial, eps) <= current + 1e-4 * t * slope {
                x.copy_from_slice(&trial);
                return Ok(true);
            }
            t *= 0.5;
        }
        Ok(false)
    }
}

/// Levenberg–Marquardt damping of the Newton systems, relative to their mean diagonal.
const DAMPING: f64 = 1e-9;

/// True when the face `f` of `x` has positive area.
fn positive(x: &[[f64; 3]], f: [u32; 3]) -> bool {
    signed_area_2d(x[f[0] as usize], x[f[1] as usize], x[f[2] as usize]) > 0.0
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::generate_fixtures::grid;

    #[test]
    fn chi_is_positive_and_tends_to_the_positive_part() {
        for d in [-2.0, -1e-3, 0.0, 1e-3, 2.0] {
            assert!(chi(d, 1e-2)[0] > 0.0);
        }
        assert!((chi(2.0, 1e-8)[0] - 2.0).abs() < 1e-12);
        assert!(chi(-2.0, 1e-8)[0] < 1e-15);
    }

    #[test]
    fn derivatives_match_finite_differences() {
        let (p, q, eps) = (0.7, 0.2, 0.3);
        let d = g(p, q, eps);
        let h = 1e-6;
        let num = |f: &dyn Fn(f64, f64) -> f64| {
            [
                (f(p + h, q) - f(p - h, q)) / (2.0 * h),
                (f(p, q + h) - f(p, q - h)) / (2.0 * h),
            ]
        };
        let first = num(&|a, b| g(a, b, eps)[0]);
        assert!((first[0] - d[1]).abs() < 1e-6 && (first[1] - d[2]).abs() < 1e-6);
        let dp = num(&|a, b| g(a, b, eps)[1]);
        let dq = num(&|a, b| g(a, b, eps)[2]);
        assert!((dp[0] - d[3]).abs() < 1e-5, "{} {}", dp[0], d[3]);
        assert!((dp[1] - d[4]).abs() < 1e-5 && (dq[0] - d[4]).abs() < 1e-5);
        assert!((dq[1] - d[5]).abs() < 1e-5);
    }

    #[test]
    fn a_folded_grid_is_untangled_with_its_boundary_held() {
        let (pos, faces, boundary) = grid(8, 0.0);
        let mut x = pos.clone();
        // Push an interior vertex across its neighbours: several faces fold.
        let v = (0..pos.len())
            .find(|&v| (pos[v][0] - 0.5).abs() < 0.07 && (pos[v][1] - 0.5).abs() < 0.07)
            .unwrap();
        x[v][0] += 0.3;
        x[v][1] += 0.2;
        assert!(crate::geometry::count_nonpositive(&x, &faces) > 0);
        let free: Vec<bool> = boundary.iter().map(|b| !b).collect();
        let ratio = vec![1.0; faces.len()];
        assert!(untangle(&pos, &faces, &ratio, &free, 3, &mut x).unwrap());
        assert_eq!(crate::geometry::count_nonpositive(&x, &faces), 0);
        for (v, &b) in boundary.iter().enumerate() {
            if b {
                assert_eq!(x[v], pos[v]);
            }
        }
    }
}
