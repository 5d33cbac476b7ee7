//! The density-equalizing methods, by the domain they map onto: the plane ([`disk`]), the
//! sphere ([`sphere`]), circle domains ([`circle`]) and the torus ([`torus`]), each with the
//! parts its methods share beside them; [`common`] holds what all share — the one
//! density-equalizing iteration, the result and the input checks. Each method is a `Config`
//! whose `Default` is its paper's defaults (departures in `docs/deviations.md`) that runs
//! the method: through [`MethodConfig::run`] where the input is a surface and its population
//! alone, through the module's `run` function where it takes landmarks or a torus too; either
//! returns a [`MapResult`].

pub mod circle;
pub mod common;
pub mod disk;
pub mod sphere;
pub mod torus;

pub use circle::{circle_conformal, deq, ldeq};
pub(crate) use common::iteration;
pub use common::{MapResult, Progress, ProgressFn, RefinedSurface, StopReason};
pub(crate) use common::{check_landmark_vertices, require_valid_mesh};
pub use disk::{dem, dem_shape};
pub(crate) use sphere::input::check_sphere_input;
pub use sphere::{edem, edeq, lsdem, sdem, spherical_conformal};
pub use torus::tdem;

use crate::{Result, TriMesh};

/// The parameters of a method whose input is a surface with one population value per face and
/// nothing else: DEM ([`dem::Config`]), DEM onto a shape ([`dem_shape::Config`]), DEQ
/// ([`deq::Config`]), SDEM ([`sdem::Config`]), EDEM ([`edem::Config`]) and EDEQ
/// ([`edeq::Config`]). Each method's module documents its algorithm and the paper it follows.
pub trait MethodConfig {
    /// Computes the map of `mesh` with one `population` value per face, reporting each iteration
    /// to `progress`; the result is in input vertex order.
    fn run(&self, mesh: &TriMesh, population: &[f64], progress: ProgressFn) -> Result<MapResult>;
}

#[cfg(test)]
mod input_tests {
    use super::*;
    use crate::TriMesh;

    /// An unvalidated mesh with a face index out of range: every method refuses it with an
    /// error, none panics.
    #[test]
    fn every_method_refuses_an_out_of_range_face_index() {
        let mesh = TriMesh::new(
            vec![[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
            vec![[0, 1, 7]],
        );
        let pop = [1.0];
        let quiet = &mut |_| {};
        assert!(dem::Config::default().run(&mesh, &pop, quiet).is_err());
        assert!(
            dem_shape::Config::default()
                .run(&mesh, &pop, quiet)
                .is_err()
        );
        assert!(sdem::Config::default().run(&mesh, &pop, quiet).is_err());
        assert!(deq::Config::default().run(&mesh, &pop, quiet).is_err());
        assert!(spherical_conformal::run(&mesh, &pop).is_err());
        assert!(circle_conformal::run(&mesh, &pop).is_err());
        let lm = [(0usize, [0.0, 0.0, 1.0])];
        assert!(lsdem::run(&mesh, &pop, &lm, &Default::default(), quiet).is_err());
        assert!(ldeq::run(&mesh, &pop, &lm, &Default::default(), quiet).is_err());
        let torus = crate::geometry::torus::Torus::new(2.0, 1.0).unwrap();
        assert!(tdem::run(&mesh, &pop, &torus, &Default::default(), quiet).is_err());
    }
}
