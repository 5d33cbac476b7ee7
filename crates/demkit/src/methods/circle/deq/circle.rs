//! A circle of the circle domain: the outer loop's or a hole's, fitted to its loop's points.
//! Apart from the boundary in motion ([`super::circles`]) so that the hole patches, which the
//! motion uses, can name it without an import cycle.

/// A circle `|z − center| = radius`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Circle {
    pub center: [f64; 2],
    pub radius: f64,
}

impl Circle {
    /// The unit vector from the centre towards `p`.
    pub fn radial(&self, p: [f64; 3]) -> [f64; 2] {
        let (dx, dy) = (p[0] - self.center[0], p[1] - self.center[1]);
        let r = dx.hypot(dy);
        if r > 0.0 {
            [dx / r, dy / r]
        } else {
            [1.0, 0.0]
        }
    }

    /// The point of the circle nearest to `p` (z = 0).
    pub fn project(&self, p: [f64; 3]) -> [f64; 3] {
        let u = self.radial(p);
        [
            self.center[0] + self.radius * u[0],
            self.center[1] + self.radius * u[1],
            0.0,
        ]
    }

    /// The circle through the points of `lp` in `x` (algebraic least squares; exact for points
    /// on a circle).
    pub fn fit(x: &[[f64; 3]], lp: &[u32]) -> Circle {
        // Minimise Σ (|p|² − 2 c·p − k)² over c and k = ρ² − |c|², about the mean point.
        let m = lp.len() as f64;
        let mean = lp.iter().fold([0.0; 2], |s, &v| {
            [s[0] + x[v as usize][0] / m, s[1] + x[v as usize][1] / m]
        });
        let (mut sxx, mut sxy, mut syy, mut sxz, mut syz) = (0.0, 0.0, 0.0, 0.0, 0.0);
        let mut szz = 0.0;
        for &v in lp {
            let (px, py) = (x[v as usize][0] - mean[0], x[v as usize][1] - mean[1]);
            let z = px * px + py * py;
            sxx += px * px;
            sxy += px * py;
            syy += py * py;
            sxz += px * z;
            syz += py * z;
            szz += z;
        }
        // With centred points the normal equations decouple: 2 [sxx sxy; sxy syy] c = [sxz; syz].
        let det = sxx * syy - sxy * sxy;
        let (cx, cy) = if det != 0.0 {
            (
                0.5 * (syy * sxz - sxy * syz) / det,
                0.5 * (sxx * syz - sxy * sxz) / det,
            )
        } else {
            (0.0, 0.0)
        };
        let radius = (szz / m + cx * cx + cy * cy).sqrt();
        Circle {
            center: [mean[0] + cx, mean[1] + cy],
            radius,
        }
    }
}
