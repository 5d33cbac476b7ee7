//! A spatial index of the ROI boundary polygon for the fill: inside/outside and distance
//! queries.

use super::clean_up::orient2;
use crate::geometry::grid::{Buckets, GridCells};
use crate::geometry::segment::segment_distance;

/// Spatial index of the ROI boundary polygon: horizontal slabs for point-in-polygon by ray
/// casting, and a uniform grid for "farther than `dist` from every edge" (both
/// [`crate::geometry::grid`] grids of the edges).
pub(super) struct BoundaryIndex<'a> {
    poly: &'a [[f64; 2]],
    slabs: Buckets<1>,
    dist: f64,
    grid: Buckets<2>,
}

impl<'a> BoundaryIndex<'a> {
    pub(super) fn new(poly: &'a [[f64; 2]], dist: f64) -> Self {
        let b = poly.len();
        let (mut xmin, mut xmax, mut ymin, mut ymax) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
        for p in poly {
            xmin = xmin.min(p[0]);
            xmax = xmax.max(p[0]);
            ymin = ymin.min(p[1]);
            ymax = ymax.max(p[1]);
        }
        let edge = |k: usize| (poly[k], poly[(k + 1) % b]);

        // Slabs.
        let n_slabs = b.clamp(1, 1 << 16);
        let slab_h = ((ymax - ymin) / n_slabs as f64).max(f64::MIN_POSITIVE);
        let slab_cells = GridCells::new([ymin], [slab_h], [n_slabs]);
        let slabs = slab_cells.bucket(b, |k| {
            let (p, q) = edge(k);
            Some((
                slab_cells.cell_of([p[1].min(q[1])]),
                slab_cells.cell_of([p[1].max(q[1])]),
            ))
        });

        // Grid of cells of side >= dist, at most 512 per axis.
        let (gx, gy) = (xmin - dist, ymin - dist);
        let extent = (xmax - xmin).max(ymax - ymin) + 2.0 * dist;
        let cell = (2.0 * dist).max(extent / 512.0).max(f64::MIN_POSITIVE);
        let nx = ((xmax + dist - gx) / cell).floor() as usize + 1;
        let ny = ((ymax + dist - gy) / cell).floor() as usize + 1;
        let cells = GridCells::new([gx, gy], [cell; 2], [nx, ny]);
        let grid = cells.bucket(b, |k| {
            let (p, q) = edge(k);
            Some((
                cells.cell_of([p[0].min(q[0]) - dist, p[1].min(q[1]) - dist]),
                cells.cell_of([p[0].max(q[0]) + dist, p[1].max(q[1]) + dist]),
            ))
        });
        BoundaryIndex {
            poly,
            slabs,
            dist,
            grid,
        }
    }

    /// Point in polygon by ray casting towards +x, with the half-open rule on y.
    pub(super) fn contains(&self, p: [f64; 2]) -> bool {
        let cells = self.slabs.cells();
        let n_slabs = cells.dims()[0];
        let s = cells.coordinates([p[1]])[0];
        if !(s >= 0.0 && s < n_slabs as f64 + 1.0) {
            return false;
        }
        let b = self.poly.len();
        let mut inside = false;
        for &e in self.slabs.at(cells.cell_of([p[1]])) {
            let (a, c) = (self.poly[e as usize], self.poly[(e as usize + 1) % b]);
            if (a[1] > p[1]) != (c[1] > p[1]) {
                let o = orient2(a, c, p);
                if (c[1] > a[1] && o > 0.0) || (c[1] < a[1] && o < 0.0) {
                    inside = !inside;
                }
            }
        }
        inside
    }

    /// True if `p` is at distance ≥ `dist` from every boundary edge.
    pub(super) fn far_from_boundary(&self, p: [f64; 2]) -> bool {
        let Some(c) = self.grid.cells().cell_within(p) else {
            return true;
        };
        let b = self.poly.len();
        let d2 = self.dist * self.dist;
        self.grid.at(c).iter().all(|&e| {
            let (a, q) = (self.poly[e as usize], self.poly[(e as usize + 1) % b]);
            segment_distance(p, a, q).0.powi(2) >= d2
        })
    }
}
