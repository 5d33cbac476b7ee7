//! A checkerboard carried by the mesh: cells laid out in the coordinates of the initial map
//! (the map before density equalization), so the same cells can be followed from the input
//! surface to the final map, and a cell's change of size is the map's change of area.
//!
//! The cells are squares in a plane (planar and circle-domain maps), 20° × 20° cells of
//! longitude and latitude on the sphere, and cells of the two angles of a torus, about square
//! on its surface. Each covered sample of a face takes the cell of its point of the initial
//! map, interpolated linearly between the face's corners, so the cell borders are drawn at
//! the resolution of the picture, not of the mesh.

/// Dark cells keep this share of their colour.
pub const DARK: f64 = 0.8;

/// About this many cells across a planar initial map's larger side.
const PLANE_CELLS: f64 = 12.0;

/// Degrees per cell on the sphere.
const SPHERE_DEGREES: f64 = 20.0;

/// Cells around the tube of a torus.
const TUBE_CELLS: f64 = 8.0;

/// How the initial map is divided into cells.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Checker {
    /// Squares of side `cell` in the xy-plane.
    Plane {
        /// The side of a cell.
        cell: f64,
    },
    /// Cells of `SPHERE_DEGREES` in longitude and latitude about the origin.
    Sphere,
    /// Cells of the angles around the z-axis and around the tube (major radius `major`).
    Torus {
        /// The distance of the tube's centre from the z-axis.
        major: f64,
        /// Cells around the z-axis.
        around: f64,
    },
}

/// Where a map lies, for choosing its cells.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Kind {
    /// In the plane (planar and circle-domain maps).
    Plane,
    /// On the unit sphere about the origin.
    Sphere,
    /// On a torus about the z-axis.
    Torus,
}

impl Checker {
    /// The cells for an initial map with vertex positions `initial`.
    pub fn fit(initial: &[[f64; 3]], kind: Kind) -> Checker {
        let finite = || initial.iter().filter(|p| p.iter().all(|c| c.is_finite()));
        match kind {
            Kind::Plane => {
                let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
                for p in finite() {
                    for k in 0..2 {
                        lo[k] = lo[k].min(p[k]);
                        hi[k] = hi[k].max(p[k]);
                    }
                }
                let side = (hi[0] - lo[0]).max(hi[1] - lo[1]);
                let cell = if side.is_finite() && side > 0.0 {
                    side / PLANE_CELLS
                } else {
                    1.0
                };
                Checker::Plane { cell }
            }
            Kind::Sphere => Checker::Sphere,
            Kind::Torus => {
                let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
                for p in finite() {
                    let rho = p[0].hypot(p[1]);
                    lo = lo.min(rho);
                    hi = hi.max(rho);
                }
                let (major, minor) = ((lo + hi) / 2.0, (hi - lo) / 2.0);
                let around = if major.is_finite() && minor > 0.0 {
                    (TUBE_CELLS * major / minor).round().max(TUBE_CELLS)
                } else {
                    2.0 * TUBE_CELLS
                };
                Checker::Torus { major, around }
            }
        }
    }

    /// The brightness factor of point `p` of the initial map: 1 in light cells, [`DARK`] in
    /// dark ones.
    #[cfg(test)]
    pub fn shade(&self, p: [f64; 3]) -> f64 {
        if self.is_dark(p) { DARK } else { 1.0 }
    }

    /// Whether point `p` of the initial map is in a dark cell.
    pub fn is_dark(&self, p: [f64; 3]) -> bool {
        let cells = match *self {
            Checker::Plane { cell } => (p[0] / cell).floor() + (p[1] / cell).floor(),
            Checker::Sphere => {
                let step = SPHERE_DEGREES.to_radians();
                let lon = atan2(p[1], p[0]);
                let lat = atan2(p[2], (p[0] * p[0] + p[1] * p[1]).sqrt());
                (lon / step).floor() + (lat / step).floor()
            }
            Checker::Torus { major, around } => {
                let u = atan2(p[1], p[0]);
                let v = atan2(p[2], (p[0] * p[0] + p[1] * p[1]).sqrt() - major);
                let tau = std::f64::consts::TAU;
                (u / tau * around).floor() + (v / tau * TUBE_CELLS).floor()
            }
        };
        // Cells far beyond ±2^62 (none on a picture) saturate; their parity is irrelevant.
        cells.is_finite() && (cells as i64) & 1 == 1
    }
}

/// atan2 within 3e-4 radians (a polynomial for atan on [0, 1], then the octant): cell
/// borders move by far less than a pixel, at a fraction of the library function's cost per
/// sample.
fn atan2(y: f64, x: f64) -> f64 {
    let (ax, ay) = (x.abs(), y.abs());
    let (lo, hi) = if ax < ay { (ax, ay) } else { (ay, ax) };
    if hi == 0.0 || !hi.is_finite() {
        return y.atan2(x);
    }
    let a = lo / hi;
    let s = a * a;
    let mut r = ((-0.046_496_474_9 * s + 0.159_314_22) * s - 0.327_622_764) * s * a + a;
    if ay > ax {
        r = std::f64::consts::FRAC_PI_2 - r;
    }
    if x < 0.0 {
        r = std::f64::consts::PI - r;
    }
    if y < 0.0 { -r } else { r }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_fast_atan2_is_within_its_bound() {
        for i in 0..3600 {
            let t = f64::from(i).to_radians() / 10.0;
            for r in [1e-3, 1.0, 7.0] {
                let (y, x) = (r * t.sin(), r * t.cos());
                let d = (atan2(y, x) - y.atan2(x)).abs();
                assert!(
                    d < 3e-4 || (d - std::f64::consts::TAU).abs() < 3e-4,
                    "{t} {d}"
                );
            }
        }
        assert_eq!(atan2(0.0, 0.0), 0.0);
    }

    #[test]
    fn plane_cells_alternate_across_the_map() {
        let c = Checker::fit(&[[-1.0, -1.0, 0.0], [1.0, 0.5, 0.0]], Kind::Plane);
        assert_eq!(c, Checker::Plane { cell: 2.0 / 12.0 });
        let (a, b) = (c.shade([0.01, 0.01, 0.0]), c.shade([0.2, 0.01, 0.0]));
        assert!(a != b && a.max(b) == 1.0 && a.min(b) == DARK);
        // Diagonal neighbours match.
        assert_eq!(c.shade([0.01, 0.01, 0.0]), c.shade([0.2, 0.2, 0.0]));
        // A degenerate map still gets a cell size.
        assert_eq!(
            Checker::fit(&[[0.0; 3]], Kind::Plane),
            Checker::Plane { cell: 1.0 }
        );
    }

    #[test]
    fn sphere_cells_follow_longitude_and_latitude() {
        let c = Checker::fit(&[], Kind::Sphere);
        let at = |lon: f64, lat: f64| {
            let (lon, lat) = (lon.to_radians(), lat.to_radians());
            c.shade([lat.cos() * lon.cos(), lat.cos() * lon.sin(), lat.sin()])
        };
        assert_ne!(at(10.0, 10.0), at(30.0, 10.0));
        assert_ne!(at(10.0, 10.0), at(10.0, 30.0));
        assert_eq!(at(10.0, 10.0), at(30.0, 30.0));
        // Only the direction matters.
        assert_eq!(c.shade([0.5, 0.1, 0.2]), c.shade([5.0, 1.0, 2.0]));
    }

    #[test]
    fn torus_cells_are_about_square() {
        // A torus R = 2, r = 1 sampled on its outer and inner equators.
        let pts = [[3.0, 0.0, 0.0], [-1.0, 0.0, 0.0], [0.0, 2.0, 1.0]];
        let c = Checker::fit(&pts, Kind::Torus);
        assert_eq!(
            c,
            Checker::Torus {
                major: 2.0,
                around: 16.0
            }
        );
        // Half a cell either side of the outer equator, around the tube: different cells.
        let v = std::f64::consts::TAU / 16.0;
        let tube = |a: f64| [2.0 + a.cos(), 0.01, a.sin()];
        assert_ne!(c.shade(tube(v / 2.0)), c.shade(tube(-v / 2.0)));
    }
}
