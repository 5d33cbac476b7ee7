//! Contiguous area cartograms. In the plane ([`planar`]), the flow-based method of Gastner,
//! Seguy & More (2018): the regions' densities are rasterized on a grid, diffused in closed
//! form with the discrete cosine transform, and every vertex moves with the diffusion's
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
mod densify;
pub mod diffusion;
pub mod geojson;
pub mod planar;
pub mod raster;
pub mod regions;
pub mod sphere;
pub mod svg;

use crate::methods::StopReason;
use regions::{RegionSet, polygon_area};

/// A polygon's rings (exterior first, then holes), each a list of positions without the
/// closing repetition.
pub type Polygon = Vec<Vec<[f64; 2]>>;

/// The most faces a cartogram's mesh may have ...
pub const MAX_FACES: usize = 5_000_000;

/// ... at about this many bytes of working memory per face (the triangulation, the map's own
/// sea and the Cholesky factor of its diffusion, measured at 1.4–1.7 kB).
pub const BYTES_PER_FACE: usize = 2_000;

/// The fewest faces a cap may ask for.
pub const MIN_FACES: usize = 1_000;

/// The memory a mesh of `faces` faces needs, in GB.
fn gigabytes(faces: f64) -> f64 {
    faces * BYTES_PER_FACE as f64 / 1e9
}

/// Refuses a cap on the mesh ([`Config::max_faces`], `--faces`) outside
/// [[`MIN_FACES`], [`MAX_FACES`]], with the memory a cap beyond it would take.
pub fn check_max_faces(n: usize) -> crate::Result<()> {
    if n > MAX_FACES {
        return Err(crate::Error::Argument(format!(
            "--faces {n} would need about {:.0} GB of memory; at most {MAX_FACES} faces",
            gigabytes(n as f64)
        )));
    }
    if n < MIN_FACES {
        return Err(crate::Error::Argument(format!(
            "--faces must be at least {MIN_FACES}, got {n}"
        )));
    }
    Ok(())
}

/// Cartogram settings.
#[derive(Debug, Clone, PartialEq)]
pub struct Config {
    /// About how many triangles would fill the regions and their sea at the base spacing,
    /// where no polygon asks for finer (the mesh-based engine's setting; the flow has no
    /// mesh and ignores it).
    pub target_faces: usize,
    /// Every polygon gets about this many triangles where [`Config::max_faces`] allows.
    pub polygon_faces: usize,
    /// The cap on the mesh: with many small polygons, each gets fewer triangles so that the
    /// mesh stays under about this many (it always has every region vertex). At most
    /// [`MAX_FACES`].
    pub max_faces: usize,
    /// The iteration limit per round (`None`: the method's default; in the plane, the flow's
    /// integration steps).
    pub max_iter: Option<usize>,
    /// At most this many rounds (each starts from the map the previous one reached).
    pub rounds: usize,
    /// No further round once every region that counts (see [`counts`]) has a share error
    /// within this fraction; the cartogram has converged when it does (default 1 %).
    pub tolerance: f64,
    /// The planar grid's longer side, in cells (a power of two, default 512).
    pub grid: usize,
    /// No further round starts after this many seconds (`None`: no limit).
    pub time_limit: Option<f64>,
    /// DEM's stationary test: a round ends when its density error has improved by less than
    /// 2% over this many iterations. Sharp steps of density between regions make DEM's
    /// progress slow but steady, so the default waits longer than DEM's own 5.
    pub patience: usize,
}

/// The default cap on the mesh (see [`Config::max_faces`]).
pub const DEFAULT_MAX_FACES: usize = 150_000;

impl Default for Config {
    fn default() -> Self {
        Self {
            target_faces: 20_000,
            polygon_faces: 200,
            max_faces: DEFAULT_MAX_FACES,
            max_iter: None,
            rounds: 30,
            tolerance: 0.01,
            grid: 512,
            time_limit: None,
            patience: 10,
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
    /// (output area / value) / mean over the regions of (output area / value) − 1.
    pub ratio_error: f64,
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
    /// Median of |ratio_error|.
    pub median_error: f64,
    /// Largest |ratio_error|.
    pub worst_error: f64,
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

/// Reads a GeoJSON file of regions with their values in property `field` (see
/// [`geojson::parse_regions`]) and builds their shared vertex graph ([`RegionSet::build`]).
/// With `sphere`, positions are longitude/latitude degrees and a latitude outside [−90, 90] is
/// refused.
///
/// Errors: [`crate::Error::Io`] for an unreadable file; [`crate::Error::Format`] naming the
/// feature for everything else.
pub fn load(
    path: &std::path::Path,
    field: &str,
    sphere: bool,
) -> crate::Result<(::geojson::FeatureCollection, RegionSet)> {
    let label = crate::io::path_label(path);
    let bytes = crate::io::read_file(path)?;
    let text = String::from_utf8_lossy(&bytes);
    let (fc, raw) = geojson::parse_regions(&text, field, &label)?;
    if sphere {
        for r in &raw {
            if let Some(p) = r
                .polygons
                .iter()
                .flatten()
                .flatten()
                .find(|p| !(-90.0..=90.0).contains(&p[1]))
            {
                return Err(crate::Error::Format {
                    path: label,
                    msg: format!(
                        "{}: latitude {} is outside [-90, 90] (--sphere reads longitude, latitude in degrees)",
                        r.label, p[1]
                    ),
                });
            }
        }
    }
    let set = RegionSet::build(&raw, &label)?;
    Ok((fc, set))
}

/// Every region's (area / value) relative to the mean over the regions, minus 1; areas from
/// the rings (`coordinates`, planar).
pub fn ratio_errors(values: &[f64], coordinates: &[Vec<Polygon>]) -> Vec<f64> {
    let areas: Vec<f64> = coordinates
        .iter()
        .map(|polys| polys.iter().map(|p| polygon_area(p)).sum())
        .collect();
    ratio_errors_of_areas(values, &areas)
}

/// [`ratio_errors`] from the areas.
pub fn ratio_errors_of_areas(values: &[f64], areas: &[f64]) -> Vec<f64> {
    let ratios: Vec<f64> = areas.iter().zip(values).map(|(a, v)| a / v).collect();
    let mean = ratios.iter().sum::<f64>() / ratios.len() as f64;
    ratios.iter().map(|r| r / mean - 1.0).collect()
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

/// Median and maximum of |e|.
fn median_and_worst(errors: &[f64]) -> (f64, f64) {
    let mut a: Vec<f64> = errors.iter().map(|e| e.abs()).collect();
    a.sort_by(f64::total_cmp);
    let n = a.len();
    if n == 0 {
        return (0.0, 0.0);
    }
    let median = if n % 2 == 1 {
        a[n / 2]
    } else {
        0.5 * (a[n / 2 - 1] + a[n / 2])
    };
    (median, a[n - 1])
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
    let errors = ratio_errors_of_areas(&values, measured);
    let (median_error, worst_error) = median_and_worst(&errors);
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
            ratio_error: errors[i],
            error: shares[i],
        })
        .collect();
    Cartogram {
        coordinates,
        regions,
        median_error,
        worst_error,
        mean_error,
        max_error,
        max_error_region,
        run,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ratio_errors_are_relative_to_the_mean_ratio() {
        // Ratios 1, 2, 3 (mean 2): errors −½, 0, ½.
        let e = ratio_errors_of_areas(&[1.0, 1.0, 2.0], &[1.0, 2.0, 6.0]);
        assert_eq!(e, vec![-0.5, 0.0, 0.5]);
        assert_eq!(median_and_worst(&e), (0.5, 0.5));
        assert_eq!(
            median_and_worst(&[0.1, -0.3, 0.2, 0.0]),
            (0.15000000000000002, 0.3)
        );
    }
}
