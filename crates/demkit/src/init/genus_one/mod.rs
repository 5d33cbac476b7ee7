//! The initial map of the toroidal density-equalizing parameterization (TDEM paper §4,
//! Algorithm 2 line 1): a bijective map of any closed genus-one mesh onto the flat torus
//! `[0, 2πR) × [−πr, πr)` of a target torus, opposite sides identified ((24)–(25)).
//!
//! The paper slices the surface along two cut paths and computes a rectangular conformal map
//! with periodic boundary conditions. demkit finds the cut itself and solves for the periodic
//! map directly, without duplicating seam vertices:
//!
//! 1. [`cut_graph`]: the tree–cotree decomposition gives two homology generators and the dual
//!    basis of closed integer 1-forms `η₁, η₂` (the lattice translation across every edge).
//! 2. [`periodic_harmonic`]: the harmonic maps with unit periods along `η₁` and `η₂` (one
//!    sparse Cholesky factorization, two right-hand sides). Harmonic maps are linear in their
//!    periods, so every lattice's harmonic map is a linear image of this one.
//! 3. [`lattice`]: the lattice assignment — which homology classes go onto the `2πR` and `2πr`
//!    sides — that minimises the Dirichlet energy of the final map, i.e. its mean conformal
//!    distortion (a Lagrange–Gauss reduction of the energy form; optimal, see there). The
//!    orientation is then fixed so that faces come out counter-clockwise.
//! 4. [`flat_map`]: the points wrapped into the rectangle, per-corner whole-period offsets.
//! 5. [`translation`]: the map translated along `v` so that its face areas on the target
//!    torus (where `φ` shrinks the inner and stretches the outer side) best match the source
//!    face areas — the one free parameter left that changes the areas on the torus.
//!
//! With cotangent weights the map is the discrete harmonic map with the target's periods: the
//! conformal map followed by the one linear map that fits the conformal periods onto the
//! rectangle. If it flips a triangle (possible with negative cotangent weights on obtuse
//! meshes), the edges of the faces around the folds get positive weights, the region growing
//! by one ring per try (up to three tries); then every edge does, for which the periodic
//! harmonic map is an embedding; finally uniform weights ([`weights`]). The lattice
//! assignment always minimises the true (cotangent) Dirichlet energy of the map returned.
//!
//! The map is not `φ⁻¹` even on a torus of revolution with the target's radii: `φ⁻¹` is not
//! harmonic (nor conformal). There the map is `u = Rα`, `v = 2r atan(k tan(θ/2))`,
//! `k = √((R − r)/(R + r))`, spacing the rings `∝ 1/(R + r cos θ)` where `φ⁻¹` spaces them
//! uniformly; the density diffusion of TDEM evens out such area differences.

pub mod cut_graph;
pub mod flat_map;
pub mod lattice;
pub mod periodic_harmonic;
pub mod translation;
pub mod weights;

#[cfg(test)]
mod tests;

use crate::fem::cotangent_weights;
use crate::geometry::torus::{FlatTorusMap, Torus};
use crate::geometry::{face_areas, triangle_area};
use crate::mesh::topology::topology;
use crate::mesh::validate::check;
use crate::{Error, Result, TriMesh};
use cut_graph::CutGraph;
use periodic_harmonic::{PeriodicLaplacian, dirichlet_gram, total_signed_area};
pub use weights::HarmonicWeights;

/// Rounds of local repair (positive weights on the folds grown by one more ring each round)
/// before all weights are made positive.
const LOCAL_ROUNDS: usize = 3;

/// The method name used in topology errors.
const METHOD: &str = "TDEM";

/// How [`flat_torus_map_with_report`] got its map.
#[derive(Debug, Clone, PartialEq)]
pub struct FlatTorusReport {
    /// The edge weights of the map returned.
    pub weights: HarmonicWeights,
    /// The maps tried before it and rejected for folding: their weights and their numbers of
    /// flipped triangles.
    pub rejected: Vec<(HarmonicWeights, usize)>,
    /// The two generator edges of the cut, as vertex pairs.
    pub generators: [[u32; 2]; 2],
    /// The lattice assignment: row 0 (row 1) is the cohomology class, in the basis dual to the
    /// generators, sent onto the `2πR` (`2πr`) side; determinant ±1.
    pub lattice: [[i64; 2]; 2],
    /// Dirichlet energy of the map over twice its area: the mean conformal distortion
    /// `(σ₁² + σ₂²) / 2σ₁σ₂` weighted by image area, 1 for a conformal map.
    pub conformal_distortion: f64,
    /// The translation along `v` applied to balance the areas on the torus, in `[0, 2πr)`.
    pub v_shift: f64,
    /// The area distortion (27) of the map on the target torus: the mean over the faces of
    /// `|log((a_f / Σa) / (A_f / ΣA))|`, `a_f` the source face areas and `A_f` the areas of
    /// the triangles through the `φ`-images of the corners.
    pub area_distortion: f64,
}

/// A bijective map of the closed genus-one `mesh` onto the flat torus of `torus`, the periodic
/// rectangle `[0, 2πR) × [−πr, πr)` (TDEM paper §4, Algorithm 2 line 1, the initial
/// parameterization `h`; `φ` of it lies on the target torus): the discrete harmonic map with
/// periods `(2πR, 0)` and `(0, 2πr)` along a homology basis found by a tree–cotree cut, the
/// basis chosen to minimise conformal distortion, translated along `v` to balance the face
/// areas on the target torus (see the module documentation). Every face is counter-clockwise
/// (no flipped triangle, [`FlatTorusMap::count_flipped`] is 0) and the image areas add up to
/// `4π²Rr`.
///
/// Errors: [`Error::Argument`] for radii without `R > r > 0`; [`Error::Topology`] unless the
/// mesh is one connected closed surface of genus 1; [`Error::InvalidMesh`] when it fails
/// [`crate::mesh::validate::check`] otherwise; [`Error::Numerical`] when no map without
/// flipped triangles was found.
pub fn flat_torus_map(mesh: &TriMesh, torus: &Torus) -> Result<FlatTorusMap> {
    flat_torus_map_with_report(mesh, torus).map(|(map, _)| map)
}

/// [`flat_torus_map`] with how the map was obtained.
pub fn flat_torus_map_with_report(
    mesh: &TriMesh,
    torus: &Torus,
) -> Result<(FlatTorusMap, FlatTorusReport)> {
    let torus = Torus::new(torus.major, torus.minor)?;
    check_genus_one(mesh, METHOD)?;
    let setup = Setup::new(mesh)?;
    let faces = &mesh.faces;
    let mut rejected = Vec::new();
    let mut last_error = None;
    // Faces whose edges get positive weights in the local repair: the folds found so far.
    let mut folds = vec![false; faces.len()];
    let plan = [HarmonicWeights::Cotangent]
        .into_iter()
        .chain([HarmonicWeights::LocallyPositive; LOCAL_ROUNDS])
        .chain([HarmonicWeights::PositiveCotangent, HarmonicWeights::Uniform]);
    let mut rings = 0;
    for kind in plan {
        let w = match kind {
            HarmonicWeights::Cotangent => setup.cot.clone(),
            HarmonicWeights::LocallyPositive => {
                if !folds.iter().any(|&f| f) {
                    continue;
                }
                rings += 1;
                let mut region = folds.clone();
                for _ in 0..rings {
                    region = weights::grow(faces, mesh.n_vertices(), &region);
                }
                weights::raised_cotangent(&setup.cot, &setup.cut.twin, Some(&region))
            }
            HarmonicWeights::PositiveCotangent => {
                weights::raised_cotangent(&setup.cot, &setup.cut.twin, None)
            }
            HarmonicWeights::Uniform => weights::uniform(faces.len()),
        };
        let a = match setup.attempt(mesh, &torus, &w) {
            Ok(a) => a,
            Err(e) => {
                last_error = Some(e);
                continue;
            }
        };
        if !a.flipped.is_empty() {
            rejected.push((kind, a.flipped.len()));
            for &f in &a.flipped {
                folds[f] = true;
            }
            continue;
        }
        let areas = face_areas(&mesh.positions, faces);
        let v_shift = translation::area_balanced_shift(&a.map, faces, &torus, &areas);
        let map = flat_map::translated(&a.map, faces, &torus, [0.0, v_shift])?;
        let area_distortion = area_distortion(&map, faces, &torus, &areas);
        let report = FlatTorusReport {
            weights: kind,
            rejected,
            generators: setup.generators,
            lattice: a.lattice,
            conformal_distortion: a.conformal_distortion,
            v_shift,
            area_distortion,
        };
        return Ok((map, report));
    }
    let detail = match (rejected.last(), last_error) {
        (Some((kind, flips)), _) => {
            format!("{flips} flipped triangles even with {kind:?} weights")
        }
        (None, Some(e)) => e.to_string(),
        (None, None) => "no weights left to try".to_string(),
    };
    Err(Error::Numerical(format!(
        "no bijective map onto the flat torus was found: {detail}"
    )))
}

/// The cut, its cohomology basis and the cotangent weights of a genus-one mesh, shared by
/// the attempts with different weights.
struct Setup {
    cut: CutGraph,
    eta: [Vec<i64>; 2],
    generators: [[u32; 2]; 2],
    laplacian: PeriodicLaplacian,
    cot: Vec<[f64; 3]>,
}

/// One periodic harmonic map onto the target's flat torus.
struct Attempt {
    map: FlatTorusMap,
    /// The faces with a non-positive signed area.
    flipped: Vec<usize>,
    lattice: [[i64; 2]; 2],
    conformal_distortion: f64,
}

impl Setup {
    /// The cut of `mesh` (checked by [`check_genus_one`]).
    fn new(mesh: &TriMesh) -> Result<Self> {
        let n = mesh.n_vertices();
        let faces = &mesh.faces;
        let cut = CutGraph::new(n, faces)?;
        if cut.generators.len() != 2 {
            return Err(Error::Numerical(format!(
                "the tree–cotree cut of a genus-one surface left {} generators instead of 2",
                cut.generators.len()
            )));
        }
        let generators = [0, 1].map(|k| cut.edges[cut.generators[k] as usize]);
        let eta = [cut.cohomology_form(0), cut.cohomology_form(1)];
        // One vertex pinned, and any vertex no face uses (it has no equation).
        let mut pinned = vec![true; n];
        for &v in faces.iter().flatten() {
            pinned[v as usize] = false;
        }
        pinned[cut.root as usize] = true;
        let laplacian = PeriodicLaplacian::new(n, faces, &pinned)?;
        let cot = cotangent_weights(&mesh.positions, faces);
        Ok(Self {
            cut,
            eta,
            generators,
            laplacian,
            cot,
        })
    }

    /// The periodic harmonic map with the per-corner weights `w`, its lattice assignment
    /// chosen and its orientation fixed; its flipped triangles listed.
    fn attempt(&self, mesh: &TriMesh, torus: &Torus, w: &[[f64; 3]]) -> Result<Attempt> {
        let faces = &mesh.faces;
        let forms = [&self.eta[0][..], &self.eta[1][..]];
        let unit = self.laplacian.solve(faces, w, forms)?;
        // ±1: the degree of the map times the unit lattice's area.
        let degree = total_signed_area(faces, forms, &unit);
        if !((degree.abs() - 1.0).abs() < 1e-6) {
            return Err(Error::Numerical(format!(
                "the periodic harmonic map covers the torus {degree} times instead of once"
            )));
        }
        // The assignment minimises the true Dirichlet energy (cotangent weights) of the map
        // actually returned, whatever weights it was solved with.
        let gram = dirichlet_gram(faces, &self.cot, forms, &unit);
        let mut p = lattice::reduced_basis(gram)?;
        let det = p[0][0] * p[1][1] - p[0][1] * p[1][0];
        if (det as f64) * degree < 0.0 {
            // A reflection v → −v makes the faces counter-clockwise; the energy is unchanged.
            p[1] = [-p[1][0], -p[1][1]];
        }
        let map = flat_map::flat_map(faces, &unit, forms, p, torus)?;
        let period = torus.periods();
        let flipped = (0..faces.len())
            .filter(|&f| {
                let [a, b, c] = map.corners(faces, f, period);
                !((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]) > 0.0)
            })
            .collect();
        let q = |v: [i64; 2]| {
            let v = v.map(|x| x as f64);
            v[0] * (gram[0][0] * v[0] + gram[0][1] * v[1])
                + v[1] * (gram[1][0] * v[0] + gram[1][1] * v[1])
        };
        let [a, b] = torus.periods();
        let energy = a * a * q(p[0]) + b * b * q(p[1]);
        Ok(Attempt {
            map,
            flipped,
            lattice: p,
            conformal_distortion: energy / (2.0 * a * b),
        })
    }
}

/// The area distortion (27) between the source face areas `areas` and the triangles through
/// the `φ`-images of the corners of `map`.
fn area_distortion(map: &FlatTorusMap, faces: &[[u32; 3]], torus: &Torus, areas: &[f64]) -> f64 {
    let period = torus.periods();
    let image: Vec<f64> = (0..faces.len())
        .map(|f| {
            let p = map
                .corners(faces, f, period)
                .map(|c| torus.project([c[0], c[1]]));
            triangle_area(p[0], p[1], p[2])
        })
        .collect();
    if faces.is_empty() {
        return 0.0;
    }
    crate::metrics::log_area_misfit(&image, areas)
}

/// Checks that `mesh` is one connected closed surface of genus 1 that passes
/// [`crate::mesh::validate::check`] (unused vertices allowed): [`Error::Topology`] for another
/// topology (several pieces included), [`Error::InvalidMesh`] for anything else.
pub(crate) fn check_genus_one(mesh: &TriMesh, method: &str) -> Result<()> {
    let findings = check(mesh);
    let topo = topology(mesh);
    let needs = format!("{method} needs a connected closed surface of genus 1");
    if topo.components > 1 {
        return Err(Error::Topology {
            method: method.to_string(),
            msg: format!(
                "{needs}, but this is a mesh of {} separate pieces",
                topo.components
            ),
        });
    }
    if let Some(first) = findings.errors.into_iter().next() {
        return Err(Error::InvalidMesh(first));
    }
    if !topo.is_closed() || topo.euler_characteristic != 0 {
        let what = if topo.is_closed() {
            format!("a closed surface of genus {}", topo.genus)
        } else {
            let k = topo.n_boundaries();
            format!(
                "an open surface of genus {} with {k} boundary loop{}",
                topo.genus,
                if k == 1 { "" } else { "s" }
            )
        };
        return Err(Error::Topology {
            method: method.to_string(),
            msg: format!("{needs}, but this is {what}"),
        });
    }
    Ok(())
}
