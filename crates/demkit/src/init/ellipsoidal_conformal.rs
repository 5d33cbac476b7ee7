//! Ellipsoidal conformal parameterization of a genus-0 closed surface (Choi, "Fast ellipsoidal
//! conformal and quasi-conformal parameterization of genus-0 closed surfaces", 2024, §3): the
//! initial map of EDEM and EDEQ.
//!
//! 1. The spherical conformal map S of the surface ([`super::spherical_conformal`]).
//! 2. The Möbius normalization: the surface's topmost and bottommost points (largest and
//!    smallest input z) are sent to the north and south poles, its rightmost point (largest x)
//!    to the meridian of +x, and the plane of the stereographic projection is scaled so that
//!    the faces at the two poles get the same size (§3.1). The ellipsoid's long axis then lies
//!    along the surface's own.
//! 3. The ellipsoidal stereographic map `E = M ∘ σ⁻¹` (σ the stereographic projection from the
//!    north pole, `M = diag(a, b, c)`) carries the plane onto the ellipsoid, but not
//!    conformally. Its Beltrami coefficient μ_E is measured on every face of the plane image of
//!    the surface (the face at the north pole punctured, its corners fixed), and the linear
//!    Beltrami solver gives the quasi-conformal map g of the plane with μ_g = μ_E (§3.2). Then
//!    `E ∘ g⁻¹` is conformal, and the map is `E ∘ g⁻¹ ∘ σ ∘ S`.
//! 4. `g⁻¹` at each vertex: the vertex's point is located in the triangulation g(σ ∘ S) (on the
//!    sphere, [`SphericalWalk`]) and interpolated back with its barycentric coordinates; the
//!    result is sent onto the ellipsoid by E exactly, so every vertex lies on the ellipsoid to
//!    rounding. (The authors interpolate E's values with scattered-data interpolation, whose
//!    points lie inside the ellipsoid between its vertices.)
//! 5. g is the identity near the north pole, where it is pinned, so the scale of step 2 is not
//!    kept between the poles. Every dilation λ of the plane is a Möbius map keeping both poles
//!    and the meridian, so `E ∘ g⁻¹ ∘ (λ ·)` is as conformal; λ is chosen to match the face
//!    areas to the population best (as SDEM's initial map takes the Möbius map that does,
//!    SDEM paper §3.1.1).

use crate::geometry::ellipsoid::Ellipsoid;
use crate::geometry::locate::SphericalWalk;
use crate::geometry::sphere::{
    mat_vec, normalize, project_from_north, rotation_to_north, spherical_flipped,
    spherical_orientation, unproject_from_north,
};
use crate::geometry::{add, face_areas, norm, scale, sub};
use crate::linalg::VertexOrder;
use crate::metrics::log_area_misfit;
use crate::optimize::sampled_golden_section;
use crate::qc::{LinearBeltramiSolver, beltrami_coefficient_plane_to_surface, truncate};
use crate::{Error, Result};
use num_complex::Complex64;
use rayon::prelude::*;

/// The ellipsoidal conformal map of the genus-0 closed mesh (`positions`, `faces`) onto
/// `ellipsoid`: one point of the ellipsoid per vertex, faces counter-clockwise seen from
/// outside. Of the conformal maps that keep the poles and the meridian of step 2, the one
/// whose face areas best match `population` (one positive value per face; the input's face
/// areas for an area-preserving start): the dilation of the plane is searched (module docs).
/// `notes` receives remarks (fallbacks taken).
pub fn ellipsoidal_conformal_map(
    positions: &[[f64; 3]],
    faces: &[[u32; 3]],
    ellipsoid: &Ellipsoid,
    population: &[f64],
    notes: &mut Vec<String>,
) -> Result<Vec<[f64; 3]>> {
    if positions.len() < 4 || faces.len() < 4 {
        return Err(Error::InvalidMesh(
            "a closed surface needs at least 4 vertices and 4 faces".into(),
        ));
    }
    crate::population::check_population(population, faces.len())?;
    let order = VertexOrder::of_mesh(positions.len(), faces)?;
    ellipsoidal_conformal_map_in_order(positions, faces, ellipsoid, population, &order, notes)
}

/// [`ellipsoidal_conformal_map`] with the connectivity's elimination `order` computed by the
/// caller ([`VertexOrder`]), who solves other systems on the same connectivity.
pub(crate) fn ellipsoidal_conformal_map_in_order(
    positions: &[[f64; 3]],
    faces: &[[u32; 3]],
    ellipsoid: &Ellipsoid,
    population: &[f64],
    order: &VertexOrder,
    notes: &mut Vec<String>,
) -> Result<Vec<[f64; 3]>> {
    let sphere = NormalizedSphere::new(positions, faces, order, notes)?;
    Ok(sphere.onto(faces, ellipsoid, population, order, notes))
}

/// Steps 1 and 2, which do not depend on the ellipsoid: the surface's spherical conformal
/// map, Möbius-normalized. One of them serves the maps onto any number of ellipsoids
/// ([`Self::onto`]).
pub(crate) struct NormalizedSphere {
    normalized: Vec<[f64; 3]>,
    poles: Poles,
}

impl NormalizedSphere {
    /// Steps 1 and 2 for the genus-0 closed mesh (`positions`, `faces`) with its elimination
    /// `order`; `notes` receives the spherical map's remarks.
    pub(crate) fn new(
        positions: &[[f64; 3]],
        faces: &[[u32; 3]],
        order: &VertexOrder,
        notes: &mut Vec<String>,
    ) -> Result<Self> {
        let sphere = super::spherical_conformal::spherical_conformal_map_in_order(
            positions, faces, order, notes,
        )?;
        let poles = Poles::of(positions, faces);
        let normalized = normalize_mobius(&sphere, faces, &poles);
        Ok(Self { normalized, poles })
    }

    /// Steps 3 to 5 onto `ellipsoid`: the ellipsoidal conformal map of the surface whose face
    /// areas best match `population`. When the correction fails or folds, the normalized
    /// spherical map scaled onto the ellipsoid, with a note.
    pub(crate) fn onto(
        &self,
        faces: &[[u32; 3]],
        ellipsoid: &Ellipsoid,
        population: &[f64],
        order: &VertexOrder,
        notes: &mut Vec<String>,
    ) -> Vec<[f64; 3]> {
        let (normalized, poles) = (&self.normalized, &self.poles);
        let corrected = if ellipsoid.is_unit_sphere() {
            Ok(Dilations::new(
                normalized,
                normalized.clone(),
                faces,
                poles,
                ellipsoid,
            ))
        } else {
            conformal_correction(normalized, faces, ellipsoid, poles, order)
        };
        if let Ok(dilations) = corrected {
            if let Some(map) = dilations.balanced(population)
                && !faces.par_iter().any(|&f| spherical_flipped(&map, f))
            {
                return map;
            }
            notes.push(
                "the ellipsoidal conformal correction folded the map; the normalized spherical \
                 conformal map scaled onto the ellipsoid was used instead"
                    .into(),
            );
        } else {
            notes.push(
                "the ellipsoidal conformal correction failed; the normalized spherical \
                 conformal map scaled onto the ellipsoid was used instead"
                    .into(),
            );
        }
        normalized
            .iter()
            .map(|&u| ellipsoid.from_sphere(u))
            .collect()
    }
}

/// The faces of the surface that go to the poles, and the vertex that goes to the meridian of
/// +x (step 2).
struct Poles {
    /// The face whose centroid is closest to the topmost vertex (largest z).
    north: usize,
    /// The face whose centroid is closest to the bottommost vertex.
    south: usize,
    /// The rightmost vertex (largest x).
    right: usize,
}

impl Poles {
    fn of(positions: &[[f64; 3]], faces: &[[u32; 3]]) -> Self {
        let extreme = |key: &dyn Fn(&[f64; 3]) -> f64| {
            (0..positions.len())
                .max_by(|&i, &j| key(&positions[i]).total_cmp(&key(&positions[j])))
                .unwrap_or(0)
        };
        let top = positions[extreme(&|p| p[2])];
        let bottom = positions[extreme(&|p| -p[2])];
        let right = extreme(&|p| p[0]);
        let nearest = |target: [f64; 3]| {
            (0..faces.len())
                .min_by(|&f, &g| {
                    let d = |f: usize| {
                        let c = faces[f]
                            .iter()
                            .fold([0.0; 3], |c, &v| add(c, positions[v as usize]));
                        norm(sub(scale(c, 1.0 / 3.0), target))
                    };
                    d(f).total_cmp(&d(g))
                })
                .unwrap_or(0)
        };
        let north = nearest(top);
        let mut south = nearest(bottom);
        if south == north {
            south = (north + 1) % faces.len();
        }
        Poles {
            north,
            south,
            right,
        }
    }
}

/// The unit vector of the centroid of face `f` of the spherical map `s`.
fn face_direction(s: &[[f64; 3]], f: [u32; 3]) -> [f64; 3] {
    normalize(f.iter().fold([0.0; 3], |c, &v| add(c, s[v as usize])))
}

/// Step 2: the Möbius transformation of the sphere sending the north face's centroid to the
/// north pole and the south face's to the south pole, the rightmost vertex to the meridian of
/// +x, scaled so that both polar faces have the same perimeter in the plane that sees them
/// from the other pole.
fn normalize_mobius(s: &[[f64; 3]], faces: &[[u32; 3]], poles: &Poles) -> Vec<[f64; 3]> {
    // Rotate the north face's centroid to the north pole, project from it: the plane w.
    let r = rotation_to_north(face_direction(s, faces[poles.north]));
    let w: Vec<[f64; 2]> = s
        .par_iter()
        .map(|&p| {
            let q = project_from_north(mat_vec(&r, p));
            [q[0], q[1]]
        })
        .collect();
    // Translate the south face's centroid to 0 (the south pole), turn the rightmost vertex
    // onto the positive real axis.
    let sc = project_from_north(mat_vec(&r, face_direction(s, faces[poles.south])));
    let shifted = |p: [f64; 2]| Complex64::new(p[0] - sc[0], p[1] - sc[1]);
    let turn = {
        let z = shifted(w[poles.right]);
        if z.norm() > 0.0 {
            z.conj() / z.norm()
        } else {
            Complex64::new(1.0, 0.0)
        }
    };
    let z: Vec<Complex64> = w.par_iter().map(|&p| shifted(p) * turn).collect();
    // Scale: the north face's perimeter in z (it lies far out) against the south face's in
    // 1/z (it lies around 0); scaling z by λ multiplies the first by λ and divides the second.
    let perimeter = |f: [u32; 3], m: &dyn Fn(Complex64) -> Complex64| {
        (0..3)
            .map(|k| (m(z[f[k] as usize]) - m(z[f[(k + 1) % 3] as usize])).norm())
            .sum::<f64>()
    };
    let pn = perimeter(faces[poles.north], &|x| x);
    let ps = perimeter(faces[poles.south], &|x| x.inv());
    let lambda = if pn > 0.0 && ps > 0.0 && (ps / pn).is_finite() {
        (ps / pn).sqrt()
    } else {
        1.0
    };
    z.par_iter()
        .map(|&x| unproject_from_north([lambda * x.re, lambda * x.im, 0.0]))
        .collect()
}

/// Step 3 on the normalized spherical map `u` (north face `north` around the north pole): the
/// quasi-conformal map g of its plane, with which the maps `E ∘ g⁻¹ ∘ (λ ·)` onto `ellipsoid`
/// are conformal.
fn conformal_correction<'a>(
    u: &'a [[f64; 3]],
    faces: &'a [[u32; 3]],
    ellipsoid: &'a Ellipsoid,
    poles: &Poles,
    order: &VertexOrder,
) -> Result<Dilations<'a>> {
    let north = poles.north;
    let n = u.len();
    // The plane of the punctured sphere, and E of it.
    let p: Vec<[f64; 3]> = u.par_iter().map(|&x| project_from_north(x)).collect();
    let on_ellipsoid: Vec<[f64; 3]> = u.par_iter().map(|&x| ellipsoid.from_sphere(x)).collect();
    let punctured: Vec<[u32; 3]> = faces
        .iter()
        .enumerate()
        .filter(|&(f, _)| f != north)
        .map(|(_, &t)| t)
        .collect();
    let mu: Vec<Complex64> = beltrami_coefficient_plane_to_surface(&p, &on_ellipsoid, &punctured)
        .into_iter()
        .map(|m| truncate(m, 0.1))
        .collect();
    // g = identity on the punctured face's corners and the outermost vertices of the plane
    // (about one in a hundred, at most 50: where the plane is coarsest), as in §3.2.
    let mut fixed = vec![false; n];
    for &v in &faces[north] {
        fixed[v as usize] = true;
    }
    let mut by_radius: Vec<usize> = (0..n).collect();
    by_radius.sort_unstable_by(|&i, &j| {
        let r = |k: usize| p[k][0] * p[k][0] + p[k][1] * p[k][1];
        r(j).total_cmp(&r(i))
    });
    for &v in by_radius.iter().take((n / 100).min(50)) {
        fixed[v] = true;
    }
    let lbs = LinearBeltramiSolver::in_order(n, &punctured, &fixed, Some(order))?;
    let g = lbs.solve(&p, &mu, &p)?;
    if g.iter().any(|q| !q[0].is_finite() || !q[1].is_finite()) {
        return Err(Error::Numerical(
            "the ellipsoidal conformal correction diverged".into(),
        ));
    }
    let image: Vec<[f64; 3]> = g.par_iter().map(|&q| unproject_from_north(q)).collect();
    Ok(Dilations::new(u, image, faces, poles, ellipsoid))
}

/// The conformal maps `E ∘ g⁻¹ ∘ T` of the plane of the normalized spherical map `u`, for the
/// Möbius maps `T(z) = λ e^{iθ} z + g(0)` that keep the surface's poles on the ellipsoid's
/// (g moves the plane's origin, which E sends to the south pole): each vertex's point of the
/// plane, moved by T, is located in the triangulation g(u) (on the sphere) and pulled back by
/// its barycentric coordinates (step 4).
struct Dilations<'a> {
    /// The normalized spherical map (the plane's points, on the sphere).
    u: &'a [[f64; 3]],
    /// Its stereographic image, as complex numbers.
    plane: Vec<Complex64>,
    faces: &'a [[u32; 3]],
    /// Point location in the triangulation g(u), on the sphere.
    locator: SphericalWalk,
    /// g(0), in the plane.
    origin: Complex64,
    /// The vertex to keep on the meridian of +x.
    right: usize,
    ellipsoid: &'a Ellipsoid,
}

impl<'a> Dilations<'a> {
    /// `image`: g(u) on the sphere (u itself for the unit sphere, where g is the identity);
    /// `poles`: where the poles and the meridian are.
    fn new(
        u: &'a [[f64; 3]],
        image: Vec<[f64; 3]>,
        faces: &'a [[u32; 3]],
        poles: &Poles,
        ellipsoid: &'a Ellipsoid,
    ) -> Self {
        let plane: Vec<Complex64> = u
            .par_iter()
            .map(|&x| {
                let p = project_from_north(x);
                Complex64::new(p[0], p[1])
            })
            .collect();
        // g(0): the south pole lies in the south face; its barycentric coordinates there (of
        // the ray's crossing with the flat face) carried to the face's corners in g(u).
        let south = faces[poles.south];
        let c = south.map(|v| u[v as usize]);
        let pole = [0.0, 0.0, -1.0];
        let w = [
            spherical_orientation(pole, c[1], c[2]),
            spherical_orientation(c[0], pole, c[2]),
            spherical_orientation(c[0], c[1], pole),
        ];
        let sum = w[0] + w[1] + w[2];
        let origin = if sum > 0.0 && w.iter().all(|&x| x >= 0.0) {
            let q = (0..3).fold([0.0; 3], |acc, k| {
                add(acc, scale(image[south[k] as usize], w[k] / sum))
            });
            let q = project_from_north(normalize(q));
            Complex64::new(q[0], q[1])
        } else {
            Complex64::new(0.0, 0.0)
        };
        Self {
            u,
            plane,
            faces,
            locator: SphericalWalk::new(&image, faces),
            origin,
            right: poles.right,
            ellipsoid,
        }
    }

    /// `g⁻¹(T(z))` on the sphere for `T(z) = rotation · z + g(0)`; `None` outside the
    /// triangulation.
    fn pull_back(&self, z: Complex64, rotation: Complex64) -> Option<[f64; 3]> {
        let w = z * rotation + self.origin;
        let at = self
            .locator
            .locate(unproject_from_north([w.re, w.im, 0.0]))?;
        let f = self.faces[at.face];
        let q = (0..3).fold([0.0; 3], |c, k| {
            add(c, scale(self.u[f[k] as usize], at.weights[k]))
        });
        Some(normalize(q))
    }

    /// The points of `vertices` on the ellipsoid for `T(z) = rotation · z + g(0)` (rotation
    /// = λ e^{iθ}); `None` if a point falls outside the triangulation.
    fn points(&self, vertices: &[u32], rotation: Complex64) -> Option<Vec<[f64; 3]>> {
        vertices
            .par_iter()
            .map(|&v| {
                let q = self.pull_back(self.plane[v as usize], rotation)?;
                Some(self.ellipsoid.project(self.ellipsoid.from_sphere(q)))
            })
            .collect()
    }

    /// The map of every vertex for `T(z) = rotation · z + g(0)`.
    fn map(&self, rotation: Complex64) -> Option<Vec<[f64; 3]>> {
        let all: Vec<u32> = (0..self.plane.len() as u32).collect();
        self.points(&all, rotation)
    }

    /// The map whose face areas best match `population`: the dilation λ = e^t minimising the
    /// face misfit mean |log((A/ΣA)/(P/ΣP))| over t ∈ [−6, 6] (7 samples, then golden sections
    /// in the bracket around the best; the misfit measured on at most [`SEARCH_FACES`] faces
    /// spread over the mesh), then θ turning the rightmost vertex onto the meridian of +x.
    /// `None` if no dilation gives a map.
    fn balanced(&self, population: &[f64]) -> Option<Vec<[f64; 3]>> {
        let sample = FaceSample::new(self.faces, population, SEARCH_FACES);
        let misfit = |t: f64| {
            self.points(&sample.vertices, Complex64::new(t.exp(), 0.0))
                .map_or(f64::INFINITY, |p| {
                    log_area_misfit(&sample.population, &face_areas(&p, &sample.faces))
                })
        };
        let (t, _) = sampled_golden_section(misfit, -DILATION_RANGE, DILATION_RANGE, 7, 24);
        // θ by a few fixed-point steps: turn by the longitude the rightmost vertex lands at.
        let mut rotation = Complex64::new(t.exp(), 0.0);
        for _ in 0..4 {
            let Some(q) = self.pull_back(self.plane[self.right], rotation) else {
                break;
            };
            let longitude = q[1].atan2(q[0]);
            if !longitude.is_finite() || longitude.abs() < 1e-9 {
                break;
            }
            // The plane of `project_from_north` has y mirrored: a longitude φ is at −φ in it.
            rotation *= Complex64::from_polar(1.0, longitude);
        }
        self.map(rotation)
    }
}

/// The dilation search measures the misfit on at most this many faces.
const SEARCH_FACES: usize = 4096;

/// Every k-th face of a mesh (k the least that leaves at most `limit`), re-indexed over the
/// vertices they use, with their population.
struct FaceSample {
    /// The vertices used, in the mesh's numbering.
    vertices: Vec<u32>,
    /// The faces, over `vertices`.
    faces: Vec<[u32; 3]>,
    population: Vec<f64>,
}

impl FaceSample {
    fn new(faces: &[[u32; 3]], population: &[f64], limit: usize) -> Self {
        let stride = faces.len().div_ceil(limit.max(1)).max(1);
        let mut local = std::collections::HashMap::new();
        let mut vertices = Vec::new();
        let mut sample = Vec::new();
        let mut pop = Vec::new();
        for f in (0..faces.len()).step_by(stride) {
            sample.push(faces[f].map(|v| {
                *local.entry(v).or_insert_with(|| {
                    vertices.push(v);
                    (vertices.len() - 1) as u32
                })
            }));
            pop.push(population[f]);
        }
        Self {
            vertices,
            faces: sample,
            population: pop,
        }
    }
}

/// The dilations searched are e^t for |t| up to this.
const DILATION_RANGE: f64 = 6.0;

#[cfg(test)]
mod tests {
    use super::*;
    use crate::generate::icosphere;
    use crate::qc::beltrami_coefficient_surfaces;

    fn mean_abs(mu: &[Complex64]) -> f64 {
        mu.iter().map(|m| m.norm()).sum::<f64>() / mu.len() as f64
    }

    /// The icosphere stretched onto the ellipsoid `e`.
    fn stretched(e: &Ellipsoid, level: usize) -> crate::TriMesh {
        let mut mesh = icosphere(level).unwrap();
        for p in mesh.positions.iter_mut() {
            *p = e.from_sphere(*p);
        }
        mesh
    }

    #[test]
    fn an_ellipsoid_maps_conformally_onto_itself_near_the_identity() {
        // The ellipsoid's own surface onto the same ellipsoid: a conformal map fixing the
        // poles and the +x meridian, which by symmetry is close to the identity.
        let e = Ellipsoid::new(1.0, 1.0, 2.0).unwrap();
        let mesh = stretched(&e, 4);
        let mut notes = Vec::new();
        let area = face_areas(&mesh.positions, &mesh.faces);
        let map =
            ellipsoidal_conformal_map(&mesh.positions, &mesh.faces, &e, &area, &mut notes).unwrap();
        assert!(notes.is_empty(), "{notes:?}");
        for p in &map {
            assert!(e.residual(*p) < 1e-12);
        }
        assert!(!mesh.faces.iter().any(|&f| spherical_flipped(&map, f)));
        let mu = beltrami_coefficient_surfaces(&mesh.positions, &map, &mesh.faces);
        assert!(mean_abs(&mu) < 0.02, "mean |mu| {}", mean_abs(&mu));
        let d: Vec<f64> = mesh
            .positions
            .iter()
            .zip(&map)
            .map(|(a, b)| norm(sub(*a, *b)))
            .collect();
        let far = d.iter().copied().fold(0.0, f64::max);
        let mean = d.iter().sum::<f64>() / d.len() as f64;
        assert!(
            far < 0.08 && mean < 0.04,
            "largest displacement {far}, mean {mean}"
        );
    }

    #[test]
    fn the_correction_beats_the_stretched_sphere_map() {
        // A sphere mapped onto a 1:2:4 ellipsoid: the spherical map stretched by M is far from
        // conformal; the corrected map is close to it.
        let e = Ellipsoid::new(1.0, 2.0, 4.0).unwrap();
        let mesh = icosphere(4).unwrap();
        let mut notes = Vec::new();
        let area = face_areas(&mesh.positions, &mesh.faces);
        let map =
            ellipsoidal_conformal_map(&mesh.positions, &mesh.faces, &e, &area, &mut notes).unwrap();
        assert!(notes.is_empty(), "{notes:?}");
        let stretched: Vec<[f64; 3]> = mesh.positions.iter().map(|&p| e.from_sphere(p)).collect();
        let mu_map = mean_abs(&beltrami_coefficient_surfaces(
            &mesh.positions,
            &map,
            &mesh.faces,
        ));
        let mu_stretched = mean_abs(&beltrami_coefficient_surfaces(
            &mesh.positions,
            &stretched,
            &mesh.faces,
        ));
        assert!(mu_stretched > 0.2, "{mu_stretched}");
        assert!(mu_map < 0.05, "{mu_map} against {mu_stretched}");
        assert!(!mesh.faces.iter().any(|&f| spherical_flipped(&map, f)));
        for p in &map {
            assert!(e.residual(*p) < 1e-12);
        }
    }

    #[test]
    fn the_normalization_puts_the_extremes_on_the_poles() {
        let mesh = stretched(&Ellipsoid::new(1.0, 1.5, 3.0).unwrap(), 3);
        let mut notes = Vec::new();
        let s = crate::init::spherical_conformal::spherical_conformal_map(
            &mesh.positions,
            &mesh.faces,
            &mut notes,
        )
        .unwrap();
        let poles = Poles::of(&mesh.positions, &mesh.faces);
        let u = normalize_mobius(&s, &mesh.faces, &poles);
        // The poles lie inside the polar faces.
        let inside = |f: [u32; 3], pole: [f64; 3]| {
            (0..3).all(|k| {
                let (a, b) = (u[f[k] as usize], u[f[(k + 1) % 3] as usize]);
                crate::geometry::sphere::spherical_orientation(a, b, pole) > 0.0
            })
        };
        assert!(inside(mesh.faces[poles.north], [0.0, 0.0, 1.0]));
        assert!(inside(mesh.faces[poles.south], [0.0, 0.0, -1.0]));
        let right = u[poles.right];
        assert!(right[0] > 0.0 && right[1].abs() < 1e-12, "{right:?}");
        // Still the same map up to a Möbius transformation: no flip, all on the sphere.
        assert!(!mesh.faces.iter().any(|&f| spherical_flipped(&u, f)));
        assert!(u.iter().all(|p| (norm(*p) - 1.0).abs() < 1e-12));
    }
}
