//! The view and the orthographic camera that fits a mesh into a picture.

/// A direction of view: the viewer sits at azimuth `azimuth` (degrees, counter-clockwise from
/// +x in the xy-plane) and elevation `elevation` (degrees above the xy-plane), z up.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct View {
    /// Degrees counter-clockwise from +x.
    pub azimuth: f64,
    /// Degrees above the xy-plane, in [−90, 90].
    pub elevation: f64,
}

impl View {
    /// Straight down from +z, x to the right and y up: how planar meshes are drawn.
    pub const TOP: View = View {
        azimuth: -90.0,
        elevation: 90.0,
    };
    /// The oblique default for closed surfaces (sphere and torus maps).
    pub const OBLIQUE: View = View {
        azimuth: -60.0,
        elevation: 30.0,
    };
    /// The default for height fields (surfaces thin in z): from the front, high up.
    pub const HIGH: View = View {
        azimuth: -90.0,
        elevation: 60.0,
    };

    /// Reads `AZIMUTH:ELEVATION` in degrees; the message says what is wrong.
    pub fn parse(s: &str) -> Result<View, String> {
        let bad = || {
            format!(
                "--view must be AZIMUTH:ELEVATION in degrees with the azimuth in [-360, 360] and the elevation in [-90, 90] (e.g. -60:30), got '{s}'"
            )
        };
        let (az, el) = s.split_once(':').ok_or_else(bad)?;
        let azimuth: f64 = az.trim().parse().map_err(|_| bad())?;
        let elevation: f64 = el.trim().parse().map_err(|_| bad())?;
        if !(-360.0..=360.0).contains(&azimuth) || !(-90.0..=90.0).contains(&elevation) {
            return Err(bad());
        }
        Ok(View { azimuth, elevation })
    }

    /// The screen axes in world coordinates: right, up, and towards the viewer.
    pub fn axes(self) -> [[f64; 3]; 3] {
        let (sa, ca) = self.azimuth.to_radians().sin_cos();
        let (se, ce) = self.elevation.to_radians().sin_cos();
        let toward = [ce * ca, ce * sa, se];
        let right = [-sa, ca, 0.0];
        // up = toward × right
        let up = [
            toward[1] * right[2] - toward[2] * right[1],
            toward[2] * right[0] - toward[0] * right[2],
            toward[0] * right[1] - toward[1] * right[0],
        ];
        [right, up, toward]
    }
}

/// An orthographic camera: world points to pixel coordinates (x right, y down) and a depth
/// (larger is nearer the viewer).
#[derive(Debug, Clone, Copy)]
pub struct Camera {
    axes: [[f64; 3]; 3],
    scale: f64,
    offset: [f64; 2],
}

impl Camera {
    /// The camera looking along `view` whose picture (`width` × `height` pixels) holds every
    /// finite point of `points`, centred, with `margin` (a fraction of the smaller side) free
    /// on each side.
    pub fn fit(points: &[[f64; 3]], view: View, width: f64, height: f64, margin: f64) -> Camera {
        let axes = view.axes();
        let mut lo = [f64::INFINITY; 2];
        let mut hi = [f64::NEG_INFINITY; 2];
        for p in points.iter().filter(|p| p.iter().all(|c| c.is_finite())) {
            for k in 0..2 {
                let s = dot(axes[k], *p);
                lo[k] = lo[k].min(s);
                hi[k] = hi[k].max(s);
            }
        }
        if lo[0] > hi[0] {
            lo = [0.0; 2];
            hi = [0.0; 2];
        }
        let free = margin * width.min(height);
        let (span_x, span_y) = (hi[0] - lo[0], hi[1] - lo[1]);
        let sx = (width - 2.0 * free) / span_x;
        let sy = (height - 2.0 * free) / span_y;
        let scale = match (sx.is_finite(), sy.is_finite()) {
            (true, true) => sx.min(sy),
            (true, false) => sx,
            (false, true) => sy,
            (false, false) => 1.0,
        };
        let centre = [(lo[0] + hi[0]) / 2.0, (lo[1] + hi[1]) / 2.0];
        Camera {
            axes,
            scale,
            offset: [
                width / 2.0 - scale * centre[0],
                height / 2.0 + scale * centre[1],
            ],
        }
    }

    /// Pixel x, pixel y (down) and depth of a world point.
    pub fn project(&self, p: [f64; 3]) -> [f64; 3] {
        [
            self.offset[0] + self.scale * dot(self.axes[0], p),
            self.offset[1] - self.scale * dot(self.axes[1], p),
            dot(self.axes[2], p),
        ]
    }

    /// A world direction in screen axes (right, up, toward the viewer).
    pub fn screen_direction(self, v: [f64; 3]) -> [f64; 3] {
        self.axes.map(|a| dot(a, v))
    }

    /// Pixels per world unit.
    #[cfg(test)]
    pub fn scale(&self) -> f64 {
        self.scale
    }
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: [f64; 3], b: [f64; 3]) -> bool {
        (0..3).all(|k| (a[k] - b[k]).abs() < 1e-12)
    }

    #[test]
    fn view_axes() {
        let [r, u, t] = View::TOP.axes();
        assert!(close(r, [1.0, 0.0, 0.0]) && close(u, [0.0, 1.0, 0.0]));
        assert!(close(t, [0.0, 0.0, 1.0]));
        let [r, u, t] = View {
            azimuth: 0.0,
            elevation: 0.0,
        }
        .axes();
        assert!(close(r, [0.0, 1.0, 0.0]) && close(u, [0.0, 0.0, 1.0]));
        assert!(close(t, [1.0, 0.0, 0.0]));
    }

    #[test]
    fn parse_views() {
        assert_eq!(
            View::parse("-60:30"),
            Ok(View {
                azimuth: -60.0,
                elevation: 30.0
            })
        );
        assert_eq!(View::parse(" 10 : -90 ").map(|v| v.elevation), Ok(-90.0));
        for bad in ["", "30", "a:b", "0:91", "0:-100", "inf:0", "0:NaN", "1:2:3"] {
            let e = View::parse(bad).unwrap_err();
            assert!(e.contains("AZIMUTH:ELEVATION") && e.contains(bad), "{e}");
        }
    }

    #[test]
    fn fit_centres_the_points_with_the_margin() {
        // The square [0,2]×[0,1] from above in a 100 × 100 picture with a 10 % margin:
        // 80 pixels for 2 units, centred.
        let pts = [[0.0, 0.0, 0.0], [2.0, 1.0, 0.0]];
        let c = Camera::fit(&pts, View::TOP, 100.0, 100.0, 0.1);
        assert!((c.scale() - 40.0).abs() < 1e-12);
        assert!(close(c.project([0.0, 0.0, 0.0]), [10.0, 70.0, 0.0]));
        assert!(close(c.project([2.0, 1.0, 0.0]), [90.0, 30.0, 0.0]));
        // A single point: scale 1, centred.
        let c = Camera::fit(&[[5.0, 5.0, 5.0]], View::TOP, 10.0, 10.0, 0.1);
        assert!(close(c.project([5.0, 5.0, 5.0]), [5.0, 5.0, 5.0]));
    }
}
