//! The tree–cotree decomposition (Eppstein 2003) of a closed oriented surface mesh and the
//! integer cohomology basis dual to its homology generators.
//!
//! A breadth-first spanning tree of the vertices (the primal tree) and a spanning tree of the
//! faces joined across the edges the primal tree does not use (the dual tree) leave
//! `E − (V − 1) − (F − 1) = 2 − χ = 2g` edges over: the generators. Generator `k` closes a
//! loop with the primal tree, and these `2g` loops form a basis of the first homology.
//!
//! The dual basis of closed integer 1-forms `η_k` (one value per half-edge, `η(i→j) = −η(j→i)`)
//! vanishes on the primal tree, is `δ_kl` on generator `l` (in its direction from the smaller
//! to the larger vertex index), and is fixed on the dual-tree edges by closedness (the sum over
//! the three half-edges of every face is 0), peeling the dual tree from its leaves: a face whose
//! children are done has one unknown edge left, the one to its parent. The root face closes by
//! itself, since the face sums add up to zero over the whole closed surface.

use crate::mesh::topology::{EdgeGroups, half_edge};
use crate::{Error, Result};
use std::collections::VecDeque;

const NONE: u32 = u32::MAX;

/// The role of an undirected edge in the tree–cotree decomposition.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum EdgeKind {
    /// An edge of the breadth-first spanning tree of the vertices.
    PrimalTree,
    /// An edge crossed by the spanning tree of the faces.
    DualTree,
    /// One of the `2g` leftover edges: each closes a homology generator with the primal tree.
    Generator,
}

/// The half-edge connectivity of a closed, consistently oriented manifold mesh with its
/// tree–cotree decomposition. Half-edge `3f + c` runs from corner `c` to corner `c + 1`
/// (mod 3) of face `f`.
#[derive(Debug, Clone)]
pub struct CutGraph {
    /// The undirected edges as `[smaller, larger]` vertex index, sorted.
    pub edges: Vec<[u32; 2]>,
    /// Per half-edge, its undirected edge.
    pub edge_of: Vec<u32>,
    /// Per half-edge, the opposite half-edge (same edge, other face, other direction).
    pub twin: Vec<u32>,
    /// Per edge, its role.
    pub kind: Vec<EdgeKind>,
    /// The generator edges, in increasing edge order (two on a torus).
    pub generators: Vec<u32>,
    /// The root of the primal tree (the first corner of face 0).
    pub root: u32,
    /// Per edge, its half-edge from the smaller to the larger vertex.
    forward: Vec<u32>,
    /// Per vertex, the half-edge from its parent in the primal tree (`u32::MAX` at the root and
    /// at vertices no face uses).
    primal_parent: Vec<u32>,
    /// Per face, its half-edge on the dual-tree edge to its parent (`u32::MAX` at face 0).
    dual_parent: Vec<u32>,
    /// The faces in breadth-first order of the dual tree, face 0 first.
    dual_order: Vec<u32>,
}

impl CutGraph {
    /// Builds the half-edge connectivity of `faces` on `n_vertices` vertices and its
    /// tree–cotree decomposition.
    ///
    /// Errors: [`Error::InvalidMesh`] for a face index out of range, a face with a repeated
    /// vertex, or an edge that does not have exactly two faces traversing it in opposite
    /// directions (a boundary, a non-manifold edge, inconsistent orientation);
    /// [`Error::Topology`] when the faces are not connected. Non-manifold vertices are not
    /// detected here (see [`crate::mesh::validate::check`]).
    pub fn new(n_vertices: usize, faces: &[[u32; 3]]) -> Result<Self> {
        if faces.is_empty() {
            return Err(Error::InvalidMesh("the mesh has no faces".into()));
        }
        if 3 * faces.len() >= NONE as usize || n_vertices >= NONE as usize {
            return Err(Error::InvalidMesh(
                "the mesh is too large for 32-bit half-edge indices".into(),
            ));
        }
        for (f, t) in faces.iter().enumerate() {
            if t.iter().any(|&v| v as usize >= n_vertices) {
                return Err(Error::InvalidMesh(format!(
                    "face {f} uses a vertex index out of range (the mesh has {n_vertices} vertices)"
                )));
            }
            if t[0] == t[1] || t[1] == t[2] || t[2] == t[0] {
                return Err(Error::InvalidMesh(format!("face {f} repeats a vertex")));
            }
        }
        let pairs = pair_half_edges(n_vertices, faces)?;
        let root = faces[0][0];
        let mut kind = vec![EdgeKind::Generator; pairs.edges.len()];
        let primal_parent = primal_tree(n_vertices, faces, &pairs.edge_of, root, &mut kind)?;
        let (dual_parent, dual_order) =
            dual_tree(faces.len(), &pairs.edge_of, &pairs.twin, &mut kind)?;
        let generators = (0..pairs.edges.len() as u32)
            .filter(|&e| kind[e as usize] == EdgeKind::Generator)
            .collect();
        Ok(Self {
            edges: pairs.edges,
            edge_of: pairs.edge_of,
            twin: pairs.twin,
            kind,
            generators,
            root,
            forward: pairs.forward,
            primal_parent,
            dual_parent,
            dual_order,
        })
    }

    /// The closed 1-form dual to generator `k` (see the module documentation): one integer per
    /// half-edge, `η_k(twin h) = −η_k(h)`, zero on the primal tree, `δ_kl` on generator `l`
    /// from its smaller to its larger vertex, and summing to zero over every face.
    ///
    /// # Panics
    /// If `k >= self.generators.len()`.
    pub fn cohomology_form(&self, k: usize) -> Vec<i64> {
        let mut eta = vec![0i64; self.edge_of.len()];
        let h = self.forward[self.generators[k] as usize] as usize;
        eta[h] = 1;
        eta[self.twin[h] as usize] = -1;
        // Children come after their parent in breadth-first order: peel from the back.
        for &f in self.dual_order.iter().rev() {
            let up = self.dual_parent[f as usize];
            if up == NONE {
                continue;
            }
            let base = 3 * (f as usize);
            let others: i64 = (base..base + 3)
                .filter(|&h| h != up as usize)
                .map(|h| eta[h])
                .sum();
            eta[up as usize] = -others;
            eta[self.twin[up as usize] as usize] = others;
        }
        eta
    }

    /// The closed loop of generator `k`: the half-edges from the root down the primal tree to
    /// the generator's smaller vertex, across the generator, and back up the tree to the root.
    ///
    /// # Panics
    /// If `k >= self.generators.len()`.
    pub fn generator_loop(&self, faces: &[[u32; 3]], k: usize) -> Vec<u32> {
        let h = self.forward[self.generators[k] as usize];
        let (a, b) = half_edge(faces, h);
        // Down from the root to a (reversed climb from a), then across, then up from b.
        let mut down: Vec<u32> = self.climb(faces, a);
        down.reverse();
        let mut out = down;
        out.push(h);
        out.extend(
            self.climb(faces, b)
                .into_iter()
                .map(|h| self.twin[h as usize]),
        );
        out
    }

    /// The tree half-edges from the root down to `v`, listed from `v` upwards.
    fn climb(&self, faces: &[[u32; 3]], mut v: u32) -> Vec<u32> {
        let mut out = Vec::new();
        while self.primal_parent[v as usize] != NONE {
            let h = self.primal_parent[v as usize];
            out.push(h);
            v = half_edge(faces, h).0;
        }
        out
    }
}

/// The half-edges of a closed oriented manifold paired into edges.
struct Pairs {
    edges: Vec<[u32; 2]>,
    edge_of: Vec<u32>,
    twin: Vec<u32>,
    forward: Vec<u32>,
}

/// Pairs every half-edge with its twin; every edge must have exactly two half-edges of
/// opposite directions.
fn pair_half_edges(n_vertices: usize, faces: &[[u32; 3]]) -> Result<Pairs> {
    let groups = EdgeGroups::new(n_vertices, faces);
    let n_half = 3 * faces.len();
    let mut edges = Vec::with_capacity(n_half / 2);
    let mut forward = Vec::with_capacity(n_half / 2);
    let mut edge_of = vec![NONE; n_half];
    let mut twin = vec![NONE; n_half];
    let mut problem: Option<String> = None;
    groups.for_each_edge(|lo, hi, hes| {
        if problem.is_some() {
            return;
        }
        if hes.len() != 2 {
            problem = Some(if hes.len() == 1 {
                format!("edge ({lo}, {hi}) is on a boundary: the surface is not closed")
            } else {
                format!(
                    "edge ({lo}, {hi}) is shared by {} faces: the mesh is not manifold",
                    hes.len()
                )
            });
            return;
        }
        let (a0, _) = half_edge(faces, hes[0]);
        let (a1, _) = half_edge(faces, hes[1]);
        if a0 == a1 {
            problem = Some(format!(
                "faces {} and {} have inconsistent orientation across edge ({lo}, {hi})",
                hes[0] / 3,
                hes[1] / 3
            ));
            return;
        }
        let e = edges.len() as u32;
        edges.push([lo, hi]);
        forward.push(if a0 == lo { hes[0] } else { hes[1] });
        edge_of[hes[0] as usize] = e;
        edge_of[hes[1] as usize] = e;
        twin[hes[0] as usize] = hes[1];
        twin[hes[1] as usize] = hes[0];
    });
    if let Some(msg) = problem {
        return Err(Error::InvalidMesh(msg));
    }
    Ok(Pairs {
        edges,
        edge_of,
        twin,
        forward,
    })
}

/// Breadth-first spanning tree of the vertices from `root` over the half-edges; marks its
/// edges in `kind` and returns the half-edge from each vertex's parent.
fn primal_tree(
    n_vertices: usize,
    faces: &[[u32; 3]],
    edge_of: &[u32],
    root: u32,
    kind: &mut [EdgeKind],
) -> Result<Vec<u32>> {
    // Outgoing half-edges per vertex (CSR over the vertex–face incidence): half-edge `3f + c`
    // leaves corner c of face f.
    let (start, incident) = crate::mesh::vertex_faces(n_vertices, faces);
    let out: Vec<u32> = (0..n_vertices)
        .flat_map(|v| {
            incident[start[v]..start[v + 1]].iter().map(move |&f| {
                let c = faces[f as usize]
                    .iter()
                    .position(|&w| w as usize == v)
                    .unwrap_or(0);
                3 * f + c as u32
            })
        })
        .collect();
    let mut parent = vec![NONE; n_vertices];
    let mut seen = vec![false; n_vertices];
    seen[root as usize] = true;
    let mut queue = VecDeque::from([root]);
    while let Some(v) = queue.pop_front() {
        for &h in &out[start[v as usize]..start[v as usize + 1]] {
            let (_, w) = half_edge(faces, h);
            if !seen[w as usize] {
                seen[w as usize] = true;
                parent[w as usize] = h;
                kind[edge_of[h as usize] as usize] = EdgeKind::PrimalTree;
                queue.push_back(w);
            }
        }
    }
    let used = |v: usize| start[v + 1] > start[v];
    if let Some(v) = (0..n_vertices).find(|&v| used(v) && !seen[v]) {
        return Err(not_connected(format!(
            "vertex {v} is not connected to vertex {root}"
        )));
    }
    Ok(parent)
}

/// Spanning tree of the faces across the edges not in the primal tree, breadth first from
/// face 0; marks its edges in `kind` and returns each face's half-edge towards its parent and
/// the visiting order.
fn dual_tree(
    n_faces: usize,
    edge_of: &[u32],
    twin: &[u32],
    kind: &mut [EdgeKind],
) -> Result<(Vec<u32>, Vec<u32>)> {
    let mut parent = vec![NONE; n_faces];
    let mut seen = vec![false; n_faces];
    let mut order = Vec::with_capacity(n_faces);
    seen[0] = true;
    order.push(0u32);
    let mut next = 0;
    while next < order.len() {
        let f = order[next] as usize;
        next += 1;
        for h in 3 * f..3 * f + 3 {
            let e = edge_of[h] as usize;
            if kind[e] == EdgeKind::PrimalTree {
                continue;
            }
            let across = twin[h];
            let g = (across / 3) as usize;
            if !seen[g] {
                seen[g] = true;
                parent[g] = across;
                kind[e] = EdgeKind::DualTree;
                order.push(g as u32);
            }
        }
    }
    if order.len() != n_faces {
        let f = (0..n_faces).find(|&f| !seen[f]).unwrap_or(0);
        return Err(not_connected(format!(
            "face {f} cannot be reached from face 0"
        )));
    }
    Ok((parent, order))
}

fn not_connected(detail: String) -> Error {
    Error::Topology {
        method: "the tree–cotree decomposition".into(),
        msg: format!("the surface must be connected, but {detail}"),
    }
}
