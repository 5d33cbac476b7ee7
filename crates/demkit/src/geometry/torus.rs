//! The torus of revolution and its flat periodic plane (TDEM paper §3): the toroidal projection
//! φ (8), its inverse (9)–(10), and maps of genus-one meshes onto the flat torus stored as one
//! point per vertex plus a lattice translation per face corner (no duplicated seam vertices).

use crate::{Error, Result};
use std::f64::consts::PI;

/// The torus `(√(X² + Y²) − R)² + Z² = r²` (6) with major radius `R` and minor radius `r`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Torus {
    /// Major radius R (centre of the tube to the axis).
    pub major: f64,
    /// Minor radius r (radius of the tube).
    pub minor: f64,
}

impl Torus {
    /// The same torus with both radii multiplied by 2^k (exact; see [`crate::mesh::scale`]).
    pub fn scaled_by_power_of_two(&self, k: i32) -> Self {
        use crate::mesh::scale::ldexp;
        Self {
            major: ldexp(self.major, k),
            minor: ldexp(self.minor, k),
        }
    }

    /// The torus with radii `R > r > 0`; anything else is an argument error.
    pub fn new(major: f64, minor: f64) -> Result<Self> {
        if !(major.is_finite() && minor.is_finite() && minor > 0.0 && major > minor) {
            return Err(Error::Argument(format!(
                "a torus needs radii R > r > 0, got R = {major}, r = {minor}"
            )));
        }
        Ok(Self { major, minor })
    }

    /// The periods of the flat torus: `[2πR, 2πr]`.
    pub fn periods(&self) -> [f64; 2] {
        [2.0 * PI * self.major, 2.0 * PI * self.minor]
    }

    /// The toroidal projection φ(u, v) (8); periodic in u with period 2πR and in v with 2πr.
    pub fn project(&self, p: [f64; 2]) -> [f64; 3] {
        let (su, cu) = (p[0] / self.major).sin_cos();
        let (sv, cv) = (p[1] / self.minor).sin_cos();
        let ring = self.major + self.minor * cv;
        [ring * cu, ring * su, self.minor * sv]
    }

    /// The inverse projection φ⁻¹ (9)–(10) of a point on (or near) the torus, in
    /// `[0, 2πR) × [−πr, πr)`: the angles of the point around the axis and around the tube.
    pub fn unproject(&self, p: [f64; 3]) -> [f64; 2] {
        let mut theta = p[1].atan2(p[0]);
        if theta < 0.0 {
            theta += 2.0 * PI;
        }
        let ring = p[0].hypot(p[1]) - self.major;
        let mut phi = p[2].atan2(ring);
        if phi >= PI {
            phi -= 2.0 * PI;
        }
        let u = (self.major * theta).min(self.periods()[0] * (1.0 - f64::EPSILON));
        [u, self.minor * phi]
    }

    /// The distance of `p` from the torus: `| |(√(X² + Y²) − R, Z)| − r |`.
    pub fn distance(&self, p: [f64; 3]) -> f64 {
        ((p[0].hypot(p[1]) - self.major).hypot(p[2]) - self.minor).abs()
    }
}

/// A map of a genus-one mesh onto the flat torus of [`Torus::periods`] `[a, b]`: vertex `v` sits
/// at `points[v]`, and corner `k` of face `f` is drawn at
/// `points[faces[f][k]] + offsets[f][k] · (a, b)`, so that every face is an ordinary planar
/// triangle and opposite sides of the period rectangle are translates of each other by
/// construction ((24)–(25)).
#[derive(Debug, Clone, PartialEq)]
pub struct FlatTorusMap {
    /// One point per vertex in the periodic plane.
    pub points: Vec<[f64; 2]>,
    /// Per face corner, the lattice translation in periods.
    pub offsets: Vec<[[i32; 2]; 3]>,
}

impl FlatTorusMap {
    /// The map of a mesh lying on `torus`: φ⁻¹ of every vertex, and each face drawn around its
    /// first corner (its other corners translated by whole periods to within half a period).
    pub fn from_surface(positions: &[[f64; 3]], faces: &[[u32; 3]], torus: &Torus) -> Self {
        let points: Vec<[f64; 2]> = positions.iter().map(|&p| torus.unproject(p)).collect();
        let period = torus.periods();
        let offsets = faces
            .iter()
            .map(|f| {
                let base = points[f[0] as usize];
                let mut out = [[0i32; 2]; 3];
                for k in 1..3 {
                    let p = points[f[k] as usize];
                    for d in 0..2 {
                        out[k][d] = ((base[d] - p[d]) / period[d]).round() as i32;
                    }
                }
                out
            })
            .collect();
        Self { points, offsets }
    }

    /// The planar corners of face `f` (z = 0).
    pub fn corners(&self, faces: &[[u32; 3]], f: usize, period: [f64; 2]) -> [[f64; 3]; 3] {
        let mut out = [[0.0; 3]; 3];
        for k in 0..3 {
            let p = self.points[faces[f][k] as usize];
            let o = self.offsets[f][k];
            out[k] = [
                p[0] + o[0] as f64 * period[0],
                p[1] + o[1] as f64 * period[1],
                0.0,
            ];
        }
        out
    }

    /// The planar corners of every face, three consecutive points per face, with the faces
    /// `[3f, 3f + 1, 3f + 2]` over them: any planar per-face operator applies unchanged.
    pub fn unfolded(&self, faces: &[[u32; 3]], period: [f64; 2]) -> (Vec<[f64; 3]>, Vec<[u32; 3]>) {
        let mut points = Vec::with_capacity(3 * faces.len());
        for f in 0..faces.len() {
            points.extend_from_slice(&self.corners(faces, f, period));
        }
        let local = (0..faces.len() as u32)
            .map(|f| [3 * f, 3 * f + 1, 3 * f + 2])
            .collect();
        (points, local)
    }

    /// The number of faces whose planar image has signed area ≤ 0 (the report's
    /// `flipped_triangles` for toroidal maps).
    pub fn count_flipped(&self, faces: &[[u32; 3]], period: [f64; 2]) -> usize {
        (0..faces.len())
            .filter(|&f| {
                let [a, b, c] = self.corners(faces, f, period);
                (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]) <= 0.0
            })
            .count()
    }

    /// The points on the torus: φ of every vertex.
    pub fn on_torus(&self, torus: &Torus) -> Vec<[f64; 3]> {
        self.points.iter().map(|&p| torus.project(p)).collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn radii_must_satisfy_r_below_major() {
        assert!(Torus::new(3.0, 1.0).is_ok());
        for (a, b) in [
            (1.0, 2.0),
            (1.0, 1.0),
            (2.0, 0.0),
            (f64::NAN, 1.0),
            (2.0, -1.0),
        ] {
            assert!(Torus::new(a, b).is_err(), "{a} {b}");
        }
    }

    #[test]
    fn projection_and_inverse_round_trip() {
        let t = Torus::new(3.0, 1.0).unwrap();
        let [a, b] = t.periods();
        for i in 0..7 {
            for j in 0..5 {
                let uv = [
                    a * (i as f64 + 0.3) / 7.0,
                    -b / 2.0 + b * (j as f64 + 0.1) / 5.0,
                ];
                let p = t.project(uv);
                assert!(t.distance(p) < 1e-14);
                let back = t.unproject(p);
                assert!((back[0] - uv[0]).abs() < 1e-12 && (back[1] - uv[1]).abs() < 1e-12);
            }
        }
        // (8) at the paper's reference points: u = 0 on the +X axis, v = 0 on the outer equator,
        // v = ±πr on the inner equator.
        let p = t.project([0.0, 0.0]);
        assert!((p[0] - 4.0).abs() < 1e-15 && p[1].abs() < 1e-15 && p[2].abs() < 1e-15);
        let q = t.project([0.0, PI]);
        assert!((q[0] - 2.0).abs() < 1e-14);
        // Periodic in both directions.
        let r = t.project([0.4 + a, 0.2 - b]);
        let s = t.project([0.4, 0.2]);
        for d in 0..3 {
            assert!((r[d] - s[d]).abs() < 1e-12);
        }
    }

    #[test]
    fn faces_across_the_seam_get_whole_period_offsets() {
        let t = Torus::new(2.0, 1.0).unwrap();
        let [a, b] = t.periods();
        // A triangle straddling u = 0 and v = ±πr.
        let uv = [
            [a - 0.1, b / 2.0 - 0.05],
            [0.1, b / 2.0 - 0.05],
            [0.0, -b / 2.0 + 0.1],
        ];
        let positions: Vec<[f64; 3]> = uv.iter().map(|&p| t.project(p)).collect();
        let map = FlatTorusMap::from_surface(&positions, &[[0, 1, 2]], &t);
        assert_eq!(map.offsets[0], [[0, 0], [1, 0], [1, 1]]);
        let c = map.corners(&[[0, 1, 2]], 0, t.periods());
        assert!((c[1][0] - (a + 0.1)).abs() < 1e-12 && (c[2][1] - (b / 2.0 + 0.1)).abs() < 1e-12);
        assert_eq!(map.count_flipped(&[[0, 1, 2]], t.periods()), 0);
    }
}
