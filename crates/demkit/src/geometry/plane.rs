//! Detecting planar input and expressing it in 2D (DEM Alg. 5 line 1: a planar surface is its
//! own initial map).

use super::{cross, dot, norm, scale, sub};

/// An orthonormal frame of the plane containing a planar mesh, oriented so that the mesh's
/// faces are counter-clockwise in it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PlaneFrame {
    /// First in-plane axis.
    pub e1: [f64; 3],
    /// Second in-plane axis (`n × e1`).
    pub e2: [f64; 3],
}

impl PlaneFrame {
    /// 2D coordinates of `p` in the frame (z = 0).
    pub fn project(&self, p: [f64; 3]) -> [f64; 3] {
        [dot(p, self.e1), dot(p, self.e2), 0.0]
    }
}

/// If every vertex lies within `rel_tol ×` (bounding-box diagonal) of one plane, returns the
/// frame of that plane. The plane normal is the area-weighted face normal, so the majority
/// orientation of the faces is counter-clockwise in the frame. A mesh in the plane z = 0 with
/// counter-clockwise faces gets the identity frame (its coordinates are kept as they are).
pub fn planar_frame(
    positions: &[[f64; 3]],
    faces: &[[u32; 3]],
    rel_tol: f64,
) -> Option<PlaneFrame> {
    let mut nsum = [0.0; 3];
    for f in faces {
        let [a, b, c] = f.map(|v| positions[v as usize]);
        let n = cross(sub(b, a), sub(c, a));
        nsum = [nsum[0] + n[0], nsum[1] + n[1], nsum[2] + n[2]];
    }
    let l = norm(nsum);
    if l == 0.0 || positions.is_empty() {
        return None;
    }
    let n = scale(nsum, 1.0 / l);
    let (mut lo, mut hi) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
    for p in positions {
        for d in 0..3 {
            lo[d] = lo[d].min(p[d]);
            hi[d] = hi[d].max(p[d]);
        }
    }
    let diag = norm(sub(hi, lo));
    let o = positions[0];
    let tol = rel_tol * diag;
    if positions.iter().any(|&p| dot(sub(p, o), n).abs() > tol) {
        return None;
    }
    // Keep x as the first axis where possible (identity frame for the z = 0 plane).
    let seed = if n[0].abs() < 0.9 {
        [1.0, 0.0, 0.0]
    } else {
        [0.0, 1.0, 0.0]
    };
    let e1 = sub(seed, scale(n, dot(seed, n)));
    let e1 = scale(e1, 1.0 / norm(e1));
    let e2 = cross(n, e1);
    Some(PlaneFrame { e1, e2 })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn detects_planes_and_keeps_xy_plane_coordinates() {
        let pos = vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
        let fr = planar_frame(&pos, &[[0, 1, 2]], 1e-9).unwrap();
        assert_eq!(fr.project([0.3, 0.7, 0.0]), [0.3, 0.7, 0.0]);
        // Clockwise in xy: the frame flips so the face is counter-clockwise.
        let fr2 = planar_frame(&pos, &[[0, 2, 1]], 1e-9).unwrap();
        let q: Vec<[f64; 3]> = pos.iter().map(|&p| fr2.project(p)).collect();
        assert!(crate::geometry::signed_area_2d(q[0], q[2], q[1]) > 0.0);
        // A bent mesh is not planar.
        let bent = vec![
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [1.0, 1.0, 0.5],
        ];
        assert!(planar_frame(&bent, &[[0, 1, 2], [1, 3, 2]], 1e-9).is_none());
    }
}
