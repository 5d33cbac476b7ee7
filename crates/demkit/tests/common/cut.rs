//! Surfaces with holes made for the DEQ tests: holes cut into a mesh around chosen points, with
//! the jagged, ear-ridden loops real cut-outs have.

use demkit::TriMesh;
use demkit::mesh::Hole;
use std::collections::HashMap;

/// `mesh` with every face removed whose centroid lies within `r` of a hole's centre `c`
/// (distance in the plane z = 0 when `planar`), made a manifold surface again
/// ([`demkit::mesh::cut_holes`]), its vertices numbered in the order the faces first use them
/// (the numbering the tests' placements were chosen with: the coarse copy of a large surface
/// depends on it).
pub fn cut_holes(mesh: &TriMesh, holes: &[([f64; 3], f64)], planar: bool) -> TriMesh {
    let holes: Vec<Hole> = holes
        .iter()
        .map(|&(centre, radius)| Hole { centre, radius })
        .collect();
    let cut = demkit::mesh::cut_holes(mesh, &holes, planar).expect("the holes leave a surface");
    let mut index = vec![u32::MAX; cut.n_vertices()];
    let mut positions = Vec::with_capacity(cut.n_vertices());
    let faces = cut
        .faces
        .iter()
        .map(|f| {
            f.map(|v| {
                if index[v as usize] == u32::MAX {
                    index[v as usize] = positions.len() as u32;
                    positions.push(cut.positions[v as usize]);
                }
                index[v as usize]
            })
        })
        .collect();
    TriMesh::new(positions, faces)
}

/// `k` hole centres on `mesh`, drawn from its face centroids by a fixed `seed`, each at least
/// `2.5 r` from the boundary and `3.5 r` from the others, with `r` the given share of the
/// bounding box's diagonal.
pub fn random_holes(mesh: &TriMesh, k: usize, seed: u64, share: f64) -> Vec<([f64; 3], f64)> {
    let (lo, hi) = mesh.positions.iter().fold(
        ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]),
        |(lo, hi), p| {
            (
                [0, 1, 2].map(|i| lo[i].min(p[i])),
                [0, 1, 2].map(|i| hi[i].max(p[i])),
            )
        },
    );
    let r = share * (0..3).map(|i| (hi[i] - lo[i]).powi(2)).sum::<f64>().sqrt();
    let boundary: Vec<[f64; 3]> = boundary_edges(&mesh.faces)
        .into_iter()
        .map(|(a, _)| mesh.positions[a as usize])
        .collect();
    let d = |a: [f64; 3], b: [f64; 3]| (0..3).map(|i| (a[i] - b[i]).powi(2)).sum::<f64>().sqrt();
    let mut state = seed
        .wrapping_mul(6364136223846793005)
        .wrapping_add(1442695040888963407);
    let mut holes: Vec<([f64; 3], f64)> = Vec::new();
    for _ in 0..100_000 {
        if holes.len() == k {
            break;
        }
        state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        let f = mesh.faces[(state >> 33) as usize % mesh.faces.len()];
        let p = f.map(|v| mesh.positions[v as usize]);
        let c = [0, 1, 2].map(|i| (p[0][i] + p[1][i] + p[2][i]) / 3.0);
        if boundary.iter().all(|&b| d(b, c) > 2.5 * r) && holes.iter().all(|h| d(h.0, c) > 3.5 * r)
        {
            holes.push((c, r));
        }
    }
    assert_eq!(holes.len(), k, "room for only {} holes", holes.len());
    holes
}

/// The edges used by one face only.
fn boundary_edges(faces: &[[u32; 3]]) -> Vec<(u32, u32)> {
    let mut count: HashMap<(u32, u32), usize> = HashMap::new();
    for f in faces {
        for k in 0..3 {
            let (a, b) = (f[k], f[(k + 1) % 3]);
            *count.entry((a.min(b), a.max(b))).or_default() += 1;
        }
    }
    let mut edges: Vec<(u32, u32)> = count
        .into_iter()
        .filter(|&(_, c)| c == 1)
        .map(|(e, _)| e)
        .collect();
    edges.sort_unstable();
    edges
}
