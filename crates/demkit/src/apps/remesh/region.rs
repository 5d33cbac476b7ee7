//! The planar region a map covers: the area enclosed by the images of the input's boundary
//! loops (the outer loop minus the holes, even–odd rule), with a bucket grid over the boundary
//! segments for distance queries.

use super::sampling::hex_rows;
use crate::geometry::grid::{Buckets, GridCells};
use crate::geometry::segment::segment_distance;

/// The boundary polylines of a planar map and a grid of their segments.
pub struct Region {
    /// Every boundary segment `[a, b]`.
    segments: Vec<[[f64; 2]; 2]>,
    lo: [f64; 2],
    hi: [f64; 2],
    /// Per cell, the segments whose box (grown by one cell) touches it.
    grid: Buckets<2>,
}

impl Region {
    /// The region bounded by the closed polylines `loops`; `cell` is the distance that
    /// [`Region::near_boundary`] can answer about (larger distances are clamped to it).
    pub fn new(loops: &[Vec<[f64; 2]>], cell: f64) -> Self {
        let mut segments = Vec::new();
        let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
        for l in loops {
            for k in 0..l.len() {
                let (a, b) = (l[k], l[(k + 1) % l.len()]);
                segments.push([a, b]);
                for d in 0..2 {
                    lo[d] = lo[d].min(a[d]);
                    hi[d] = hi[d].max(a[d]);
                }
            }
        }
        let cell = cell.max(1e-12 * (hi[0] - lo[0]).max(hi[1] - lo[1]).max(1e-300));
        // At most about 4 million cells, whatever the cell size asked for.
        let mut cell_size = cell;
        let span = [(hi[0] - lo[0]).max(0.0), (hi[1] - lo[1]).max(0.0)];
        while (span[0] / cell_size + 1.0) * (span[1] / cell_size + 1.0) > 4.0e6 {
            cell_size *= 2.0;
        }
        let dims = [0, 1].map(|d| (span[d] / cell_size).floor() as usize + 1);
        let cells = GridCells::new(lo, [cell_size; 2], dims);
        let grid = cells.bucket(segments.len(), |s| {
            let [a, b] = segments[s];
            let c0 = cells.cell_of([a[0].min(b[0]), a[1].min(b[1])]);
            let c1 = cells.cell_of([a[0].max(b[0]), a[1].max(b[1])]);
            let grown = |c: [usize; 2], up: bool| {
                [0, 1].map(|d| {
                    if up {
                        (c[d] + 1).min(dims[d] - 1)
                    } else {
                        c[d].saturating_sub(1)
                    }
                })
            };
            Some((grown(c0, false), grown(c1, true)))
        });
        Self {
            segments,
            lo,
            hi,
            grid,
        }
    }

    /// The bounding box of the boundary.
    pub fn bounds(&self) -> ([f64; 2], [f64; 2]) {
        (self.lo, self.hi)
    }

    /// The abscissae where the horizontal line at height `y` crosses the boundary, sorted: a
    /// point `(x, y)` is inside when an odd number of them are below `x`.
    pub fn crossings(&self, y: f64) -> Vec<f64> {
        let mut xs: Vec<f64> = self
            .segments
            .iter()
            .filter(|[a, b]| (a[1] > y) != (b[1] > y))
            .map(|[a, b]| a[0] + (y - a[1]) / (b[1] - a[1]) * (b[0] - a[0]))
            .collect();
        xs.sort_by(f64::total_cmp);
        xs
    }

    /// The points of the hexagonal lattice of spacing `h` over the boundary's bounding box
    /// ([`hex_rows`]) that lie inside the region (even–odd rule), row by row.
    pub fn lattice_inside(&self, h: f64) -> Vec<[f64; 2]> {
        let mut inside = Vec::new();
        for (y, xs) in hex_rows(self.lo, self.hi, h) {
            let cross = self.crossings(y);
            let mut k = 0;
            for x in xs {
                while k < cross.len() && cross[k] < x {
                    k += 1;
                }
                if k % 2 == 1 {
                    inside.push([x, y]);
                }
            }
        }
        inside
    }

    /// True when `p` lies inside the region (even–odd rule).
    #[cfg(test)]
    pub fn contains(&self, p: [f64; 2]) -> bool {
        self.crossings(p[1]).iter().filter(|&&x| x < p[0]).count() % 2 == 1
    }

    /// True when some boundary segment is closer to `p` than `d` (`d` at most the grid cell).
    pub fn near_boundary(&self, p: [f64; 2], d: f64) -> bool {
        if p[0] < self.lo[0] - d
            || p[1] < self.lo[1] - d
            || p[0] > self.hi[0] + d
            || p[1] > self.hi[1] + d
        {
            return false;
        }
        self.grid
            .at(self.grid.cells().cell_of(p))
            .iter()
            .any(|&s| {
                let [a, b] = self.segments[s as usize];
                segment_distance(p, a, b).0
            } < d)
    }

    /// The boundary segment nearest to `p` and the parameter of the nearest point on it.
    #[cfg(test)]
    pub fn nearest_segment(&self, p: [f64; 2]) -> (usize, f64) {
        let mut best = (usize::MAX, 0.0, f64::INFINITY);
        for (s, seg) in self.segments.iter().enumerate() {
            let (d, t) = segment_distance(p, seg[0], seg[1]);
            if d < best.2 {
                best = (s, t, d);
            }
        }
        (best.0, best.1)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn annulus() -> Region {
        let circle = |r: f64, n: usize, ccw: bool| -> Vec<[f64; 2]> {
            (0..n)
                .map(|k| {
                    let a = 2.0 * std::f64::consts::PI * k as f64 / n as f64;
                    let a = if ccw { a } else { -a };
                    [r * a.cos(), r * a.sin()]
                })
                .collect()
        };
        Region::new(&[circle(1.0, 64, true), circle(0.4, 32, false)], 0.1)
    }

    #[test]
    fn an_annulus_contains_its_ring_only() {
        let r = annulus();
        assert!(r.contains([0.7, 0.0]));
        assert!(r.contains([0.0, -0.7]));
        assert!(!r.contains([0.0, 0.0]));
        assert!(!r.contains([1.2, 0.3]));
        assert_eq!(r.crossings(0.0).len(), 4);
    }

    #[test]
    fn distances_to_the_boundary() {
        let r = annulus();
        assert!(r.near_boundary([0.95, 0.0], 0.1));
        assert!(r.near_boundary([0.0, 0.45], 0.1));
        assert!(!r.near_boundary([0.7, 0.0], 0.1));
        assert!(!r.near_boundary([5.0, 5.0], 0.1));
        let (d, t) = segment_distance([0.5, 1.0], [0.0, 0.0], [1.0, 0.0]);
        assert!((d - 1.0).abs() < 1e-15 && (t - 0.5).abs() < 1e-15);
        let (s, _) = r.nearest_segment([1.1, 0.01]);
        assert!(s == 0 || s == 63);
    }
}
