//! The Equal Earth projection (Šavrič, Patterson & Jenny 2018), an equal-area
//! pseudocylindrical projection of the world: longitude/latitude degrees to kilometres on a
//! sphere of radius [`EARTH_RADIUS_KM`], so that the planar cartogram of projected regions
//! measures their areas as on the globe. Long edges are split before projecting
//! ([`densify_degrees`]), since a straight edge in degrees is a curve in the projection.

use super::Polygon;

/// The sphere's radius, in km (the mean Earth radius).
pub const EARTH_RADIUS_KM: f64 = 6371.0;

const A1: f64 = 1.340264;
const A2: f64 = -0.081106;
const A3: f64 = 0.000893;
const A4: f64 = 0.003796;

/// √3 / 2: sin θ = M · sin φ.
const M: f64 = 0.866_025_403_784_438_6;

/// Longitude/latitude degrees to Equal Earth kilometres (x east, y north).
pub fn forward(p: [f64; 2]) -> [f64; 2] {
    let (lambda, phi) = (p[0].to_radians(), p[1].to_radians());
    let theta = (M * phi.sin()).clamp(-1.0, 1.0).asin();
    let t2 = theta * theta;
    let t6 = t2 * t2 * t2;
    let x = 2.0 * 3f64.sqrt() * lambda * theta.cos()
        / (3.0 * (A1 + 3.0 * A2 * t2 + t6 * (7.0 * A3 + 9.0 * A4 * t2)));
    let y = theta * (A1 + A2 * t2 + t6 * (A3 + A4 * t2));
    [EARTH_RADIUS_KM * x, EARTH_RADIUS_KM * y]
}

/// The inverse of [`forward`]: θ from y by Newton's iteration, then longitude and latitude.
/// A point beyond the poles' y is put on the pole.
pub fn inverse(q: [f64; 2]) -> [f64; 2] {
    let (x, y) = (q[0] / EARTH_RADIUS_KM, q[1] / EARTH_RADIUS_KM);
    let y_pole = {
        let t = (M).asin();
        let t2 = t * t;
        let t6 = t2 * t2 * t2;
        t * (A1 + A2 * t2 + t6 * (A3 + A4 * t2))
    };
    let y = y.clamp(-y_pole, y_pole);
    let mut theta = y / A1;
    for _ in 0..20 {
        let t2 = theta * theta;
        let t6 = t2 * t2 * t2;
        let f = theta * (A1 + A2 * t2 + t6 * (A3 + A4 * t2)) - y;
        let df = A1 + 3.0 * A2 * t2 + t6 * (7.0 * A3 + 9.0 * A4 * t2);
        let step = f / df;
        theta -= step;
        if step.abs() < 1e-15 {
            break;
        }
    }
    let t2 = theta * theta;
    let t6 = t2 * t2 * t2;
    let df = A1 + 3.0 * A2 * t2 + t6 * (7.0 * A3 + 9.0 * A4 * t2);
    let cos = theta.cos();
    let lambda = if cos > 0.0 {
        3.0 * x * df / (2.0 * 3f64.sqrt() * cos)
    } else {
        0.0
    };
    let phi = (theta.sin() / M).clamp(-1.0, 1.0).asin();
    [lambda.to_degrees(), phi.to_degrees()]
}

/// Edges longer than this, in degrees, are split before projecting.
pub const MAX_EDGE_DEGREES: f64 = 1.0;

/// Splits every edge of the rings longer than [`MAX_EDGE_DEGREES`] into equal parts, the
/// same points whichever way the edge is run (so that a border shared by two regions gets
/// the same vertices on both sides).
pub fn densify_degrees(polygons: &mut [Polygon]) {
    for ring in polygons.iter_mut().flatten() {
        let n = ring.len();
        let mut out = Vec::with_capacity(n);
        for i in 0..n {
            let (a, b) = (ring[i], ring[(i + 1) % n]);
            out.push(a);
            let len = (b[0] - a[0]).hypot(b[1] - a[1]);
            let parts = (len / MAX_EDGE_DEGREES).ceil();
            if !(parts > 1.0 && parts < 1e6) {
                continue;
            }
            let parts = parts as usize;
            // Computed from the lexicographically smaller end, so both directions agree.
            let (p, q, flip) = if (a[0], a[1]) <= (b[0], b[1]) {
                (a, b, false)
            } else {
                (b, a, true)
            };
            for k in 1..parts {
                let j = if flip { parts - k } else { k };
                let t = j as f64 / parts as f64;
                out.push([p[0] + t * (q[0] - p[0]), p[1] + t * (q[1] - p[1])]);
            }
        }
        *ring = out;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_inverse_undoes_the_projection() {
        for lon in [-180.0, -123.4, 0.0, 45.0, 179.9] {
            for lat in [-89.9, -60.0, -12.3, 0.0, 33.3, 75.0, 89.9] {
                let q = inverse(forward([lon, lat]));
                assert!(
                    (q[0] - lon).abs() < 1e-9 && (q[1] - lat).abs() < 1e-9,
                    "{lon} {lat}: {q:?}"
                );
            }
        }
        // On the equator (θ = 0), x = 2√3 λ / (3 A1) · R.
        let x = forward([180.0, 0.0])[0];
        let want = 2.0 * 3f64.sqrt() * std::f64::consts::PI / (3.0 * A1) * EARTH_RADIUS_KM;
        assert!((x - want).abs() < 1e-9, "{x} {want}");
    }

    #[test]
    fn small_cells_keep_their_area_on_the_sphere() {
        let r = EARTH_RADIUS_KM;
        for (lon, lat) in [(0.0, 0.0), (100.0, 45.0), (-170.0, -70.0), (30.0, 84.0)] {
            let d = 0.01f64;
            let cell = [
                [lon, lat],
                [lon + d, lat],
                [lon + d, lat + d],
                [lon, lat + d],
            ];
            let projected: Vec<[f64; 2]> = cell.iter().map(|&p| forward(p)).collect();
            let area = super::super::regions::ring_area(&projected);
            let sphere =
                r * r * d.to_radians() * ((lat + d).to_radians().sin() - lat.to_radians().sin());
            assert!(
                (area / sphere - 1.0).abs() < 1e-6,
                "({lon}, {lat}): {area} vs {sphere}"
            );
        }
    }

    #[test]
    fn long_edges_are_split_alike_in_both_directions() {
        let mut a = vec![vec![vec![[0.0, 0.0], [3.0, 0.0], [3.0, 1.0]]]];
        let mut b = vec![vec![vec![[3.0, 1.0], [3.0, 0.0], [0.0, 0.0]]]];
        densify_degrees(&mut a);
        densify_degrees(&mut b);
        // The 3 vertices, 2 inside the edge of length 3 and 3 inside that of length √10.
        assert_eq!(a[0][0].len(), 3 + 2 + 3);
        let mut pa = a[0][0].clone();
        let mut pb = b[0][0].clone();
        pa.sort_by(|p, q| p.partial_cmp(q).unwrap());
        pb.sort_by(|p, q| p.partial_cmp(q).unwrap());
        assert_eq!(pa, pb);
    }
}
