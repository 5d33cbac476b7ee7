//! Mesh topology: unique edges, vertex–face incidence, boundary loops ordered along the face
//! orientation, Euler characteristic, connected components and genus.
//!
//! Everything here works by counting and sorting integer keys (no hash maps), so it runs in
//! (close to) linear time on meshes of a few million faces. The functions accept any mesh, even
//! an invalid one, without panicking (except where documented); the numbers they report are only
//! meaningful for meshes that pass [`fn@crate::mesh::validate`].

use super::TriMesh;

/// Topological summary of a triangle mesh.
///
/// Vertices that no face uses are not part of the surface: they are not counted in
/// `n_vertices`, in the Euler characteristic nor in the components.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Topology {
    /// Number of vertices used by at least one face.
    pub n_vertices: usize,
    /// Number of unique undirected edges.
    pub n_edges: usize,
    /// Number of faces.
    pub n_faces: usize,
    /// Boundary loops, longest first. Each loop follows the face orientation: for a boundary
    /// edge a→b of a face, b comes right after a (the outer loop of a counter-clockwise planar
    /// disk is counter-clockwise). A closed loop starts at its smallest vertex index and does not
    /// repeat its first vertex at the end.
    pub boundary_loops: Vec<Vec<u32>>,
    /// Euler characteristic χ = V − E + F.
    pub euler_characteristic: i64,
    /// Number of connected components (vertices joined by faces).
    pub components: usize,
    /// Genus g = (2·components − χ − #boundary loops) / 2, applied to the whole mesh (for a
    /// mesh with several components this is the sum of the components' genera).
    pub genus: i64,
}

impl Topology {
    /// True when the surface has no boundary.
    pub fn is_closed(&self) -> bool {
        self.boundary_loops.is_empty()
    }

    /// Number of boundary loops.
    pub fn n_boundaries(&self) -> usize {
        self.boundary_loops.len()
    }
}

/// Computes the topology of `mesh` (see [`Topology`]).
///
/// Faces with a repeated vertex contribute to `n_faces` but to no edge.
pub fn topology(mesh: &TriMesh) -> Topology {
    let faces = &mesh.faces;
    let n = vertex_bound(mesh.positions.len(), faces);
    let groups = EdgeGroups::new(n, faces);

    let mut n_edges = 0usize;
    let mut boundary: Vec<u32> = Vec::new();
    groups.for_each_edge(|_, _, hes| {
        n_edges += 1;
        if hes.len() == 1 {
            boundary.push(hes[0]);
        }
    });
    boundary.sort_unstable();

    let (components, labels) = connected_components(n, faces);
    let n_vertices = labels.iter().filter(|&&l| l != u32::MAX).count();
    let boundary_loops = trace_loops(n, faces, &boundary);

    let euler_characteristic = n_vertices as i64 - n_edges as i64 + faces.len() as i64;
    let genus =
        (2 * components as i64 - euler_characteristic - boundary_loops.len() as i64).div_euclid(2);
    Topology {
        n_vertices,
        n_edges,
        n_faces: faces.len(),
        boundary_loops,
        euler_characteristic,
        components,
        genus,
    }
}

/// Unique undirected edges of `faces`, each as `[min, max]`, sorted.
///
/// Faces with a repeated vertex are ignored.
pub fn edges(faces: &[[u32; 3]]) -> Vec<[u32; 2]> {
    let groups = EdgeGroups::new(vertex_bound(0, faces), faces);
    let mut out = Vec::with_capacity(faces.len() * 3 / 2 + 3);
    groups.for_each_edge(|lo, hi, _| out.push([lo, hi]));
    out
}

/// Vertex–face incidence in compressed form: the faces around vertex `v` are
/// `ids[offsets[v]..offsets[v + 1]]`, in increasing order (a face with a repeated vertex is
/// listed once per corner). `offsets` has `n_vertices + 1` entries.
///
/// # Panics
/// If a face uses a vertex index `>= n_vertices` (validated meshes never do).
pub fn vertex_faces(n_vertices: usize, faces: &[[u32; 3]]) -> (Vec<usize>, Vec<u32>) {
    vertex_faces_where(n_vertices, faces, |_, _| true)
}

/// [`vertex_faces`] keeping only the pairs (vertex, face) for which `keep(vertex, face)` is
/// true.
///
/// # Panics
/// If a face uses a vertex index `>= n_vertices` (validated meshes never do).
pub fn vertex_faces_where(
    n_vertices: usize,
    faces: &[[u32; 3]],
    keep: impl Fn(usize, usize) -> bool,
) -> (Vec<usize>, Vec<u32>) {
    vertex_corners(n_vertices, faces, |f, c| {
        keep(faces[f][c] as usize, f).then_some(f as u32)
    })
}

/// Vertex–corner incidence in compressed form, with an entry of the caller's choosing per
/// corner: `entry(f, c)` for corner `c` of face `f` is listed at vertex `faces[f][c]` (or
/// nowhere if it is `None`), the entries of vertex `v` being `out[offsets[v]..offsets[v + 1]]`
/// in increasing (face, corner) order. `entry` is called twice per corner (count, then fill)
/// and must answer the same both times. [`vertex_faces`] is this with the face index.
///
/// # Panics
/// If a face uses a vertex index `>= n_vertices` (validated meshes never do).
pub fn vertex_corners<T: Copy + Default>(
    n_vertices: usize,
    faces: &[[u32; 3]],
    entry: impl Fn(usize, usize) -> Option<T>,
) -> (Vec<usize>, Vec<T>) {
    let mut offsets = vec![0usize; n_vertices + 1];
    for (fi, f) in faces.iter().enumerate() {
        for (c, &v) in f.iter().enumerate() {
            if entry(fi, c).is_some() {
                offsets[v as usize + 1] += 1;
            }
        }
    }
    for i in 0..n_vertices {
        offsets[i + 1] += offsets[i];
    }
    let mut fill = offsets.clone();
    let mut out = vec![T::default(); offsets[n_vertices]];
    for (fi, f) in faces.iter().enumerate() {
        for (c, &v) in f.iter().enumerate() {
            if let Some(e) = entry(fi, c) {
                let slot = &mut fill[v as usize];
                out[*slot] = e;
                *slot += 1;
            }
        }
    }
    (offsets, out)
}

/// The vertices joined to each vertex by an edge of `faces` (each once).
///
/// # Panics
/// If a face uses a vertex index `>= n_vertices` (validated meshes never do).
pub fn vertex_neighbours(n_vertices: usize, faces: &[[u32; 3]]) -> Vec<Vec<u32>> {
    let mut out = vec![Vec::new(); n_vertices];
    for f in faces {
        for k in 0..3 {
            let (a, b) = (f[k], f[(k + 1) % 3]);
            if a != b && !out[a as usize].contains(&b) {
                out[a as usize].push(b);
                out[b as usize].push(a);
            }
        }
    }
    out
}

/// Every vertex's number of edges from the nearest of `seeds`, counted up to `rings`
/// (`usize::MAX` beyond, and for vertices not reached), over the adjacency `neighbours`
/// ([`vertex_neighbours`]).
pub fn ring_distances(
    neighbours: &[Vec<u32>],
    seeds: impl IntoIterator<Item = u32>,
    rings: usize,
) -> Vec<usize> {
    let mut distance = vec![usize::MAX; neighbours.len()];
    let mut queue = std::collections::VecDeque::new();
    for s in seeds {
        if distance[s as usize] != 0 {
            distance[s as usize] = 0;
            queue.push_back(s as usize);
        }
    }
    while let Some(u) = queue.pop_front() {
        if distance[u] >= rings {
            continue;
        }
        for &w in &neighbours[u] {
            if distance[w as usize] == usize::MAX {
                distance[w as usize] = distance[u] + 1;
                queue.push_back(w as usize);
            }
        }
    }
    distance
}

/// Connected components of the vertices joined by `faces`: returns the number of components and
/// a label per vertex (`0..count`, numbered in order of each component's smallest vertex;
/// `u32::MAX` for vertices no face uses).
///
/// Faces with an index `>= n_vertices` are ignored.
pub fn connected_components(n_vertices: usize, faces: &[[u32; 3]]) -> (usize, Vec<u32>) {
    let mut sets = super::union_find::UnionFind::new(n_vertices);
    let mut used = vec![false; n_vertices];
    for f in faces {
        if f.iter().any(|&v| v as usize >= n_vertices) {
            continue;
        }
        for &v in f {
            used[v as usize] = true;
        }
        // Each set is held by its smallest vertex: labels come out in vertex order.
        sets.union(f[0], f[1]);
        sets.union(f[1], f[2]);
    }
    let mut labels = vec![u32::MAX; n_vertices];
    let mut count = 0usize;
    for v in 0..n_vertices {
        if !used[v] {
            continue;
        }
        let r = sets.find(v as u32) as usize;
        if labels[r] == u32::MAX {
            labels[r] = count as u32;
            count += 1;
        }
        labels[v] = labels[r];
    }
    (count, labels)
}

/// One more than the largest vertex index used by `faces`, or `n_vertices` if larger.
pub(crate) fn vertex_bound(n_vertices: usize, faces: &[[u32; 3]]) -> usize {
    let max = faces.iter().flatten().copied().max();
    max.map_or(n_vertices, |m| n_vertices.max(m as usize + 1))
}

/// Tail and head of half-edge `h = 3 * face + corner` (from corner to the next corner).
#[inline]
pub(crate) fn half_edge(faces: &[[u32; 3]], h: u32) -> (u32, u32) {
    let f = &faces[(h / 3) as usize];
    let c = (h % 3) as usize;
    (f[c], f[(c + 1) % 3])
}

/// Half-edges grouped by undirected edge, built by a counting sort on the smaller endpoint
/// followed by a sort of each (small) bucket on the larger endpoint. Faces with a repeated vertex
/// are left out.
pub(crate) struct EdgeGroups {
    offsets: Vec<usize>,
    /// (larger endpoint, half-edge id) sorted within each bucket.
    entries: Vec<(u32, u32)>,
}

impl EdgeGroups {
    /// Groups the half-edges of `faces`; every index must be `< n_vertices`.
    pub(crate) fn new(n_vertices: usize, faces: &[[u32; 3]]) -> Self {
        let proper = |f: &[u32; 3]| f[0] != f[1] && f[1] != f[2] && f[2] != f[0];
        let mut offsets = vec![0usize; n_vertices + 1];
        for f in faces.iter().filter(|f| proper(f)) {
            for c in 0..3 {
                let lo = f[c].min(f[(c + 1) % 3]);
                offsets[lo as usize + 1] += 1;
            }
        }
        for i in 0..n_vertices {
            offsets[i + 1] += offsets[i];
        }
        let mut fill = offsets.clone();
        let mut entries = vec![(0u32, 0u32); offsets[n_vertices]];
        for (fi, f) in faces.iter().enumerate() {
            if !proper(f) {
                continue;
            }
            for c in 0..3 {
                let (a, b) = (f[c], f[(c + 1) % 3]);
                let slot = &mut fill[a.min(b) as usize];
                entries[*slot] = (a.max(b), (3 * fi + c) as u32);
                *slot += 1;
            }
        }
        for v in 0..n_vertices {
            entries[offsets[v]..offsets[v + 1]].sort_unstable();
        }
        Self { offsets, entries }
    }

    /// Calls `f(lo, hi, half_edges)` for every undirected edge, in increasing `(lo, hi)` order;
    /// `half_edges` lists the edge's half-edge ids in increasing order.
    pub(crate) fn for_each_edge(&self, mut f: impl FnMut(u32, u32, &[u32])) {
        let mut hes: Vec<u32> = Vec::with_capacity(4);
        for lo in 0..self.offsets.len() - 1 {
            let bucket = &self.entries[self.offsets[lo]..self.offsets[lo + 1]];
            let mut i = 0;
            while i < bucket.len() {
                let hi = bucket[i].0;
                hes.clear();
                while i < bucket.len() && bucket[i].0 == hi {
                    hes.push(bucket[i].1);
                    i += 1;
                }
                f(lo as u32, hi, &hes);
            }
        }
    }
}

/// Chains the boundary half-edges (sorted ids) into loops following the face orientation.
fn trace_loops(n: usize, faces: &[[u32; 3]], boundary: &[u32]) -> Vec<Vec<u32>> {
    // Outgoing boundary half-edges of every vertex (indices into `boundary`).
    let mut offsets = vec![0usize; n + 1];
    for &h in boundary {
        offsets[half_edge(faces, h).0 as usize + 1] += 1;
    }
    for i in 0..n {
        offsets[i + 1] += offsets[i];
    }
    let mut fill = offsets.clone();
    let mut out = vec![0usize; boundary.len()];
    for (k, &h) in boundary.iter().enumerate() {
        let slot = &mut fill[half_edge(faces, h).0 as usize];
        out[*slot] = k;
        *slot += 1;
    }
    let mut done = vec![false; boundary.len()];
    let mut loops: Vec<Vec<u32>> = Vec::new();
    for start in 0..boundary.len() {
        if done[start] {
            continue;
        }
        let start_vertex = half_edge(faces, boundary[start]).0;
        let mut chain = Vec::new();
        let mut k = start;
        let closed = loop {
            done[k] = true;
            let (a, b) = half_edge(faces, boundary[k]);
            chain.push(a);
            if b == start_vertex {
                break true;
            }
            let next = out[offsets[b as usize]..offsets[b as usize + 1]]
                .iter()
                .copied()
                .find(|&j| !done[j]);
            match next {
                Some(j) => k = j,
                None => {
                    // An open chain (only on broken meshes): keep its last vertex too.
                    chain.push(b);
                    break false;
                }
            }
        };
        if closed {
            let first = (0..chain.len()).min_by_key(|&i| chain[i]).unwrap_or(0);
            chain.rotate_left(first);
        }
        loops.push(chain);
    }
    loops.sort_by(|a, b| b.len().cmp(&a.len()).then_with(|| a.cmp(b)));
    loops
}

#[cfg(test)]
mod tests {
    use super::*;

    fn mesh(positions: Vec<[f64; 3]>, faces: Vec<[u32; 3]>) -> TriMesh {
        TriMesh::new(positions, faces)
    }

    use crate::generate_fixtures::unit_square as square;

    fn tetrahedron() -> TriMesh {
        mesh(
            vec![[0., 0., 0.], [1., 0., 0.], [0., 1., 0.], [0., 0., 1.]],
            vec![[0, 2, 1], [0, 1, 3], [1, 2, 3], [0, 3, 2]],
        )
    }

    #[test]
    fn neighbours_and_ring_distances_of_a_strip() {
        // A strip of four triangles: 0-1-2-3 along the bottom, 4-5-6 along the top.
        let faces = vec![[0, 1, 4], [1, 5, 4], [1, 2, 5], [2, 6, 5], [2, 3, 6]];
        let nb = vertex_neighbours(7, &faces);
        let mut n1 = nb[1].clone();
        n1.sort();
        assert_eq!(n1, vec![0, 2, 4, 5]);
        assert_eq!(nb[3].len(), 2);
        let d = ring_distances(&nb, [0], 2);
        assert_eq!(d[0], 0);
        assert_eq!((d[1], d[4]), (1, 1));
        assert_eq!((d[2], d[5]), (2, 2));
        // Beyond two rings: not reached.
        assert_eq!((d[3], d[6]), (usize::MAX, usize::MAX));
    }

    /// Square annulus: outer square 0..4 (counter-clockwise), inner square 4..8.
    fn annulus() -> TriMesh {
        let positions = vec![
            [-2., -2., 0.],
            [2., -2., 0.],
            [2., 2., 0.],
            [-2., 2., 0.],
            [-1., -1., 0.],
            [1., -1., 0.],
            [1., 1., 0.],
            [-1., 1., 0.],
        ];
        let mut faces = Vec::new();
        for i in 0..4u32 {
            let j = (i + 1) % 4;
            faces.push([i, j, 4 + j]);
            faces.push([i, 4 + j, 4 + i]);
        }
        mesh(positions, faces)
    }

    /// Torus as an n×m periodic grid.
    fn grid_torus(n: u32, m: u32) -> TriMesh {
        let id = |i: u32, j: u32| (i % n) * m + (j % m);
        let mut faces = Vec::new();
        for i in 0..n {
            for j in 0..m {
                faces.push([id(i, j), id(i + 1, j), id(i + 1, j + 1)]);
                faces.push([id(i, j), id(i + 1, j + 1), id(i, j + 1)]);
            }
        }
        mesh(vec![[0.; 3]; (n * m) as usize], faces)
    }

    /// Signed area of a planar polygon given by vertex indices.
    fn signed_area(m: &TriMesh, lp: &[u32]) -> f64 {
        let mut s = 0.0;
        for i in 0..lp.len() {
            let p = m.positions[lp[i] as usize];
            let q = m.positions[lp[(i + 1) % lp.len()] as usize];
            s += p[0] * q[1] - q[0] * p[1];
        }
        s / 2.0
    }

    #[test]
    fn square_is_a_disk() {
        let m = square();
        let t = topology(&m);
        assert_eq!((t.n_vertices, t.n_edges, t.n_faces), (4, 5, 2));
        assert_eq!(t.euler_characteristic, 1);
        assert_eq!(t.components, 1);
        assert_eq!(t.genus, 0);
        assert_eq!(t.boundary_loops, vec![vec![0, 1, 2, 3]]);
        assert!(
            signed_area(&m, &t.boundary_loops[0]) > 0.0,
            "outer loop is counter-clockwise"
        );
        assert!(!t.is_closed());
        assert_eq!(t.n_boundaries(), 1);
    }

    #[test]
    fn reversed_square_has_reversed_loop() {
        let mut m = square();
        for f in &mut m.faces {
            f.swap(1, 2);
        }
        let t = topology(&m);
        assert_eq!(t.boundary_loops, vec![vec![0, 3, 2, 1]]);
        assert!(signed_area(&m, &t.boundary_loops[0]) < 0.0);
    }

    #[test]
    fn tetrahedron_is_a_sphere() {
        let t = topology(&tetrahedron());
        assert_eq!((t.n_vertices, t.n_edges, t.n_faces), (4, 6, 4));
        assert_eq!(t.euler_characteristic, 2);
        assert!(t.boundary_loops.is_empty());
        assert!(t.is_closed());
        assert_eq!(t.components, 1);
        assert_eq!(t.genus, 0);
    }

    #[test]
    fn annulus_has_two_loops() {
        let m = annulus();
        let t = topology(&m);
        assert_eq!((t.n_vertices, t.n_edges, t.n_faces), (8, 16, 8));
        assert_eq!(t.euler_characteristic, 0);
        assert_eq!(t.genus, 0);
        assert_eq!(t.boundary_loops.len(), 2);
        assert_eq!(t.boundary_loops[0], vec![0, 1, 2, 3]);
        // The hole is traversed clockwise (the surface lies to its left).
        assert_eq!(t.boundary_loops[1], vec![4, 7, 6, 5]);
        assert!(signed_area(&m, &t.boundary_loops[1]) < 0.0);
    }

    #[test]
    fn loops_are_sorted_longest_first() {
        // A square (loop of 4) followed by a separate hexagonal fan (loop of 6).
        let mut positions = square().positions;
        let mut faces = square().faces;
        positions.push([5., 5., 0.]);
        for k in 0..6 {
            let a = k as f64 * std::f64::consts::PI / 3.0;
            positions.push([5. + a.cos(), 5. + a.sin(), 0.]);
        }
        for k in 0..6u32 {
            faces.push([4, 5 + k, 5 + (k + 1) % 6]);
        }
        let t = topology(&mesh(positions, faces));
        assert_eq!(t.boundary_loops.len(), 2);
        assert_eq!(t.boundary_loops[0], vec![5, 6, 7, 8, 9, 10]);
        assert_eq!(t.boundary_loops[1], vec![0, 1, 2, 3]);
        assert_eq!(t.components, 2);
        assert_eq!(t.euler_characteristic, 2);
        assert_eq!(t.genus, 0);
    }

    #[test]
    fn torus_has_genus_one() {
        let t = topology(&grid_torus(4, 5));
        assert_eq!(t.n_vertices, 20);
        assert_eq!(t.n_faces, 40);
        assert_eq!(t.n_edges, 60);
        assert_eq!(t.euler_characteristic, 0);
        assert_eq!(t.genus, 1);
        assert!(t.is_closed());
    }

    #[test]
    fn unreferenced_vertices_are_ignored() {
        let mut m = tetrahedron();
        m.positions.push([9., 9., 9.]);
        let t = topology(&m);
        assert_eq!(t.n_vertices, 4);
        assert_eq!(t.euler_characteristic, 2);
        assert_eq!(t.components, 1);
    }

    #[test]
    fn empty_mesh() {
        let t = topology(&TriMesh::default());
        assert_eq!(t.n_vertices + t.n_edges + t.n_faces + t.components, 0);
        assert_eq!(t.genus, 0);
    }

    #[test]
    fn out_of_range_faces_do_not_panic() {
        let m = mesh(vec![[0.; 3]; 2], vec![[0, 1, 7]]);
        let t = topology(&m);
        assert_eq!(t.n_edges, 3);
    }

    #[test]
    fn edges_are_unique_sorted() {
        assert_eq!(
            edges(&square().faces),
            vec![[0, 1], [0, 2], [0, 3], [1, 2], [2, 3]]
        );
        assert_eq!(edges(&tetrahedron().faces).len(), 6);
        assert_eq!(edges(&[[0, 0, 1]]), Vec::<[u32; 2]>::new());
        assert!(edges(&[]).is_empty());
    }

    #[test]
    fn vertex_faces_is_csr() {
        let (offsets, ids) = vertex_faces(5, &square().faces);
        assert_eq!(offsets, vec![0, 2, 3, 5, 6, 6]);
        assert_eq!(ids, vec![0, 1, 0, 0, 1, 1]);
    }

    #[test]
    fn components_are_labelled_in_vertex_order() {
        let faces = [[3, 4, 5], [0, 1, 2], [2, 6, 7]];
        let (n, labels) = connected_components(9, &faces);
        assert_eq!(n, 2);
        assert_eq!(labels, vec![0, 0, 0, 1, 1, 1, 0, 0, u32::MAX]);
    }

    #[test]
    #[ignore = "needs real meshes (DEMKIT_DATA)"]
    fn real_meshes_have_the_expected_topology() {
        let dir = crate::io::test_util::data_dir();
        let load = |rel: &str| {
            let mesh = crate::io::read_mesh(&dir.join(rel)).unwrap();
            crate::mesh::validate(mesh).map(|(m, _)| topology(&m))
        };
        let face = load("open/human_face.obj").unwrap();
        assert_eq!((face.boundary_loops.len(), face.genus), (1, 0));
        assert_eq!(load("genus0/brain.obj").unwrap().euler_characteristic, 2);

        let mut problems = Vec::new();
        for folder in ["open", "genus0", "genus1", "multiply-connected"] {
            let mut names: Vec<_> = std::fs::read_dir(dir.join(folder))
                .unwrap()
                .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
                .filter(|n| n.ends_with(".obj"))
                .collect();
            names.sort();
            for name in names {
                let rel = format!("{folder}/{name}");
                let t = match load(&rel) {
                    Ok(t) => t,
                    Err(e) => {
                        problems.push(format!("{rel}: {e}"));
                        continue;
                    }
                };
                let loops = t.boundary_loops.len();
                let ok = match folder {
                    "open" => loops == 1 && t.genus == 0,
                    "genus0" => loops == 0 && t.euler_characteristic == 2,
                    "genus1" => loops == 0 && t.genus == 1,
                    _ => loops >= 2 && t.genus == 0,
                };
                eprintln!(
                    "{rel}: V={} F={} loops={loops} chi={} genus={}",
                    t.n_vertices, t.n_faces, t.euler_characteristic, t.genus
                );
                if !ok {
                    problems.push(format!("{rel}: unexpected topology {t:?}"));
                }
            }
        }
        assert!(problems.is_empty(), "{problems:#?}");
    }

    #[test]
    fn large_grid_is_fast_and_correct() {
        // 300×300 grid disk: V = 90601, F = 180000, E = V + F − 1.
        let n = 300u32;
        let id = |i: u32, j: u32| i * (n + 1) + j;
        let mut faces = Vec::new();
        for i in 0..n {
            for j in 0..n {
                faces.push([id(i, j), id(i + 1, j), id(i + 1, j + 1)]);
                faces.push([id(i, j), id(i + 1, j + 1), id(i, j + 1)]);
            }
        }
        let m = mesh(vec![[0.; 3]; ((n + 1) * (n + 1)) as usize], faces);
        let t = topology(&m);
        assert_eq!(t.euler_characteristic, 1);
        assert_eq!(t.boundary_loops.len(), 1);
        assert_eq!(t.boundary_loops[0].len(), 4 * n as usize);
        assert_eq!(t.genus, 0);
    }
}
