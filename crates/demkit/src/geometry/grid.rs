//! A uniform grid of cells over an axis-aligned box, in `D` dimensions, and items bucketed in
//! its cells: the spatial index behind point location, distance-to-boundary queries and the
//! neighbour searches of remeshing and cartograms.
//!
//! [`GridCells`] is the geometry alone: an origin `lo`, a cell size per axis and a number of
//! cells per axis. The cell of a point is `⌊(p − lo) / cell⌋` on every axis (or
//! `⌊(p − lo) · (1 / cell)⌋` for a grid given by its inverse cell size,
//! [`GridCells::with_inverse`]: the two can differ by one rounding at a cell wall), clamped to
//! the grid ([`GridCells::cell_of`]) or `None` outside it ([`GridCells::cell_within`]).
//! [`Buckets`] lists items (faces, segments, points) in the cells of an inclusive range each,
//! within every cell in increasing item order. The lists are stored compressed: one offset per
//! cell when the grid has few cells for its entries, otherwise one per occupied cell, found by
//! binary search (a fine 3D grid over a surface is mostly empty); both answer alike.

/// The geometry of a uniform grid: cell `c` (per axis `0 ≤ c[d] < dims[d]`) covers
/// `lo + c · cell ≤ p < lo + (c + 1) · cell`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct GridCells<const D: usize> {
    lo: [f64; D],
    /// The cell size per axis, or its inverse when `inverse`.
    step: [f64; D],
    inverse: bool,
    dims: [usize; D],
}

impl<const D: usize> GridCells<D> {
    /// The grid with origin `lo`, cell sizes `cell` and `dims` cells per axis (at least one).
    pub(crate) fn new(lo: [f64; D], cell: [f64; D], dims: [usize; D]) -> Self {
        Self {
            lo,
            step: cell,
            inverse: false,
            dims: dims.map(|n| n.max(1)),
        }
    }

    /// The grid with origin `lo`, inverse cell sizes `inv_cell` (cells per unit length) and
    /// `dims` cells per axis (at least one): positions in cell units are `(p − lo) · inv_cell`.
    pub(crate) fn with_inverse(lo: [f64; D], inv_cell: [f64; D], dims: [usize; D]) -> Self {
        Self {
            inverse: true,
            ..Self::new(lo, inv_cell, dims)
        }
    }

    /// Cells per axis.
    pub(crate) fn dims(&self) -> [usize; D] {
        self.dims
    }

    /// The position of `p` in cell units, `(p − lo) / cell` per axis.
    pub(crate) fn coordinates(&self, p: [f64; D]) -> [f64; D] {
        if self.inverse {
            std::array::from_fn(|d| (p[d] - self.lo[d]) * self.step[d])
        } else {
            std::array::from_fn(|d| (p[d] - self.lo[d]) / self.step[d])
        }
    }

    /// The cell of `p`, clamped to the grid (a NaN coordinate counts as below it).
    pub(crate) fn cell_of(&self, p: [f64; D]) -> [usize; D] {
        let x = self.coordinates(p);
        std::array::from_fn(|d| (x[d].floor().max(0.0) as usize).min(self.dims[d] - 1))
    }

    /// The cell of `p`, or `None` when `p` lies outside the grid on some axis.
    pub(crate) fn cell_within(&self, p: [f64; D]) -> Option<[usize; D]> {
        let x = self.coordinates(p);
        (0..D)
            .all(|d| x[d] >= 0.0 && x[d] < self.dims[d] as f64)
            .then(|| std::array::from_fn(|d| x[d] as usize))
    }

    /// The linear index of cell `c`, the first axis varying fastest.
    pub(crate) fn index(&self, c: [usize; D]) -> usize {
        (0..D).rev().fold(0, |acc, d| acc * self.dims[d] + c[d])
    }

    /// The number of cells.
    fn len(&self) -> usize {
        self.dims.iter().product()
    }

    /// Buckets `n_items` items, item `k` in every cell from `range(k).0` to `range(k).1`
    /// (inclusive on every axis; `None` for an item listed nowhere).
    pub(crate) fn bucket(
        self,
        n_items: usize,
        range: impl Fn(usize) -> Option<([usize; D], [usize; D])>,
    ) -> Buckets<D> {
        let mut pairs: Vec<(usize, u32)> = Vec::new();
        for k in 0..n_items {
            if let Some((a, b)) = range(k) {
                self.for_each_cell(a, b, |c| pairs.push((self.index(c), k as u32)));
            }
        }
        // Stable: items stay in increasing order within a cell.
        pairs.sort_by_key(|p| p.0);
        let items = pairs.iter().map(|p| p.1).collect();
        let dense = self.len() <= 4 * pairs.len() + 1024;
        let storage = if dense {
            let mut start = vec![0usize; self.len() + 1];
            for p in &pairs {
                start[p.0 + 1] += 1;
            }
            for i in 0..self.len() {
                start[i + 1] += start[i];
            }
            Storage::Dense { start }
        } else {
            let (mut keys, mut start) = (Vec::new(), Vec::new());
            for (at, p) in pairs.iter().enumerate() {
                if keys.last() != Some(&p.0) {
                    keys.push(p.0);
                    start.push(at);
                }
            }
            start.push(pairs.len());
            Storage::Sparse { keys, start }
        };
        Buckets {
            cells: self,
            storage,
            items,
        }
    }

    /// Calls `f` on every cell from `a` to `b` (inclusive), the first axis varying fastest.
    pub(crate) fn for_each_cell(
        &self,
        a: [usize; D],
        b: [usize; D],
        mut f: impl FnMut([usize; D]),
    ) {
        if (0..D).any(|d| a[d] > b[d]) {
            return;
        }
        let mut c = a;
        loop {
            f(c);
            let mut d = 0;
            loop {
                if d == D {
                    return;
                }
                if c[d] < b[d] {
                    c[d] += 1;
                    break;
                }
                c[d] = a[d];
                d += 1;
            }
        }
    }
}

/// Where the item lists of the cells start.
#[derive(Debug, Clone)]
enum Storage {
    /// One offset per cell (and one past the end).
    Dense { start: Vec<usize> },
    /// The occupied cells' indices, sorted, and one offset per occupied cell.
    Sparse { keys: Vec<usize>, start: Vec<usize> },
}

/// Items listed in the cells of a [`GridCells`].
#[derive(Debug, Clone)]
pub(crate) struct Buckets<const D: usize> {
    cells: GridCells<D>,
    storage: Storage,
    items: Vec<u32>,
}

impl<const D: usize> Buckets<D> {
    /// The grid's geometry.
    pub(crate) fn cells(&self) -> &GridCells<D> {
        &self.cells
    }

    /// The items listed in cell `c`, in increasing order.
    pub(crate) fn at(&self, c: [usize; D]) -> &[u32] {
        let i = self.cells.index(c);
        let (a, b) = match &self.storage {
            Storage::Dense { start } => (start[i], start[i + 1]),
            Storage::Sparse { keys, start } => match keys.binary_search(&i) {
                Ok(k) => (start[k], start[k + 1]),
                Err(_) => (0, 0),
            },
        };
        &self.items[a..b]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cells_of_points_floor_and_clamp() {
        let g = GridCells::new([1.0, -2.0], [0.5, 2.0], [4, 3]);
        assert_eq!(g.dims(), [4, 3]);
        assert_eq!(g.coordinates([2.0, 1.0]), [2.0, 1.5]);
        assert_eq!(g.cell_of([2.0, 1.0]), [2, 1]);
        assert_eq!(g.cell_of([1.0, -2.0]), [0, 0]);
        assert_eq!(g.cell_of([0.0, 100.0]), [0, 2]);
        assert_eq!(g.cell_of([f64::NAN, 3.99]), [0, 2]);
        assert_eq!(g.cell_within([2.9, 3.9]), Some([3, 2]));
        assert_eq!(g.cell_within([3.0, 0.0]), None);
        assert_eq!(g.cell_within([0.99, 0.0]), None);
        assert_eq!(g.cell_within([f64::NAN, 0.0]), None);
        assert_eq!(g.index([3, 2]), 11);
        assert_eq!(g.index([1, 1]), 5);
        assert_eq!(GridCells::new([0.0], [1.0], [0]).dims(), [1]);
        // At a cell wall the two can differ: 0.3 / 0.1 rounds below 3, 0.3 · 10 to 3 exactly.
        let (div, mul) = (
            GridCells::new([0.0], [0.1], [20]),
            GridCells::with_inverse([0.0], [10.0], [20]),
        );
        assert_eq!(div.coordinates([0.3]), [2.9999999999999996]);
        assert_eq!(mul.coordinates([0.3]), [3.0]);
        assert_eq!((div.cell_of([0.3]), mul.cell_of([0.3])), ([2], [3]));
        assert_eq!(mul.cell_of([0.25]), [2]);
    }

    #[test]
    fn ranges_are_visited_first_axis_fastest() {
        let g = GridCells::new([0.0; 3], [1.0; 3], [3, 3, 3]);
        let mut seen = Vec::new();
        g.for_each_cell([1, 0, 2], [2, 1, 2], |c| seen.push(c));
        assert_eq!(seen, [[1, 0, 2], [2, 0, 2], [1, 1, 2], [2, 1, 2]]);
        seen.clear();
        g.for_each_cell([2, 0, 0], [1, 0, 0], |c| seen.push(c));
        assert!(seen.is_empty());
    }

    #[test]
    fn buckets_list_items_in_order_dense_and_sparse() {
        // Item 0 covers the 2x2 corner, item 1 one cell, item 2 nothing, item 3 a row.
        let ranges = [
            Some(([0, 0], [1, 1])),
            Some(([1, 1], [1, 1])),
            None,
            Some(([0, 1], [2, 1])),
        ];
        let small = GridCells::new([0.0; 2], [1.0; 2], [3, 2]).bucket(4, |k| ranges[k]);
        let large = GridCells::new([0.0; 2], [1.0; 2], [3000, 2]).bucket(4, |k| ranges[k]);
        assert!(matches!(small.storage, Storage::Dense { .. }));
        assert!(matches!(large.storage, Storage::Sparse { .. }));
        for b in [&small, &large] {
            assert_eq!(b.at([0, 0]), [0]);
            assert_eq!(b.at([1, 0]), [0]);
            assert_eq!(b.at([2, 0]), [] as [u32; 0]);
            assert_eq!(b.at([0, 1]), [0, 3]);
            assert_eq!(b.at([1, 1]), [0, 1, 3]);
            assert_eq!(b.at([2, 1]), [3]);
        }
        assert_eq!(large.at([2999, 1]), [] as [u32; 0]);
        assert_eq!(small.cells().dims(), [3, 2]);
    }
}
