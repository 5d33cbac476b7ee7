//! The normalised frame of a cartogram's regions: input coordinates moved and scaled so that
//! squares of side 1e300 or 1e-300 are computed on the same numbers as unit squares.

/// A similarity of the plane that takes input coordinates to a normalised frame:
/// `q = (p − centre) / scale`. Built from a bounding box, it puts the box's centre at the
/// origin and its larger half-side at 1, with every step free of overflow and underflow for
/// any finite box of positive extent.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Frame {
    /// The input position that becomes the origin.
    pub centre: [f64; 2],
    /// The input length that becomes 1.
    pub scale: f64,
}

impl Frame {
    /// The identity (input coordinates are already normalised).
    pub const IDENTITY: Frame = Frame {
        centre: [0.0, 0.0],
        scale: 1.0,
    };

    /// The frame of the box `lo`–`hi` (centre at the origin, larger half-side 1), or `None`
    /// when the box is not finite or has no extent.
    pub fn of_box(lo: [f64; 2], hi: [f64; 2]) -> Option<Frame> {
        // Halves first: (hi − lo) may overflow, hi/2 − lo/2 cannot.
        let centre = [0.5 * lo[0] + 0.5 * hi[0], 0.5 * lo[1] + 0.5 * hi[1]];
        let scale = (0.5 * hi[0] - 0.5 * lo[0]).max(0.5 * hi[1] - 0.5 * lo[1]);
        (scale > 0.0 && scale.is_finite() && centre.iter().all(|c| c.is_finite()))
            .then_some(Frame { centre, scale })
    }

    /// Input coordinates → normalised ones.
    pub fn to_unit(&self, p: [f64; 2]) -> [f64; 2] {
        [
            (p[0] - self.centre[0]) / self.scale,
            (p[1] - self.centre[1]) / self.scale,
        ]
    }

    /// Normalised coordinates → input ones (not finite when the result lies beyond the range
    /// of `f64`).
    pub fn to_input(&self, q: [f64; 2]) -> [f64; 2] {
        [
            self.centre[0] + self.scale * q[0],
            self.centre[1] + self.scale * q[1],
        ]
    }

    /// A normalised area in input units (infinite beyond the range of `f64`, as for squares
    /// of side 1e300, whose area 1e600 has no `f64`).
    pub fn area_to_input(&self, a: f64) -> f64 {
        a * self.scale * self.scale
    }
}
