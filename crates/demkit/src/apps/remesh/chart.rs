//! The target domain of a map seen as a chart of the input surface: locating a domain point in
//! the mapped mesh and pulling it back (barycentric interpolation of the input positions), the
//! orientation of a triangle in the domain, and the domain displacement that moves a pulled-back
//! point by a given tangent vector on the surface (through the inverse of the map's Jacobian on
//! the face it lies in).

use super::Target;
use crate::TriMesh;
use crate::geometry::locate::{
    Location, PeriodicLocator, PlanarLocator, SphericalLocator, interpolate,
};
use crate::geometry::{cross, dot, sub};

enum Locator {
    Plane(PlanarLocator, f64),
    Sphere(SphericalLocator),
    Torus(PeriodicLocator, [f64; 2]),
}

/// A chart: the input surface over the domain of its map. Domain points are `[f64; 3]`: z = 0
/// in the plane and on the flat torus, unit vectors on the sphere (on an ellipsoid, the map's
/// image on the unit sphere).
pub struct Chart<'a> {
    input: &'a TriMesh,
    locator: Locator,
    /// The domain corners of every input face (on the flat torus, translated next to the
    /// face's first corner).
    corners: Vec<[[f64; 3]; 3]>,
    /// The domain point of every input vertex.
    points: Vec<[f64; 3]>,
}

/// A point of the chart: where it lies in the domain, the input face it falls in and its
/// position on the surface.
#[derive(Debug, Clone, Copy)]
pub struct ChartPoint {
    /// The point in the domain.
    pub domain: [f64; 3],
    /// The input face containing it.
    pub face: usize,
    /// Its position on the input surface.
    pub position: [f64; 3],
}

impl<'a> Chart<'a> {
    /// The chart of `input` through its map (`mapped` for planar and spherical maps).
    pub fn new(input: &'a TriMesh, mapped: &[[f64; 3]], target: Target) -> Self {
        let faces = &input.faces;
        match target {
            Target::Plane => {
                let signed: f64 = faces
                    .iter()
                    .map(|f| {
                        let [a, b, c] = f.map(|v| mapped[v as usize]);
                        cross2(a, b, c)
                    })
                    .sum();
                Chart {
                    input,
                    locator: Locator::Plane(
                        PlanarLocator::new(mapped, faces),
                        if signed < 0.0 { -1.0 } else { 1.0 },
                    ),
                    corners: face_corners(mapped, faces),
                    points: mapped.to_vec(),
                }
            }
            Target::Sphere => Chart {
                input,
                locator: Locator::Sphere(SphericalLocator::new(mapped, faces)),
                corners: face_corners(mapped, faces),
                points: mapped.to_vec(),
            },
            Target::Ellipsoid(e) => {
                let on_sphere: Vec<[f64; 3]> = mapped.iter().map(|&p| e.to_sphere(p)).collect();
                Self::new(input, &on_sphere, Target::Sphere)
            }
            Target::Torus { map, torus } => {
                let period = torus.periods();
                Chart {
                    input,
                    locator: Locator::Torus(PeriodicLocator::new(map, faces, period), period),
                    corners: (0..faces.len())
                        .map(|f| map.corners(faces, f, period))
                        .collect(),
                    points: map.points.iter().map(|p| [p[0], p[1], 0.0]).collect(),
                }
            }
        }
    }

    /// The face containing domain point `p` and the point on the surface, or `None` outside
    /// the map.
    pub fn pull(&self, p: [f64; 3]) -> Option<ChartPoint> {
        let loc: Location = match &self.locator {
            Locator::Plane(l, _) => l.locate([p[0], p[1]]),
            Locator::Sphere(l) => l.locate(p),
            Locator::Torus(l, _) => l.locate([p[0], p[1]]),
        }?;
        let face = self.input.faces[loc.face];
        Some(ChartPoint {
            domain: p,
            face: loc.face,
            position: interpolate(&self.input.positions, face, loc.weights),
        })
    }

    /// [`Chart::pull`], or where it fails (a gap in a map that is not bijective; never for
    /// points well inside a bijective map), the input vertex whose domain point is nearest.
    pub fn pull_or_nearest(&self, p: [f64; 3]) -> ChartPoint {
        if let Some(c) = self.pull(p) {
            return c;
        }
        let d2 = |q: &[f64; 3]| -> f64 {
            let mut e = sub(*q, p);
            if let Locator::Torus(_, period) = &self.locator {
                for d in 0..2 {
                    e[d] -= (e[d] / period[d]).round() * period[d];
                }
            }
            dot(e, e)
        };
        let v = (0..self.points.len())
            .min_by(|&a, &b| d2(&self.points[a]).total_cmp(&d2(&self.points[b])))
            .unwrap_or(0);
        let face = self
            .input
            .faces
            .iter()
            .position(|f| f.contains(&(v as u32)))
            .unwrap_or(0);
        ChartPoint {
            domain: self.points[v],
            face,
            position: self.input.positions[v],
        }
    }

    /// The orientation of the domain triangle `(a, b, c)`: positive when it is oriented like
    /// the map's image of the input faces.
    pub fn orientation(&self, a: [f64; 3], b: [f64; 3], c: [f64; 3]) -> f64 {
        match &self.locator {
            Locator::Plane(_, sign) => sign * cross2(a, b, c),
            Locator::Sphere(_) => dot(a, cross(b, c)),
            Locator::Torus(_, period) => {
                let near = |q: [f64; 3]| {
                    let mut q = q;
                    for d in 0..2 {
                        q[d] -= ((q[d] - a[d]) / period[d]).round() * period[d];
                    }
                    q
                };
                cross2(a, near(b), near(c))
            }
        }
    }

    /// The domain point reached from `p` (lying in input face `face`) by the displacement whose
    /// image on the surface is the tangent part of `d` (least squares through the map's
    /// Jacobian on that face); `None` when the face is degenerate.
    pub fn displaced(&self, p: [f64; 3], face: usize, d: [f64; 3]) -> Option<[f64; 3]> {
        let [x0, x1, x2] = self.input.corners(face);
        let (e1, e2) = (sub(x1, x0), sub(x2, x0));
        let (g11, g12, g22) = (dot(e1, e1), dot(e1, e2), dot(e2, e2));
        let det = g11 * g22 - g12 * g12;
        if !(det > 1e-14 * g11 * g22) {
            return None;
        }
        let (r1, r2) = (dot(e1, d), dot(e2, d));
        let a1 = (g22 * r1 - g12 * r2) / det;
        let a2 = (g11 * r2 - g12 * r1) / det;
        let [m0, m1, m2] = self.corners[face];
        let q = [0, 1, 2].map(|k| p[k] + a1 * (m1[k] - m0[k]) + a2 * (m2[k] - m0[k]));
        Some(match &self.locator {
            Locator::Sphere(_) => {
                let n = dot(q, q).sqrt();
                q.map(|x| x / n)
            }
            _ => q,
        })
    }
}

fn face_corners(points: &[[f64; 3]], faces: &[[u32; 3]]) -> Vec<[[f64; 3]; 3]> {
    faces
        .iter()
        .map(|f| f.map(|v| points[v as usize]))
        .collect()
}

fn cross2(a: [f64; 3], b: [f64; 3], c: [f64; 3]) -> f64 {
    (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two triangles of the unit square in space (tilted), mapped affinely onto the plane.
    fn tilted_square() -> (TriMesh, Vec<[f64; 3]>) {
        let input = TriMesh::new(
            vec![
                [0.0, 0.0, 0.0],
                [1.0, 0.0, 1.0],
                [1.0, 1.0, 1.0],
                [0.0, 1.0, 0.0],
            ],
            vec![[0, 1, 2], [0, 2, 3]],
        );
        // (x, y, z) ↦ (3x, y): a stretched domain.
        let mapped = input
            .positions
            .iter()
            .map(|p| [3.0 * p[0], p[1], 0.0])
            .collect();
        (input, mapped)
    }

    #[test]
    fn pulling_back_inverts_an_affine_map() {
        let (input, mapped) = tilted_square();
        let chart = Chart::new(&input, &mapped, Target::Plane);
        let p = chart.pull([1.5, 0.25, 0.0]).unwrap();
        for (a, b) in p.position.iter().zip([0.5, 0.25, 0.5]) {
            assert!((a - b).abs() < 1e-12);
        }
        assert!(chart.pull([3.5, 0.5, 0.0]).is_none());
        let far = chart.pull_or_nearest([3.5, 0.9, 0.0]);
        assert_eq!(far.position, [1.0, 1.0, 1.0]);
        assert!(chart.orientation([0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]) > 0.0);
    }

    #[test]
    fn a_move_on_the_surface_becomes_the_matching_move_in_the_domain() {
        let (input, mapped) = tilted_square();
        let chart = Chart::new(&input, &mapped, Target::Plane);
        let p = chart.pull([1.5, 0.25, 0.0]).unwrap();
        // Along the surface by (0.1, 0, 0.1): x grows by 0.1, so the domain's u by 0.3.
        let q = chart.displaced(p.domain, p.face, [0.1, 0.0, 0.1]).unwrap();
        assert!((q[0] - 1.8).abs() < 1e-12 && (q[1] - 0.25).abs() < 1e-12);
        // The normal part of a move is dropped.
        let r = chart.displaced(p.domain, p.face, [-0.1, 0.0, 0.1]).unwrap();
        assert!((r[0] - 1.5).abs() < 1e-12 && (r[1] - 0.25).abs() < 1e-12);
    }
}
