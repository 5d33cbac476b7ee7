//! Mesh validation: everything demkit needs of an input surface, checked once, with messages
//! that name the offending vertex, face or edge (0-based indices).
//!
//! Errors (in the order they are checked and reported): no faces; a non-finite coordinate; a
//! face index out of range; a face with a repeated vertex; a face of zero area; duplicate faces
//! and edges shared by more than two faces (not manifold); vertices whose faces form more than
//! one fan (not manifold); inconsistent face orientation; more than one connected component.
//! Vertices used by no face are not an error: [`validate`] drops them with a warning.

use super::TriMesh;
use super::topology::{EdgeGroups, connected_components, half_edge, vertex_faces};
use crate::{Error, Result};

/// At most this many messages of one kind are listed; the rest are summed up in one line.
const MAX_PER_KIND: usize = 10;

/// A face counts as zero-area when its area is at most this times the squared bounding-box
/// diagonal.
const ZERO_AREA_RATIO: f64 = 1e-14;

/// The problems found in a mesh by [`check`].
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Findings {
    /// Problems that make the mesh unusable, most fundamental first. At most ten messages of
    /// each kind are listed, followed by a line "... and N more ..." when there are more.
    pub errors: Vec<String>,
    /// Harmless oddities (e.g. unused vertices).
    pub warnings: Vec<String>,
}

impl Findings {
    /// True when no error was found.
    pub fn is_valid(&self) -> bool {
        self.errors.is_empty()
    }
}

/// Checks `mesh` and lists every problem found (for `demkit info`).
///
/// Checks that need valid indices are skipped when some face index is out of range, and the
/// zero-area check is skipped when some coordinate is not finite.
pub fn check(mesh: &TriMesh) -> Findings {
    let (mut findings, unused) = inspect(mesh);
    if let Some((count, first)) = unused {
        findings.warnings.insert(
            0,
            format!(
                "{count} {} not used by any face (first: {first}); validation drops {}",
                if count == 1 {
                    "vertex is"
                } else {
                    "vertices are"
                },
                if count == 1 { "it" } else { "them" },
            ),
        );
    }
    findings
}

/// Validates `mesh` for mapping: returns [`Error::InvalidMesh`] with the first problem found
/// (see [`check`]), or the mesh without its unused vertices, plus warnings.
///
/// Dropping unused vertices keeps the order of the remaining ones and renumbers the faces.
pub fn validate(mesh: TriMesh) -> Result<(TriMesh, Vec<String>)> {
    let (findings, unused) = inspect(&mesh);
    if let Some(first) = findings.errors.into_iter().next() {
        return Err(Error::InvalidMesh(first));
    }
    let mut warnings = findings.warnings;
    let Some((count, first)) = unused else {
        return Ok((mesh, warnings));
    };
    warnings.insert(
        0,
        format!(
            "dropped {count} unreferenced {} (first: {first}); output vertex indices refer to \
             the remaining vertices",
            if count == 1 { "vertex" } else { "vertices" }
        ),
    );
    Ok((drop_unused_vertices(mesh.positions, mesh.faces), warnings))
}

/// The mesh of `faces` on the vertices they use, in their order in `positions`, the faces
/// renumbered to match (every index of `faces` below `positions.len()`).
pub(crate) fn drop_unused_vertices(positions: Vec<[f64; 3]>, faces: Vec<[u32; 3]>) -> TriMesh {
    let mut used = vec![false; positions.len()];
    for &v in faces.iter().flatten() {
        used[v as usize] = true;
    }
    let mut new_index = vec![u32::MAX; positions.len()];
    let mut kept = Vec::new();
    for (v, p) in positions.into_iter().enumerate() {
        if used[v] {
            new_index[v] = kept.len() as u32;
            kept.push(p);
        }
    }
    let faces = faces
        .into_iter()
        .map(|f| f.map(|v| new_index[v as usize]))
        .collect();
    TriMesh::new(kept, faces)
}

/// Collects up to [`MAX_PER_KIND`] messages of one kind, counting the rest.
struct Kind<'a> {
    out: &'a mut Vec<String>,
    total: usize,
}

impl<'a> Kind<'a> {
    fn new(out: &'a mut Vec<String>) -> Self {
        Self { out, total: 0 }
    }

    fn add(&mut self, msg: impl FnOnce() -> String) {
        if self.total < MAX_PER_KIND {
            self.out.push(msg());
        }
        self.total += 1;
    }

    /// Closes the kind with "... and N more {what}" if messages were left out; returns the
    /// total count.
    fn finish(self, what: &str) -> usize {
        if self.total > MAX_PER_KIND {
            self.out
                .push(format!("... and {} more {what}", self.total - MAX_PER_KIND));
        }
        self.total
    }
}

/// All checks; the unused vertices are returned as (count, first index) for the caller to word.
fn inspect(mesh: &TriMesh) -> (Findings, Option<(usize, usize)>) {
    let mut findings = Findings::default();
    let errors = &mut findings.errors;
    let (positions, faces) = (&mesh.positions, &mesh.faces);
    let n = positions.len();
    if faces.is_empty() {
        errors.push("the mesh has no faces".to_string());
        return (findings, None);
    }

    let mut kind = Kind::new(errors);
    for (v, p) in positions.iter().enumerate() {
        if !p.iter().all(|x| x.is_finite()) {
            kind.add(|| format!("vertex {v} has a non-finite coordinate"));
        }
    }
    let non_finite = kind.finish("vertices with a non-finite coordinate");

    let mut out_of_range = Kind::new(errors);
    for (fi, f) in faces.iter().enumerate() {
        if let Some(&v) = f.iter().find(|&&v| v as usize >= n) {
            out_of_range.add(|| {
                format!(
                    "face {fi} uses vertex {v}, which is out of range (the mesh has {n} vertices)"
                )
            });
        }
    }
    if out_of_range.finish("faces with a vertex index out of range") > 0 {
        return (findings, None);
    }

    let mut repeated = Kind::new(errors);
    for (fi, f) in faces.iter().enumerate() {
        if f[0] == f[1] || f[1] == f[2] || f[2] == f[0] {
            let [a, b, c] = *f;
            repeated.add(|| format!("face {fi} repeats a vertex (its vertices are {a}, {b}, {c})"));
        }
    }
    repeated.finish("faces with a repeated vertex");

    let mut used = vec![false; n];
    for &v in faces.iter().flatten() {
        used[v as usize] = true;
    }
    let unused_count = used.iter().filter(|&&u| !u).count();
    let unused =
        (unused_count > 0).then(|| (unused_count, used.iter().position(|&u| !u).unwrap_or(0)));

    // Faces without a repeated vertex, and their ids in `faces`.
    let (proper_ids, proper): (Vec<u32>, Vec<[u32; 3]>) = faces
        .iter()
        .enumerate()
        .filter(|(_, f)| f[0] != f[1] && f[1] != f[2] && f[2] != f[0])
        .map(|(fi, f)| (fi as u32, *f))
        .unzip();

    if non_finite == 0 {
        check_areas(positions, &used, &proper, &proper_ids, errors);
    }

    // Duplicate faces (same vertex set, any order or orientation).
    let mut sorted: Vec<([u32; 3], u32)> = proper
        .iter()
        .zip(&proper_ids)
        .map(|(f, &fi)| {
            let mut s = *f;
            s.sort_unstable();
            (s, fi)
        })
        .collect();
    sorted.sort_unstable();
    let mut duplicates = Kind::new(errors);
    for w in sorted.windows(2) {
        if w[0].0 == w[1].0 {
            let ([a, b, c], f0, f1) = (w[0].0, w[0].1, w[1].1);
            duplicates.add(|| {
                format!(
                    "faces {f0} and {f1} are duplicates (both have vertices {a}, {b}, {c}): the \
                     mesh is not manifold"
                )
            });
        }
    }
    duplicates.finish("duplicate faces");
    let same_vertices = |f0: u32, f1: u32| {
        let mut a = faces[f0 as usize];
        let mut b = faces[f1 as usize];
        a.sort_unstable();
        b.sort_unstable();
        a == b
    };

    // Edges: more than two faces, or two faces traversing the edge in the same direction.
    let groups = EdgeGroups::new(n, &proper);
    let mut non_manifold = Kind::new(errors);
    let mut flipped: Vec<(u32, u32, u32, u32)> = Vec::new();
    groups.for_each_edge(|lo, hi, hes| {
        if hes.len() > 2 {
            non_manifold.add(|| {
                format!(
                    "edge ({lo}, {hi}) is shared by {} faces: the mesh is not manifold",
                    hes.len()
                )
            });
        } else if hes.len() == 2 {
            let (a0, _) = half_edge(&proper, hes[0]);
            let (a1, _) = half_edge(&proper, hes[1]);
            let f0 = proper_ids[(hes[0] / 3) as usize];
            let f1 = proper_ids[(hes[1] / 3) as usize];
            if a0 == a1 && !same_vertices(f0, f1) {
                flipped.push((f0.min(f1), f0.max(f1), lo, hi));
            }
        }
    });
    non_manifold.finish("edges shared by more than two faces");

    check_fans(n, &proper, errors);

    flipped.sort_unstable();
    let mut orientation = Kind::new(errors);
    for &(f0, f1, lo, hi) in &flipped {
        orientation.add(|| {
            format!("faces {f0} and {f1} have inconsistent orientation across edge ({lo}, {hi})")
        });
    }
    orientation.finish("edges with inconsistent orientation");

    let (components, _) = connected_components(n, faces);
    if components > 1 {
        errors.push(format!(
            "the mesh has {components} connected components; demkit maps one connected surface \
             at a time"
        ));
    }
    (findings, unused)
}

/// Zero-area faces: area <= ZERO_AREA_RATIO · (bounding-box diagonal of the used vertices)².
fn check_areas(
    positions: &[[f64; 3]],
    used: &[bool],
    proper: &[[u32; 3]],
    proper_ids: &[u32],
    errors: &mut Vec<String>,
) {
    // The test is relative to the size of the mesh: compute it at unit size, where areas
    // neither overflow nor vanish (an exact rescaling).
    let k = super::scale::normalizing_exponent(positions);
    let scaled;
    let positions = if k == 0 {
        positions
    } else {
        scaled = {
            let mut p = positions.to_vec();
            super::scale::scale_positions(&mut p, k);
            p
        };
        &scaled[..]
    };
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for (p, _) in positions.iter().zip(used).filter(|(_, u)| **u) {
        for k in 0..3 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    let diag2: f64 = (0..3).map(|k| (hi[k] - lo[k]).powi(2)).sum();
    let threshold = ZERO_AREA_RATIO * diag2;
    let mut kind = Kind::new(errors);
    for (f, &fi) in proper.iter().zip(proper_ids) {
        let [a, b, c] = f.map(|v| positions[v as usize]);
        let u = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
        let w = [c[0] - a[0], c[1] - a[1], c[2] - a[2]];
        let cross = [
            u[1] * w[2] - u[2] * w[1],
            u[2] * w[0] - u[0] * w[2],
            u[0] * w[1] - u[1] * w[0],
        ];
        let area = 0.5 * (cross[0] * cross[0] + cross[1] * cross[1] + cross[2] * cross[2]).sqrt();
        if area <= threshold {
            let [x, y, z] = *f;
            kind.add(|| {
                format!(
                    "face {fi} has zero area (its vertices {x}, {y}, {z} are collinear or coincide)"
                )
            });
        }
    }
    kind.finish("faces with zero area");
}

/// Non-manifold vertices: the faces around a vertex, joined when they share an edge at the
/// vertex, must form a single fan.
fn check_fans(n: usize, faces: &[[u32; 3]], errors: &mut Vec<String>) {
    let (offsets, ids) = vertex_faces(n, faces);
    let mut kind = Kind::new(errors);
    let mut spokes: Vec<(u32, u32)> = Vec::new(); // (other vertex, local face index)
    let mut sets = super::union_find::UnionFind::default();
    for v in 0..n {
        let around = &ids[offsets[v]..offsets[v + 1]];
        if around.len() < 2 {
            continue;
        }
        spokes.clear();
        for (local, &fi) in around.iter().enumerate() {
            for &u in &faces[fi as usize] {
                if u as usize != v {
                    spokes.push((u, local as u32));
                }
            }
        }
        spokes.sort_unstable();
        sets.reset(around.len());
        let mut fans = around.len();
        for w in spokes.windows(2) {
            if w[0].0 == w[1].0 && sets.union(w[0].1, w[1].1) {
                fans -= 1;
            }
        }
        if fans > 1 {
            kind.add(|| format!("vertex {v} is not manifold (its faces form {fans} fans)"));
        }
    }
    kind.finish("non-manifold vertices");
}

#[cfg(test)]
mod tests {
    use super::*;

    use crate::generate_fixtures::unit_square as square;

    fn tetrahedron() -> TriMesh {
        TriMesh::new(
            vec![[0., 0., 0.], [1., 0., 0.], [0., 1., 0.], [0., 0., 1.]],
            vec![[0, 2, 1], [0, 1, 3], [1, 2, 3], [0, 3, 2]],
        )
    }

    fn first_error(m: TriMesh) -> String {
        match validate(m) {
            Err(Error::InvalidMesh(msg)) => msg,
            other => panic!("expected InvalidMesh, got {other:?}"),
        }
    }

    #[test]
    fn valid_meshes_pass_unchanged() {
        for m in [square(), tetrahedron()] {
            assert!(check(&m).is_valid());
            let (out, warnings) = validate(m.clone()).unwrap();
            assert_eq!(out, m);
            assert!(warnings.is_empty());
        }
    }

    #[test]
    fn empty_mesh() {
        assert_eq!(first_error(TriMesh::default()), "the mesh has no faces");
        let m = TriMesh::new(vec![[0.; 3]; 3], vec![]);
        assert_eq!(first_error(m), "the mesh has no faces");
    }

    #[test]
    fn non_finite_coordinate() {
        let mut m = square();
        m.positions[2][1] = f64::NAN;
        m.positions[3][0] = f64::INFINITY;
        assert_eq!(
            first_error(m.clone()),
            "vertex 2 has a non-finite coordinate"
        );
        let f = check(&m);
        assert_eq!(f.errors.len(), 2);
        assert_eq!(f.errors[1], "vertex 3 has a non-finite coordinate");
    }

    #[test]
    fn index_out_of_range() {
        let mut m = square();
        m.faces[1] = [0, 2, 9];
        assert_eq!(
            first_error(m),
            "face 1 uses vertex 9, which is out of range (the mesh has 4 vertices)"
        );
    }

    #[test]
    fn repeated_vertex() {
        let mut m = square();
        m.faces[1] = [0, 2, 2];
        assert_eq!(
            first_error(m),
            "face 1 repeats a vertex (its vertices are 0, 2, 2)"
        );
    }

    #[test]
    fn zero_area_face() {
        // Vertex 3 on the diagonal 0–2: face 1 is flat.
        let mut m = square();
        m.positions[3] = [0.5, 0.5, 0.0];
        let msg = first_error(m);
        assert!(msg.starts_with("face 1 has zero area"), "{msg}");
        // Exactly coincident vertices in a mesh of zero extent.
        let m = TriMesh::new(vec![[1.0; 3]; 3], vec![[0, 1, 2]]);
        assert!(first_error(m).starts_with("face 0 has zero area"));
        // A tiny but proper triangle in a small mesh is fine.
        let mut m = square();
        for p in &mut m.positions {
            *p = p.map(|x| x * 1e-9);
        }
        assert!(validate(m).is_ok());
    }

    #[test]
    fn non_manifold_edge() {
        let m = TriMesh::new(
            vec![
                [0., 0., 0.],
                [1., 0., 0.],
                [0., 1., 0.],
                [0., -1., 0.],
                [0., 0., 1.],
            ],
            vec![[0, 1, 2], [1, 0, 3], [0, 1, 4]],
        );
        let msg = first_error(m);
        assert_eq!(
            msg,
            "edge (0, 1) is shared by 3 faces: the mesh is not manifold"
        );
        assert!(msg.contains("manifold"));
    }

    #[test]
    fn duplicate_faces_are_not_manifold() {
        for dup in [[0, 1, 2], [0, 2, 1], [1, 2, 0]] {
            let mut m = square();
            m.faces.push(dup);
            let msg = first_error(m);
            assert!(msg.contains("faces 0 and 2 are duplicates"), "{msg}");
            assert!(msg.contains("manifold"), "{msg}");
        }
    }

    #[test]
    fn non_manifold_vertex() {
        // Two triangles touching at vertex 2 only (a bow tie).
        let m = TriMesh::new(
            vec![
                [0., 0., 0.],
                [1., 0., 0.],
                [0.5, 1., 0.],
                [0., 2., 0.],
                [1., 2., 0.],
            ],
            vec![[0, 1, 2], [2, 4, 3]],
        );
        assert_eq!(
            first_error(m),
            "vertex 2 is not manifold (its faces form 2 fans)"
        );
    }

    #[test]
    fn two_closed_fans_at_a_vertex() {
        // Two tetrahedra sharing vertex 0: every edge has two faces but vertex 0 has two fans.
        let mut m = tetrahedron();
        m.positions
            .extend([[-1., 0., 0.], [0., -1., 0.], [0., 0., -1.]]);
        m.faces.extend([[0, 5, 4], [0, 4, 6], [4, 5, 6], [0, 6, 5]]);
        assert_eq!(
            first_error(m),
            "vertex 0 is not manifold (its faces form 2 fans)"
        );
    }

    #[test]
    fn inconsistent_orientation() {
        let mut m = square();
        m.faces[1] = [0, 3, 2];
        assert_eq!(
            first_error(m),
            "faces 0 and 1 have inconsistent orientation across edge (0, 2)"
        );
    }

    #[test]
    fn several_components() {
        let mut m = square();
        m.positions
            .extend([[5., 0., 0.], [6., 0., 0.], [5., 1., 0.]]);
        m.faces.push([4, 5, 6]);
        m.positions
            .extend([[8., 0., 0.], [9., 0., 0.], [8., 1., 0.]]);
        m.faces.push([7, 8, 9]);
        assert_eq!(
            first_error(m),
            "the mesh has 3 connected components; demkit maps one connected surface at a time"
        );
    }

    #[test]
    fn unreferenced_vertices_are_dropped() {
        let m = TriMesh::new(
            vec![
                [9., 9., 9.],
                [0., 0., 0.],
                [1., 0., 0.],
                [7., 7., 7.],
                [1., 1., 0.],
                [0., 1., 0.],
                [8., 8., 8.],
            ],
            vec![[1, 2, 4], [1, 4, 5]],
        );
        let f = check(&m);
        assert!(f.is_valid());
        assert_eq!(
            f.warnings,
            vec!["3 vertices are not used by any face (first: 0); validation drops them"]
        );
        let (out, warnings) = validate(m).unwrap();
        assert_eq!(out, square());
        assert_eq!(
            warnings,
            vec![
                "dropped 3 unreferenced vertices (first: 0); output vertex indices refer to the \
                 remaining vertices"
            ]
        );
    }

    #[test]
    fn check_lists_everything_and_caps_each_kind() {
        // 25 disjoint triangles with one flipped pair: components + nothing else.
        let mut m = TriMesh::default();
        for k in 0..25u32 {
            let x = k as f64 * 3.0;
            m.positions
                .extend([[x, 0., f64::NAN], [x + 1., 0., 0.], [x, 1., 0.]]);
            m.faces.push([3 * k, 3 * k + 1, 3 * k + 2]);
        }
        let f = check(&m);
        assert_eq!(f.errors.len(), MAX_PER_KIND + 2);
        assert_eq!(f.errors[0], "vertex 0 has a non-finite coordinate");
        assert_eq!(
            f.errors[MAX_PER_KIND],
            "... and 15 more vertices with a non-finite coordinate"
        );
        assert!(f.errors[MAX_PER_KIND + 1].starts_with("the mesh has 25 connected components"));
    }
}
