//! Contiguous area cartograms. In the plane ([`planar`]), the flow-based method of Gastner,
//! Seguy & More (2018): the regions' densities are rasterized on a grid, the flow that takes
//! them linearly to their mean is solved in closed form with the discrete cosine transform,
//! and every vertex moves with that flow's
//! velocity field, in rounds, until every region's share of the total area is within
//! [`Config::tolerance`] of its share of the values. On the globe ([`sphere`]), the same flow
//! in an equal-area projection.
//!
//! Neighbouring regions keep sharing their borders: all regions move over one shared vertex
//! list. The ring structure (polygons, rings) is kept; edges may gain vertices.
//!
//! Errors are measured on shares: a region's error is |A_i/ΣA − v_i/Σv| / (v_i/Σv), and only
//! the regions with at least [`MIN_COUNTED_SHARE`] of the total value count towards
//! convergence.

mod advect;
mod buckets;
mod cleaning;
pub mod colours;
mod crossings;
pub mod degrees;
mod densify;
pub mod flow;
mod frame;
pub mod geojson;
mod loops;
pub mod planar;
pub mod project;
pub mod raster;
pub mod regions;
mod rings;
mod sides;
pub mod sphere;
pub mod svg;
mod topology;
pub mod validity;
pub mod values;

use crate::methods::StopReason;
use regions::{RegionSet, polygon_area};

/// A polygon's rings (exterior first, then holes), each a list of positions without the
/// closing repetition.
pub type Polygon = Vec<Vec<[f64; 2]>>;

/// Cartogram settings.
#[derive(Debug, Clone, PartialEq)]
pub struct Config {
    /// The iteration limit per round (`None`: the method's default; in the plane, the flow's
    /// integration steps).
    pub max_iter: Option<usize>,
    /// At most this many rounds (each starts from the map the previous one reached).
    pub rounds: usize,
    /// No further round once every region that counts (see [`counts`]) has a share error
    /// within this fraction; the cartogram has converged when it does (default 1 %).
    pub tolerance: f64,
    /// The planar grid's longer side, in cells (a power of two, default 1024).
    pub grid: usize,
    /// No further round starts after this many seconds (`None`: no limit).
    pub time_limit: Option<f64>,
}

impl Default for Config {
    fn default() -> Self {
        Self {
            max_iter: None,
            rounds: 30,
            tolerance: 0.01,
            grid: 1024,
            time_limit: None,
        }
    }
}

/// One region's figures in the result.
#[derive(Debug, Clone, PartialEq)]
pub struct RegionFigures {
    /// The feature's label (index and name).
    pub label: String,
    /// Its value.
    pub value: f64,
    /// Its area before, in input units (infinite when beyond the range of `f64`, as for
    /// coordinates above about 1e154).
    pub input_area: f64,
    /// Its area after, likewise.
    pub output_area: f64,
    /// Its value's share of all the values (the share of the total area it should get).
    pub target_share: f64,
    /// Its share of the regions' total area after.
    pub output_share: f64,
    /// The relative error of its share: output_share / target_share − 1.
    pub error: f64,
}

/// A computed cartogram.
#[derive(Debug, Clone, PartialEq)]
pub struct Cartogram {
    /// Every feature's new rings, in the input's ring structure.
    pub coordinates: Vec<Vec<Polygon>>,
    /// Per-region figures, in feature order.
    pub regions: Vec<RegionFigures>,
    /// Mean |share error| over the regions that count (see [`counts`]).
    pub mean_error: f64,
    /// Largest |share error| over the regions that count.
    pub max_error: f64,
    /// The region with the largest |share error| that counts (its label).
    pub max_error_region: String,

    /// How the run went.
    pub run: Run,
}

/// How a run went.
#[derive(Debug, Clone, PartialEq)]
pub struct Run {
    /// Density-equalizing iterations over all rounds.
    pub iterations: usize,
    /// Rounds of the map (see [`Config::rounds`]).
    pub rounds: usize,
    /// Why the last round stopped.
    pub stop_reason: StopReason,
    /// Size of the mesh (regions and sea, without the method's own sea).
    pub mesh_vertices: usize,
    /// See `mesh_vertices` (0 for the planar flow, which has no mesh).
    pub mesh_faces: usize,
    /// The planar flow's grid in its last round, cells along x and y (0 without one).
    pub grid: [usize; 2],
    /// Mesh faces the map flipped (0 for a bijective map).
    pub flipped_triangles: usize,
    /// Remarks of the method.
    pub notes: Vec<String>,
    /// Seconds.
    pub time_s: f64,
}

/// How the input's positions are read.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Positions {
    /// Plane coordinates, used as they are.
    Plane,
    /// Longitude/latitude degrees, for the cartogram on the globe ([`sphere`]).
    Sphere,
    /// Longitude/latitude degrees, projected to Equal Earth kilometres ([`project`]) for the
    /// planar cartogram.
    Project,
}

/// Reads a GeoJSON file of regions ([`geojson::parse_shapes`]) with their values from
/// `source` ([`values::read`], missing and zero values completed by [`values::complete`] on
/// the regions' areas as computed), and builds their shared vertex graph
/// ([`RegionSet::build`]). With [`Positions::Sphere`] or [`Positions::Project`], positions are
/// longitude/latitude degrees and a latitude outside [−90, 90] is refused; with
/// [`Positions::Project`] they are projected (long edges split first). The values' warnings
/// come first in the set's warnings.
///
/// Errors: [`crate::Error::Io`] for an unreadable file; [`crate::Error::Parse`] for a bad
/// table line; [`crate::Error::Format`] naming the feature for everything else, and when no
/// region has a positive value.
pub fn load(
    path: &std::path::Path,
    source: &values::ValueSource,
    positions: Positions,
) -> crate::Result<(::geojson::FeatureCollection, RegionSet)> {
    let label = crate::io::path_label(path);
    let bytes = crate::io::read_file(path)?;
    load_text(&String::from_utf8_lossy(&bytes), &label, source, positions)
}

/// [`load`] of GeoJSON `text` already in memory; `label` names it in messages (a file name,
/// or e.g. `"<geojson>"`).
pub fn load_text(
    text: &str,
    label: &str,
    source: &values::ValueSource,
    positions: Positions,
) -> crate::Result<(::geojson::FeatureCollection, RegionSet)> {
    let label = label.to_string();
    let (fc, mut shapes) = geojson::parse_shapes(text, &label)?;
    let (read, mut warnings) = values::read(&fc, &shapes, source, &label)?;
    if positions != Positions::Plane {
        for s in &shapes {
            if let Some(p) = s
                .polygons
                .iter()
                .flatten()
                .flatten()
                .find(|p| !(-90.0..=90.0).contains(&p[1]))
            {
                let option = if positions == Positions::Sphere {
                    "`sphere`"
                } else {
                    "`project`"
                };
                return Err(crate::Error::Format {
                    path: label,
                    msg: format!(
                        "{}: latitude {} is outside [-90, 90] ({option} reads longitude, latitude in degrees)",
                        s.label, p[1]
                    ),
                });
            }
        }
    }
    if positions == Positions::Project {
        for s in shapes.iter_mut() {
            project::densify_degrees(&mut s.polygons);
            for p in s.polygons.iter_mut().flatten().flatten() {
                *p = project::forward(*p);
            }
        }
    }
    let areas: Vec<f64> = shapes
        .iter()
        .map(|s| {
            s.polygons
                .iter()
                .map(|rings| {
                    if positions == Positions::Sphere {
                        let projected: Polygon = rings
                            .iter()
                            .map(|r| r.iter().map(|&p| sphere::project(p)).collect())
                            .collect();
                        polygon_area(&projected)
                    } else {
                        polygon_area(rings)
                    }
                })
                .sum()
        })
        .collect();
    let labels: Vec<String> = shapes.iter().map(|s| s.label.clone()).collect();
    let (complete, filled) =
        values::complete(&read, &areas, &labels).map_err(|msg| crate::Error::Format {
            path: label.clone(),
            msg,
        })?;
    warnings.extend(filled);
    let raw: Vec<geojson::RawRegion> = shapes
        .into_iter()
        .zip(complete)
        .map(|(s, v)| s.with_value(v))
        .collect();
    let mut set = RegionSet::build(&raw, &label)?;
    warnings.append(&mut set.warnings);
    set.warnings = warnings;
    Ok((fc, set))
}

/// The values divided by the largest one: only their ratios matter, and sums of them cannot
/// overflow (values up to the largest `f64` are accepted).
pub(crate) fn unit_values(values: &[f64]) -> Vec<f64> {
    let max = values.iter().fold(0.0f64, |m, &v| m.max(v));
    values.iter().map(|v| v / max).collect()
}

/// Regions with at least this share of the total value count towards convergence; smaller
/// ones are reported but may stay further off (a grid cell is the flow's resolution).
pub const MIN_COUNTED_SHARE: f64 = 1e-4;

/// Whether a region with this target share counts towards convergence.
pub fn counts(target_share: f64) -> bool {
    target_share >= MIN_COUNTED_SHARE
}

/// Every region's share error |A_i/ΣA − v_i/Σv| / (v_i/Σv), signed (positive: too large).
pub fn share_errors(values: &[f64], areas: &[f64]) -> Vec<f64> {
    let unit = unit_values(values);
    let vt: f64 = unit.iter().sum();
    let at: f64 = areas.iter().sum();
    unit.iter()
        .zip(areas)
        .map(|(v, a)| {
            let target = v / vt;
            if target > 0.0 && at > 0.0 {
                (a / at) / target - 1.0
            } else {
                f64::INFINITY
            }
        })
        .collect()
}

/// Assembles the result with planar areas: `coordinates` in the set's normalised frame, the
/// figures from them, then the coordinates taken back to input units.
///
/// Errors: [`crate::Error::Format`] when an output position lies beyond the range of `f64`
/// (an input reaching within a small factor of ±1.8e308).
fn finish(
    set: &RegionSet,
    coordinates: Vec<Vec<Polygon>>,
    run: Run,
    path: &str,
) -> crate::Result<Cartogram> {
    let input = set.coordinates();
    let area = |c: &Vec<Polygon>| c.iter().map(|p| polygon_area(p)).sum::<f64>();
    let out_areas: Vec<f64> = coordinates.iter().map(area).collect();
    let in_areas: Vec<f64> = input.iter().map(area).collect();
    let frame = set.frame;
    let mut coordinates = coordinates;
    for p in coordinates.iter_mut().flatten().flatten().flatten() {
        *p = frame.to_input(*p);
        if !(p[0].is_finite() && p[1].is_finite()) {
            return Err(crate::Error::Format {
                path: path.to_string(),
                msg: "the cartogram's coordinates would lie beyond the range of f64 (the \
                      regions reach too close to ±1.8e308)"
                    .into(),
            });
        }
    }
    let to_input = |a: &[f64]| {
        a.iter()
            .map(|&a| frame.area_to_input(a))
            .collect::<Vec<_>>()
    };
    Ok(figures(
        set,
        coordinates,
        (&to_input(&in_areas), &to_input(&out_areas)),
        &out_areas,
        run,
    ))
}

/// Assembles the result from the regions' areas before and after (`areas`, as reported) and
/// the areas the errors and shares are measured on (`measured`, the output areas in any unit
/// that keeps them finite).
pub(crate) fn figures(
    set: &RegionSet,
    coordinates: Vec<Vec<Polygon>>,
    areas: (&[f64], &[f64]),
    measured: &[f64],
    run: Run,
) -> Cartogram {
    let values: Vec<f64> = set.regions.iter().map(|r| r.value).collect();
    // Shares of values scaled to a largest value of 1, so that the sum cannot overflow.
    let unit = unit_values(&values);
    let value_total: f64 = unit.iter().sum();
    let area_total: f64 = measured.iter().sum();
    let shares = share_errors(&values, measured);
    let (mut sum, mut n, mut max_error, mut max_error_region) = (0.0, 0, 0.0f64, String::new());
    for (i, r) in set.regions.iter().enumerate() {
        if counts(unit[i] / value_total) {
            let e = shares[i].abs();
            sum += e;
            n += 1;
            if e > max_error || max_error_region.is_empty() {
                max_error = e;
                max_error_region = r.label.clone();
            }
        }
    }
    let mean_error = if n > 0 { sum / n as f64 } else { 0.0 };
    let regions = set
        .regions
        .iter()
        .enumerate()
        .map(|(i, r)| RegionFigures {
            label: r.label.clone(),
            value: r.value,
            input_area: areas.0[i],
            output_area: areas.1[i],
            target_share: unit[i] / value_total,
            output_share: measured[i] / area_total,
            error: shares[i],
        })
        .collect();
    Cartogram {
        coordinates,
        regions,
        mean_error,
        max_error,
        max_error_region,
        run,
    }
}
