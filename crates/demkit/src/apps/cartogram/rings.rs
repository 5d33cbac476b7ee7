//! Plane geometry of rings and segments: signed areas and orientations, the area of a
//! polygon with holes, point-in-ring, orientation of a point to a line, point-to-segment
//! distance and bounding boxes.

/// Twice the signed area of a closed ring given without closing point, halved: positive when
/// counter-clockwise (shoelace formula).
pub fn ring_area(ring: &[[f64; 2]]) -> f64 {
    let n = ring.len();
    let mut s = 0.0;
    for i in 0..n {
        let (p, q) = (ring[i], ring[(i + 1) % n]);
        s += p[0] * q[1] - p[1] * q[0];
    }
    0.5 * s
}

/// +1 when the ring runs counter-clockwise, −1 when clockwise, 0 when its area vanishes;
/// decided on the ring moved to its first point and scaled to unit size, so that no product
/// overflows or underflows whatever the coordinates' magnitude.
pub fn ring_orientation(ring: &[[f64; 2]]) -> f64 {
    let Some(&o) = ring.first() else { return 0.0 };
    // Halved offsets cannot overflow; their largest magnitude sets the scale.
    let half: Vec<[f64; 2]> = ring
        .iter()
        .map(|p| [0.5 * p[0] - 0.5 * o[0], 0.5 * p[1] - 0.5 * o[1]])
        .collect();
    let s = half
        .iter()
        .fold(0.0f64, |m, d| m.max(d[0].abs()).max(d[1].abs()));
    if !(s > 0.0 && s.is_finite()) {
        return 0.0;
    }
    let unit: Vec<[f64; 2]> = half.iter().map(|d| [d[0] / s, d[1] / s]).collect();
    let a = ring_area(&unit);
    if a > 0.0 {
        1.0
    } else if a < 0.0 {
        -1.0
    } else {
        0.0
    }
}

/// The area of a polygon (exterior minus holes, whatever the rings' orientations).
pub fn polygon_area(rings: &[Vec<[f64; 2]>]) -> f64 {
    rings
        .iter()
        .enumerate()
        .map(|(j, r)| {
            if j == 0 {
                ring_area(r).abs()
            } else {
                -ring_area(r).abs()
            }
        })
        .sum()
}

/// Whether `p` lies inside the closed polygon `ring` (even–odd rule).
pub(crate) fn inside_ring(p: [f64; 2], ring: &[[f64; 2]]) -> bool {
    let mut inside = false;
    let n = ring.len();
    for i in 0..n {
        let (a, b) = (ring[i], ring[(i + 1) % n]);
        if (a[1] > p[1]) != (b[1] > p[1]) {
            let x = a[0] + (p[1] - a[1]) / (b[1] - a[1]) * (b[0] - a[0]);
            if p[0] < x {
                inside = !inside;
            }
        }
    }
    inside
}

/// Orientation of `c` with respect to the line `a → b` (positive: left).
pub(crate) fn orient(a: [f64; 2], b: [f64; 2], c: [f64; 2]) -> f64 {
    (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])
}

/// The point of the segment `a`–`b` nearest to `p`.
pub(crate) fn closest_point(p: [f64; 2], a: [f64; 2], b: [f64; 2]) -> [f64; 2] {
    let d = [b[0] - a[0], b[1] - a[1]];
    let len2 = d[0] * d[0] + d[1] * d[1];
    let t = if len2 > 0.0 {
        (((p[0] - a[0]) * d[0] + (p[1] - a[1]) * d[1]) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    [a[0] + t * d[0], a[1] + t * d[1]]
}

/// The distance from `p` to the segment `a`–`b`.
pub(crate) fn segment_distance(p: [f64; 2], a: [f64; 2], b: [f64; 2]) -> f64 {
    let q = closest_point(p, a, b);
    (p[0] - q[0]).hypot(p[1] - q[1])
}

/// The lower corner of the box of `a` and `b`, moved by `pad` on both axes.
pub(crate) fn min2(a: [f64; 2], b: [f64; 2], pad: f64) -> [f64; 2] {
    [a[0].min(b[0]) + pad, a[1].min(b[1]) + pad]
}

/// The upper corner of the box of `a` and `b`, moved by `pad` on both axes.
pub(crate) fn max2(a: [f64; 2], b: [f64; 2], pad: f64) -> [f64; 2] {
    [a[0].max(b[0]) + pad, a[1].max(b[1]) + pad]
}

/// One region's polygons with every ring vertex `v` replaced by `point(v)`, in ring order:
/// index rings made coordinates, coordinates carried to another frame, or coordinates
/// numbered.
pub(crate) fn map_polygons<T: Copy, U>(
    polygons: &[Vec<Vec<T>>],
    mut point: impl FnMut(T) -> U,
) -> Vec<Vec<Vec<U>>> {
    polygons
        .iter()
        .map(|p| {
            p.iter()
                .map(|ring| ring.iter().map(|&v| point(v)).collect())
                .collect()
        })
        .collect()
}

/// Bounding box of points.
pub(crate) fn bbox(points: impl Iterator<Item = [f64; 2]>) -> ([f64; 2], [f64; 2]) {
    crate::geometry::bounds(points)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn square(x: f64, y: f64, s: f64) -> Vec<[f64; 2]> {
        vec![[x, y], [x + s, y], [x + s, y + s], [x, y + s]]
    }

    #[test]
    fn polygon_area_subtracts_holes_whatever_their_orientation() {
        let outer = square(0.0, 0.0, 3.0);
        let mut hole = square(1.0, 1.0, 1.0);
        assert_eq!(polygon_area(&[outer.clone(), hole.clone()]), 8.0);
        hole.reverse();
        assert_eq!(polygon_area(&[outer, hole]), 8.0);
    }
}
