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
    CachedCholesky, ElementPattern, SpdSolver, StiffnessPattern, minimum_degree_order, packed_index,
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
fn ordered_loops(mesh: &TriMesh, loops: &[Vec<u32>]) -> Result<Vec<Vec<u32>>> {
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

/// The source surface's fixed data: each face's (C1) coefficients and the vertex–face
/// incidence.
struct Geometry {
    n: usize,
    faces: Vec<[u32; 3]>,
    /// `d_k = q_{k+2} − q_{k+1}` of each face (C1).
    face_d: Vec<[C64; 3]>,
    /// `1 / (8 A_T)` (C2).
    face_scale: Vec<f64>,
    /// The faces around each vertex (CSR).
    vf_ptr: Vec<usize>,
    vf: Vec<u32>,
}

impl Geometry {
    fn new(mesh: &TriMesh) -> Self {
        let (face_d, face_scale) = mesh
            .faces
            .par_iter()
            .map(|f| {
                let q = local_frame(f.map(|v| mesh.positions[v as usize]))
                    .map(|p| C64::new(p[0], p[1]));
                let d = std::array::from_fn(|k| q[(k + 2) % 3] - q[(k + 1) % 3]);
                let area = 0.5 * (q[1] - q[0]).re * (q[2] - q[0]).im;
                (d, if area > 0.0 { 0.125 / area } else { 0.0 })
            })
            .unzip();
        let (vf_ptr, vf) = vertex_faces(mesh.n_vertices(), &mesh.faces);
        Self {
            n: mesh.n_vertices(),
            faces: mesh.faces.clone(),
            face_d,
            face_scale,
            vf_ptr,
            vf,
        }
    }

    /// A fill-reducing elimination order of the vertices (minimum degree on the mesh graph),
    /// shared by every system: their unknowns are blocks per vertex.
    fn vertex_order(&self) -> Result<Vec<usize>> {
        let graph = ElementPattern::new(self.n, self.faces.iter().map(|f| &f[..]))?;
        minimum_degree_order(self.n, graph.col_ptr(), graph.row_idx())
    }

    fn faces_around(&self, v: usize) -> &[u32] {
        &self.vf[self.vf_ptr[v]..self.vf_ptr[v + 1]]
    }

    /// `Σ_k d_k w_k` of face `t` (C1, C2).
    fn residual(&self, t: usize, z: &[C64]) -> C64 {
        let (f, d) = (self.faces[t], self.face_d[t]);
        d[0] * z[f[0] as usize] + d[1] * z[f[1] as usize] + d[2] * z[f[2] as usize]
    }

    /// The conformal energy (C2) of the planar image `z` with face weights `weights` (all 1
    /// when `None`), summed in a fixed order.
    fn conformal_energy(&self, z: &[C64], weights: Option<&[f64]>) -> f64 {
        let per_chunk: Vec<f64> = (0..self.faces.len())
            .collect::<Vec<_>>()
            .par_chunks(4096)
            .map(|chunk| {
                chunk
                    .iter()
                    .map(|&t| {
                        let w = weights.map_or(1.0, |w| w[t]);
                        w * self.residual(t, z).norm_sqr() * self.face_scale[t]
                    })
                    .sum::<f64>()
            })
            .collect();
        per_chunk.iter().sum()
    }

    /// Gradient of (C2) per vertex, as `∂E/∂x + i ∂E/∂y`: `Σ_T 2 ω_T d̄_k r_T / (8 A_T)` over
    /// the faces `T` around the vertex, `k` its corner in `T`, `r_T = Σ_k d_k w_k`.
    fn gradient(&self, z: &[C64], weights: &[f64]) -> Vec<C64> {
        let r: Vec<C64> = (0..self.faces.len())
            .into_par_iter()
            .map(|t| 2.0 * weights[t] * self.face_scale[t] * self.residual(t, z))
            .collect();
        (0..self.n)
            .into_par_iter()
            .map(|v| {
                self.faces_around(v)
                    .iter()
                    .map(|&t| {
                        let t = t as usize;
                        let k = self.faces[t]
                            .iter()
                            .position(|&x| x as usize == v)
                            .unwrap_or(0);
                        self.face_d[t][k].conj() * r[t]
                    })
                    .sum()
            })
            .collect()
    }
}

/// The interior vertex at the largest edge distance from every boundary loop (multi-source
/// BFS), the smallest index among ties; `None` when every vertex is on a boundary.
fn farthest_from_boundary(geo: &Geometry, loops: &[Vec<u32>]) -> Option<u32> {
    let mut dist = vec![u32::MAX; geo.n];
    let mut queue: Vec<u32> = loops.iter().flatten().copied().collect();
    for &v in &queue {
        dist[v as usize] = 0;
    }
    let mut head = 0;
    while head < queue.len() {
        let v = queue[head] as usize;
        head += 1;
        for &t in geo.faces_around(v) {
            for &j in &geo.faces[t as usize] {
                if dist[j as usize] == u32::MAX {
                    dist[j as usize] = dist[v] + 1;
                    queue.push(j);
                }
            }
        }
    }
    let mut best: Option<(u32, u32)> = None;
    for (v, &d) in dist.iter().enumerate() {
        if d != 0 && d != u32::MAX && best.is_none_or(|(bd, _)| d > bd) {
            best = Some((d, v as u32));
        }
    }
    best.map(|(_, v)| v)
}

/// What a vertex contributes to the unknowns.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Role {
    /// Vertex with unknowns `x` (its x displacement) and `x + 1` (y).
    Free(u32),
    /// Fixed vertex.
    Pinned,
    /// Vertex kept on the circle of loop `lp` (C3), with its tangential move `s` unless pinned.
    Boundary { lp: u32, s: Option<u32> },
}

/// How the hole boundaries enter a [`Layout`].
#[derive(Debug, Clone, Copy, PartialEq)]
enum Holes {
    /// On their circles (C3).
    OnCircles,
    /// Free, pulled towards their circles by the penalty (C5).
    Penalized,
}

/// One term of the penalty (C5): a hole vertex and its unknowns (x, y, c_x, c_y, ρ).
#[derive(Debug, Clone, Copy)]
struct Penalty {
    vertex: u32,
    hole: u32,
    ids: [u32; 5],
}

/// Numbering of the unknowns: vertex displacements, tangential moves on the circles (C3), and
/// per hole its centre (two unknowns) and radius.
struct Layout {
    role: Vec<Role>,
    /// First of the three unknowns (c_x, c_y, ρ) of each hole (unused for the outer loop).
    hole_base: Vec<u32>,
    /// The terms of the penalty (C5).
    penalized: Vec<Penalty>,
    n_unknowns: usize,
}

impl Layout {
    /// The unknowns of the Gauss–Newton step: every vertex but `pin` and `outer_pins` moves,
    /// the outer loop on the unit circle, the holes as `holes` says.
    fn new(
        n: usize,
        loops: &[Vec<u32>],
        pin: Option<u32>,
        outer_pins: &[u32],
        holes: Holes,
    ) -> Self {
        let mut role = vec![Role::Pinned; n];
        let mut next = 0u32;
        let mut take = |k: u32| {
            next += k;
            next - k
        };
        for &v in &loops[0] {
            let s = (!outer_pins.contains(&v)).then(|| take(1));
            role[v as usize] = Role::Boundary { lp: 0, s };
        }
        if holes == Holes::OnCircles {
            for (l, lp) in loops.iter().enumerate().skip(1) {
                for &v in lp {
                    let s = Some(take(1));
                    role[v as usize] = Role::Boundary { lp: l as u32, s };
                }
            }
        }
        let mut hole_base = vec![u32::MAX; loops.len()];
        for base in hole_base.iter_mut().skip(1) {
            *base = take(3);
        }
        for (v, r) in role.iter_mut().enumerate() {
            if *r == Role::Pinned && pin != Some(v as u32) {
                *r = Role::Free(take(2));
            }
        }
        let mut penalized = Vec::new();
        if holes == Holes::Penalized {
            for (l, lp) in loops.iter().enumerate().skip(1) {
                let c = hole_base[l];
                for &v in lp {
                    if let Role::Free(x) = role[v as usize] {
                        let ids = [x, x + 1, c, c + 1, c + 2];
                        penalized.push(Penalty {
                            vertex: v,
                            hole: l as u32,
                            ids,
                        });
                    }
                }
            }
        }
        Self {
            role,
            hole_base,
            penalized,
            n_unknowns: next as usize,
        }
    }

    /// The unknowns of the interior correction: every boundary vertex and `pin` stay.
    fn interior(n: usize, loops: &[Vec<u32>], pin: Option<u32>) -> Self {
        let mut boundary = vec![false; n];
        for &v in loops.iter().flatten() {
            boundary[v as usize] = true;
        }
        let mut next = 0u32;
        let role = (0..n)
            .map(|v| {
                if boundary[v] || pin == Some(v as u32) {
                    Role::Pinned
                } else {
                    next += 2;
                    Role::Free(next - 2)
                }
            })
            .collect();
        Self {
            role,
            hole_base: vec![u32::MAX; loops.len()],
            penalized: Vec::new(),
            n_unknowns: next as usize,
        }
    }

    /// The unknowns moving vertex `v` and the plane direction each moves it in (C3); `u` is the
    /// vertex's unit radial direction when it is on a boundary.
    fn basis(&self, v: usize, u: C64) -> ([(u32, C64); 4], usize) {
        let mut out = [(0u32, C64::new(0.0, 0.0)); 4];
        let mut len = 0;
        let mut push = |k: u32, d: C64| {
            out[len] = (k, d);
            len += 1;
        };
        let i = C64::new(0.0, 1.0);
        match self.role[v] {
            Role::Free(x) => {
                push(x, C64::new(1.0, 0.0));
                push(x + 1, i);
            }
            Role::Pinned => {}
            Role::Boundary { lp, s } => {
                if let Some(s) = s {
                    push(s, i * u);
                }
                if lp > 0 {
                    let h = self.hole_base[lp as usize];
                    push(h, C64::new(1.0, 0.0));
                    push(h + 1, i);
                    push(h + 2, u);
                }
            }
        }
        (out, len)
    }

    /// `Pᵀ y`: the gradient in the unknowns from the gradient `y` per vertex.
    fn pull_back(&self, y: &[C64], u: &[C64]) -> Vec<f64> {
        let mut g = vec![0.0; self.n_unknowns];
        for (v, &yv) in y.iter().enumerate() {
            let (basis, len) = self.basis(v, u.get(v).copied().unwrap_or_default());
            for &(id, d) in &basis[..len] {
                g[id as usize] += dot2(d, yv);
            }
        }
        g
    }

    /// The unknowns in the order their vertices come in `vertex_order`, then the circles'.
    fn elimination_order(&self, vertex_order: &[usize]) -> Vec<usize> {
        let mut order = Vec::with_capacity(self.n_unknowns);
        for &v in vertex_order {
            match self.role[v] {
                Role::Free(x) => order.extend([x as usize, x as usize + 1]),
                Role::Boundary { s: Some(s), .. } => order.push(s as usize),
                _ => {}
            }
        }
        for &h in self.hole_base.iter().filter(|&&h| h != u32::MAX) {
            order.extend(h as usize..h as usize + 3);
        }
        order
    }
}

/// The circles and the planar image of every vertex.
#[derive(Debug, Clone)]
struct State {
    z: Vec<C64>,
    centers: Vec<C64>,
    radii: Vec<f64>,
}

impl State {
    /// `|w_v − c_h| − ρ_h`: how far vertex `v` is off the circle of loop `h` (C5).
    fn off_circle(&self, v: u32, h: u32) -> f64 {
        (self.z[v as usize] - self.centers[h as usize]).norm() - self.radii[h as usize]
    }
}

/// The circle constraints (C3) linearised at the current state: each boundary vertex's unit
/// radial direction `u_b` from its circle's centre, and `offset_b = c + ρ u_b − w_b`, the move
/// onto the circle.
struct Linearization {
    u: Vec<C64>,
    offset: Vec<C64>,
}

fn circle_constraints(state: &State, loops: &[Vec<u32>]) -> Linearization {
    let n = state.z.len();
    let mut u = vec![C64::new(0.0, 0.0); n];
    let mut offset = vec![C64::new(0.0, 0.0); n];
    for (l, lp) in loops.iter().enumerate() {
        let (c, r) = (state.centers[l], state.radii[l]);
        for &b in lp {
            let b = b as usize;
            let d = state.z[b] - c;
            let len = d.norm();
            let ub = if len > 0.0 {
                d / len
            } else {
                C64::new(1.0, 0.0)
            };
            u[b] = ub;
            offset[b] = c + r * ub - state.z[b];
        }
    }
    Linearization { u, offset }
}

/// The unknowns moving a face's corners with, per unknown, the move of each corner.
struct Columns {
    ids: [u32; 12],
    moves: [[C64; 3]; 12],
    len: usize,
}

/// The [`Columns`] of face `t` (the same order whatever `u`; `u` may be empty to get the ids).
fn face_columns(t: usize, geo: &Geometry, layout: &Layout, u: &[C64]) -> Columns {
    let mut cols = Columns {
        ids: [0; 12],
        moves: [[C64::new(0.0, 0.0); 3]; 12],
        len: 0,
    };
    for (corner, &v) in geo.faces[t].iter().enumerate() {
        let v = v as usize;
        let (basis, len) = layout.basis(v, u.get(v).copied().unwrap_or_default());
        for &(id, d) in &basis[..len] {
            if let Some(k) = cols.ids[..cols.len].iter().position(|&x| x == id) {
                cols.moves[k][corner] += d;
            } else {
                cols.ids[cols.len] = id;
                cols.moves[cols.len][corner] = d;
                cols.len += 1;
            }
        }
    }
    cols
}

/// Packed lower triangle of the face's block of `Pᵀ H P`: `2 ω_T Re(R̄_a R_b) / (8 A_T)` with
/// `R_a = Σ_k d_k m_a[k]` the change of `Σ d_k w_k` per unit of unknown `a` (C2).
fn face_matrix(t: usize, weight: f64, geo: &Geometry, layout: &Layout, u: &[C64], out: &mut [f64]) {
    let cols = face_columns(t, geo, layout, u);
    let d = geo.face_d[t];
    let scale = 2.0 * weight * geo.face_scale[t];
    let mut r = [C64::new(0.0, 0.0); 12];
    for (ra, m) in r.iter_mut().zip(&cols.moves[..cols.len]) {
        *ra = d[0] * m[0] + d[1] * m[1] + d[2] * m[2];
    }
    for a in 0..cols.len {
        for b in 0..=a {
            out[packed_index(a, b)] = scale * dot2(r[a], r[b]);
        }
    }
}

/// Derivatives of `|w − c| − ρ` (C5) in (x, y, c_x, c_y, ρ), with `u` the unit vector from
/// `c` to `w`.
fn penalty_row(u: C64) -> [f64; 5] {
    [u.re, u.im, -u.re, -u.im, -1.0]
}

/// A normal matrix `Pᵀ H P` (plus `2 λ j jᵀ` per penalty term (C5), `j` its [`penalty_row`]) over a [`Layout`]'s unknowns:
/// its pattern and symbolic factorization are computed once, [`factor`](Self::factor)
/// refactors for new directions `u`, weights or `λ`.
struct NormalSystem {
    layout: Layout,
    pattern: ElementPattern,
    solver: Option<SpdSolver>,
    element_values: Vec<f64>,
    values: Vec<f64>,
}

impl NormalSystem {
    /// The system of `layout`'s unknowns, eliminated vertex by vertex in `vertex_order` (the
    /// circles' unknowns last).
    fn new(geo: &Geometry, layout: Layout, vertex_order: &[usize]) -> Result<Self> {
        let faces: Vec<Columns> = (0..geo.faces.len())
            .map(|t| face_columns(t, geo, &layout, &[]))
            .collect();
        let pattern = ElementPattern::new(
            layout.n_unknowns,
            faces
                .iter()
                .map(|c| &c.ids[..c.len])
                .chain(layout.penalized.iter().map(|p| &p.ids[..])),
        )?;
        let solver = if layout.n_unknowns > 0 {
            let order = layout.elimination_order(vertex_order);
            Some(SpdSolver::with_ordering(
                pattern.n_unknowns(),
                pattern.col_ptr(),
                pattern.row_idx(),
                Some(&order),
            )?)
        } else {
            None
        };
        Ok(Self {
            element_values: vec![0.0; pattern.n_element_values()],
            values: vec![0.0; pattern.nnz()],
            layout,
            pattern,
            solver,
        })
    }

    /// Assembles and factors the matrix for directions `u`, face weights and penalty weight
    /// `λ`; with `curvature` = (vertex gradient, radii), adds the circles' curvature term
    /// (see [`add_circle_curvature`](Self::add_circle_curvature)).
    fn factor(
        &mut self,
        geo: &Geometry,
        weights: &[f64],
        u: &[C64],
        lambda: f64,
        curvature: Option<(&[C64], &[f64])>,
    ) -> Result<()> {
        if self.solver.is_none() {
            return Ok(());
        }
        let layout = &self.layout;
        let n_faces = geo.faces.len();
        self.pattern
            .element_slices(&mut self.element_values)
            .into_par_iter()
            .enumerate()
            .for_each(|(e, out)| {
                if e < n_faces {
                    face_matrix(e, weights[e], geo, layout, u, out);
                } else {
                    let j = penalty_row(u[layout.penalized[e - n_faces].vertex as usize]);
                    for a in 0..5 {
                        for b in 0..=a {
                            out[packed_index(a, b)] = 2.0 * lambda * j[a] * j[b];
                        }
                    }
                }
            });
        self.pattern
            .assemble(&self.element_values, &mut self.values);
        if let Some((y, radii)) = curvature {
            self.add_circle_curvature(y, u, radii);
        }
        let Some(solver) = self.solver.as_mut() else {
            return Ok(());
        };
        solver.factor(&self.values)
    }

    /// Newton's term of the circles' curvature: along its circle (C4) a boundary vertex moves
    /// by `s t_b − (s² / 2ρ) u_b + …`, which adds `−(y_b · u_b) / ρ` to the second derivative
    /// of (C2) in `s_b` (`y_b` the vertex gradient). Kept above −½ of the diagonal so the
    /// matrix stays positive definite.
    fn add_circle_curvature(&mut self, y: &[C64], u: &[C64], radii: &[f64]) {
        let col_ptr = self.pattern.col_ptr();
        for (v, role) in self.layout.role.iter().enumerate() {
            if let Role::Boundary { lp, s: Some(s) } = *role {
                let diag = &mut self.values[col_ptr[s as usize]];
                let term = -dot2(y[v], u[v]) / radii[lp as usize];
                *diag += term.max(-0.5 * *diag);
            }
        }
    }

    /// The gradient in the unknowns: `Pᵀ y` for the vertex gradient `y`, plus the penalty's
    /// `2 λ (|w − c| − ρ) j`.
    fn gradient(&self, y: &[C64], u: &[C64], state: &State, lambda: f64) -> Vec<f64> {
        let mut g = self.layout.pull_back(y, u);
        for p in &self.layout.penalized {
            let j = penalty_row(u[p.vertex as usize]);
            let e = 2.0 * lambda * state.off_circle(p.vertex, p.hole);
            for (&id, jk) in p.ids.iter().zip(j) {
                g[id as usize] += e * jk;
            }
        }
        g
    }

    /// Solves `K δ = −g` with the last factorization.
    fn solve(&mut self, mut g: Vec<f64>) -> Result<Vec<f64>> {
        g.iter_mut().for_each(|x| *x = -*x);
        if let Some(solver) = self.solver.as_mut() {
            solver.solve_in_place(&mut g)?;
        }
        Ok(g)
    }
}

struct Outcome {
    iterations: usize,
    converged: bool,
    initial_energy: f64,
}

/// Where the iteration is: pulling the holes onto circles by the penalty (C5) with weight `λ`,
/// or with the boundary on the circles (C3) — `feasible` once it is exactly on them.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Phase {
    Penalty(f64),
    Circles { feasible: bool },
}

/// The Gauss–Newton iteration, with the interior correction and the face weights of the
/// module documentation.
struct GaussNewton<'a> {
    geo: &'a Geometry,
    loops: &'a [Vec<u32>],
    penalty: Option<NormalSystem>,
    circles: NormalSystem,
    interior: NormalSystem,
    interior_factored: bool,
    weights: Vec<f64>,
}

/// A tried step: the state it gives, the faces it flips.
struct Trial {
    state: State,
    flipped: Vec<u32>,
}

impl<'a> GaussNewton<'a> {
    fn new(
        geo: &'a Geometry,
        loops: &'a [Vec<u32>],
        pin: Option<u32>,
        outer_pins: &[u32],
    ) -> Result<Self> {
        let layout = |holes| Layout::new(geo.n, loops, pin, outer_pins, holes);
        let order = geo.vertex_order()?;
        let penalty = if loops.len() > 1 {
            Some(NormalSystem::new(geo, layout(Holes::Penalized), &order)?)
        } else {
            None
        };
        Ok(Self {
            geo,
            loops,
            penalty,
            circles: NormalSystem::new(geo, layout(Holes::OnCircles), &order)?,
            interior: NormalSystem::new(geo, Layout::interior(geo.n, loops, pin), &order)?,
            interior_factored: false,
            weights: vec![1.0; geo.faces.len()],
        })
    }

    /// The unknowns of the phase.
    fn layout(&self, phase: Phase) -> &Layout {
        match (phase, self.penalty.as_ref()) {
            (Phase::Penalty(_), Some(p)) => &p.layout,
            _ => &self.circles.layout,
        }
    }

    /// The objective of the phase: (C2) with the current weights, plus (C5).
    fn merit(&self, state: &State, phase: Phase) -> f64 {
        let e = self.geo.conformal_energy(&state.z, Some(&self.weights));
        match (phase, &self.penalty) {
            (Phase::Penalty(lambda), Some(p)) => {
                e + lambda
                    * p.layout
                        .penalized
                        .iter()
                        .map(|p| state.off_circle(p.vertex, p.hole).powi(2))
                        .sum::<f64>()
            }
            _ => e,
        }
    }

    /// Largest distance of a hole vertex from its circle, relative to the radius.
    fn largest_off_circle(&self, state: &State) -> f64 {
        self.loops
            .iter()
            .enumerate()
            .skip(1)
            .flat_map(|(h, lp)| lp.iter().map(move |&v| (v, h as u32)))
            .map(|(v, h)| state.off_circle(v, h).abs() / state.radii[h as usize])
            .fold(0.0, f64::max)
    }

    /// Iterates from `state` until convergence, the iteration cap, or a step that cannot be
    /// taken without folding the map.
    fn run(&mut self, state: &mut State) -> Result<Outcome> {
        let mut phase = if self.penalty.is_some() {
            Phase::Penalty(LAMBDA_START)
        } else {
            Phase::Circles { feasible: true }
        };
        let mut outcome = Outcome {
            iterations: 0,
            converged: self.circles.layout.n_unknowns == 0,
            initial_energy: self.geo.conformal_energy(&state.z, None),
        };
        if self.circles.layout.n_unknowns == 0 {
            return Ok(outcome);
        }
        while outcome.iterations < MAX_ITERATIONS {
            let lin = circle_constraints(state, self.loops);
            let (delta, full, stiffened) =
                self.stiffened_step(state, &lin, phase, &mut outcome.iterations)?;
            let merit = self.merit(state, phase);
            let largest = delta.iter().fold(0.0f64, |m, d| m.max(d.abs()));
            let Some((next, alpha)) = self.line_search(state, &lin, &delta, merit, phase, full)?
            else {
                break;
            };
            *state = next;
            phase = match phase {
                Phase::Penalty(_) if self.largest_off_circle(state) <= PENALTY_TOLERANCE => {
                    Phase::Circles { feasible: false }
                }
                Phase::Penalty(lambda) if alpha == 1.0 => Phase::Penalty(lambda * LAMBDA_GROWTH),
                Phase::Circles { feasible: false } if alpha == 1.0 => {
                    outcome.initial_energy = self.geo.conformal_energy(&state.z, None);
                    Phase::Circles { feasible: true }
                }
                Phase::Circles { feasible: true } if !stiffened => {
                    let decrease = merit - self.merit(state, phase);
                    let small = largest < STEP_TOLERANCE
                        || (alpha == 1.0 && decrease <= ENERGY_TOLERANCE * (merit - decrease));
                    if small {
                        outcome.converged = true;
                        break;
                    }
                    phase
                }
                _ => phase,
            };
        }
        if phase != (Phase::Circles { feasible: true }) {
            outcome.converged = false;
        }
        Ok(outcome)
    }

    /// The step of the phase and the state after it in full; while the full step folds
    /// triangles, they are stiffened and the step recomputed (at most [`MAX_STIFFEN_ROUNDS`]
    /// times). Every step counts as an iteration. Also returns whether weights changed.
    fn stiffened_step(
        &mut self,
        state: &State,
        lin: &Linearization,
        phase: Phase,
        iterations: &mut usize,
    ) -> Result<(Vec<f64>, Trial, bool)> {
        *iterations += 1;
        let mut delta = self.step(state, lin, phase)?;
        let mut full = self.moved(state, lin, &delta, 1.0, phase)?;
        let mut rounds = 0;
        while !full.flipped.is_empty()
            && rounds < MAX_STIFFEN_ROUNDS
            && *iterations < MAX_ITERATIONS
            && self.stiffen(&full.flipped)
        {
            rounds += 1;
            *iterations += 1;
            delta = self.step(state, lin, phase)?;
            full = self.moved(state, lin, &delta, 1.0, phase)?;
        }
        Ok((delta, full, rounds > 0))
    }

    /// The Gauss–Newton step of the phase: the minimiser of the quadratic model of (C2) (plus
    /// the linearised (C5)) over the phase's unknowns.
    fn step(&mut self, state: &State, lin: &Linearization, phase: Phase) -> Result<Vec<f64>> {
        let lambda = match phase {
            Phase::Penalty(l) => l,
            Phase::Circles { .. } => 0.0,
        };
        // On the circles, the model is taken at the boundary moved onto them.
        let target: Vec<C64> = match phase {
            Phase::Penalty(_) => state.z.clone(),
            Phase::Circles { .. } => state
                .z
                .iter()
                .zip(&lin.offset)
                .map(|(&z, &o)| z + o)
                .collect(),
        };
        let y = self.geo.gradient(&target, &self.weights);
        let curvature = match phase {
            Phase::Circles { .. } => Some((&y[..], &state.radii[..])),
            Phase::Penalty(_) => None,
        };
        let sys = match (phase, self.penalty.as_mut()) {
            (Phase::Penalty(_), Some(p)) => p,
            _ => &mut self.circles,
        };
        sys.factor(self.geo, &self.weights, &lin.u, lambda, curvature)?;
        let g = sys.gradient(&y, &lin.u, state, lambda);
        sys.solve(g)
    }

    /// Multiplies the weights of the `flipped` faces and of the faces sharing a vertex with
    /// them by [`STIFFEN`] (up to [`MAX_WEIGHT`]). True if a weight changed.
    fn stiffen(&mut self, flipped: &[u32]) -> bool {
        let mut changed = false;
        let mut mark = vec![false; self.weights.len()];
        for &t in flipped {
            for &v in &self.geo.faces[t as usize] {
                for &s in self.geo.faces_around(v as usize) {
                    mark[s as usize] = true;
                }
            }
        }
        for (w, m) in self.weights.iter_mut().zip(mark) {
            if m && *w < MAX_WEIGHT {
                *w = (*w * STIFFEN).min(MAX_WEIGHT);
                changed = true;
            }
        }
        if changed {
            self.interior_factored = false;
        }
        changed
    }

    /// The largest step `α δ`, α = 1, ½, ¼, …, whose image is valid and does not increase the
    /// phase's objective (not checked before the boundary first reaches its circles); `full`
    /// is the step with α = 1.
    fn line_search(
        &mut self,
        state: &State,
        lin: &Linearization,
        delta: &[f64],
        merit: f64,
        phase: Phase,
        full: Trial,
    ) -> Result<Option<(State, f64)>> {
        let mut alpha = 1.0;
        let mut trial = full;
        for _ in 0..MAX_HALVINGS {
            let check = match phase {
                Phase::Penalty(_) => Check::Outer,
                Phase::Circles { feasible: false } if alpha < 1.0 => Check::Loops,
                Phase::Circles { .. } => Check::Circles,
            };
            let ok = trial.flipped.is_empty()
                && invalidity(&trial.state, self.loops, check).is_none()
                && (phase == Phase::Circles { feasible: false }
                    || self.merit(&trial.state, phase) <= merit * (1.0 + 1e-12) + 1e-300);
            if ok {
                return Ok(Some((trial.state, alpha)));
            }
            alpha *= 0.5;
            trial = self.moved(state, lin, delta, alpha, phase)?;
        }
        Ok(None)
    }

    /// The state after the step `α δ`: circles change by `α (δc, δρ)`, vertices on circles
    /// slide along them (C4) — off-circle ones (before the first full step) keep the fraction
    /// `1 − α` of their offset — free boundary vertices move by `α δ`, and the interior moves
    /// by `α` times its correction to the minimiser of (C2) for the new boundary.
    fn moved(
        &mut self,
        state: &State,
        lin: &Linearization,
        delta: &[f64],
        alpha: f64,
        phase: Phase,
    ) -> Result<Trial> {
        let mut centers = state.centers.clone();
        let mut radii = state.radii.clone();
        let mut z = state.z.clone();
        {
            let layout = self.layout(phase);
            for l in 1..self.loops.len() {
                let h = layout.hole_base[l] as usize;
                centers[l] += alpha * C64::new(delta[h], delta[h + 1]);
                radii[l] += alpha * delta[h + 2];
            }
            for &v in self.loops.iter().flatten() {
                let v = v as usize;
                z[v] = match layout.role[v] {
                    Role::Free(x) => {
                        let x = x as usize;
                        z[v] + alpha * C64::new(delta[x], delta[x + 1])
                    }
                    Role::Pinned => z[v],
                    Role::Boundary { lp, s } => {
                        let (c, r) = (centers[lp as usize], radii[lp as usize]);
                        let s = s.map_or(0.0, |s| delta[s as usize]);
                        let turn = C64::from_polar(1.0, alpha * s / r);
                        c + r * lin.u[v] * turn - (1.0 - alpha) * lin.offset[v]
                    }
                };
            }
        }
        if !self.interior_factored {
            self.interior
                .factor(self.geo, &self.weights, &[], 0.0, None)?;
            self.interior_factored = true;
        }
        let y = self.geo.gradient(&z, &self.weights);
        let g = self.interior.layout.pull_back(&y, &[]);
        let correction = self.interior.solve(g)?;
        for (v, w) in z.iter_mut().enumerate() {
            if let Role::Free(x) = self.interior.layout.role[v] {
                let x = x as usize;
                *w += alpha * C64::new(correction[x], correction[x + 1]);
            }
        }
        let flipped = flipped_faces(&z, &self.geo.faces);
        Ok(Trial {
            state: State { z, centers, radii },
            flipped,
        })
    }
}

/// What [`invalidity`] checks beyond positive radii.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Check {
    /// The outer loop winds once, counter-clockwise, step by step.
    Outer,
    /// Every loop winds once around its circle's centre in its direction.
    Loops,
    /// The loops, and the holes inside the unit circle and apart.
    Circles,
}

/// The first reason the circles and loops of `state` do not form a circle domain, if any: a
/// radius that is not positive, a loop that does not wind once around its circle's centre in
/// its direction step by step (counter-clockwise for the outer loop, clockwise for the holes),
/// a hole reaching the unit circle or another hole — as far as `check` asks.
fn invalidity(state: &State, loops: &[Vec<u32>], check: Check) -> Option<String> {
    let finite = |c: C64| c.re.is_finite() && c.im.is_finite();
    if !state.radii.iter().all(|&r| r > 0.0 && r.is_finite())
        || !state.centers.iter().all(|&c| finite(c))
    {
        return Some("a circle has a non-positive or non-finite radius".into());
    }
    if check == Check::Circles {
        for i in 1..loops.len() {
            if state.centers[i].norm() + state.radii[i] >= 1.0 {
                return Some(format!("hole {i} reaches the unit circle"));
            }
            for j in 1..i {
                if (state.centers[i] - state.centers[j]).norm() <= state.radii[i] + state.radii[j] {
                    return Some(format!("holes {j} and {i} overlap"));
                }
            }
        }
    }
    let n_checked = if check == Check::Outer {
        1
    } else {
        loops.len()
    };
    for (l, lp) in loops.iter().enumerate().take(n_checked) {
        let c = state.centers[l];
        let sign = if l == 0 { 1.0 } else { -1.0 };
        let mut turn = 0.0;
        for k in 0..lp.len() {
            let a = state.z[lp[k] as usize] - c;
            let b = state.z[lp[(k + 1) % lp.len()] as usize] - c;
            let step = (a.conj() * b).arg() * sign;
            if !(step > 0.0) {
                return Some(format!(
                    "boundary loop {l} turns back at its vertex {}",
                    lp[k]
                ));
            }
            turn += step;
        }
        if (turn - TAU).abs() > 1e-6 {
            return Some(format!(
                "boundary loop {l} does not wind once around its circle"
            ));
        }
    }
    None
}

/// Faces whose planar image has a signed area ≤ 0 (or is not finite).
fn flipped_faces(z: &[C64], faces: &[[u32; 3]]) -> Vec<u32> {
    let p = |v: u32| {
        let w = z[v as usize];
        [w.re, w.im, 0.0]
    };
    (0..faces.len() as u32)
        .into_par_iter()
        .filter(|&t| {
            let f = faces[t as usize];
            !(signed_area_2d(p(f[0]), p(f[1]), p(f[2])) > 0.0)
        })
        .collect()
}

fn count_flips(z: &[C64], faces: &[[u32; 3]]) -> usize {
    flipped_faces(z, faces).len()
}

/// Smallest corner weight of the initial embedding: cotangent weights below it (angles above
/// about 89°) are raised to it, so that every edge weight is positive.
const MIN_CORNER_WEIGHT: f64 = 0.01;

/// Angles of the outer loop's vertices on the unit circle (counter-clockwise from 0 at its
/// first vertex), proportional to the harmonic measure of the outer boundary seen from the
/// pinned vertex `p` (the holes reflecting): the flux `Σ_j w_bj G_j` of the discrete Green's
/// function `L G = δ_p`, `G = 0` on the outer loop, through each outer vertex `b`. A conformal
/// map of a disk sending `p` to 0 distributes its boundary that way. Fluxes are floored at
/// 1e-3 of their mean. Without a pinned vertex (or if the solve fails), by arc length.
fn outer_angles(mesh: &TriMesh, loops: &[Vec<u32>], pin: Option<u32>) -> Vec<f64> {
    let outer = &loops[0];
    let m = outer.len();
    let mut share: Vec<f64> = (0..m)
        .map(|k| {
            let (a, b) = (outer[k] as usize, outer[(k + 1) % m] as usize);
            norm(sub(mesh.positions[b], mesh.positions[a]))
        })
        .collect();
    // Arc length: vertex k + 1 is `share[k]` after vertex k.
    let mut gaps = share.clone();
    if let Some(flux) = pin.and_then(|p| harmonic_measure(mesh, outer, p)) {
        share = flux;
        let floor = 1e-3 * share.iter().sum::<f64>() / m as f64;
        share.iter_mut().for_each(|f| *f = f.max(floor));
        // The flux of a vertex spreads over half the gaps on its two sides.
        gaps = (0..m)
            .map(|k| 0.5 * (share[k] + share[(k + 1) % m]))
            .collect();
    }
    let total: f64 = gaps.iter().sum();
    let mut angles = Vec::with_capacity(m);
    let mut acc = 0.0;
    for (k, g) in gaps.iter().enumerate() {
        angles.push(if total > 0.0 {
            TAU * acc / total
        } else {
            TAU * k as f64 / m as f64
        });
        acc += g;
    }
    angles
}

/// The flux of the discrete Green's function of [`outer_angles`] through each vertex of
/// `outer`; `None` if the solve fails.
fn harmonic_measure(mesh: &TriMesh, outer: &[u32], p: u32) -> Option<Vec<f64>> {
    let n = mesh.n_vertices();
    let mut fixed = vec![false; n];
    for &v in outer {
        fixed[v as usize] = true;
    }
    let weights = cotangent_weights(&mesh.positions, &mesh.faces);
    let pattern = StiffnessPattern::new(n, &mesh.faces, Some(&fixed));
    let mut values = vec![0.0; pattern.nnz()];
    pattern.assemble(&weights, &[], &mut values);
    let chol = CachedCholesky::new(&pattern).ok()?;
    let factor = chol.factor(&pattern, &values).ok()?;
    let mut g = vec![0.0; pattern.n_unknowns()];
    g[pattern.unknown_of(p as usize)?] = 1.0;
    factor.solve_in_place(&mut g);
    let green = |v: u32| pattern.unknown_of(v as usize).map_or(0.0, |u| g[u]);
    let mut flux = vec![0.0; n];
    for (f, w) in mesh.faces.iter().zip(&weights) {
        for c in 0..3 {
            let (a, b) = (f[(c + 1) % 3], f[(c + 2) % 3]);
            flux[a as usize] += w[c] * green(b);
            flux[b as usize] += w[c] * green(a);
        }
    }
    let out: Vec<f64> = outer.iter().map(|&v| flux[v as usize]).collect();
    out.iter().all(|f| f.is_finite()).then_some(out)
}

/// Tutte's embedding, with positive weights, of the surface with every hole filled by a fan:
/// the outer loop on the unit circle at [`outer_angles`], every other vertex at the weighted
/// mean of its neighbours, with the cotangent weights of the surface raised to at least
/// [`MIN_CORNER_WEIGHT`] and ½ per corner on the fans. Positive weights and a convex boundary
/// make the embedding bijective (Floater) in exact arithmetic; in floating point, regions the
/// embedding shrinks exponentially can still fold. Returns the image of the surface's vertices
/// followed by each hole's fan vertex, and the faces of the filled surface.
#[allow(clippy::type_complexity)]
fn fan_tutte(
    mesh: &TriMesh,
    loops: &[Vec<u32>],
    pin: Option<u32>,
) -> Result<(Vec<C64>, Vec<[u32; 3]>)> {
    let n = mesh.n_vertices();
    let n_filled = n + loops.len() - 1;
    let mut faces = mesh.faces.clone();
    let mut weights: Vec<[f64; 3]> = cotangent_weights(&mesh.positions, &mesh.faces)
        .into_iter()
        .map(|w| w.map(|c| c.max(MIN_CORNER_WEIGHT)))
        .collect();
    for (h, lp) in loops.iter().enumerate().skip(1) {
        let c = (n + h - 1) as u32;
        for k in 0..lp.len() {
            // The hole's loop runs along the surface's faces; the fan runs against it.
            faces.push([lp[(k + 1) % lp.len()], lp[k], c]);
            weights.push([0.5; 3]);
        }
    }
    let mut fixed = vec![false; n_filled];
    let mut z = vec![C64::new(0.0, 0.0); n_filled];
    for (&v, t) in loops[0].iter().zip(outer_angles(mesh, loops, pin)) {
        fixed[v as usize] = true;
        z[v as usize] = C64::from_polar(1.0, t);
    }
    let pattern = StiffnessPattern::new(n_filled, &faces, Some(&fixed));
    let m = pattern.n_unknowns();
    if m > 0 {
        let mut values = vec![0.0; pattern.nnz()];
        pattern.assemble(&weights, &[], &mut values);
        let chol = CachedCholesky::new(&pattern)?;
        let factor = chol.factor(&pattern, &values)?;
        let bx: Vec<f64> = z.iter().map(|w| w.re).collect();
        let by: Vec<f64> = z.iter().map(|w| w.im).collect();
        let mut rhs = pattern.fixed_rhs(&weights, &bx);
        rhs.extend(pattern.fixed_rhs(&weights, &by));
        factor.solve_many_in_place(&mut rhs, 2);
        for (v, w) in z.iter_mut().enumerate() {
            if let Some(u) = pattern.unknown_of(v) {
                *w = C64::new(rhs[u], rhs[m + u]);
            }
        }
    }
    Ok((z, faces))
}

/// The disk automorphism `M(w) = e^{iφ} (w − a) / (1 − ā w)` (|a| < 1).
#[derive(Debug, Clone, Copy)]
struct Mobius {
    a: C64,
    rotation: C64,
}

impl Mobius {
    fn apply(&self, w: C64) -> C64 {
        self.rotation * (w - self.a) / (1.0 - self.a.conj() * w)
    }

    /// Image of the circle `|w − c| = r` (inside the unit disk): the images of its two points
    /// on the line through `c` and the pole `1/ā` are diametrically opposite.
    fn circle(&self, c: C64, r: f64) -> (C64, f64) {
        let dir = if self.a.norm() > 0.0 {
            let d = c - 1.0 / self.a.conj();
            d / d.norm()
        } else {
            C64::new(1.0, 0.0)
        };
        let (p, q) = (self.apply(c + r * dir), self.apply(c - r * dir));
        (0.5 * (p + q), 0.5 * (p - q).norm())
    }

    fn apply_state(&self, state: &State) -> State {
        let mut out = State {
            z: state.z.par_iter().map(|&w| self.apply(w)).collect(),
            centers: state.centers.clone(),
            radii: state.radii.clone(),
        };
        for l in 0..state.centers.len() {
            (out.centers[l], out.radii[l]) = self.circle(state.centers[l], state.radii[l]);
        }
        out
    }
}

/// Refuses an initial embedding with folded triangles, naming the likely cause. Folds of
/// triangles whose areas are below 1e-12 of the mean are rounding errors in a region the
/// embedding shrinks exponentially: a long narrow inlet of a boundary, such as a hole shaped
/// like a spiral corridor (conformal maps shrink it too: seen from the outer boundary, the
/// harmonic measure of such a corridor's walls can fall below 1e-12). Larger folds mean loops
/// that do not follow the face orientation.
fn check_embedding(z: &[C64], faces: &[[u32; 3]]) -> Result<()> {
    let flipped = flipped_faces(z, faces);
    if flipped.is_empty() {
        return Ok(());
    }
    let area = |t: usize| {
        let p = faces[t].map(|v| [z[v as usize].re, z[v as usize].im, 0.0]);
        signed_area_2d(p[0], p[1], p[2])
    };
    let mean = (0..faces.len()).map(|t| area(t).abs()).sum::<f64>() / faces.len() as f64;
    let worst = flipped
        .iter()
        .map(|&t| area(t as usize).abs())
        .fold(0.0, f64::max);
    let n = flipped.len();
    Err(Error::Numerical(if worst <= 1e-12 * mean {
        format!(
            "the initial embedding collapses {n} triangles below double precision: a boundary \
             of the surface has a long narrow inlet (such as a spiral-shaped hole), which maps \
             onto a disk or a circle domain shrink exponentially; this surface's circle domain \
             map cannot be represented in floating point"
        )
    } else {
        format!(
            "Tutte's embedding of the hole-filled surface has {n} non-positive triangles (are \
             the boundary loops ordered along the face orientation?)"
        )
    }))
}

/// The interior vertex nearest the conformal centre of the surface's area in the planar map
/// `z`: the point the disk automorphism moving the area-weighted mean of the vertices to the
/// origin (iterated until the mean is 0) sends to 0. Pinning it at the origin spreads the
/// surface evenly over the disk; pinning a vertex far from the holes instead can push them
/// against the unit circle, where the map shrinks them exponentially.
fn balanced_pin(mesh: &TriMesh, loops: &[Vec<u32>], z: &[C64]) -> Option<u32> {
    let mass = lumped_mass(
        mesh.n_vertices(),
        &mesh.faces,
        &face_areas(&mesh.positions, &mesh.faces),
    );
    let total: f64 = mass.iter().sum();
    let mut w: Vec<C64> = z[..mesh.n_vertices()].to_vec();
    for _ in 0..100 {
        let mean: C64 = w.iter().zip(&mass).map(|(&p, &m)| p * m).sum::<C64>() / total;
        if !(mean.norm() > 1e-9) {
            break;
        }
        let a = if mean.norm() > 0.5 {
            mean * (0.5 / mean.norm())
        } else {
            mean
        };
        let m = Mobius {
            a,
            rotation: C64::new(1.0, 0.0),
        };
        w.iter_mut().for_each(|p| *p = m.apply(*p));
    }
    let mut on_loop = vec![false; mesh.n_vertices()];
    for &v in loops.iter().flatten() {
        on_loop[v as usize] = true;
    }
    (0..mesh.n_vertices())
        .filter(|&v| !on_loop[v] && w[v].norm().is_finite())
        .min_by(|&a, &b| w[a].norm().total_cmp(&w[b].norm()))
        .map(|v| v as u32)
}

/// The initial state and the vertex to pin: Tutte's map of the hole-filled surface
/// ([`fan_tutte`], first with `pin`, then again with the [`balanced_pin`] if it differs),
/// moved by the disk automorphism sending the pinned vertex to the origin (by a fraction of it
/// if the whole would fold a triangle), with each hole's reference circle centred at its fan
/// vertex with the mean distance of its loop as radius.
fn initial_state(
    mesh: &TriMesh,
    loops: &[Vec<u32>],
    pin: Option<u32>,
) -> Result<(State, Option<u32>)> {
    let (mut filled, all_faces) = fan_tutte(mesh, loops, pin)?;
    let pin = match pin.and(balanced_pin(mesh, loops, &filled)) {
        Some(p) if Some(p) != pin => {
            filled = fan_tutte(mesh, loops, Some(p))?.0;
            Some(p)
        }
        _ => pin,
    };
    check_embedding(&filled, &all_faces)?;
    let n = mesh.n_vertices();
    if let Some(p) = pin {
        let a0 = filled[p as usize];
        let mut t = 1.0;
        while t > 1e-3 {
            let m = Mobius {
                a: t * a0,
                rotation: C64::new(1.0, 0.0),
            };
            let moved: Vec<C64> = filled.par_iter().map(|&w| m.apply(w)).collect();
            if count_flips(&moved, &all_faces) == 0 {
                filled = moved;
                break;
            }
            t *= 0.5;
        }
    }
    let fans = filled.split_off(n);
    let mut centers = vec![C64::new(0.0, 0.0)];
    let mut radii = vec![1.0];
    for (lp, &c) in loops.iter().skip(1).zip(&fans) {
        let mean = lp
            .iter()
            .map(|&b| (filled[b as usize] - c).norm())
            .sum::<f64>()
            / lp.len() as f64;
        centers.push(c);
        radii.push(mean);
    }
    let state = State {
        z: filled,
        centers,
        radii,
    };
    Ok((state, pin))
}

/// Puts every boundary vertex exactly on its circle (radial projection from the centre).
fn project_onto_circles(state: &mut State, loops: &[Vec<u32>]) {
    // The outer circle is the unit circle exactly.
    state.centers[0] = C64::new(0.0, 0.0);
    state.radii[0] = 1.0;
    for (l, lp) in loops.iter().enumerate() {
        let (c, r) = (state.centers[l], state.radii[l]);
        for &b in lp {
            let d = state.z[b as usize] - c;
            let len = d.norm();
            if len > 0.0 {
                state.z[b as usize] = c + r * (d / len);
            }
        }
    }
}

/// The final normalisation — the pinned vertex at the origin (already there unless the initial
/// map could not be moved all the way), the first vertex of the outer loop at angle 0 — with
/// every boundary vertex projected onto its circle, and the bijectivity check. Returns the
/// vertex at the origin, if any.
fn finish(
    mut state: State,
    loops: &[Vec<u32>],
    faces: &[[u32; 3]],
    pin: Option<u32>,
) -> Result<(CircleDomain, Option<u32>)> {
    project_onto_circles(&mut state, loops);
    let a = pin.map_or(C64::new(0.0, 0.0), |p| state.z[p as usize]);
    let mut why = String::new();
    for a in [a, C64::new(0.0, 0.0)] {
        let normalized = normalized(&state, loops, a);
        let flips = count_flips(&normalized.z, faces);
        let problem = invalidity(&normalized, loops, Check::Circles).or_else(|| {
            (flips > 0).then(|| format!("{flips} triangles have a non-positive signed area"))
        });
        match problem {
            Some(p) => why = p,
            None => {
                let at_origin = pin.filter(|&p| normalized.z[p as usize] == C64::new(0.0, 0.0));
                let domain = CircleDomain {
                    positions: normalized.z.iter().map(|w| [w.re, w.im, 0.0]).collect(),
                    loops: loops.to_vec(),
                    centers: normalized.centers.iter().map(|c| [c.re, c.im]).collect(),
                    radii: normalized.radii,
                };
                return Ok((domain, at_origin));
            }
        }
    }
    Err(Error::Numerical(format!(
        "the circle domain map is not bijective: {why}"
    )))
}

/// `state` moved by the disk automorphism sending `a` to the origin and the first vertex of
/// the outer loop to angle 0, its boundary projected onto the circles.
fn normalized(state: &State, loops: &[Vec<u32>], a: C64) -> State {
    let mut m = Mobius {
        a,
        rotation: C64::new(1.0, 0.0),
    };
    let first = m.apply(state.z[loops[0][0] as usize]);
    if first.norm() > 0.0 {
        m.rotation = first.conj() / first.norm();
    }
    let mut out = m.apply_state(state);
    project_onto_circles(&mut out, loops);
    out.z[loops[0][0] as usize] = C64::new(1.0, 0.0);
    for (z, w) in out.z.iter_mut().zip(&state.z) {
        if *w == a {
            *z = C64::new(0.0, 0.0);
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::generate;
    use crate::qc::beltrami_coefficient_surface;

    fn mean_mu(mesh: &TriMesh, d: &CircleDomain) -> (f64, f64) {
        let mu = beltrami_coefficient_surface(&mesh.positions, &d.positions, &mesh.faces);
        let mean = mu.iter().map(|m| m.norm()).sum::<f64>() / mu.len() as f64;
        let max = mu.iter().map(|m| m.norm()).fold(0.0, f64::max);
        (mean, max)
    }

    fn run(mesh: &TriMesh) -> (CircleDomain, CircleDomainReport) {
        let loops = topology(mesh).boundary_loops;
        circle_domain_map_with_report(mesh, &loops).unwrap()
    }

    /// Zero flips and every boundary vertex on its circle to 1e-12 relative.
    fn check_domain(d: &CircleDomain, faces: &[[u32; 3]]) {
        let flips = faces
            .iter()
            .filter(|f| {
                let p = f.map(|v| d.positions[v as usize]);
                !(signed_area_2d(p[0], p[1], p[2]) > 0.0)
            })
            .count();
        assert_eq!(flips, 0);
        assert_eq!(d.centers[0], [0.0, 0.0]);
        assert_eq!(d.radii[0], 1.0);
        for (l, lp) in d.loops.iter().enumerate() {
            let (c, r) = (d.centers[l], d.radii[l]);
            for &v in lp {
                let p = d.positions[v as usize];
                let off = ((p[0] - c[0]).hypot(p[1] - c[1]) - r).abs();
                assert!(
                    off <= 1e-12 * r,
                    "loop {l} vertex {v} off its circle by {off}"
                );
            }
        }
    }

    /// Inversive distance of two circles, invariant under Möbius maps:
    /// `|r₁² + r₂² − |c₁ − c₂|²| / (2 r₁ r₂)`.
    fn inversive(c1: [f64; 2], r1: f64, c2: [f64; 2], r2: f64) -> f64 {
        let d2 = (c1[0] - c2[0]).powi(2) + (c1[1] - c2[1]).powi(2);
        (r1 * r1 + r2 * r2 - d2).abs() / (2.0 * r1 * r2)
    }

    fn lifted(holes: &[(f64, f64, f64)], resolution: usize) -> TriMesh {
        let mut mesh = generate::disk_with_holes(holes, resolution).unwrap();
        for p in &mut mesh.positions {
            p[2] = 0.3 * (p[0] * p[0] - p[1] * p[1]);
        }
        mesh
    }

    #[test]
    fn energy_is_zero_for_similarities_and_its_gradient_is_exact() {
        let flat = generate::disk_with_holes(&[(0.3, 0.1, 0.2)], 24).unwrap();
        let g = Geometry::new(&flat);
        let sim: Vec<C64> = complex_positions(&flat.positions)
            .iter()
            .map(|&z| C64::new(0.5, 2.0) * z + 3.0)
            .collect();
        assert!(g.conformal_energy(&sim, None) < 1e-24);
        // Central differences of the (quadratic) energy are exact up to rounding.
        let mesh = lifted(&[(0.3, 0.1, 0.2)], 24);
        let geo = Geometry::new(&mesh);
        let weights: Vec<f64> = (0..mesh.faces.len())
            .map(|t| 1.0 + (t % 3) as f64)
            .collect();
        let z: Vec<C64> = complex_positions(&mesh.positions)
            .iter()
            .map(|&z| z + 0.2 * z * z)
            .collect();
        let y = geo.gradient(&z, &weights);
        for v in [0, 7, 30, mesh.n_vertices() - 1] {
            for dir in [C64::new(1.0, 0.0), C64::new(0.0, 1.0)] {
                let h = 1e-4;
                let mut zp = z.clone();
                zp[v] += h * dir;
                let mut zm = z.clone();
                zm[v] -= h * dir;
                let fd = (geo.conformal_energy(&zp, Some(&weights))
                    - geo.conformal_energy(&zm, Some(&weights)))
                    / (2.0 * h);
                assert!(
                    (fd - dot2(dir, y[v])).abs() < 1e-8 * (1.0 + fd.abs()),
                    "vertex {v}: {fd} vs {}",
                    dot2(dir, y[v])
                );
            }
        }
    }

    #[test]
    fn normal_matrix_is_the_energy_curvature() {
        // E_C is quadratic: along any δ of the unknowns, δᵀ (Pᵀ H P) δ = 2 E_C(P δ).
        let mesh = lifted(&[(0.3, 0.1, 0.2), (-0.4, -0.2, 0.15)], 20);
        let loops = ordered_loops(&mesh, &topology(&mesh).boundary_loops).unwrap();
        let geo = Geometry::new(&mesh);
        let pin = farthest_from_boundary(&geo, &loops);
        let layout = Layout::new(geo.n, &loops, pin, &[loops[0][0]], Holes::OnCircles);
        let order = geo.vertex_order().unwrap();
        let mut sys = NormalSystem::new(&geo, layout, &order).unwrap();
        let state = State {
            z: complex_positions(&mesh.positions),
            centers: vec![C64::new(0.0, 0.0), C64::new(0.3, 0.1), C64::new(-0.4, -0.2)],
            radii: vec![1.0, 0.2, 0.15],
        };
        let lin = circle_constraints(&state, &loops);
        let weights: Vec<f64> = (0..mesh.faces.len())
            .map(|t| 1.0 + (t % 2) as f64)
            .collect();
        sys.factor(&geo, &weights, &lin.u, 0.0, None).unwrap();
        let delta: Vec<f64> = (0..sys.layout.n_unknowns)
            .map(|k| ((k * 7919) % 13) as f64 / 13.0 - 0.5)
            .collect();
        let pd: Vec<C64> = (0..geo.n)
            .map(|v| {
                let (basis, len) = sys.layout.basis(v, lin.u[v]);
                basis[..len]
                    .iter()
                    .map(|&(id, m)| delta[id as usize] * m)
                    .sum()
            })
            .collect();
        let kd = sys.pattern.mul(&sys.values, &delta);
        let quad: f64 = kd.iter().zip(&delta).map(|(a, b)| a * b).sum();
        let e = geo.conformal_energy(&pd, Some(&weights));
        assert!((quad - 2.0 * e).abs() < 1e-10 * e, "{quad} vs {}", 2.0 * e);
        // The step solves the normal equations K δ = −Pᵀ y.
        let y = geo.gradient(&state.z, &weights);
        let g = sys.gradient(&y, &lin.u, &state, 0.0);
        let step = sys.solve(g.clone()).unwrap();
        let ks = sys.pattern.mul(&sys.values, &step);
        for (a, b) in ks.iter().zip(&g) {
            assert!((a + b).abs() < 1e-8 * (1.0 + b.abs()));
        }
    }

    /// The disk automorphism of the planar points `p` (scaled by `1 / scale`) sending the
    /// pinned vertex to the origin and the first outer vertex to angle 0: the exact map when
    /// the input already is a circle domain (up to scale).
    fn exact_map(p: &[[f64; 3]], scale: f64, d: &CircleDomain, pin: u32) -> Vec<[f64; 3]> {
        let w: Vec<C64> = p.iter().map(|q| C64::new(q[0], q[1]) / scale).collect();
        let mut m = Mobius {
            a: w[pin as usize],
            rotation: C64::new(1.0, 0.0),
        };
        let first = m.apply(w[d.loops[0][0] as usize]);
        m.rotation = first.conj() / first.norm();
        w.iter()
            .map(|&z| {
                let q = m.apply(z);
                [q.re, q.im, 0.0]
            })
            .collect()
    }

    /// The mean |μ| of the map is within 5% (+0.001) of that of the exact map's piecewise-linear
    /// interpolation, which is not zero on a coarse mesh.
    fn assert_close_to_exact_mu(mesh: &TriMesh, d: &CircleDomain, exact: Vec<[f64; 3]>) {
        let (mean, _) = mean_mu(mesh, d);
        let exact = CircleDomain {
            positions: exact,
            ..d.clone()
        };
        let (base, _) = mean_mu(mesh, &exact);
        assert!(
            mean <= 1.05 * base + 1e-3,
            "mean |mu| {mean}, exact map's {base}"
        );
    }

    /// Largest distance between the discrete map and the [`exact_map`].
    fn deviation(d: &CircleDomain, exact: &[[f64; 3]]) -> f64 {
        exact
            .iter()
            .zip(&d.positions)
            .map(|(e, q)| (e[0] - q[0]).hypot(e[1] - q[1]))
            .fold(0.0, f64::max)
    }

    /// The input hole each output loop is (nearest centre), for loops of `disk_with_holes`.
    fn hole_of_loop(mesh: &TriMesh, lp: &[u32], holes: &[(f64, f64, f64)]) -> usize {
        let c = lp.iter().fold(C64::new(0.0, 0.0), |s, &v| {
            s + C64::new(mesh.positions[v as usize][0], mesh.positions[v as usize][1])
        }) / lp.len() as f64;
        (0..holes.len())
            .min_by(|&i, &j| {
                let d = |k: usize| (c - C64::new(holes[k].0, holes[k].1)).norm();
                d(i).total_cmp(&d(j))
            })
            .unwrap_or(0)
    }

    #[test]
    fn annulus_keeps_its_conformal_modulus() {
        // The annulus r ≤ |z| ≤ R is a circle domain once scaled by 1/R: the map is the disk
        // automorphism of the normalisation, and the inversive distance (1 + q²) / (2q) of its
        // two circles, q = r / R (Möbius-invariant), is kept.
        let (r, big_r) = (0.4, 1.3);
        let mesh = generate::annulus(r, big_r, 12, 96).unwrap();
        let (d, report) = run(&mesh);
        check_domain(&d, &mesh.faces);
        assert!(report.converged, "{report:?}");
        let inv = inversive(d.centers[0], d.radii[0], d.centers[1], d.radii[1]);
        let q = inv - (inv * inv - 1.0).sqrt();
        assert!((q - r / big_r).abs() < 1e-3, "modulus {q} vs {}", r / big_r);
        let pin = report.pinned_vertex.unwrap();
        assert_eq!(d.positions[pin as usize], [0.0, 0.0, 0.0]);
        let first = d.positions[d.loops[0][0] as usize];
        assert!((first[0] - 1.0).abs() < 1e-15 && first[1].abs() < 1e-15);
        let exact = exact_map(&mesh.positions, big_r, &d, pin);
        let dev = deviation(&d, &exact);
        assert!(dev < 0.02, "deviation from the exact map {dev}");
        assert_close_to_exact_mu(&mesh, &d, exact);
        // Second-order convergence to the exact map under refinement.
        let fine = generate::annulus(r, big_r, 24, 192).unwrap();
        let (df, rf) = run(&fine);
        let exact = exact_map(&fine.positions, big_r, &df, rf.pinned_vertex.unwrap());
        let dev_fine = deviation(&df, &exact);
        assert!(dev_fine < dev / 3.0, "deviation {dev} then {dev_fine}");
    }

    #[test]
    fn circle_domain_maps_to_a_mobius_image_of_itself() {
        // A disk with round holes is already a circle domain: the map is a disk automorphism,
        // which keeps every pair of circles' inversive distance. Lifted onto the unit sphere by
        // the inverse stereographic projection (conformal, circles to circles) it has the same
        // map.
        let holes = [(0.35, 0.2, 0.2), (-0.4, -0.1, 0.25), (0.1, -0.55, 0.15)];
        let flat = generate::disk_with_holes(&holes, 128).unwrap();
        let mut sphere = flat.clone();
        for p in &mut sphere.positions {
            let s = 1.0 + p[0] * p[0] + p[1] * p[1];
            *p = [2.0 * p[0] / s, 2.0 * p[1] / s, (s - 2.0) / s];
        }
        for mesh in [&flat, &sphere] {
            let (d, report) = run(mesh);
            check_domain(&d, &mesh.faces);
            assert!(report.converged, "{report:?}");
            let exact = exact_map(&flat.positions, 1.0, &d, report.pinned_vertex.unwrap());
            let dev = deviation(&d, &exact);
            assert!(dev < 0.01, "deviation from the exact map {dev}");
            assert_close_to_exact_mu(mesh, &d, exact);
            let circle = |l: usize| match l {
                0 => ([0.0, 0.0], 1.0),
                _ => {
                    let h = holes[hole_of_loop(&flat, &d.loops[l], &holes)];
                    ([h.0, h.1], h.2)
                }
            };
            for i in 0..d.loops.len() {
                for j in 0..i {
                    let ((ci, ri), (cj, rj)) = (circle(i), circle(j));
                    let want = inversive(ci, ri, cj, rj);
                    let got = inversive(d.centers[i], d.radii[i], d.centers[j], d.radii[j]);
                    assert!(
                        (got - want).abs() < 0.01 * want,
                        "circles {i},{j}: {got} vs {want}"
                    );
                }
            }
        }
    }

    #[test]
    fn disk_maps_onto_the_unit_disk() {
        // The unit disk lifted onto the sphere by the inverse stereographic projection: its
        // conformal map is the projection back, up to a disk automorphism.
        let flat = generate::disk_with_holes(&[], 64).unwrap();
        let mut cap = flat.clone();
        for p in &mut cap.positions {
            let s = 1.0 + p[0] * p[0] + p[1] * p[1];
            *p = [2.0 * p[0] / s, 2.0 * p[1] / s, (s - 2.0) / s];
        }
        let (d, report) = run(&cap);
        check_domain(&d, &cap.faces);
        assert_eq!(d.loops.len(), 1);
        assert!(report.converged, "{report:?}");
        let exact = exact_map(&flat.positions, 1.0, &d, report.pinned_vertex.unwrap());
        let dev = deviation(&d, &exact);
        assert!(dev < 5e-3, "deviation from the exact map {dev}");
        assert_close_to_exact_mu(&cap, &d, exact);
        // A rectangle: its corners are singular points of the map onto the disk (angle π/2
        // opened to π), where the coarse grid cannot be conformal.
        let mesh = generate::square_grid(24, 16, 1.5, 1.0).unwrap();
        let (d, report) = run(&mesh);
        check_domain(&d, &mesh.faces);
        assert!(report.converged, "{report:?}");
        let (mean, _) = mean_mu(&mesh, &d);
        assert!(mean < 0.07, "mean |mu| {mean}");
    }

    #[test]
    fn curved_surface_with_holes() {
        let mesh = lifted(&[(0.3, 0.25, 0.2), (-0.35, -0.2, 0.2)], 96);
        let (d, report) = run(&mesh);
        check_domain(&d, &mesh.faces);
        assert!(report.converged, "{report:?}");
        assert!(report.conformal_energy <= report.initial_energy);
        let (mean, _) = mean_mu(&mesh, &d);
        assert!(mean < 0.02, "mean |mu| {mean}");
        // The outer loop is the one spanning the largest area, whatever the input order.
        let mut loops = topology(&mesh).boundary_loops;
        loops.reverse();
        let d2 = circle_domain_map(&mesh, &loops).unwrap();
        assert_eq!(d2.loops[0], d.loops[0]);
        assert_eq!(d2.loops[1], loops[0]);
    }

    /// A unit square minus the square `[0.35, 0.65]²`, on an `n × n` grid.
    fn square_frame(n: usize) -> TriMesh {
        let grid = generate::square_grid(n, n, 1.0, 1.0).unwrap();
        let inside = |x: f64| (0.35..=0.65).contains(&x);
        let faces = grid
            .faces
            .iter()
            .copied()
            .filter(|f| {
                let c = f.iter().fold([0.0, 0.0], |c, &v| {
                    let p = grid.positions[v as usize];
                    [c[0] + p[0] / 3.0, c[1] + p[1] / 3.0]
                });
                !(inside(c[0]) && inside(c[1]))
            })
            .collect();
        crate::mesh::validate::validate(TriMesh::new(grid.positions, faces))
            .unwrap()
            .0
    }

    /// The radius ratio of the concentric annulus conformal to the circle domain `d` (two
    /// loops): from the inversive distance `I`, `q = I − √(I² − 1)`.
    fn modulus(d: &CircleDomain) -> f64 {
        let inv = inversive(d.centers[0], d.radii[0], d.centers[1], d.radii[1]);
        inv - (inv * inv - 1.0).sqrt()
    }

    #[test]
    fn polygonal_hole_becomes_a_circle() {
        // Square boundaries: the hole starts as a square around its fan vertex and is pulled
        // onto a circle. The conformal modulus of the frame converges under refinement.
        let coarse = square_frame(40);
        let (d, report) = run(&coarse);
        check_domain(&d, &coarse.faces);
        assert!(report.converged, "{report:?}");
        let fine = square_frame(80);
        let (df, _) = run(&fine);
        check_domain(&df, &fine.faces);
        let (q, qf) = (modulus(&d), modulus(&df));
        assert!((q - qf).abs() < 5e-3 * qf, "modulus {q} then {qf}");
        let (mean, _) = mean_mu(&fine, &df);
        assert!(mean < 0.05, "mean |mu| {mean}");
    }

    #[test]
    fn mesh_without_interior_vertices() {
        // One ring of faces: every vertex is on a boundary; three outer vertices are pinned.
        let mesh = generate::annulus(0.5, 1.0, 1, 16).unwrap();
        let (d, _) = run(&mesh);
        check_domain(&d, &mesh.faces);
        let tri = TriMesh::new(
            vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
            vec![[0, 1, 2]],
        );
        let (d, _) = run(&tri);
        check_domain(&d, &tri.faces);
    }

    #[test]
    fn bad_input_is_an_error() {
        let closed = generate::icosphere(1).unwrap();
        assert!(matches!(
            circle_domain_map(&closed, &[]),
            Err(Error::Topology { .. })
        ));
        let mesh = generate::annulus(0.5, 1.0, 2, 16).unwrap();
        let loops = topology(&mesh).boundary_loops;
        assert!(circle_domain_map(&mesh, &loops[..1]).is_err());
        assert!(circle_domain_map(&mesh, &[vec![0, 1]]).is_err());
        assert!(circle_domain_map(&mesh, &[vec![0, 1, 999]]).is_err());
        let torus = generate::torus(2.0, 1.0, 12, 8).unwrap();
        assert!(circle_domain_map(&torus, &[vec![0, 1, 2]]).is_err());
        // Reversed loops: the Tutte map is inside out.
        let rev: Vec<Vec<u32>> = loops
            .iter()
            .map(|l| l.iter().rev().copied().collect())
            .collect();
        assert!(matches!(
            circle_domain_map(&mesh, &rev),
            Err(Error::Numerical(_))
        ));
    }
}
