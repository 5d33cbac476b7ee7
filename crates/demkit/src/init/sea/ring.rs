//! The ring between the ROI and the unit circle, triangulated (DEM paper Algorithm 4, step 3).

use super::boundary_index::BoundaryIndex;
use crate::mesh::triangulate::constrained_delaunay;
use crate::{Error, Result};

/// The constrained Delaunay triangulation of the ROI boundary, the lattice and the circle
/// points, constrained by the ROI boundary edges (Algorithm 4, step 3); returns the faces
/// outside the ROI polygon, with ROI boundary vertices by their ROI indices and the others at
/// `n + k` (fill point k) and `n + fill.len() + k` (circle point k).
pub(super) fn triangulate_ring(
    bpoly: &[[f64; 2]],
    boundary: &[u32],
    fill: &[[f64; 2]],
    circle: &[[f64; 2]],
    n: usize,
    index: &BoundaryIndex,
) -> Result<Vec<[u32; 3]>> {
    let b = bpoly.len();
    let m = fill.len();
    let points: Vec<[f64; 2]> = bpoly.iter().chain(fill).chain(circle).copied().collect();
    let edges: Vec<[usize; 2]> = (0..b).map(|k| [k, (k + 1) % b]).collect();
    // Fill and circle points keep away from the boundary by construction, so any coincidence
    // or crossing is the boundary loop's own.
    if let Some((i, j)) = crate::mesh::triangulate::coincident_pair(bpoly) {
        return Err(Error::InvalidMesh(format!(
            "boundary vertices {} and {} are at the same position in the initial map (is one a \
             duplicate of the other?)",
            boundary[i], boundary[j]
        )));
    }
    let cdt = constrained_delaunay(&points, &edges).map_err(|e| {
        let detail = match e {
            Error::InvalidMesh(m) => m,
            other => other.to_string(),
        };
        Error::InvalidMesh(format!(
            "the boundary loop of the region of interest is not a simple polygon \
             (it touches, crosses or repeats itself): {detail}"
        ))
    })?;
    let next = |k: usize| if k + 1 == b { 0 } else { k + 1 };
    let global = |k: usize| -> u32 {
        if k < b {
            boundary[k]
        } else {
            (n + k - b) as u32
        }
    };
    let mut out = Vec::with_capacity(cdt.faces.len());
    for f in &cdt.faces {
        let v = f.map(|i| i as usize);
        if v.iter().all(|&k| k >= b + m) {
            // Three circle points: its reflection is itself; leave the cap out.
            continue;
        }
        let outside = if v.iter().any(|&k| k >= b) {
            // A lattice or circle vertex is strictly outside the ROI, and no triangle crosses
            // a constraint edge.
            true
        } else {
            // All three on the ROI boundary: a constraint edge decides combinatorially (the ROI
            // is on its left); otherwise the centroid does.
            let mut side = None;
            for e in 0..3 {
                let (p, q) = (v[e], v[(e + 1) % 3]);
                if next(p) == q {
                    side = Some(false);
                } else if next(q) == p {
                    side = Some(true);
                }
            }
            side.unwrap_or_else(|| {
                let c = [
                    (bpoly[v[0]][0] + bpoly[v[1]][0] + bpoly[v[2]][0]) / 3.0,
                    (bpoly[v[0]][1] + bpoly[v[1]][1] + bpoly[v[2]][1]) / 3.0,
                ];
                !index.contains(c)
            })
        };
        if outside {
            out.push(v.map(global));
        }
    }
    Ok(out)
}
