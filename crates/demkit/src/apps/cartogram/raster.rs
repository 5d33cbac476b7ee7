//! The density of a map on a grid of unit cells: every cell gets the area-weighted mean of
//! the densities of the regions covering it, and the sea (the part no region covers) its own
//! density. Coverage is measured on [`SUBROWS`] scanlines per cell row, with exact spans along
//! each scanline; a polygon smaller than a cell, which scanlines could miss, puts its whole
//! area into the cell of its centroid instead.

use super::regions::ring_area;
use super::rings::bbox;

/// Scanlines per row of cells.
pub const SUBROWS: usize = 4;

/// One region's rings: polygons → rings (exterior first) → point indices.
pub type IndexRings = Vec<Vec<Vec<usize>>>;

/// The density of every cell (row-major, nx × ny) for regions with densities `density` over
/// `points` (cell units, inside [0, nx] × [0, ny]) and the sea at `sea`.
pub fn density(
    points: &[[f64; 2]],
    regions: &[IndexRings],
    density: &[f64],
    sea: f64,
    nx: usize,
    ny: usize,
) -> Vec<f64> {
    let mut mass = vec![0.0; nx * ny];
    let mut cover = vec![0.0; nx * ny];
    let rows = (ny * SUBROWS) as f64;
    // The scanlines an edge from `a` to `b` crosses: s with s in (min, max], where
    // y_s = (s + 0.5) / SUBROWS.
    let span = |a: [f64; 2], b: [f64; 2]| {
        let (s0, s1) = (a[1] * SUBROWS as f64 - 0.5, b[1] * SUBROWS as f64 - 0.5);
        let from = (s0.min(s1).floor() + 1.0).max(0.0);
        let to = s0.max(s1).floor().min(rows - 1.0);
        (s0, s1, from, to)
    };
    // Crossings of scanlines: (scanline, region, x), counted first so that the list is
    // allocated once.
    let count: usize = regions
        .iter()
        .flatten()
        .flatten()
        .map(|ring| {
            (0..ring.len())
                .map(|i| {
                    let (a, b) = (points[ring[i]], points[ring[(i + 1) % ring.len()]]);
                    let (_, _, from, to) = span(a, b);
                    (to - from + 1.0).max(0.0) as usize
                })
                .sum::<usize>()
        })
        .sum();
    let mut crossings: Vec<(u32, u32, f64)> = Vec::with_capacity(count);
    let cell_of = |p: [f64; 2]| {
        let x = (p[0].floor().max(0.0) as usize).min(nx - 1);
        let y = (p[1].floor().max(0.0) as usize).min(ny - 1);
        y * nx + x
    };
    for (r, polygons) in regions.iter().enumerate() {
        for rings in polygons {
            let (lo, hi) = bbox(rings[0].iter().map(|&v| points[v]));
            if hi[0] - lo[0] < 1.0 || hi[1] - lo[1] < 1.0 {
                // Small: its area, at its centroid.
                let (area, c) = polygon_area_centroid(points, rings);
                let k = cell_of(c);
                mass[k] += area * density[r];
                cover[k] += area;
                continue;
            }
            for ring in rings {
                let n = ring.len();
                for i in 0..n {
                    let (a, b) = (points[ring[i]], points[ring[(i + 1) % n]]);
                    let (s0, s1, from, to) = span(a, b);
                    let mut s = from;
                    while s <= to {
                        let f = (s - s0) / (s1 - s0);
                        let x = a[0] + f * (b[0] - a[0]);
                        crossings.push((s as u32, r as u32, x));
                        s += 1.0;
                    }
                }
            }
        }
    }
    crossings.sort_unstable_by(|a, b| (a.0, a.1).cmp(&(b.0, b.1)).then(a.2.total_cmp(&b.2)));
    let w = 1.0 / SUBROWS as f64;
    let mut k = 0;
    while k + 1 < crossings.len() {
        let (s, r, x0) = crossings[k];
        let (s1, r1, x1) = crossings[k + 1];
        if (s, r) != (s1, r1) {
            k += 1;
            continue;
        }
        let row = s as usize / SUBROWS * nx;
        let (x0, x1) = (x0.clamp(0.0, nx as f64), x1.clamp(0.0, nx as f64));
        let d = density[r as usize];
        let (c0, c1) = (
            (x0.floor() as usize).min(nx - 1),
            (x1.floor() as usize).min(nx - 1),
        );
        for c in c0..=c1 {
            let len = (x1.min(c as f64 + 1.0) - x0.max(c as f64)).max(0.0) * w;
            mass[row + c] += len * d;
            cover[row + c] += len;
        }
        k += 2;
    }
    for (m, c) in mass.iter_mut().zip(&cover) {
        *m += (1.0 - c).max(0.0) * sea;
    }
    mass
}

/// The area (holes subtracted) and area centroid of a polygon's rings.
pub fn polygon_area_centroid(points: &[[f64; 2]], rings: &[Vec<usize>]) -> (f64, [f64; 2]) {
    let (mut a, mut cx, mut cy) = (0.0, 0.0, 0.0);
    for (j, ring) in rings.iter().enumerate() {
        let pts: Vec<[f64; 2]> = ring.iter().map(|&v| points[v]).collect();
        let s = ring_area(&pts);
        // Exterior counted positive, holes negative, whatever their orientation.
        let sign = if (j == 0) == (s >= 0.0) { 1.0 } else { -1.0 };
        let n = pts.len();
        for i in 0..n {
            let (p, q) = (pts[i], pts[(i + 1) % n]);
            let cross = p[0] * q[1] - q[0] * p[1];
            cx += sign * (p[0] + q[0]) * cross / 6.0;
            cy += sign * (p[1] + q[1]) * cross / 6.0;
        }
        a += sign * s;
    }
    if a.abs() > 0.0 {
        (a.abs(), [cx / a, cy / a])
    } else {
        let p = points[rings[0][0]];
        (0.0, p)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn coverage_is_exact_for_a_rectangle_and_sea_fills_the_rest() {
        // A 2.5 × 2 rectangle from (0.5, 1) in a 4 × 4 grid, density 3, sea 1.
        let pts = vec![[0.5, 1.0], [3.0, 1.0], [3.0, 3.0], [0.5, 3.0]];
        let rho = density(&pts, &[vec![vec![vec![0, 1, 2, 3]]]], &[3.0], 1.0, 4, 4);
        let total: f64 = rho.iter().sum();
        // 5 cells' worth at 3 and 11 at 1.
        assert!((total - (15.0 + 11.0)).abs() < 1e-12, "{total}");
        assert!((rho[4] - 2.0).abs() < 1e-12, "{}", rho[4]);
        assert!((rho[5] - 3.0).abs() < 1e-12);
    }

    #[test]
    fn a_polygon_smaller_than_a_cell_keeps_its_mass() {
        let pts = vec![[1.2, 1.2], [1.4, 1.2], [1.4, 1.3]];
        let rho = density(&pts, &[vec![vec![vec![0, 1, 2]]]], &[100.0], 1.0, 3, 3);
        let total: f64 = rho.iter().sum();
        let a = 0.01;
        assert!((total - (9.0 - a + 100.0 * a)).abs() < 1e-12, "{total}");
    }
}
