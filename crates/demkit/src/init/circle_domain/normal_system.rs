//! The unknowns of one Gauss–Newton step (C3)–(C5): their layout (interior displacements,
//! tangential moves, hole centres and radii), the circle linearisation and the normal system
//! with its one-time symbolic analysis.

use super::*;

/// What a vertex contributes to the unknowns.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum Role {
    /// Vertex with unknowns `x` (its x displacement) and `x + 1` (y).
    Free(u32),
    /// Fixed vertex.
    Pinned,
    /// Vertex kept on the circle of loop `lp` (C3), with its tangential move `s` unless pinned.
    Boundary { lp: u32, s: Option<u32> },
}

/// How the hole boundaries enter a [`Layout`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum Holes {
    /// On their circles (C3).
    OnCircles,
    /// Free, pulled towards their circles by the penalty (C5).
    Penalized,
}

/// One term of the penalty (C5): a hole vertex and its unknowns (x, y, c_x, c_y, ρ).
#[derive(Debug, Clone, Copy)]
pub(super) struct Penalty {
    pub(super) vertex: u32,
    pub(super) hole: u32,
    pub(super) ids: [u32; 5],
}

/// Numbering of the unknowns: vertex displacements, tangential moves on the circles (C3), and
/// per hole its centre (two unknowns) and radius.
pub(super) struct Layout {
    pub(super) role: Vec<Role>,
    /// First of the three unknowns (c_x, c_y, ρ) of each hole (unused for the outer loop).
    pub(super) hole_base: Vec<u32>,
    /// The terms of the penalty (C5).
    pub(super) penalized: Vec<Penalty>,
    pub(super) n_unknowns: usize,
}

impl Layout {
    /// The unknowns of the Gauss–Newton step: every vertex but `pin` and `outer_pins` moves,
    /// the outer loop on the unit circle, the holes as `holes` says.
    pub(super) fn new(
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
    pub(super) fn interior(n: usize, loops: &[Vec<u32>], pin: Option<u32>) -> Self {
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
    pub(super) fn basis(&self, v: usize, u: C64) -> ([(u32, C64); 4], usize) {
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
    pub(super) fn pull_back(&self, y: &[C64], u: &[C64]) -> Vec<f64> {
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
    pub(super) fn elimination_order(&self, vertex_order: &[usize]) -> Vec<usize> {
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
pub(super) struct State {
    pub(super) z: Vec<C64>,
    pub(super) centers: Vec<C64>,
    pub(super) radii: Vec<f64>,
}

impl State {
    /// `|w_v − c_h| − ρ_h`: how far vertex `v` is off the circle of loop `h` (C5).
    pub(super) fn off_circle(&self, v: u32, h: u32) -> f64 {
        (self.z[v as usize] - self.centers[h as usize]).norm() - self.radii[h as usize]
    }
}

/// The circle constraints (C3) linearised at the current state: each boundary vertex's unit
/// radial direction `u_b` from its circle's centre, and `offset_b = c + ρ u_b − w_b`, the move
/// onto the circle.
pub(super) struct Linearization {
    pub(super) u: Vec<C64>,
    pub(super) offset: Vec<C64>,
}

pub(super) fn circle_constraints(state: &State, loops: &[Vec<u32>]) -> Linearization {
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
pub(super) struct Columns {
    pub(super) ids: [u32; 12],
    pub(super) moves: [[C64; 3]; 12],
    pub(super) len: usize,
}

/// The [`Columns`] of face `t` (the same order whatever `u`; `u` may be empty to get the ids).
pub(super) fn face_columns(t: usize, geo: &Geometry, layout: &Layout, u: &[C64]) -> Columns {
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
pub(super) fn face_matrix(
    t: usize,
    weight: f64,
    geo: &Geometry,
    layout: &Layout,
    u: &[C64],
    out: &mut [f64],
) {
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
pub(super) fn penalty_row(u: C64) -> [f64; 5] {
    [u.re, u.im, -u.re, -u.im, -1.0]
}

/// A normal matrix `Pᵀ H P` (plus `2 λ j jᵀ` per penalty term (C5), `j` its [`penalty_row`]) over a [`Layout`]'s unknowns:
/// its pattern and symbolic factorization are computed once, [`factor`](Self::factor)
/// refactors for new directions `u`, weights or `λ`.
pub(super) struct NormalSystem {
    pub(super) layout: Layout,
    pub(super) pattern: ElementPattern,
    pub(super) solver: Option<SparseCholesky>,
    pub(super) element_values: Vec<f64>,
    pub(super) values: Vec<f64>,
}

impl NormalSystem {
    /// The system of `layout`'s unknowns, eliminated vertex by vertex in `vertex_order` (the
    /// circles' unknowns last).
    pub(super) fn new(geo: &Geometry, layout: Layout, vertex_order: &[usize]) -> Result<Self> {
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
            Some(SparseCholesky::with_ordering(
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
    pub(super) fn factor(
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
    pub(super) fn add_circle_curvature(&mut self, y: &[C64], u: &[C64], radii: &[f64]) {
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
    pub(super) fn gradient(&self, y: &[C64], u: &[C64], state: &State, lambda: f64) -> Vec<f64> {
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
    pub(super) fn solve(&mut self, mut g: Vec<f64>) -> Result<Vec<f64>> {
        g.iter_mut().for_each(|x| *x = -*x);
        if let Some(solver) = self.solver.as_mut() {
            solver.solve_finite_in_place(&mut g)?;
        }
        Ok(g)
    }
}
