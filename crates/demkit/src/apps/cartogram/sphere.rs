//! The cartogram on the globe: longitude/latitude degrees are projected to an equal-area
//! cylindrical projection (standard parallels ±[`STANDARD_PARALLEL`]°, areas in steradians),
//! the planar flow ([`super::planar::flow`]) equalizes the density there, and the result is
//! projected back ([`super::degrees`]). Equal areas in the projection are equal areas on the
//! globe, so the shares reached in the plane are those on the sphere. The flow's grid has its walls on the poles,
//! so no point is moved past them.

use super::degrees::to_degrees_indexed;
use super::planar::flow;
use super::raster::IndexRings;
use super::regions::RegionSet;
use super::{Cartogram, Config, figures};
use crate::Result;
use crate::methods::ProgressFn;

/// The standard parallel of the projection, in degrees (Behrmann's).
pub const STANDARD_PARALLEL: f64 = 30.0;

/// Longitude/latitude degrees to the equal-area cylindrical projection of the unit sphere.
pub fn project(p: [f64; 2]) -> [f64; 2] {
    let k = STANDARD_PARALLEL.to_radians().cos();
    [p[0].to_radians() * k, p[1].to_radians().sin() / k]
}

/// The inverse of [`project`]; a point beyond the poles is put on the pole.
pub fn unproject(q: [f64; 2]) -> [f64; 2] {
    let k = STANDARD_PARALLEL.to_radians().cos();
    [
        (q[0] / k).to_degrees(),
        (q[1] * k).clamp(-1.0, 1.0).asin().to_degrees(),
    ]
}

/// Computes the cartogram of `set` on the globe (positions are longitude/latitude degrees):
/// [`flow`] in the projection of [`project`]; areas in the figures are on the unit sphere.
///
/// Errors: those of [`flow`].
pub fn run(
    set: &RegionSet,
    config: &Config,
    _path: &str,
    progress: ProgressFn,
) -> Result<Cartogram> {
    let points: Vec<[f64; 2]> = set.input_points().into_iter().map(project).collect();
    let values: Vec<f64> = set.regions.iter().map(|r| r.value).collect();
    let rings: Vec<IndexRings> = set.regions.iter().map(|r| r.polygons.clone()).collect();
    let in_areas = super::planar::region_areas(&points, &rings);
    let pole = project([0.0, 90.0])[1];
    let f = flow(
        points,
        rings,
        &values,
        config,
        Some([-pole, pole]),
        progress,
    )?;
    let out_areas = super::planar::region_areas(&f.points, &f.rings);
    // Written in degrees with the edges split where their chords would cross.
    let (coordinates, _) = to_degrees_indexed(f.points, f.rings, unproject);
    Ok(figures(
        set,
        coordinates,
        (&in_areas, &out_areas),
        &out_areas,
        f.run,
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_projection_keeps_areas_and_inverts() {
        // A 1° × 1° cell at the equator and at 60°: areas in steradians.
        let cell = |lat: f64| {
            let a = project([0.0, lat]);
            let b = project([1.0, lat + 1.0]);
            (b[0] - a[0]) * (b[1] - a[1])
        };
        let exact = |lat: f64| {
            1f64.to_radians() * ((lat + 1.0).to_radians().sin() - lat.to_radians().sin())
        };
        for lat in [0.0, 60.0] {
            assert!((cell(lat) - exact(lat)).abs() < 1e-15);
        }
        let p = [123.0, -45.0];
        let q = unproject(project(p));
        assert!((p[0] - q[0]).abs() < 1e-12 && (p[1] - q[1]).abs() < 1e-12);
    }
}
