//! EDEM: ellipsoidal density-equalizing maps of genus-0 closed surfaces (Lyu, Lui & Choi,
//! "Ellipsoidal density-equalizing map for genus-0 closed surfaces", 2026, Algorithm 1).
//!
//! 1. Initial map: the ellipsoidal conformal map ([`crate::init::ellipsoidal_conformal`]); a
//!    surface that lies on the target ellipsoid already is its own initial map, as in the
//!    paper's examples (its mirror image in the plane x = 0 when its faces are oriented
//!    inwards, so that the map's faces are counter-clockwise seen from outside).
//! 2. SDEM's iteration ([`super::sdem`]) on the ellipsoid: the density diffused on the current
//!    map, the velocity −∇ρ/ρ made tangential to the ellipsoid (its normal is the gradient of
//!    x²/a² + y²/b² + z²/c²), the move brought back onto the ellipsoid along the ray from its
//!    centre, and the sphere's overlap correction applied to the map's image on the unit
//!    sphere through diag(1/a, 1/b, 1/c) — the paper's choices.
//! 3. Local area matching ([`super::polish`]): what the flow leaves of the face density's
//!    variance alternates from one triangle to the next, below what the vertex density it
//!    follows can see; sweeps of per-vertex least-squares moves take most of it away.
//!
//! Any radii work: the map is computed on the ellipsoid scaled by a power of two
//! ([`Ellipsoid::normalizing_exponent`]) and scaled back exactly.

use super::input::SphereInput;
use super::sdem::{self, Target, equalize};
use crate::geometry::ellipsoid::Ellipsoid;
use crate::geometry::sphere::spherical_flipped;
use crate::geometry::{norm, sub};
use crate::init::ellipsoidal_conformal::NormalizedSphere;
use crate::linalg::VertexOrder;
use crate::methods::MethodConfig;
use crate::methods::{MapResult, ProgressFn};
use crate::{Error, Result, TriMesh};
use rayon::prelude::*;
use std::time::Instant;

/// EDEM parameters; `Default` gives the paper's defaults on the unit sphere.
#[derive(Debug, Clone, PartialEq)]
pub struct Config {
    /// The target ellipsoid.
    pub ellipsoid: Ellipsoid,
    /// The density flow's stop, iteration limit and time step, as SDEM's (the ellipsoidal
    /// paper's limit is 300 iterations, [`FLOW`]).
    pub flow: sdem::Config,
}

/// The ellipsoidal paper's flow: ε = 1e-3, at most 300 iterations, the adaptive step.
pub const FLOW: sdem::Config = sdem::Config {
    epsilon: 1e-3,
    max_iter: 300,
    dt: None,
};

impl Default for Config {
    fn default() -> Self {
        Self {
            ellipsoid: Ellipsoid::UNIT_SPHERE,
            flow: FLOW,
        }
    }
}

/// A surface lies on the ellipsoid when bringing each vertex onto it along its ray moves it by
/// at most this share of the vertex's shortest edge: the projection is then the surface itself
/// to within a small perturbation of each triangle (a mesh written with limited precision, or
/// sampled on the ellipsoid with its vertices slightly off).
const ON_ELLIPSOID: f64 = 0.1;

impl MethodConfig for Config {
    /// Computes the EDEM of `mesh` (a genus-0 closed surface) with one `population` value per face
    /// onto `self.ellipsoid`. The result lies on the ellipsoid, in input vertex order, and
    /// carries the ellipsoid ([`MapResult::ellipsoid`]).
    fn run(&self, mesh: &TriMesh, population: &[f64], progress: ProgressFn) -> Result<MapResult> {
        let t0 = Instant::now();
        let input = SphereInput::new(mesh, population, &self.flow, "edem")?;
        let (local, mesh, population, order) = input.parts();
        let mut notes = Vec::new();
        let k = self.ellipsoid.normalizing_exponent();
        let domain = self.ellipsoid.scaled_by_power_of_two(k);
        let initial =
            InitialMaps::new(mesh, population, order).onto(&self.ellipsoid, &domain, &mut notes)?;
        let time_init = t0.elapsed().as_secs_f64();
        let on = Target {
            domain,
            method: "edem",
            match_areas: true,
        };
        let mut result = equalize(
            on,
            mesh,
            population,
            initial,
            Some(order),
            &self.flow,
            progress,
        )?;
        let unscale = |x: &[[f64; 3]]| -> Vec<[f64; 3]> {
            let mut x = local.restore_vertices(x);
            crate::mesh::scale::scale_positions(&mut x, -k);
            x
        };
        result.positions = unscale(&result.positions);
        result.initial = unscale(&result.initial);
        result.ellipsoid = Some(self.ellipsoid);
        result.time_init = time_init;
        notes.append(&mut result.notes);
        result.notes = notes;
        Ok(result)
    }
}

/// The initial maps of EDEM and EDEQ of one surface, onto as many ellipsoids as asked: the
/// surface itself when it lies on the ellipsoid ([`own_initial_map`]), else its ellipsoidal
/// conformal map, whose steps that do not depend on the ellipsoid are done once
/// ([`NormalizedSphere`]).
pub(crate) struct InitialMaps<'a> {
    mesh: &'a TriMesh,
    population: &'a [f64],
    order: &'a VertexOrder,
    sphere: Option<NormalizedSphere>,
}

impl<'a> InitialMaps<'a> {
    /// The maps of `mesh` with its `population` and elimination `order`.
    pub(crate) fn new(mesh: &'a TriMesh, population: &'a [f64], order: &'a VertexOrder) -> Self {
        Self {
            mesh,
            population,
            order,
            sphere: None,
        }
    }

    /// The initial map onto `domain`, the computation's copy of `ellipsoid` (scaled by a power
    /// of two). A map that folds (a mesh too coarse) is an error.
    pub(crate) fn onto(
        &mut self,
        ellipsoid: &Ellipsoid,
        domain: &Ellipsoid,
        notes: &mut Vec<String>,
    ) -> Result<Vec<[f64; 3]>> {
        let mesh = self.mesh;
        let initial = match own_initial_map(mesh, ellipsoid, notes) {
            Some(own) => own.into_iter().map(|p| domain.from_sphere(p)).collect(),
            None => {
                let sphere = match self.sphere {
                    Some(ref s) => s,
                    None => self.sphere.insert(NormalizedSphere::new(
                        &mesh.positions,
                        &mesh.faces,
                        self.order,
                        notes,
                    )?),
                };
                sphere.onto(&mesh.faces, domain, self.population, self.order, notes)
            }
        };
        if mesh
            .faces
            .par_iter()
            .any(|&f| spherical_flipped(&initial, f))
        {
            return Err(Error::InvalidMesh(format!(
                "the mesh is too small to map onto the ellipsoid: with {} faces its initial map \
                 folds (subdivide it)",
                mesh.n_faces()
            )));
        }
        Ok(initial)
    }
}

/// The surface as its own initial map when it lies on `ellipsoid` (every vertex within
/// [`ON_ELLIPSOID`] of its shortest edge), as points of the unit sphere (`M⁻¹` of the vertices
/// brought onto the ellipsoid): the identity when its faces are counter-clockwise seen from
/// outside, its mirror image in x = 0 when they all face inwards; `None` otherwise.
fn own_initial_map(
    mesh: &TriMesh,
    ellipsoid: &Ellipsoid,
    notes: &mut Vec<String>,
) -> Option<Vec<[f64; 3]>> {
    let projected: Vec<[f64; 3]> = mesh
        .positions
        .par_iter()
        .map(|&p| ellipsoid.project(p))
        .collect();
    let mut shortest = vec![f64::INFINITY; mesh.n_vertices()];
    for f in &mesh.faces {
        for k in 0..3 {
            let (a, b) = (f[k] as usize, f[(k + 1) % 3] as usize);
            let l = norm(sub(mesh.positions[a], mesh.positions[b]));
            shortest[a] = shortest[a].min(l);
            shortest[b] = shortest[b].min(l);
        }
    }
    let off = |v: usize| norm(sub(projected[v], mesh.positions[v]));
    if (0..mesh.n_vertices()).any(|v| !(off(v) <= ON_ELLIPSOID * shortest[v])) {
        return None;
    }
    let mut own: Vec<[f64; 3]> = projected.iter().map(|&p| ellipsoid.to_sphere(p)).collect();
    let flipped = mesh
        .faces
        .par_iter()
        .filter(|&&f| spherical_flipped(&own, f))
        .count();
    if flipped == 0 {
        notes.push("the surface lies on the ellipsoid: it is its own initial map".into());
    } else if flipped == mesh.n_faces() {
        for p in own.iter_mut() {
            p[0] = -p[0];
        }
        notes.push(
            "the surface lies on the ellipsoid with its faces oriented inwards: its mirror \
             image in the plane x = 0 is its initial map"
                .into(),
        );
    } else {
        return None;
    }
    Some(own)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::generate::icosphere;
    use crate::geometry::face_areas;
    use crate::methods::sphere::sdem::tests::area_times;
    use crate::metrics::{Domain, compute};

    /// The icosphere of `level` stretched onto `e`.
    fn on(e: &Ellipsoid, level: usize) -> TriMesh {
        let mut mesh = icosphere(level).unwrap();
        for p in mesh.positions.iter_mut() {
            *p = e.from_sphere(*p);
        }
        mesh
    }

    #[test]
    fn an_ellipsoid_with_its_own_areas_stays_put() {
        let e = Ellipsoid::new(1.0, 2.0, 4.0).unwrap();
        let mesh = on(&e, 3);
        let pop = face_areas(&mesh.positions, &mesh.faces);
        let config = Config {
            ellipsoid: e,
            ..Config::default()
        };
        let r = config.run(&mesh, &pop, &mut |_| {}).unwrap();
        assert_eq!(r.iterations, 0);
        assert!(
            r.notes.iter().any(|n| n.contains("its own initial map")),
            "{:?}",
            r.notes
        );
        for (a, b) in r.positions.iter().zip(&mesh.positions) {
            assert!((0..3).all(|k| (a[k] - b[k]).abs() < 1e-14));
        }
        assert_eq!(r.ellipsoid, Some(e));
    }

    #[test]
    fn an_inward_ellipsoid_starts_from_its_mirror_image() {
        let e = Ellipsoid::new(1.0, 1.0, 1.5).unwrap();
        let mut mesh = on(&e, 3);
        for f in mesh.faces.iter_mut() {
            f.swap(1, 2);
        }
        let pop = area_times(&mesh, |c| 1.0 + 0.5 * c[2]);
        let config = Config {
            ellipsoid: e,
            ..Config::default()
        };
        let r = config.run(&mesh, &pop, &mut |_| {}).unwrap();
        assert!(
            r.notes.iter().any(|n| n.contains("mirror")),
            "{:?}",
            r.notes
        );
        let m = compute(&mesh, &pop, &r.initial, &r.positions, Domain::Sphere, None);
        assert_eq!(m.flipped_triangles, 0);
        assert!(
            m.face_density_var_final < 0.1 * m.face_density_var_initial,
            "{m:?}"
        );
        for p in &r.positions {
            assert!(e.residual(*p) < 1e-12);
        }
    }

    #[test]
    fn a_sphere_is_equalized_on_elongated_ellipsoids() {
        // The unit icosphere by area onto ellipsoids of other proportions: the initial map is
        // the ellipsoidal conformal map, far from area-preserving; EDEM equalizes it.
        let mesh = icosphere(4).unwrap();
        let pop = face_areas(&mesh.positions, &mesh.faces);
        for radii in [[1.0, 1.0, 2.5], [2.0, 1.0, 0.5], [1.0, 1.5, 3.0]] {
            let e = Ellipsoid::new(radii[0], radii[1], radii[2]).unwrap();
            let config = Config {
                ellipsoid: e,
                ..Config::default()
            };
            let r = config.run(&mesh, &pop, &mut |_| {}).unwrap();
            let m = compute(&mesh, &pop, &r.initial, &r.positions, Domain::Sphere, None);
            assert!(r.converged, "{radii:?}: {:?}", r.notes);
            assert_eq!(m.flipped_triangles, 0, "{radii:?}");
            assert!(m.density_error_mean < 0.05, "{radii:?}: {m:?}");
            assert!(
                m.face_density_var_final < 0.05 * m.face_density_var_initial,
                "{radii:?}: {m:?}"
            );
            for p in &r.positions {
                assert!(e.residual(*p) < 1e-12, "{radii:?}");
            }
        }
    }

    #[test]
    fn a_stall_at_the_scale_of_single_faces_goes_to_the_area_matching() {
        // A tenfold density from pole to pole onto 1:1:3: the adaptive step's face misfit stops
        // falling with sd/mean of ρ_V above 10 ε but below the face misfit. The paper's fixed
        // step does not run (it took 212 more iterations to the same map); the local area
        // matching takes what is left.
        let mesh = icosphere(4).unwrap();
        let pop = area_times(&mesh, |c| 1.0 + 4.5 * (c[2] + 1.0));
        let e = Ellipsoid::new(1.0, 1.0, 3.0).unwrap();
        let config = Config {
            ellipsoid: e,
            ..Config::default()
        };
        let r = config.run(&mesh, &pop, &mut |_| {}).unwrap();
        assert!(
            r.notes
                .iter()
                .any(|n| n.contains("for the local area matching")),
            "{:?}",
            r.notes
        );
        assert!(
            !r.notes.iter().any(|n| n.contains("fixed step")),
            "{:?}",
            r.notes
        );
        assert!(r.iterations < 60, "{}", r.iterations);
        let m = compute(&mesh, &pop, &r.initial, &r.positions, Domain::Sphere, None);
        assert_eq!(m.flipped_triangles, 0);
        assert!(m.face_density_var_final < 2e-5, "{m:?}");
        assert!(m.density_error_mean < 0.005, "{m:?}");
    }

    #[test]
    fn huge_radii_are_scaled_inside_and_back() {
        let mesh = icosphere(3).unwrap();
        let pop = area_times(&mesh, |c| 1.0 + 0.8 * c[0]);
        let small = Ellipsoid::new(1.0, 1.2, 1.4).unwrap();
        let huge = Ellipsoid::new(1e300, 1.2e300, 1.4e300).unwrap();
        let run_on = |e: Ellipsoid| {
            let config = Config {
                ellipsoid: e,
                ..Config::default()
            };
            config.run(&mesh, &pop, &mut |_| {}).unwrap()
        };
        let (a, b) = (run_on(small), run_on(huge));
        assert_eq!(a.iterations, b.iterations);
        for p in &b.positions {
            assert!(huge.residual(*p) < 1e-12);
            assert!(p.iter().all(|x| x.is_finite()));
        }
    }

    #[test]
    fn a_disk_is_refused() {
        let disk = crate::generate::regular_polygon(12, 3).unwrap();
        let pop = face_areas(&disk.positions, &disk.faces);
        let e = Config::default().run(&disk, &pop, &mut |_| {}).unwrap_err();
        assert!(matches!(e, Error::Topology { .. }), "{e}");
    }
}
