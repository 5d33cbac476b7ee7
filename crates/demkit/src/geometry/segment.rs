//! Distances from a point to segments and polygons in the plane.

/// The distance from `p` to the segment `[a, b]`, and the parameter `t ∈ [0, 1]` of the
/// nearest point `a + t (b − a)` (0 for a segment of zero length).
pub fn segment_distance(p: [f64; 2], a: [f64; 2], b: [f64; 2]) -> (f64, f64) {
    let (ux, uy) = (b[0] - a[0], b[1] - a[1]);
    let (wx, wy) = (p[0] - a[0], p[1] - a[1]);
    let len2 = ux * ux + uy * uy;
    let t = if len2 > 0.0 {
        ((wx * ux + wy * uy) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    ((wx - t * ux).hypot(wy - t * uy), t)
}

/// The distance from `p` to the nearest edge of the closed polygon with corners `corners`
/// (∞ for no corner).
pub fn polygon_distance(
    corners: impl ExactSizeIterator<Item = [f64; 2]> + Clone,
    p: [f64; 2],
) -> f64 {
    let n = corners.len();
    let first = corners.clone().next();
    let next = corners.clone().skip(1).chain(first);
    corners
        .zip(next)
        .take(n)
        .map(|(a, b)| segment_distance(p, a, b).0)
        .fold(f64::INFINITY, f64::min)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn distances_to_a_segment_and_a_square() {
        let (d, t) = segment_distance([0.5, 1.0], [0.0, 0.0], [1.0, 0.0]);
        assert!((d - 1.0).abs() < 1e-15 && (t - 0.5).abs() < 1e-15);
        let (d, t) = segment_distance([3.0, 4.0], [0.0, 0.0], [0.0, 0.0]);
        assert!((d - 5.0).abs() < 1e-15 && t == 0.0);
        let (d, t) = segment_distance([-1.0, 0.0], [0.0, 0.0], [2.0, 0.0]);
        assert!((d - 1.0).abs() < 1e-15 && t == 0.0);
        let square = [[0.0, 0.0], [2.0, 0.0], [2.0, 2.0], [0.0, 2.0]];
        assert!((polygon_distance(square.iter().copied(), [0.5, 1.0]) - 0.5).abs() < 1e-15);
        assert!((polygon_distance(square.iter().copied(), [3.0, 1.0]) - 1.0).abs() < 1e-15);
        assert_eq!(
            polygon_distance(std::iter::empty::<[f64; 2]>(), [0.0, 0.0]),
            f64::INFINITY
        );
    }
}
