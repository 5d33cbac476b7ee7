//! The initial conformal map of a multiply connected open surface onto a circle domain — the
//! unit disk minus k disjoint disks — for the DEQ method (DEQ paper §5.1.1, where the paper
//! uses Koebe's iteration). With a single boundary loop this is a disk conformal map onto the
//! unit disk.
//!
//! Method: constrained minimisation of the discrete conformal energy. For a piecewise-linear
//! map `f` sending triangle `T` (source corners `q_k` in its own frame, counter-clockwise) to
//! image corners `w_k` (complex), with `d_k = q_{k+2} − q_{k+1}`:
//!
//! - (C1) `f_z̄ = i Σ_k d_k w_k / (4 A_T)`, `f_z = −i Σ_k d̄_k w_k / (4 A_T)`;
//! - (C2) `E_C = Σ_T ω_T |Σ_k d_k w_k|² / (8 A_T) = Σ_T ω_T · 2 A_T |f_z̄|²`, with face weights
//!   `ω_T` (all 1: `E_C = E_Dirichlet − Area(f) ≥ 0`, zero iff every face maps conformally).
//!
//! Every boundary vertex must lie on its loop's circle: the unit circle for the outer loop, a
//! circle `|w − c_i| = ρ_i` with unknown centre and radius for hole `i`. With `u_b`,
//! `t_b = i u_b` the unit radial and tangent directions of boundary vertex `b` on its circle,
//!
//! - (C3) `w_b = c_i + ρ_i u_b + s_b t_b`, the circle linearised at `b` (`c_0 = 0`, `ρ_0 = 1`);
//! - (C4) `w_b ← c_i + ρ_i u_b e^{i s_b / ρ_i}`, the move along the circle after a step;
//! - (C5) `E_P = λ Σ_b (|w_b − c_i| − ρ_i)²`, the penalty pulling free hole vertices onto
//!   their circles.
//!
//! Gauss–Newton: (C2) is quadratic in the positions, so substituting (C3) gives a sparse
//! symmetric positive definite system `Pᵀ H P δ = −Pᵀ ∇E_C` for the unknowns `δ` (interior
//! displacements, tangential moves `s_b`, centre and radius changes), with Newton's term of
//! the circles' curvature added on the `s_b` diagonal; its ordering and symbolic factorization
//! are computed once, each iteration refactors numerically. The boundary then moves by (C4),
//! the interior is corrected to the exact minimiser of (C2) for that boundary (a solve with the
//! interior block of `H`), and the step is halved while the energy would increase or the map
//! would stop being bijective. The holes are first pulled onto their circles by the penalty
//! (C5), with `λ` growing tenfold per full step from 0.01, hole vertices free; once they are
//! within 1% of the radius the constraint (C3) takes over.
//!
//! Bijectivity: on meshes with many obtuse triangles the minimiser of (C2) can fold a few
//! triangles. When a full step folds triangles, the weights `ω_T` of those triangles and of
//! their neighbours are multiplied by 4 and the step is recomputed, which pulls them towards
//! similarity with their source. A surface whose conformal map onto a circle domain shrinks a
//! region below double precision (a hole shaped like a spiral corridor: its harmonic measure
//! falls below 1e-12) is refused with [`Error::Numerical`].
//!
//! Initial map: every hole is filled with a fan (one new vertex joined to its loop) and the
//! filled disk is embedded with positive weights (Tutte/Floater: bijective) — cotangent weights
//! raised to at least 0.01, the outer loop on the unit circle at angles proportional to its
//! harmonic measure seen from the pinned vertex (the distribution of a conformal map sending
//! that vertex to 0) — so that each hole's polygon is star-shaped around its fan vertex.
//!
//! Normalisation (the circle domain is unique up to the Möbius automorphisms of the disk): the
//! interior vertex nearest the conformal centre of the surface's area is pinned at the origin
//! and the first vertex of the outer loop is put at angle 0. A mesh without interior vertices
//! has three outer vertices pinned instead.

use crate::fem::{cotangent_weights, lumped_mass};
use crate::geometry::{add, cross, face_areas, local_frame, norm, signed_area_2d, sub};
use crate::linalg::{
    ElementPattern, SparseCholesky, StiffnessPattern, minimum_degree_order, packed_index,
};
use crate::mesh::topology::{topology, vertex_faces};
use crate::{Error, Result, TriMesh};
use num_complex::Complex64 as C64;
use rayon::prelude::*;
use std::f64::consts::TAU;

/// A circle domain: the unit disk minus k disjoint disks.
#[derive(Debug, Clone, PartialEq)]
pub struct CircleDomain {
    /// Planar image of every vertex (z = 0), counter-clockwise (positive signed areas).
    pub positions: Vec<[f64; 3]>,
    /// Boundary loops as vertex lists: `[0]` the outer loop (on the unit circle, centre 0),
    /// then the holes.
    pub loops: Vec<Vec<u32>>,
    /// Centre of each loop's circle (`loops[0]`: `[0,0]`).
    pub centers: Vec<[f64; 2]>,
    /// Radius of each loop's circle (`loops[0]`: 1).
    pub radii: Vec<f64>,
}

/// How the Gauss–Newton iteration of [`circle_domain_map_with_report`] went.
#[derive(Debug, Clone, PartialEq)]
pub struct CircleDomainReport {
    /// Gauss–Newton iterations run (each one factorization).
    pub iterations: usize,
    /// True when the iteration stopped on its tolerances (a full step changing the energy by
    /// less than 1e-9 relative, or a step below 1e-10), false when it hit the iteration cap or
    /// could not decrease the energy without folding the map.
    pub converged: bool,
    /// Conformal energy (C2, all `ω_T = 1`) of the initial map once its holes are on circles.
    pub initial_energy: f64,
    /// Conformal energy (C2, all `ω_T = 1`) of the result.
    pub conformal_energy: f64,
    /// Faces whose weight `ω_T` was raised to keep the map bijective.
    pub stiffened_faces: usize,
    /// The interior vertex at the origin (`None` without interior vertices, or in the rare
    /// case where moving it there would fold the map).
    pub pinned_vertex: Option<u32>,
}

/// Iteration cap of the Gauss–Newton loop.
const MAX_ITERATIONS: usize = 30;
/// Step halvings tried before an iteration gives up.
const MAX_HALVINGS: usize = 30;
/// Stop when a full step decreases the energy by less than this fraction.
const ENERGY_TOLERANCE: f64 = 1e-9;
/// Stop when no unknown moves by more than this (the domain has radius 1).
const STEP_TOLERANCE: f64 = 1e-10;
/// Factor applied to the weight of a face that flips in a full step (and of its neighbours).
const STIFFEN: f64 = 4.0;
/// Stiffening rounds (each a refactorization) per iteration.
const MAX_STIFFEN_ROUNDS: usize = 4;
/// Largest face weight.
const MAX_WEIGHT: f64 = 1e4;
/// Weight λ of the penalty (C5) in the first iteration.
const LAMBDA_START: f64 = 1e-2;
/// Factor applied to λ after each full step of the penalty phase.
const LAMBDA_GROWTH: f64 = 10.0;
/// The penalty phase ends when every hole vertex is this close to its circle (relative to
/// the radius).
const PENALTY_TOLERANCE: f64 = 1e-2;

/// Conformal map of `mesh` (genus 0, connected, with the boundary `loops` ordered along the
/// face orientation, as [`crate::mesh::topology::topology`] gives them) onto a circle domain,
/// by Gauss–Newton minimisation of the conformal energy (C2) with the boundary on circles
/// (C3)–(C5); see the module documentation. The outer loop is the one spanning the largest
/// area (its vector area; not the longest: a wiggly hole can be longer than the outer
/// boundary); the holes keep their input order.
///
/// Errors: [`Error::Topology`] when the loops or the mesh's topology do not describe a
/// connected genus-0 surface with these boundaries, [`Error::InvalidMesh`] for a face index out
/// of range or a vertex no face uses, [`Error::Numerical`] when a factorization fails, the
/// surface's conformal map cannot be represented (module documentation), or the final map
/// would fold a triangle.
pub fn circle_domain_map(mesh: &TriMesh, loops: &[Vec<u32>]) -> Result<CircleDomain> {
    circle_domain_map_with_report(mesh, loops).map(|(domain, _)| domain)
}

/// [`circle_domain_map`] with the figures of its iteration.
pub fn circle_domain_map_with_report(
    mesh: &TriMesh,
    loops: &[Vec<u32>],
) -> Result<(CircleDomain, CircleDomainReport)> {
    check_faces(mesh)?;
    let loops = ordered_loops(mesh, loops)?;
    check_topology(mesh, loops.len())?;
    let geo = Geometry::new(mesh);
    let pin = farthest_from_boundary(&geo, &loops);
    let outer_pins = match pin {
        Some(_) => vec![loops[0][0]],
        None => {
            let m = loops[0].len();
            vec![loops[0][0], loops[0][m / 3], loops[0][2 * m / 3]]
        }
    };
    let (mut state, pin) = initial_state(mesh, &loops, pin)?;
    let mut solver = GaussNewton::new(&geo, &loops, pin, &outer_pins)?;
    let outcome = solver.run(&mut state)?;
    let stiffened_faces = solver.weights.iter().filter(|&&w| w > 1.0).count();
    let (domain, pin) = finish(state, &loops, &mesh.faces, pin)?;
    let conformal_energy = geo.conformal_energy(&complex_positions(&domain.positions), None);
    let report = CircleDomainReport {
        iterations: outcome.iterations,
        converged: outcome.converged,
        initial_energy: outcome.initial_energy,
        conformal_energy,
        stiffened_faces,
        pinned_vertex: pin,
    };
    Ok((domain, report))
}

fn topology_error(msg: String) -> Error {
    Error::Topology {
        method: "circle domain map".into(),
        msg,
    }
}

/// Refuses face indices out of range.
fn check_faces(mesh: &TriMesh) -> Result<()> {
    let n = mesh.n_vertices();
    match mesh
        .faces
        .iter()
        .position(|f| f.iter().any(|&v| v as usize >= n))
    {
        Some(f) => Err(Error::InvalidMesh(format!(
            "face {f} refers to a vertex beyond the {n} vertices"
        ))),
        None => Ok(()),
    }
}

/// The loops with the outer one first — the one spanning the largest area ([`vector_area`]) —
/// after checking they are usable.
pub(crate) fn ordered_loops(mesh: &TriMesh, loops: &[Vec<u32>]) -> Result<Vec<Vec<u32>>> {
    if loops.is_empty() {
        return Err(topology_error(
            "the surface has no boundary; a circle domain map needs an open surface".into(),
        ));
    }
    let n = mesh.n_vertices();
    let mut seen = vec![false; n];
    for (l, lp) in loops.iter().enumerate() {
        if lp.len() < 3 {
            return Err(topology_error(format!(
                "boundary loop {l} has {} vertices; at least 3 are needed",
                lp.len()
            )));
        }
        for &v in lp {
            let Some(s) = seen.get_mut(v as usize) else {
                return Err(topology_error(format!(
                    "boundary loop {l} refers to vertex {v}, but the mesh has {n} vertices"
                )));
            };
            if *s {
                return Err(topology_error(format!(
                    "vertex {v} appears twice in the boundary loops"
                )));
            }
            *s = true;
        }
    }
    let mut outer = 0;
    let mut largest = f64::NEG_INFINITY;
    for (l, lp) in loops.iter().enumerate() {
        let area = vector_area(mesh, lp);
        if area > largest {
            (outer, largest) = (l, area);
        }
    }
    let mut out = vec![loops[outer].clone()];
    out.extend(
        loops
            .iter()
            .enumerate()
            .filter(|&(l, _)| l != outer)
            .map(|(_, lp)| lp.clone()),
    );
    Ok(out)
}

/// `|½ Σ_k p_k × p_{k+1}|`, the area a closed polygon in R³ spans (that of its projection on
/// the plane it is closest to lying in).
fn vector_area(mesh: &TriMesh, lp: &[u32]) -> f64 {
    let origin = mesh.positions[lp[0] as usize];
    let mut sum = [0.0; 3];
    for k in 1..lp.len().saturating_sub(1) {
        let a = sub(mesh.positions[lp[k] as usize], origin);
        let b = sub(mesh.positions[lp[k + 1] as usize], origin);
        sum = add(sum, cross(a, b));
    }
    0.5 * norm(sum)
}

/// Refuses surfaces that are not connected, genus 0, with exactly `n_loops` boundaries and no
/// unused vertex.
fn check_topology(mesh: &TriMesh, n_loops: usize) -> Result<()> {
    let topo = topology(mesh);
    if topo.n_vertices != mesh.n_vertices() {
        return Err(Error::InvalidMesh(format!(
            "{} vertices are not used by any face; validate the mesh first",
            mesh.n_vertices().saturating_sub(topo.n_vertices)
        )));
    }
    if topo.components != 1 || topo.genus != 0 || topo.n_boundaries() != n_loops {
        return Err(topology_error(format!(
            "the circle domain map needs a connected genus-0 surface with {n_loops} boundary \
             loop(s); this mesh has {} component(s), genus {} and {} boundary loop(s)",
            topo.components,
            topo.genus,
            topo.n_boundaries()
        )));
    }
    Ok(())
}

fn complex_positions(p: &[[f64; 3]]) -> Vec<C64> {
    p.iter().map(|q| C64::new(q[0], q[1])).collect()
}

/// Euclidean dot product of two complex numbers seen as plane vectors.
#[inline]
fn dot2(a: C64, b: C64) -> f64 {
    a.re * b.re + a.im * b.im
}

mod gauss_newton;
mod geometry;
mod initial;
mod normal_system;
#[cfg(test)]
mod tests;

use gauss_newton::*;
use geometry::*;
use initial::*;
use normal_system::*;
