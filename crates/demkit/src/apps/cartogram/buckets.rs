//! The cartograms' spatial index: boxes or points bucketed in a uniform grid
//! ([`crate::geometry::grid`]) of about one cell per item over their bounding box, to find
//! which of them may lie near a box.

use super::regions::bbox;
use crate::geometry::grid::{self, GridCells};

/// Boxes bucketed in a grid of `n × n` cells, `n = ⌈√(number of boxes)⌉` (at most 1024).
pub(crate) struct Buckets(grid::Buckets<2>);

impl Buckets {
    /// Buckets the boxes `(lo, hi)` in a grid over the box `lo..hi` that holds them.
    pub(crate) fn new(lo: [f64; 2], hi: [f64; 2], boxes: &[([f64; 2], [f64; 2])]) -> Self {
        let n = ((boxes.len() as f64).sqrt().ceil() as usize).clamp(1, 1024);
        let cell = [0, 1].map(|d| ((hi[d] - lo[d]) / n as f64).max(f64::MIN_POSITIVE));
        let cells = GridCells::new(lo, cell, [n, n]);
        Self(cells.bucket(boxes.len(), |k| {
            Some((cells.cell_of(boxes[k].0), cells.cell_of(boxes[k].1)))
        }))
    }

    /// The points bucketed, each as a box of its own.
    pub(crate) fn of_points(points: &[[f64; 2]]) -> Self {
        let (lo, hi) = bbox(points.iter().copied());
        let boxes: Vec<([f64; 2], [f64; 2])> = points.iter().map(|&p| (p, p)).collect();
        Self::new(lo, hi, &boxes)
    }

    /// Every item stored in a cell meeting the box `lo..hi` (an item may come more than once),
    /// cell by cell along x, then y within each column.
    pub(crate) fn visit(&self, lo: [f64; 2], hi: [f64; 2], mut f: impl FnMut(usize)) {
        let cells = self.0.cells();
        let (a, b) = (cells.cell_of(lo), cells.cell_of(hi));
        for i in a[0]..=b[0] {
            for j in a[1]..=b[1] {
                for &v in self.0.at([i, j]) {
                    f(v as usize);
                }
            }
        }
    }
}
