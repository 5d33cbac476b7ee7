//! Which region each face of the cartogram mesh lies in.

use super::super::buckets::Buckets;
use super::super::regions::{RegionSet, bbox};
use crate::mesh::triangulate::inside_loops;
use crate::{Error, Result};

/// The region of every face: the one polygon (even–odd over its rings) containing the face's
/// centroid, or `None`. A face inside two polygons is an overlap, refused. `polygons` are
/// (region, rings) with rings given as indices into `ring_points`.
pub(in crate::apps::cartogram) fn assign_faces(
    set: &RegionSet,
    polygons: &[(usize, Vec<Vec<usize>>)],
    ring_points: &[[f64; 2]],
    points: &[[f64; 2]],
    faces: &[[u32; 3]],
    path: &str,
) -> Result<Vec<Option<usize>>> {
    let centroids: Vec<[f64; 2]> = faces
        .iter()
        .map(|f| {
            let [a, b, c] = f.map(|v| points[v as usize]);
            [(a[0] + b[0] + c[0]) / 3.0, (a[1] + b[1] + c[1]) / 3.0]
        })
        .collect();
    let (lo, hi) = bbox(centroids.iter().copied());
    let mut grid = Buckets::new(lo, hi, centroids.len());
    for (f, &c) in centroids.iter().enumerate() {
        grid.add_box(c, c, f);
    }
    // (region, polygon) of each face.
    let mut owner: Vec<Option<(usize, usize)>> = vec![None; faces.len()];
    for (k, (r, rings)) in polygons.iter().enumerate() {
        let (r, region) = (*r, &set.regions[*r]);
        {
            let (plo, phi) = bbox(rings.iter().flatten().map(|&v| ring_points[v]));
            let mut clash = None;
            grid.visit(plo, phi, |f| {
                if clash.is_some() || !inside_loops(ring_points, rings, centroids[f]) {
                    return;
                }
                match owner[f] {
                    None => owner[f] = Some((r, k)),
                    Some(o) => clash = Some((o, f)),
                }
            });
            if let Some(((r0, _), f)) = clash {
                let c = centroids[f];
                let msg = if r0 == r {
                    format!(
                        "{}: its polygons overlap near ({}, {})",
                        region.label, c[0], c[1]
                    )
                } else {
                    format!(
                        "{} overlaps {} near ({}, {})",
                        set.regions[r0].label, region.label, c[0], c[1]
                    )
                };
                return Err(Error::Format {
                    path: path.to_string(),
                    msg,
                });
            }
        }
    }
    Ok(owner.into_iter().map(|o| o.map(|(r, _)| r)).collect())
}
