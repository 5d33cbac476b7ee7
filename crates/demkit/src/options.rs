//! Which of [`MapOptions`] each [`Method`] uses, and the ranges their values must lie in.
//!
//! One table ([`Method::options`]) says what every method reads; an option set for a method
//! that does not read it is [`unused`] (the command line warns about it). Every value is
//! checked whether the method uses it or not ([`check_values`]: a negative weight is
//! nonsense for every method), and before any computation ([`check_for`]) against the
//! surface: the target torus's size relative to the mesh, the time step relative to the
//! domain the method iterates on.

use crate::api::{MapOptions, Method};
use crate::shape::Shape;
use crate::surface::Surface;
use crate::{Error, Result};
use std::f64::consts::PI;

/// An option of [`MapOptions`] that a method may or may not read.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MapOption {
    /// [`MapOptions::landmarks`].
    Landmarks,
    /// [`MapOptions::torus`].
    Torus,
    /// [`MapOptions::shape`].
    Shape,
    /// [`MapOptions::ellipsoid`].
    Ellipsoid,
    /// [`MapOptions::alpha`].
    Alpha,
    /// [`MapOptions::beta`].
    Beta,
    /// [`MapOptions::gamma`].
    Gamma,
    /// [`MapOptions::fixed_holes`].
    FixedHoles,
    /// [`MapOptions::dt`].
    Dt,
    /// [`MapOptions::epsilon`].
    Epsilon,
    /// [`MapOptions::max_iter`].
    MaxIter,
}

impl MapOption {
    /// The parameter's name, as the library's messages write it in backquotes (the command
    /// line puts its flag there).
    pub fn name(self) -> &'static str {
        match self {
            MapOption::Landmarks => "landmarks",
            MapOption::Torus => "torus",
            MapOption::Shape => "shape",
            MapOption::Ellipsoid => "ellipsoid",
            MapOption::Alpha => "alpha",
            MapOption::Beta => "beta",
            MapOption::Gamma => "gamma",
            MapOption::FixedHoles => "fixed_holes",
            MapOption::Dt => "dt",
            MapOption::Epsilon => "epsilon",
            MapOption::MaxIter => "max_iter",
        }
    }

    /// Whether `options` sets this option.
    pub fn is_set(self, options: &MapOptions) -> bool {
        match self {
            MapOption::Landmarks => !options.landmarks.is_empty(),
            MapOption::Torus => options.torus.is_some(),
            MapOption::Shape => options.shape.is_some(),
            MapOption::Ellipsoid => options.ellipsoid.is_some(),
            MapOption::Alpha => options.alpha.is_some(),
            MapOption::Beta => options.beta.is_some(),
            MapOption::Gamma => options.gamma.is_some(),
            MapOption::FixedHoles => options.fixed_holes,
            MapOption::Dt => options.dt.is_some(),
            MapOption::Epsilon => options.epsilon.is_some(),
            MapOption::MaxIter => options.max_iter.is_some(),
        }
    }

    /// Every option.
    pub const ALL: [MapOption; 11] = [
        MapOption::Landmarks,
        MapOption::Torus,
        MapOption::Shape,
        MapOption::Ellipsoid,
        MapOption::Alpha,
        MapOption::Beta,
        MapOption::Gamma,
        MapOption::FixedHoles,
        MapOption::Dt,
        MapOption::Epsilon,
        MapOption::MaxIter,
    ];
}

impl Method {
    /// The options this method reads (one row per method; `Auto` reads none itself, the
    /// method it resolves to does). Landmarks of SDEM and the spherical conformal map are
    /// measured (the report's `landmark_error`), not imposed.
    pub fn options(self) -> &'static [MapOption] {
        use MapOption::*;
        match self {
            Method::Auto => &[],
            Method::Dem => &[Dt, Epsilon, MaxIter],
            Method::DemShape => &[Shape, Dt, Epsilon, MaxIter],
            Method::Sdem => &[Landmarks, Dt, Epsilon, MaxIter],
            Method::Lsdem => &[Landmarks, Alpha, Beta, Gamma, Dt, Epsilon, MaxIter],
            Method::Edem => &[Ellipsoid, Dt, Epsilon, MaxIter],
            Method::Edeq => &[Ellipsoid, Alpha, Dt, Epsilon, MaxIter],
            Method::Deq => &[Alpha, FixedHoles, Dt, Epsilon, MaxIter],
            Method::Ldeq => &[Landmarks, Alpha, FixedHoles, Dt, Epsilon, MaxIter],
            Method::Tdem => &[Torus, Dt, Epsilon, MaxIter],
            Method::SphericalConformal => &[Landmarks],
            Method::CircleConformal => &[],
        }
    }
}

/// The options of `set` that `method` (resolved, not `Auto`) does not read.
pub fn unused(method: Method, set: &[MapOption]) -> Vec<MapOption> {
    set.iter()
        .copied()
        .filter(|o| !method.options().contains(o))
        .collect()
}

/// The options `options` sets.
pub fn set_in(options: &MapOptions) -> Vec<MapOption> {
    MapOption::ALL
        .into_iter()
        .filter(|o| o.is_set(options))
        .collect()
}

/// The largest energy weight (α, β, γ) accepted: a million times the papers' values (1 to 5).
/// Beyond it the weighted stiffness swamps the mass matrix in rounding (LSDEM's system
/// A + δtβL stopped being positive definite at β = 1e20 on an icosphere).
pub const MAX_WEIGHT: f64 = 1e6;

/// The largest time step accepted, as a multiple of the area of the domain the method
/// iterates on ([`domain_area`]): the step's system is mass + δt · stiffness, and beyond this
/// the mass vanishes in rounding (TDEM's stopped being positive definite at δt = 1e13 times the
/// flat torus's area).
pub const MAX_STEP_PER_AREA: f64 = 1e6;

/// The target torus's radii, relative to the mesh's bounding-box diagonal, lie within
/// 1/this..this: a torus 1e30 times the mesh's size is no target for it, and its areas' powers
/// would overflow `f64` (TDEM failed from radii of 1e77 on a unit mesh).
pub const MAX_TORUS_SCALE: f64 = 1e30;

/// The thinnest target torus accepted: R / r at most this. The flat torus is a
/// 2πR × 2πr rectangle, and triangles stretched further leave the cotangent weights with
/// too few correct digits (TDEM failed from R / r = 1e12).
pub const MAX_TORUS_ASPECT: f64 = 1e6;

/// Checks every value of `options` that is set, whichever method reads it: weights finite in
/// [0, [`MAX_WEIGHT`]], `dt` finite and positive, `epsilon` in (0, 1) (every method's
/// tolerance is relative), `max_iter` at least 1.
///
/// Errors: [`Error::Argument`] naming the parameter.
pub fn check_values(options: &MapOptions) -> Result<()> {
    for (name, w) in [
        ("alpha", options.alpha),
        ("beta", options.beta),
        ("gamma", options.gamma),
    ] {
        if let Some(w) = w
            && !((0.0..=MAX_WEIGHT).contains(&w))
        {
            return Err(Error::Argument(format!(
                "{name} is an energy weight, a number from 0 to {MAX_WEIGHT:e}, got {w:?}"
            )));
        }
    }
    if let Some(dt) = options.dt
        && !(dt > 0.0 && dt.is_finite())
    {
        return Err(Error::Argument(format!(
            "dt must be positive and finite (a time step), got {dt:?}"
        )));
    }
    if let Some(e) = options.epsilon
        && !(e > 0.0 && e < 1.0)
    {
        return Err(Error::Argument(format!(
            "epsilon must be positive and below 1 (a relative tolerance), got {e:?}"
        )));
    }
    if options.max_iter == Some(0) {
        return Err(Error::Argument("max_iter must be at least 1".into()));
    }
    Ok(())
}

/// The area of the domain `method` iterates on: DEM's map normalised to area 1, the
/// prescribed shape, the unit sphere, the ellipsoid (EDEQ's guess), the unit disk, the flat torus of `torus` (in the
/// computation's units).
pub fn domain_area(method: Method, options: &MapOptions, torus: Option<[f64; 2]>) -> f64 {
    match method {
        Method::Dem | Method::Auto => 1.0,
        Method::DemShape => match options.shape.unwrap_or(Shape::Disk) {
            Shape::Disk => PI,
            Shape::Square => 4.0,
            Shape::Rectangle { width, height } => width * height,
            Shape::Ellipse { a, b } => PI * a * b,
        },
        Method::Sdem | Method::Lsdem | Method::SphericalConformal => 4.0 * PI,
        Method::Edem | Method::Edeq => options.ellipsoid.map_or(4.0 * PI, |e| e.area()),
        Method::Deq | Method::Ldeq | Method::CircleConformal => PI,
        Method::Tdem => torus.map_or(1.0, |[u, v]| u * v),
    }
}

/// [`check_values`], then what depends on `surface` and `method` (resolved): the target
/// torus within [`MAX_TORUS_SCALE`] of the mesh's size and at most [`MAX_TORUS_ASPECT`]
/// thin, the time step at most [`MAX_STEP_PER_AREA`] times [`domain_area`].
///
/// Errors: [`Error::Argument`] naming the parameter.
pub fn check_for(options: &MapOptions, method: Method, surface: &Surface) -> Result<()> {
    check_values(options)?;
    let mut periods = None;
    if let Some(t) = options.torus {
        let scale = surface.input_diagonal();
        let (ratio_r, ratio_minor) = (t.major / scale, t.minor / scale);
        let inside = |x: f64| (1.0 / MAX_TORUS_SCALE..=MAX_TORUS_SCALE).contains(&x);
        if !(inside(ratio_r) && inside(ratio_minor)) {
            return Err(Error::Argument(format!(
                "torus radii R = {:e}, r = {:e} are out of range for this mesh (bounding-box \
                 diagonal {scale:e}): each must lie within {MAX_TORUS_SCALE:e} times the \
                 mesh's size either way",
                t.major, t.minor
            )));
        }
        if t.major / t.minor > MAX_TORUS_ASPECT {
            return Err(Error::Argument(format!(
                "torus radii R = {:e}, r = {:e} are out of range: R / r must be at most \
                 {MAX_TORUS_ASPECT:e}",
                t.major, t.minor
            )));
        }
        periods = Some(t.scaled_by_power_of_two(surface.exponent()).periods());
    }
    if let Some(dt) = options.dt {
        let area = domain_area(method, options, periods);
        if dt > MAX_STEP_PER_AREA * area {
            return Err(Error::Argument(format!(
                "dt = {dt:?} is out of range for --method {}: at most {MAX_STEP_PER_AREA:e} \
                 times the area of the domain it iterates on ({area:.4})",
                method.name()
            )));
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::torus::Torus;

    fn torus_surface() -> Surface {
        let mesh = crate::generate::torus(2.0, 1.0, 16, 8).unwrap();
        Surface::new(mesh.positions, mesh.faces).unwrap()
    }

    #[test]
    fn every_method_reads_a_listed_option_and_the_others_are_unused() {
        let options = MapOptions {
            beta: Some(1.0),
            alpha: Some(0.5),
            ..Default::default()
        };
        let set = set_in(&options);
        assert_eq!(unused(Method::Deq, &set), vec![MapOption::Beta]);
        assert!(unused(Method::Lsdem, &set).is_empty());
        assert_eq!(
            unused(Method::Dem, &set),
            vec![MapOption::Alpha, MapOption::Beta]
        );
        for m in Method::ALL {
            if m != Method::Auto {
                assert!(m.options().iter().all(|o| MapOption::ALL.contains(o)));
            }
        }
    }

    #[test]
    fn values_out_of_range_are_refused_whichever_method_reads_them() {
        let bad = [
            MapOptions {
                beta: Some(-1.0),
                ..Default::default()
            },
            MapOptions {
                alpha: Some(f64::NAN),
                ..Default::default()
            },
            MapOptions {
                gamma: Some(1e300),
                ..Default::default()
            },
            MapOptions {
                dt: Some(f64::INFINITY),
                ..Default::default()
            },
            MapOptions {
                epsilon: Some(1e300),
                ..Default::default()
            },
            MapOptions {
                max_iter: Some(0),
                ..Default::default()
            },
        ];
        for o in bad {
            let e = check_values(&o).unwrap_err();
            assert!(matches!(e, Error::Argument(_)), "{e}");
        }
        let fine = MapOptions {
            alpha: Some(0.0),
            beta: Some(2.0),
            epsilon: Some(1e-3),
            dt: Some(0.1),
            ..Default::default()
        };
        assert!(check_values(&fine).is_ok());
    }

    #[test]
    fn a_torus_far_from_the_mesh_size_or_too_thin_and_a_huge_step_are_refused() {
        let surface = torus_surface();
        let with = |major: f64, minor: f64, dt: Option<f64>| MapOptions {
            method: Method::Tdem,
            torus: Some(Torus::new(major, minor).unwrap()),
            dt,
            ..Default::default()
        };
        let e = check_for(&with(1e300, 1e299, None), Method::Tdem, &surface).unwrap_err();
        assert!(e.to_string().contains("out of range"), "{e}");
        assert!(check_for(&with(1e-300, 1e-301, None), Method::Tdem, &surface).is_err());
        assert!(check_for(&with(1e8, 1.0, None), Method::Tdem, &surface).is_err());
        assert!(check_for(&with(3.0, 1.0, None), Method::Tdem, &surface).is_ok());
        assert!(check_for(&with(3.0, 1.0, Some(1e300)), Method::Tdem, &surface).is_err());
        assert!(check_for(&with(3.0, 1.0, Some(10.0)), Method::Tdem, &surface).is_ok());
    }
}
