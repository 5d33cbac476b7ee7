//! Holes cut into a surface around chosen points: the surfaces with holes that DEQ and the
//! circle-domain map take, made from a disk or a closed scan (the DEQ paper's face with its
//! eyes cut out, Fig. 9).

use super::topology::EdgeGroups;
use crate::{Error, Result, TriMesh};

/// A ball (or, with [`cut_holes`]'s `planar`, a vertical cylinder) whose faces are removed:
/// every face whose centroid lies within `radius` of `centre`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Hole {
    /// The hole's centre.
    pub centre: [f64; 3],
    /// Its radius, > 0.
    pub radius: f64,
}

/// `mesh` with every face removed whose centroid lies inside one of `holes` (the distance
/// measured in the plane z = 0 when `planar`), then made a manifold surface again: the faces
/// at a vertex where two loops touch (a pinch) are removed too, until there is none, and only
/// the largest piece joined across edges is kept. Vertices no face uses are dropped; the
/// others keep their order.
///
/// Errors: a hole with a non-finite centre or a radius that is not a positive finite number,
/// or holes that leave no face.
pub fn cut_holes(mesh: &TriMesh, holes: &[Hole], planar: bool) -> Result<TriMesh> {
    for (i, h) in holes.iter().enumerate() {
        if !(h.centre.iter().all(|x| x.is_finite()) && h.radius.is_finite() && h.radius > 0.0) {
            return Err(Error::Argument(format!(
                "hole {} has centre {:?} and radius {}: the centre must be finite and the \
                 radius a positive finite number",
                i + 1,
                h.centre,
                h.radius
            )));
        }
    }
    let n = mesh.n_vertices();
    if mesh.faces.iter().flatten().any(|&v| v as usize >= n) {
        return Err(Error::InvalidMesh(
            "a face refers to a vertex the mesh does not have".into(),
        ));
    }
    let inside = |f: &[u32; 3]| {
        let p = f.map(|v| mesh.positions[v as usize]);
        let c: [f64; 3] = std::array::from_fn(|k| (p[0][k] + p[1][k] + p[2][k]) / 3.0);
        holes.iter().any(|h| {
            let d: [f64; 3] = std::array::from_fn(|k| c[k] - h.centre[k]);
            let z = if planar { 0.0 } else { d[2] * d[2] };
            d[0] * d[0] + d[1] * d[1] + z <= h.radius * h.radius
        })
    };
    let mut faces: Vec<[u32; 3]> = mesh.faces.iter().filter(|f| !inside(f)).copied().collect();
    loop {
        let mut boundary_degree = vec![0u32; n];
        EdgeGroups::new(n, &faces).for_each_edge(|a, b, hes| {
            if hes.len() == 1 {
                boundary_degree[a as usize] += 1;
                boundary_degree[b as usize] += 1;
            }
        });
        let before = faces.len();
        faces.retain(|f| f.iter().all(|&v| boundary_degree[v as usize] <= 2));
        if faces.len() == before {
            break;
        }
    }
    let faces = largest_piece(n, &faces);
    if faces.is_empty() {
        return Err(Error::Argument(
            "the holes leave no face of the mesh".into(),
        ));
    }
    Ok(super::validate::drop_unused_vertices(
        mesh.positions.clone(),
        faces,
    ))
}

/// The faces of the largest piece of `faces` (on `n` vertices) joined across edges; the first
/// such piece when two are as large.
fn largest_piece(n: usize, faces: &[[u32; 3]]) -> Vec<[u32; 3]> {
    let mut pieces = super::union_find::UnionFind::new(faces.len());
    EdgeGroups::new(n, faces).for_each_edge(|_, _, hes| {
        for w in hes.windows(2) {
            pieces.union(w[0] / 3, w[1] / 3);
        }
    });
    let root: Vec<u32> = (0..faces.len() as u32).map(|f| pieces.find(f)).collect();
    let mut size = vec![0usize; faces.len()];
    for &r in &root {
        size[r as usize] += 1;
    }
    let Some(best) = (0..faces.len()).max_by_key(|&f| (size[f], std::cmp::Reverse(f))) else {
        return Vec::new();
    };
    faces
        .iter()
        .zip(&root)
        .filter(|&(_, &r)| r as usize == best)
        .map(|(f, _)| *f)
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::topology;

    fn hole(x: f64, y: f64, radius: f64) -> Hole {
        Hole {
            centre: [x, y, 0.0],
            radius,
        }
    }

    /// The centroid of face `f` of `mesh` in the plane.
    fn centroid(mesh: &TriMesh, f: [u32; 3]) -> [f64; 2] {
        let p = f.map(|v| mesh.positions[v as usize]);
        [0, 1].map(|k| (p[0][k] + p[1][k] + p[2][k]) / 3.0)
    }

    #[test]
    fn two_holes_in_a_disk_make_three_boundary_loops() {
        let disk = crate::generate::regular_polygon(6, 30).unwrap();
        let holes = [hole(0.4, 0.0, 0.15), hole(-0.4, 0.1, 0.2)];
        let cut = cut_holes(&disk, &holes, true).unwrap();
        let t = topology(&cut);
        assert_eq!(t.boundary_loops.len(), 3, "{t:?}");
        assert_eq!(t.euler_characteristic, -1, "{t:?}");
        // Exactly the faces whose centroids lie outside both holes are kept (these holes are
        // far apart: no pinch to remove).
        let outside = |c: [f64; 2]| {
            holes
                .iter()
                .all(|h| (c[0] - h.centre[0]).hypot(c[1] - h.centre[1]) > h.radius)
        };
        let expected = disk
            .faces
            .iter()
            .filter(|&&f| outside(centroid(&disk, f)))
            .count();
        assert_eq!(cut.n_faces(), expected);
        assert!(cut.faces.iter().all(|&f| outside(centroid(&cut, f))));
    }

    #[test]
    fn touching_holes_leave_no_pinched_vertex_and_one_piece() {
        // Two holes whose rims touch near x = −0.1: the faces there pinch the rims together
        // at single vertices, until they are removed.
        let disk = crate::generate::regular_polygon(6, 24).unwrap();
        let holes = [hole(0.1, 0.0, 0.2), hole(-0.31, 0.0, 0.2)];
        let cut = cut_holes(&disk, &holes, true).unwrap();
        assert!(crate::mesh::validate(cut.clone()).is_ok());
        assert_eq!(
            crate::mesh::connected_components(cut.n_vertices(), &cut.faces).0,
            1
        );
        assert!(topology(&cut).boundary_loops.len() >= 2);
    }

    #[test]
    fn bad_holes_are_refused() {
        let disk = crate::generate::regular_polygon(6, 4).unwrap();
        let bad = [
            Hole {
                centre: [f64::NAN, 0.0, 0.0],
                radius: 0.1,
            },
            hole(0.0, 0.0, 0.0),
            hole(0.0, 0.0, f64::INFINITY),
        ];
        for h in bad {
            assert!(matches!(
                cut_holes(&disk, &[h], true),
                Err(Error::Argument(_))
            ));
        }
        let all = hole(0.0, 0.0, 10.0);
        assert!(matches!(
            cut_holes(&disk, &[all], false),
            Err(Error::Argument(_))
        ));
    }
}
