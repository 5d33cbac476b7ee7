//! A spatial index of the ROI boundary polygon for the fill: inside/outside and distance
//! queries.

use super::clean_up::orient2;
use crate::geometry::segment::segment_distance;

/// Spatial index of the ROI boundary polygon: horizontal slabs for point-in-polygon by ray
/// casting, and a uniform grid for "farther than `dist` from every edge".
pub(super) struct BoundaryIndex<'a> {
    poly: &'a [[f64; 2]],
    ymin: f64,
    slab_h: f64,
    slab_start: Vec<u32>,
    slab_edges: Vec<u32>,
    dist: f64,
    gx: f64,
    gy: f64,
    cell: f64,
    nx: usize,
    ny: usize,
    cell_start: Vec<u32>,
    cell_edges: Vec<u32>,
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
        let slab_of = |y: f64| (((y - ymin) / slab_h).floor().max(0.0) as usize).min(n_slabs - 1);
        let (slab_start, slab_edges) = bucket(n_slabs, b, |k, push| {
            let (p, q) = edge(k);
            for s in slab_of(p[1].min(q[1]))..=slab_of(p[1].max(q[1])) {
                push(s);
            }
        });

        // Grid of cells of side >= dist, at most 512 per axis.
        let (gx, gy) = (xmin - dist, ymin - dist);
        let extent = (xmax - xmin).max(ymax - ymin) + 2.0 * dist;
        let cell = (2.0 * dist).max(extent / 512.0).max(f64::MIN_POSITIVE);
        let nx = ((xmax + dist - gx) / cell).floor() as usize + 1;
        let ny = ((ymax + dist - gy) / cell).floor() as usize + 1;
        let cell_of = |x: f64, y: f64| {
            (
                (((x - gx) / cell).floor().max(0.0) as usize).min(nx - 1),
                (((y - gy) / cell).floor().max(0.0) as usize).min(ny - 1),
            )
        };
        let (cell_start, cell_edges) = bucket(nx * ny, b, |k, push| {
            let (p, q) = edge(k);
            let (i0, j0) = cell_of(p[0].min(q[0]) - dist, p[1].min(q[1]) - dist);
            let (i1, j1) = cell_of(p[0].max(q[0]) + dist, p[1].max(q[1]) + dist);
            for j in j0..=j1 {
                for i in i0..=i1 {
                    push(j * nx + i);
                }
            }
        });
        BoundaryIndex {
            poly,
            ymin,
            slab_h,
            slab_start,
            slab_edges,
            dist,
            gx,
            gy,
            cell,
            nx,
            ny,
            cell_start,
            cell_edges,
        }
    }

    /// Point in polygon by ray casting towards +x, with the half-open rule on y.
    pub(super) fn contains(&self, p: [f64; 2]) -> bool {
        let n_slabs = self.slab_start.len() - 1;
        let s = (p[1] - self.ymin) / self.slab_h;
        if !(s >= 0.0 && s < n_slabs as f64 + 1.0) {
            return false;
        }
        let s = (s.floor() as usize).min(n_slabs - 1);
        let b = self.poly.len();
        let mut inside = false;
        for &e in &self.slab_edges[self.slab_start[s] as usize..self.slab_start[s + 1] as usize] {
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
        let (fx, fy) = ((p[0] - self.gx) / self.cell, (p[1] - self.gy) / self.cell);
        if !(fx >= 0.0 && fy >= 0.0 && fx < self.nx as f64 && fy < self.ny as f64) {
            return true;
        }
        let c = fy as usize * self.nx + fx as usize;
        let b = self.poly.len();
        let d2 = self.dist * self.dist;
        self.cell_edges[self.cell_start[c] as usize..self.cell_start[c + 1] as usize]
            .iter()
            .all(|&e| {
                let (a, q) = (self.poly[e as usize], self.poly[(e as usize + 1) % b]);
                segment_distance(p, a, q).0.powi(2) >= d2
            })
    }
}

/// Compressed buckets: `items(k, push)` pushes the buckets of item k; returns (start, items).
pub(super) fn bucket(
    n_buckets: usize,
    n_items: usize,
    items: impl Fn(usize, &mut dyn FnMut(usize)),
) -> (Vec<u32>, Vec<u32>) {
    let mut count = vec![0u32; n_buckets + 1];
    for k in 0..n_items {
        items(k, &mut |s| count[s + 1] += 1);
    }
    for s in 0..n_buckets {
        count[s + 1] += count[s];
    }
    let mut fill = count.clone();
    let mut out = vec![0u32; count[n_buckets] as usize];
    for k in 0..n_items {
        items(k, &mut |s| {
            out[fill[s] as usize] = k as u32;
            fill[s] += 1;
        });
    }
    (count, out)
}
