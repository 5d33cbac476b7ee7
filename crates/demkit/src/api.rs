//! The library's front door: [`map`] a [`Surface`] with a [`Population`] and [`MapOptions`],
//! the method chosen by topology unless named, into a [`Map`] that says where it lies.
//!
//! ```
//! use demkit::{MapOptions, Population, Surface};
//!
//! // A 2 × 1 rectangle of eight triangles: a disk, so `Method::Auto` picks DEM.
//! let mesh = demkit::generate::square_grid(4, 2, 2.0, 1.0).unwrap();
//! let surface = Surface::new(mesh.positions, mesh.faces)?;
//! let map = demkit::map(&surface, &Population::Area, &MapOptions::default())?;
//! assert_eq!(map.method, demkit::Method::Dem);
//! assert!(matches!(map.domain, demkit::Domain::Plane));
//! assert_eq!(map.metrics.flipped_triangles, 0);
//! # Ok::<(), demkit::Error>(())
//! ```

use crate::geometry::ellipsoid::Ellipsoid;
use crate::geometry::torus::{FlatTorusMap, Torus};
use crate::methods::MethodConfig;
use crate::methods::{
    MapResult, ProgressFn, circle_conformal, dem, dem_shape, deq, edem, edeq, ldeq, lsdem, sdem,
    spherical_conformal, tdem,
};
use crate::metrics::Metrics;
use crate::population::{PopulationSpec, face_populations_at_scale, unit_scale};
use crate::shape::Shape;
use crate::surface::Surface;
use crate::{Error, Result, TriMesh};

/// A density-equalizing method (or one of the conformal maps they start from).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Method {
    /// Chosen by topology ([`Method::resolve`]).
    #[default]
    Auto,
    /// DEM: a disk onto the plane, free boundary.
    Dem,
    /// DEM onto a prescribed shape ([`MapOptions::shape`]).
    DemShape,
    /// SDEM: a genus-0 closed surface onto the unit sphere.
    Sdem,
    /// LSDEM: SDEM with landmarks sent to targets on the sphere.
    Lsdem,
    /// EDEM: a genus-0 closed surface onto an ellipsoid ([`MapOptions::ellipsoid`]).
    Edem,
    /// EDEQ: EDEM with the ellipsoid's radii chosen too ([`MapOptions::ellipsoid`] is the
    /// initial guess).
    Edeq,
    /// DEQ: a surface with holes onto a circle domain.
    Deq,
    /// LDEQ: DEQ with landmarks sent to targets in the disk.
    Ldeq,
    /// TDEM: a genus-one closed surface onto a torus ([`MapOptions::torus`]).
    Tdem,
    /// The spherical conformal map (SDEM's initial map).
    SphericalConformal,
    /// The conformal circle-domain map.
    CircleConformal,
}

impl Map {
    /// How the metrics measure a map lying in [`Map::domain`].
    pub fn metrics_domain(&self) -> crate::metrics::Domain {
        match self.domain {
            Domain::Sphere | Domain::Ellipsoid { .. } => crate::metrics::Domain::Sphere,
            Domain::Torus { .. } => crate::metrics::Domain::Torus {
                flipped: self.metrics.flipped_triangles,
            },
            Domain::Plane | Domain::CircleDomain { .. } => crate::metrics::Domain::Plane,
        }
    }
}

impl Method {
    /// Every method, `Auto` first.
    pub const ALL: [Method; 12] = [
        Method::Auto,
        Method::Dem,
        Method::DemShape,
        Method::Sdem,
        Method::Lsdem,
        Method::Edem,
        Method::Edeq,
        Method::Deq,
        Method::Ldeq,
        Method::Tdem,
        Method::SphericalConformal,
        Method::CircleConformal,
    ];

    /// What the method does, in one line.
    pub fn summary(self) -> &'static str {
        match self {
            Method::Auto => {
                "Pick by topology (disk → dem, holes → deq, sphere → sdem, torus → tdem)"
            }
            Method::Dem => {
                "Density-equalizing map of a disk onto the plane with free boundary (DEM)"
            }
            Method::DemShape => "DEM onto a prescribed shape (see --shape)",
            Method::Sdem => "Spherical DEM of a genus-0 closed surface",
            Method::Lsdem => "Landmark-aligned spherical DEM",
            Method::Edem => "Ellipsoidal DEM of a genus-0 closed surface (see --ellipsoid)",
            Method::Edeq => {
                "Ellipsoidal density-equalizing quasiconformal map, the radii chosen too"
            }
            Method::Deq => "Density-equalizing quasiconformal map onto a circle domain",
            Method::Ldeq => "Landmark-matching DEQ",
            Method::Tdem => "Toroidal DEM of a genus-one surface",
            Method::SphericalConformal => {
                "Spherical conformal parameterization (the SDEM initial map)"
            }
            Method::CircleConformal => "Conformal map onto a circle domain (the DEQ initial map)",
        }
    }

    /// The method's name, as the report and the command line spell it.
    pub fn name(self) -> &'static str {
        match self {
            Method::Auto => "auto",
            Method::Dem => "dem",
            Method::DemShape => "dem-shape",
            Method::Sdem => "sdem",
            Method::Lsdem => "lsdem",
            Method::Edem => "edem",
            Method::Edeq => "edeq",
            Method::Deq => "deq",
            Method::Ldeq => "ldeq",
            Method::Tdem => "tdem",
            Method::SphericalConformal => "spherical-conformal",
            Method::CircleConformal => "circle-conformal",
        }
    }

    /// `Auto` resolved for a surface with `boundaries` loops and `genus`, with or without
    /// landmarks and a target ellipsoid: disk → DEM (LDEQ), holes → DEQ (LDEQ), genus-0
    /// closed → SDEM (LSDEM; EDEM onto an ellipsoid), genus one → TDEM; any other method is
    /// returned as it is.
    pub fn resolve(
        self,
        boundaries: usize,
        genus: i64,
        landmarks: bool,
        ellipsoid: bool,
    ) -> Result<Method> {
        if self != Method::Auto {
            return Ok(self);
        }
        Ok(match (boundaries, genus, landmarks) {
            (0, 0, false) if ellipsoid => Method::Edem,
            (1, 0, false) => Method::Dem,
            (b, 0, false) if b > 1 => Method::Deq,
            (b, 0, true) if b >= 1 => Method::Ldeq,
            (0, 0, false) => Method::Sdem,
            (0, 0, true) => Method::Lsdem,
            (0, 1, _) => Method::Tdem,
            _ => {
                return Err(Error::Topology {
                    method: "auto".into(),
                    msg: format!(
                        "no method handles a surface with {boundaries} boundary loops and genus {genus}"
                    ),
                });
            }
        })
    }

    /// True for the methods whose map lies on the unit sphere.
    pub fn maps_onto_sphere(self) -> bool {
        matches!(
            self,
            Method::Sdem | Method::Lsdem | Method::SphericalConformal
        )
    }

    /// True for the methods whose map lies on the unit sphere or an ellipsoid: a closed
    /// surface around the origin, star-shaped from it.
    pub fn maps_onto_closed_surface(self) -> bool {
        self.maps_onto_sphere() || matches!(self, Method::Edem | Method::Edeq)
    }
}

/// The population to equalize, one positive value per face.
#[derive(Debug, Clone, PartialEq)]
pub enum Population {
    /// Each face's area: an area-preserving map.
    Area,
    /// 1 on every face.
    Uniform,
    /// Given per face, in face order.
    PerFace(Vec<f64>),
    /// An expression of the face centroid `x`, `y`, `z` and its `area` ([`crate::expr`]).
    Expression(String),
}

/// What [`map`] computes and how; `Default` is the method by topology with every method's
/// own defaults.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct MapOptions {
    /// The method (default: by topology).
    pub method: Method,
    /// Landmarks: vertex index and target (on the unit sphere for LSDEM, in the unit disk,
    /// z ignored, for LDEQ).
    pub landmarks: Vec<(usize, [f64; 3])>,
    /// TDEM's target torus, in input units.
    pub torus: Option<Torus>,
    /// EDEM's target ellipsoid, EDEQ's initial guess (any radii: the domain's own size, not
    /// input units).
    pub ellipsoid: Option<Ellipsoid>,
    /// DEM-shape's target shape (default: the disk).
    pub shape: Option<Shape>,
    /// LSDEM's α, β, γ; DEQ's and EDEQ's α.
    pub alpha: Option<f64>,
    /// LSDEM's β.
    pub beta: Option<f64>,
    /// LSDEM's γ.
    pub gamma: Option<f64>,
    /// A fixed time step instead of the method's own rule.
    pub dt: Option<f64>,
    /// The stopping tolerance.
    pub epsilon: Option<f64>,
    /// The iteration limit.
    pub max_iter: Option<usize>,
    /// DEQ/LDEQ: keep every hole on its initial circle.
    pub fixed_holes: bool,
}

/// Where a map lies.
#[derive(Debug, Clone, PartialEq)]
pub enum Domain {
    /// The plane (z = 0): DEM, DEM onto a shape.
    Plane,
    /// The unit disk minus round holes: DEQ, LDEQ, the conformal circle-domain map.
    CircleDomain {
        /// Centre and radius of every hole, in the order of the surface's boundary loops
        /// (the outer loop, on the unit circle, left out).
        circles: Vec<([f64; 2], f64)>,
    },
    /// The unit sphere.
    Sphere,
    /// The ellipsoid x²/a² + y²/b² + z²/c² = 1: EDEM (the radii asked for), EDEQ (the radii it
    /// chose).
    Ellipsoid {
        /// Semi-axis along x.
        a: f64,
        /// Semi-axis along y.
        b: f64,
        /// Semi-axis along z.
        c: f64,
    },
    /// A torus of revolution about the z axis, in input units.
    Torus {
        /// The torus.
        torus: Torus,
        /// The map on the flat torus (points and lattice translations), in the computation's
        /// units, from which the positions are projected.
        flat: FlatTorusMap,
    },
}

impl Domain {
    /// The domain's name, as the report spells it.
    pub fn name(&self) -> &'static str {
        match self {
            Domain::Plane => "plane",
            Domain::CircleDomain { .. } => "circle-domain",
            Domain::Sphere => "sphere",
            Domain::Ellipsoid { .. } => "ellipsoid",
            Domain::Torus { .. } => "torus",
        }
    }
}

/// A computed map.
#[derive(Debug, Clone)]
pub struct Map {
    /// The method that ran (never `Auto`).
    pub method: Method,
    /// The surface mapped: the input (as the [`Surface`] holds it), or its refinement when the
    /// method refined it (DEQ splits the chords of holes; input vertices first).
    pub mesh: TriMesh,
    /// The population of each face of `mesh`, scaled to a unit mean.
    pub population: Vec<f64>,
    /// The mapped position of every vertex of `mesh` (in input units on a torus).
    pub positions: Vec<[f64; 3]>,
    /// Where the map lies.
    pub domain: Domain,
    /// The report's metrics (DESIGN.md, "Report").
    pub metrics: Metrics,
    /// The method's own result: initial map, convergence, history, notes, times.
    pub result: MapResult,
}

/// Maps `surface` with `population` and `options` (see the module docs).
pub fn map(surface: &Surface, population: &Population, options: &MapOptions) -> Result<Map> {
    map_with_progress(surface, population, options, &mut |_| {})
}

/// [`map`], reporting every iteration to `progress`.
pub fn map_with_progress(
    surface: &Surface,
    population: &Population,
    options: &MapOptions,
    progress: ProgressFn,
) -> Result<Map> {
    let mesh = surface.mesh();
    let topo = surface.topology();
    let method = options.method.resolve(
        topo.boundary_loops.len(),
        topo.genus,
        !options.landmarks.is_empty(),
        options.ellipsoid.is_some(),
    )?;
    crate::options::check_for(options, method, surface)?;
    let from_spec = |spec| face_populations_at_scale(&spec, mesh, surface.exponent());
    let face_population = unit_scale(&match population {
        Population::Area => from_spec(PopulationSpec::Area)?,
        Population::Uniform => from_spec(PopulationSpec::Uniform)?,
        Population::Expression(e) => from_spec(PopulationSpec::Expr(e.clone()))?,
        Population::PerFace(values) => {
            crate::population::check_population(values, mesh.n_faces())?;
            values.clone()
        }
    });
    let torus = options
        .torus
        .map(|t| t.scaled_by_power_of_two(surface.exponent()));
    let mut result = run_method(mesh, &face_population, method, options, torus, progress)?;
    let (mapped, population) = match result.refined.take() {
        Some(r) => (r.mesh, r.population),
        None => (mesh.clone(), face_population),
    };
    let loops = &topo.boundary_loops;
    let (domain, measured) = domain_of(method, &result, &mapped, loops, torus, options.torus);
    // Maps onto an ellipsoid are measured at the size they were computed at (any radii work).
    let at_unit_size = |x: &[[f64; 3]]| {
        let k = result.ellipsoid.map_or(0, |e| e.normalizing_exponent());
        let mut x = x.to_vec();
        crate::mesh::scale::scale_positions(&mut x, k);
        x
    };
    let metrics = crate::metrics::compute(
        &mapped,
        &population,
        &at_unit_size(&result.initial),
        &at_unit_size(&result.positions),
        measured,
        (!options.landmarks.is_empty()).then_some(&options.landmarks[..]),
    );
    result.judge(&metrics, options.dt);
    let mut positions = result.positions.clone();
    if matches!(domain, Domain::Torus { .. }) {
        crate::mesh::scale::scale_positions(&mut positions, -surface.exponent());
    }
    Ok(Map {
        method,
        mesh: mapped,
        population,
        positions,
        domain,
        metrics,
        result,
    })
}

/// Runs `method` with the options given, every other parameter at the method's default.
fn run_method(
    mesh: &TriMesh,
    population: &[f64],
    method: Method,
    o: &MapOptions,
    torus: Option<Torus>,
    progress: ProgressFn,
) -> Result<MapResult> {
    let common = |epsilon: &mut f64, max_iter: &mut usize| {
        if let Some(e) = o.epsilon {
            *epsilon = e;
        }
        if let Some(m) = o.max_iter {
            *max_iter = m;
        }
    };
    let deq_config = || {
        let mut c = deq::Config::default();
        common(&mut c.epsilon, &mut c.max_iter);
        c.dt = o.dt.or(c.dt);
        c.alpha = o.alpha.unwrap_or(c.alpha);
        c.geometry_update = !o.fixed_holes;
        c
    };
    match method {
        Method::Auto => Err(Error::Argument("the method was not resolved".into())),
        Method::Dem => {
            let mut c = dem::Config::default();
            common(&mut c.epsilon, &mut c.max_iter);
            c.dt = o.dt.or(c.dt);
            c.run(mesh, population, progress)
        }
        Method::DemShape => {
            let mut c = dem_shape::Config {
                shape: o.shape.unwrap_or(Shape::Disk),
                ..Default::default()
            };
            common(&mut c.epsilon, &mut c.max_iter);
            c.dt = o.dt.or(c.dt);
            c.run(mesh, population, progress)
        }
        Method::Sdem => {
            let mut c = sdem::Config::default();
            common(&mut c.epsilon, &mut c.max_iter);
            c.dt = o.dt.or(c.dt);
            c.run(mesh, population, progress)
        }
        Method::Edem => {
            let Some(ellipsoid) = o.ellipsoid else {
                return Err(Error::Argument(
                    "edem needs the target ellipsoid (radii a, b, c > 0)".into(),
                ));
            };
            let mut c = edem::Config {
                ellipsoid,
                ..Default::default()
            };
            common(&mut c.flow.epsilon, &mut c.flow.max_iter);
            c.flow.dt = o.dt.or(c.flow.dt);
            c.run(mesh, population, progress)
        }
        Method::Edeq => {
            let mut c = edeq::Config {
                guess: o.ellipsoid,
                ..Default::default()
            };
            common(&mut c.flow.epsilon, &mut c.flow.max_iter);
            c.flow.dt = o.dt.or(c.flow.dt);
            c.alpha = o.alpha.unwrap_or(c.alpha);
            c.run(mesh, population, progress)
        }
        Method::Lsdem => {
            let mut c = lsdem::Config::default();
            common(&mut c.epsilon, &mut c.max_iter);
            c.dt = o.dt.unwrap_or(c.dt);
            c.alpha = o.alpha.unwrap_or(c.alpha);
            c.beta = o.beta.unwrap_or(c.beta);
            c.gamma = o.gamma.unwrap_or(c.gamma);
            lsdem::run(mesh, population, &o.landmarks, &c, progress)
        }
        Method::Deq => MethodConfig::run(&deq_config(), mesh, population, progress),
        Method::Ldeq => {
            let c = ldeq::Config { deq: deq_config() };
            ldeq::run(mesh, population, &o.landmarks, &c, progress)
        }
        Method::Tdem => {
            let Some(torus) = torus else {
                return Err(Error::Argument(
                    "tdem needs the target torus (radii R > r > 0)".into(),
                ));
            };
            let mut c = tdem::Config::default();
            common(&mut c.epsilon, &mut c.max_iter);
            c.dt = o.dt.or(c.dt);
            tdem::run(mesh, population, &torus, &c, progress)
        }
        Method::SphericalConformal => spherical_conformal::run(mesh, population),
        Method::CircleConformal => circle_conformal::run(mesh, population),
    }
}

/// The domain of `result` (a map of `mapped`, whose boundary loops are `loops`, by `method`;
/// `computed` the torus it was computed on, `input` the same in input units) and how the
/// metrics measure it.
fn domain_of(
    method: Method,
    result: &MapResult,
    mapped: &TriMesh,
    loops: &[Vec<u32>],
    computed: Option<Torus>,
    input: Option<Torus>,
) -> (Domain, crate::metrics::Domain) {
    use crate::metrics::Domain as Measured;
    if let (Some(flat), Some(computed), Some(torus)) = (&result.flat_torus, computed, input) {
        let flipped = flat.count_flipped(&mapped.faces, computed.periods());
        let flat = flat.clone();
        return (Domain::Torus { torus, flat }, Measured::Torus { flipped });
    }
    if let Some(e) = result.ellipsoid {
        let [a, b, c] = e.radii();
        return (Domain::Ellipsoid { a, b, c }, Measured::Sphere);
    }
    if method.maps_onto_sphere() {
        return (Domain::Sphere, Measured::Sphere);
    }
    if matches!(method, Method::Deq | Method::Ldeq | Method::CircleConformal) {
        // Splitting chords adds interior vertices only: the loops are the input's.
        let circles = loops
            .iter()
            .map(|lp| crate::methods::deq::fit_circle(&result.positions, lp))
            .filter(|(c, r)| !(c[0].hypot(c[1]) < 1e-9 && (r - 1.0).abs() < 1e-9))
            .collect();
        return (Domain::CircleDomain { circles }, Measured::Plane);
    }
    (Domain::Plane, Measured::Plane)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn auto_resolves_by_topology_and_landmarks() {
        let cases = [
            (1, 0, false, Method::Dem),
            (3, 0, false, Method::Deq),
            (1, 0, true, Method::Ldeq),
            (0, 0, false, Method::Sdem),
            (0, 0, true, Method::Lsdem),
            (0, 1, false, Method::Tdem),
        ];
        for (b, g, l, m) in cases {
            assert_eq!(Method::Auto.resolve(b, g, l, false).unwrap(), m);
        }
        assert!(Method::Auto.resolve(0, 2, false, false).is_err());
        assert_eq!(
            Method::Sdem.resolve(1, 0, false, false).unwrap(),
            Method::Sdem
        );
        assert_eq!(
            Method::Auto.resolve(0, 0, false, true).unwrap(),
            Method::Edem
        );
    }

    #[test]
    fn a_surface_with_holes_lies_in_a_circle_domain_with_one_circle_per_hole() {
        let mesh =
            crate::generate::disk_with_holes(&[(0.4, 0.0, 0.2), (-0.4, 0.1, 0.15)], 32).unwrap();
        let surface = Surface::new(mesh.positions, mesh.faces).unwrap();
        let population = Population::Expression("area*(1+(x>0))".into());
        let map = super::map(&surface, &population, &MapOptions::default()).unwrap();
        assert_eq!(map.method, Method::Deq);
        let Domain::CircleDomain { circles } = &map.domain else {
            panic!("{:?}", map.domain);
        };
        assert_eq!(circles.len(), 2);
        assert!(circles.iter().all(|(c, r)| c[0].hypot(c[1]) + r < 1.0));
        assert_eq!(map.metrics.flipped_triangles, 0);
        assert!(map.result.converged);
    }

    #[test]
    fn a_per_face_population_of_the_wrong_length_is_refused() {
        let mesh = crate::generate::square_grid(2, 2, 1.0, 1.0).unwrap();
        let surface = Surface::new(mesh.positions, mesh.faces).unwrap();
        let e = super::map(
            &surface,
            &Population::PerFace(vec![1.0; 3]),
            &MapOptions::default(),
        )
        .unwrap_err();
        assert!(matches!(e, Error::Population(_)), "{e}");
    }

    #[test]
    fn tdem_without_a_torus_is_an_argument_error() {
        let mesh = crate::generate::torus(2.0, 1.0, 16, 8).unwrap();
        let surface = Surface::new(mesh.positions, mesh.faces).unwrap();
        let e = super::map(&surface, &Population::Area, &MapOptions::default()).unwrap_err();
        assert!(e.to_string().contains("torus"), "{e}");
    }
}
