//! Uniform grids of buckets over a bounding box: which points or segments may lie near a box.

use super::regions::bbox;

/// A uniform grid of buckets over a bounding box.
pub(crate) struct Buckets {
    lo: [f64; 2],
    cell: [f64; 2],
    n: usize,
    items: Vec<Vec<usize>>,
}

impl Buckets {
    pub(crate) fn new(lo: [f64; 2], hi: [f64; 2], count: usize) -> Self {
        let n = ((count as f64).sqrt().ceil() as usize).clamp(1, 1024);
        let cell = [
            ((hi[0] - lo[0]) / n as f64).max(f64::MIN_POSITIVE),
            ((hi[1] - lo[1]) / n as f64).max(f64::MIN_POSITIVE),
        ];
        Self {
            lo,
            cell,
            n,
            items: vec![Vec::new(); n * n],
        }
    }

    fn range(&self, lo: [f64; 2], hi: [f64; 2]) -> ([usize; 2], [usize; 2]) {
        let idx = |x: f64, k: usize| {
            (((x - self.lo[k]) / self.cell[k]).floor().max(0.0) as usize).min(self.n - 1)
        };
        (
            [idx(lo[0], 0), idx(lo[1], 1)],
            [idx(hi[0], 0), idx(hi[1], 1)],
        )
    }

    pub(crate) fn add_box(&mut self, lo: [f64; 2], hi: [f64; 2], item: usize) {
        let (a, b) = self.range(lo, hi);
        for i in a[0]..=b[0] {
            for j in a[1]..=b[1] {
                self.items[i * self.n + j].push(item);
            }
        }
    }

    /// Every item stored in a cell meeting the box (an item may come more than once).
    pub(crate) fn visit(&self, lo: [f64; 2], hi: [f64; 2], mut f: impl FnMut(usize)) {
        let (a, b) = self.range(lo, hi);
        for i in a[0]..=b[0] {
            for j in a[1]..=b[1] {
                for &v in &self.items[i * self.n + j] {
                    f(v);
                }
            }
        }
    }
}

/// Points bucketed on a grid.
pub(super) struct Grid(Buckets);

impl Grid {
    pub(super) fn new(points: &[[f64; 2]], count: usize) -> Self {
        let (lo, hi) = bbox(points.iter().copied());
        let mut b = Buckets::new(lo, hi, count);
        for (v, &p) in points.iter().enumerate() {
            b.add_box(p, p, v);
        }
        Grid(b)
    }

    pub(super) fn visit_box(&self, lo: [f64; 2], hi: [f64; 2], f: impl FnMut(usize)) {
        self.0.visit(lo, hi, f)
    }
}
