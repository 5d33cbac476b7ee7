//! Point location in a mapped mesh: which face of the map contains a point of the target
//! domain, and its barycentric coordinates there. With them, any per-vertex quantity of the
//! input — above all its positions — is carried through the inverse map by barycentric
//! interpolation ([`interpolate`]). Remeshing (DEM paper §6.2, SDEM paper §5.2, DEQ paper §7.1,
//! TDEM paper §5) and registration (SDEM paper §5.1) pull points back this way.
//!
//! The faces are bucketed once in a uniform grid of cells about one face across; a query tests
//! the faces of its cell only.

use super::grid::{Buckets, GridCells};
use super::torus::FlatTorusMap;

/// Where a point lies in a mesh: a face and the point's barycentric coordinates in it
/// (non-negative, summing to 1).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Location {
    /// The face index.
    pub face: usize,
    /// Barycentric coordinates with respect to the face's three corners, in face order.
    pub weights: [f64; 3],
}

/// How far outside a face (in barycentric units) a point may lie and still count as inside:
/// rounding of points computed on an edge, never a real miss.
const TOLERANCE: f64 = 1e-8;

/// `Σ wₖ values[face[k]]`: barycentric interpolation of a per-vertex quantity.
pub fn interpolate(values: &[[f64; 3]], face: [u32; 3], weights: [f64; 3]) -> [f64; 3] {
    let mut out = [0.0; 3];
    for k in 0..3 {
        let v = values[face[k] as usize];
        for d in 0..3 {
            out[d] += weights[k] * v[d];
        }
    }
    out
}

/// Point location in a planar map (z ignored), e.g. a disk or circle-domain map.
#[derive(Debug, Clone)]
pub struct PlanarLocator {
    corners: Vec<[[f64; 2]; 3]>,
    grid: FaceGrid,
}

impl PlanarLocator {
    /// Buckets the faces of the map `points` (z ignored).
    pub fn new(points: &[[f64; 3]], faces: &[[u32; 3]]) -> Self {
        let corners: Vec<[[f64; 2]; 3]> = faces
            .iter()
            .map(|f| f.map(|v| [points[v as usize][0], points[v as usize][1]]))
            .collect();
        Self::from_corners(corners)
    }

    fn from_corners(corners: Vec<[[f64; 2]; 3]>) -> Self {
        let boxes: Vec<([f64; 3], [f64; 3])> = corners
            .iter()
            .map(|c| {
                let lo = [0, 1].map(|d| c[0][d].min(c[1][d]).min(c[2][d]));
                let hi = [0, 1].map(|d| c[0][d].max(c[1][d]).max(c[2][d]));
                ([lo[0], lo[1], 0.0], [hi[0], hi[1], 0.0])
            })
            .collect();
        let grid = FaceGrid::new(&boxes);
        PlanarLocator { corners, grid }
    }

    /// The face containing `p` and the barycentric coordinates of `p` in it; `None` when `p`
    /// lies outside the map (beyond a rounding tolerance). A point on a shared edge or vertex
    /// gets one of its faces.
    pub fn locate(&self, p: [f64; 2]) -> Option<Location> {
        let mut best: Option<(f64, Location)> = None;
        for &f in self.grid.candidates([p[0], p[1], 0.0]) {
            let [a, b, c] = self.corners[f as usize];
            let area = orient(a, b, c);
            if area == 0.0 {
                continue;
            }
            let w = [orient(p, b, c), orient(a, p, c), orient(a, b, p)].map(|x| x / area);
            consider(&mut best, f as usize, w);
        }
        finish(best)
    }
}

/// Point location in a map onto the unit sphere: a point is in face (a, b, c) when its ray from
/// the centre crosses the flat triangle; the weights are those of the crossing point.
#[derive(Debug, Clone)]
pub struct SphericalLocator {
    corners: Vec<[[f64; 3]; 3]>,
    grid: FaceGrid,
}

impl SphericalLocator {
    /// Buckets the faces of the map `points` (on the unit sphere).
    pub fn new(points: &[[f64; 3]], faces: &[[u32; 3]]) -> Self {
        let corners: Vec<[[f64; 3]; 3]> = faces
            .iter()
            .map(|f| f.map(|v| points[v as usize]))
            .collect();
        let boxes: Vec<([f64; 3], [f64; 3])> = corners
            .iter()
            .map(|c| {
                // The spherical patch bulges beyond the flat triangle by at most its sagitta,
                // less than (longest edge)²/2 on the unit sphere.
                let l2 = (0..3)
                    .map(|k| dist2(c[k], c[(k + 1) % 3]))
                    .fold(0.0, f64::max);
                let pad = 0.5 * l2 + 1e-12;
                let lo = [0, 1, 2].map(|d| c[0][d].min(c[1][d]).min(c[2][d]) - pad);
                let hi = [0, 1, 2].map(|d| c[0][d].max(c[1][d]).max(c[2][d]) + pad);
                (lo, hi)
            })
            .collect();
        let grid = FaceGrid::new(&boxes);
        SphericalLocator { corners, grid }
    }

    /// The face whose cone from the centre contains the direction `p` (any non-zero vector),
    /// and the barycentric coordinates of the ray's crossing with the flat face; `None` when no
    /// face does (only possible if the map does not cover the sphere).
    pub fn locate(&self, p: [f64; 3]) -> Option<Location> {
        let n = dist2(p, [0.0; 3]).sqrt();
        if !(n > 0.0) {
            return None;
        }
        let p = p.map(|x| x / n);
        let mut best: Option<(f64, Location)> = None;
        for &f in self.grid.candidates(p) {
            let [a, b, c] = self.corners[f as usize];
            let w = [det(p, b, c), det(a, p, c), det(a, b, p)];
            let sum = w[0] + w[1] + w[2];
            let towards = (0..3).map(|d| p[d] * (a[d] + b[d] + c[d])).sum::<f64>();
            if !(towards > 0.0) || sum == 0.0 {
                continue;
            }
            consider(&mut best, f as usize, w.map(|x| x / sum));
        }
        finish(best)
    }
}

/// Point location in a map onto the unit sphere by walking from face to face: from a face
/// near the answer (a query close to the last one, say), a few steps find it, whatever the
/// spread of the faces' sizes (a conformal map's faces differ in size by many orders, which a
/// grid of uniform cells serves badly). Each step crosses the edge whose great circle has the
/// point farthest on its outer side; a walk that has not arrived after as many steps as there
/// are faces (a cycle, possible in a triangulation far from Delaunay) ends in a scan of every
/// face.
#[derive(Debug, Clone)]
pub struct SphericalWalk {
    corners: Vec<[[f64; 3]; 3]>,
    /// The face across the edge opposite each corner (`u32::MAX` on a boundary).
    neighbours: Vec<[u32; 3]>,
    /// Where [`Self::locate`] starts: a face per cell of the cube's surface ([`CubeCells`]).
    starts: CubeCells,
}

impl SphericalWalk {
    /// The walk over the faces of the map `points` (on the unit sphere, faces counter-clockwise
    /// seen from outside).
    pub fn new(points: &[[f64; 3]], faces: &[[u32; 3]]) -> Self {
        let corners: Vec<[[f64; 3]; 3]> = faces
            .iter()
            .map(|f| f.map(|v| points[v as usize]))
            .collect();
        let mut neighbours = vec![[u32::MAX; 3]; faces.len()];
        let n = crate::mesh::topology::vertex_bound(points.len(), faces);
        crate::mesh::topology::EdgeGroups::new(n, faces).for_each_edge(|_, _, hes| {
            if let [h, g] = *hes {
                // Half-edge 3f + c runs from corner c to c + 1: it is opposite corner c + 2.
                let (fh, fg) = ((h / 3) as usize, (g / 3) as usize);
                neighbours[fh][((h % 3 + 2) % 3) as usize] = fg as u32;
                neighbours[fg][((g % 3 + 2) % 3) as usize] = fh as u32;
            }
        });
        let starts = CubeCells::new(&corners);
        Self {
            corners,
            neighbours,
            starts,
        }
    }

    /// [`Self::locate_from`] a face near `p`: one whose centroid lies in `p`'s cell of the
    /// cube, or the nearest such face along the cells' order where the cell has none.
    pub fn locate(&self, p: [f64; 3]) -> Option<Location> {
        self.locate_from(p, self.starts.face(p))
    }

    /// The number of faces.
    pub fn len(&self) -> usize {
        self.corners.len()
    }

    /// True without faces.
    pub fn is_empty(&self) -> bool {
        self.corners.is_empty()
    }

    /// The face whose cone from the centre contains the direction `p` and the barycentric
    /// coordinates of the ray's crossing with it (as [`SphericalLocator::locate`]), walking
    /// from face `start`; `None` when no face contains it.
    pub fn locate_from(&self, p: [f64; 3], start: usize) -> Option<Location> {
        let n = dist2(p, [0.0; 3]).sqrt();
        if !(n > 0.0) || self.corners.is_empty() {
            return None;
        }
        let p = p.map(|x| x / n);
        let mut f = start.min(self.corners.len() - 1);
        for _ in 0..self.corners.len() {
            let [a, b, c] = self.corners[f];
            let w = [det(p, b, c), det(a, p, c), det(a, b, p)];
            let k = (0..3).min_by(|&i, &j| w[i].total_cmp(&w[j])).unwrap_or(0);
            let sum = w[0] + w[1] + w[2];
            if w[k] >= -TOLERANCE * sum.abs() && sum > 0.0 {
                return finish(Some((
                    w[k] / sum,
                    Location {
                        face: f,
                        weights: w.map(|x| x / sum),
                    },
                )));
            }
            let next = self.neighbours[f][k];
            if next == u32::MAX {
                break;
            }
            f = next as usize;
        }
        // No arrival: every face.
        let mut best: Option<(f64, Location)> = None;
        for (f, &[a, b, c]) in self.corners.iter().enumerate() {
            let w = [det(p, b, c), det(a, p, c), det(a, b, p)];
            let sum = w[0] + w[1] + w[2];
            if sum > 0.0 {
                consider(&mut best, f, w.map(|x| x / sum));
            }
        }
        finish(best)
    }
}

/// The surface of the cube [−1, 1]³ cut into `m × m` cells on each of its six sides, with a
/// face of a spherical map per cell: the direction `p` falls in the cell where its ray leaves
/// the cube, and a face's centroid names its cell. With about one face per cell, a walk from
/// the cell's face is a few steps where the faces are of even size; where they are not, from
/// a face no farther than the cell.
#[derive(Debug, Clone)]
struct CubeCells {
    m: usize,
    face: Vec<u32>,
}

impl CubeCells {
    /// The cells for the faces with `corners`, about one face per cell (at most 6 · 1024²
    /// cells). Every cell gets a face: an empty one takes the face of the cell before it in
    /// the cells' order (or after, for the first ones).
    fn new(corners: &[[[f64; 3]; 3]]) -> Self {
        let m = ((corners.len() as f64 / 6.0).sqrt().ceil() as usize).clamp(1, 1024);
        let mut cells = CubeCells {
            m,
            face: vec![u32::MAX; 6 * m * m],
        };
        for (f, c) in corners.iter().enumerate() {
            let centroid = [0, 1, 2].map(|d| c[0][d] + c[1][d] + c[2][d]);
            if let Some(i) = cells.cell(centroid) {
                cells.face[i] = f as u32;
            }
        }
        let first = cells
            .face
            .iter()
            .copied()
            .find(|&f| f != u32::MAX)
            .unwrap_or(0);
        let mut last = first;
        for f in cells.face.iter_mut() {
            if *f == u32::MAX {
                *f = last;
            } else {
                last = *f;
            }
        }
        cells
    }

    /// The cell of the direction `p`; `None` for the zero or a non-finite vector.
    fn cell(&self, p: [f64; 3]) -> Option<usize> {
        let k = (0..3).max_by(|&i, &j| p[i].abs().total_cmp(&p[j].abs()))?;
        let top = p[k].abs();
        if !(top > 0.0 && top.is_finite()) {
            return None;
        }
        let side = 2 * k + usize::from(p[k] < 0.0);
        let (u, v) = (p[(k + 1) % 3] / top, p[(k + 2) % 3] / top);
        let at = |x: f64| (((x + 1.0) * 0.5 * self.m as f64) as usize).min(self.m - 1);
        Some((side * self.m + at(u)) * self.m + at(v))
    }

    /// The face of `p`'s cell (face 0 for a vector with no cell).
    fn face(&self, p: [f64; 3]) -> usize {
        self.cell(p).map_or(0, |i| self.face[i] as usize)
    }
}

/// Point location in a map onto the flat torus: points are taken modulo the periods.
#[derive(Debug, Clone)]
pub struct PeriodicLocator {
    planar: PlanarLocator,
    period: [f64; 2],
    lo: [f64; 2],
}

impl PeriodicLocator {
    /// Buckets the faces of a flat torus map, each drawn at its corners' translations.
    pub fn new(map: &FlatTorusMap, faces: &[[u32; 3]], period: [f64; 2]) -> Self {
        let corners: Vec<[[f64; 2]; 3]> = (0..faces.len())
            .map(|f| map.corners(faces, f, period).map(|c| [c[0], c[1]]))
            .collect();
        let mut lo = [f64::INFINITY; 2];
        for c in corners.iter().flatten() {
            lo = [lo[0].min(c[0]), lo[1].min(c[1])];
        }
        PeriodicLocator {
            planar: PlanarLocator::from_corners(corners),
            period,
            lo,
        }
    }

    /// The face containing `p` modulo the periods, and its barycentric coordinates there.
    pub fn locate(&self, p: [f64; 2]) -> Option<Location> {
        if !(p[0].is_finite() && p[1].is_finite()) {
            return None;
        }
        // The drawn faces start at `lo` and reach a little over one period beyond it, so the
        // representative of p in [lo, lo + period) or its translate by one period is in one.
        let q = [0, 1].map(|d| self.lo[d] + (p[d] - self.lo[d]).rem_euclid(self.period[d]));
        let mut best: Option<(f64, Location)> = None;
        for i in 0..2 {
            for j in 0..2 {
                let s = [
                    q[0] + i as f64 * self.period[0],
                    q[1] + j as f64 * self.period[1],
                ];
                if let Some(l) = self.planar.locate(s) {
                    let m = l.weights.iter().copied().fold(f64::INFINITY, f64::min);
                    if best.as_ref().is_none_or(|(b, _)| m > *b) {
                        best = Some((m, l));
                    }
                }
            }
        }
        best.map(|(_, l)| l)
    }
}

/// Keeps the candidate whose smallest weight is largest (the face the point is most inside).
fn consider(best: &mut Option<(f64, Location)>, face: usize, weights: [f64; 3]) {
    let m = weights[0].min(weights[1]).min(weights[2]);
    if m.is_nan() {
        return;
    }
    if best.as_ref().is_none_or(|(b, _)| m > *b) {
        *best = Some((m, Location { face, weights }));
    }
}

/// Accepts the best candidate if it is inside up to the tolerance, with its weights clamped to
/// be non-negative and to sum to 1.
fn finish(best: Option<(f64, Location)>) -> Option<Location> {
    let (m, mut l) = best?;
    if m < -TOLERANCE {
        return None;
    }
    let w = l.weights.map(|x| x.max(0.0));
    let s = w[0] + w[1] + w[2];
    l.weights = w.map(|x| x / s);
    Some(l)
}

/// Twice the signed area of the planar triangle (a, b, c).
fn orient(a: [f64; 2], b: [f64; 2], c: [f64; 2]) -> f64 {
    (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])
}

/// det(a, b, c) = a · (b × c).
fn det(a: [f64; 3], b: [f64; 3], c: [f64; 3]) -> f64 {
    a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0])
        + a[2] * (b[0] * c[1] - b[1] * c[0])
}

fn dist2(a: [f64; 3], b: [f64; 3]) -> f64 {
    (0..3).map(|d| (a[d] - b[d]) * (a[d] - b[d])).sum()
}

/// The faces' boxes bucketed in a uniform grid ([`super::grid`]) of cubic cells; a box is
/// listed in every cell it overlaps.
#[derive(Debug, Clone)]
struct FaceGrid(Buckets<3>);

impl FaceGrid {
    /// Cells as wide as the boxes' mean extent (at least 1/2¹⁸ of the whole extent); boxes
    /// with a non-finite coordinate are left out.
    fn new(boxes: &[([f64; 3], [f64; 3])]) -> Self {
        let finite = |(a, b): &([f64; 3], [f64; 3])| a.iter().chain(b).all(|x| x.is_finite());
        let mut lo = [f64::INFINITY; 3];
        let mut hi = [f64::NEG_INFINITY; 3];
        let mut mean_extent = 0.0;
        let mut count = 0usize;
        for (a, b) in boxes.iter().filter(|b| finite(b)) {
            count += 1;
            for d in 0..3 {
                lo[d] = lo[d].min(a[d]);
                hi[d] = hi[d].max(b[d]);
            }
            mean_extent += (0..3).map(|d| b[d] - a[d]).fold(0.0, f64::max);
        }
        if count == 0 {
            return FaceGrid(GridCells::new([0.0; 3], [1.0; 3], [1; 3]).bucket(0, |_| None));
        }
        let whole = (0..3).map(|d| hi[d] - lo[d]).fold(0.0, f64::max);
        let cell = (mean_extent / count as f64)
            .max(whole / 262_144.0)
            .max(f64::MIN_POSITIVE);
        let inv_cell = 1.0 / cell;
        let dims = [0, 1, 2].map(|d| ((hi[d] - lo[d]) * inv_cell).floor() as usize + 1);
        let cells = GridCells::with_inverse(lo, [inv_cell; 3], dims);
        FaceGrid(cells.bucket(boxes.len(), |i| {
            let (a, b) = boxes[i];
            finite(&boxes[i]).then(|| (cells.cell_of(a), cells.cell_of(b)))
        }))
    }

    /// The boxes listed in the cell of `p` (empty outside the grid, beyond a rounding margin).
    fn candidates(&self, p: [f64; 3]) -> &[u32] {
        let cells = self.0.cells();
        let (x, dims) = (cells.coordinates(p), cells.dims());
        if (0..3).any(|d| !(x[d] >= -1e-9 && x[d] <= dims[d] as f64 + 1e-9)) {
            return &[];
        }
        self.0.at(cells.cell_of(p))
    }
}

#[cfg(test)]
mod walk_tests {
    use super::*;
    use crate::geometry::sphere::normalize;

    #[test]
    fn the_walk_finds_what_the_grid_finds() {
        let mesh = crate::generate::icosphere(4).unwrap();
        let grid = SphericalLocator::new(&mesh.positions, &mesh.faces);
        let walk = SphericalWalk::new(&mesh.positions, &mesh.faces);
        for i in 0..300 {
            let t = i as f64 * 0.713;
            let p = normalize([t.sin(), (1.3 * t).cos(), (0.37 * t).sin() - 0.2]);
            let a = grid.locate(p).unwrap();
            // From a far face, from the face found, and from the cube cell's face.
            let q = |l: &Location| interpolate(&mesh.positions, mesh.faces[l.face], l.weights);
            for start in [0, (i * 97) % walk.len(), a.face] {
                let b = walk.locate_from(p, start).unwrap();
                let d = dist2(q(&a), q(&b)).sqrt();
                assert!(d < 1e-12, "{i}: {d}");
            }
            let d = dist2(q(&a), q(&walk.locate(p).unwrap())).sqrt();
            assert!(d < 1e-12, "{i}: {d}");
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::generate;
    use crate::geometry::torus::Torus;

    fn grid_mesh(n: usize) -> (Vec<[f64; 3]>, Vec<[u32; 3]>) {
        let m = generate::square_grid(n, n, 1.0, 1.0).unwrap();
        (m.positions, m.faces)
    }

    #[test]
    fn planar_location_reproduces_linear_functions() {
        let (p, f) = grid_mesh(7);
        let loc = PlanarLocator::new(&p, &f);
        // A linear function of the vertices is interpolated exactly.
        let values: Vec<[f64; 3]> = p.iter().map(|q| [2.0 * q[0] - q[1], q[1], 1.0]).collect();
        for &(x, y) in &[
            (0.1, 0.2),
            (0.5, 0.5),
            (0.99, 0.01),
            (0.0, 0.0),
            (1.0, 1.0),
            (0.3, 1.0),
        ] {
            let l = loc.locate([x, y]).expect("inside");
            assert!(l.weights.iter().all(|&w| w >= 0.0));
            assert!((l.weights.iter().sum::<f64>() - 1.0).abs() < 1e-12);
            let v = interpolate(&values, f[l.face], l.weights);
            assert!((v[0] - (2.0 * x - y)).abs() < 1e-12 && (v[1] - y).abs() < 1e-12);
        }
        assert!(loc.locate([1.01, 0.5]).is_none());
        assert!(loc.locate([-0.5, -0.5]).is_none());
        assert!(loc.locate([f64::NAN, 0.5]).is_none());
    }

    #[test]
    fn spherical_location_finds_the_face_around_a_direction() {
        let m = generate::icosphere(3).unwrap();
        let loc = SphericalLocator::new(&m.positions, &m.faces);
        for k in 0..200 {
            let t = k as f64 * 0.37;
            let p = [
                t.cos() * (0.3 * t).sin(),
                t.sin() * (0.3 * t).sin(),
                (0.3 * t).cos(),
            ];
            let l = loc.locate(p).expect("covered");
            // The weighted corners are the ray's crossing with the face: parallel to p.
            let x = interpolate(&m.positions, m.faces[l.face], l.weights);
            let n = (x[0] * x[0] + x[1] * x[1] + x[2] * x[2]).sqrt();
            for d in 0..3 {
                assert!((x[d] / n - p[d]).abs() < 1e-12);
            }
        }
        assert!(loc.locate([0.0; 3]).is_none());
    }

    #[test]
    fn periodic_location_wraps_points_around() {
        let torus = Torus::new(2.0, 1.0).unwrap();
        let m = generate::torus(2.0, 1.0, 24, 12).unwrap();
        let map = FlatTorusMap::from_surface(&m.positions, &m.faces, &torus);
        let period = torus.periods();
        let loc = PeriodicLocator::new(&map, &m.faces, period);
        for k in 0..100 {
            let u = -20.0 + 0.731 * k as f64;
            let v = 9.0 - 0.377 * k as f64;
            let l = loc.locate([u, v]).expect("the flat torus is covered");
            let [a, b, c] = map.corners(&m.faces, l.face, period);
            let x = [0, 1].map(|d| l.weights[0] * a[d] + l.weights[1] * b[d] + l.weights[2] * c[d]);
            // The located point equals (u, v) up to whole periods.
            for (d, w) in [u, v].iter().enumerate() {
                let r = (x[d] - w) / period[d];
                assert!((r - r.round()).abs() < 1e-9, "{r}");
            }
        }
    }
}
