//! Contiguous area cartograms (DEM paper §6.1; on the globe, SDEM paper §5.3): regions read
//! from GeoJSON are triangulated together with the sea around them, every triangle gets its
//! region's value in proportion to its share of the region's area, the density-equalizing map
//! of that mesh is computed, and every region vertex is moved with the map. Neighbouring
//! regions keep sharing their borders, since a border is one chain of mesh edges, and the map
//! is bijective, so regions cannot overlap.
//!
//! The output rings are the images of the input rings under the piecewise-linear map: each
//! input vertex, followed by the mesh vertices the triangulation put on its edge to the next
//! one (a straight edge becomes a polyline). The ring structure (polygons, rings) is kept.

pub mod geojson;
pub mod planar;
pub mod regions;
pub mod sphere;
pub mod svg;
pub mod triangulate;

use crate::methods::StopReason;
use regions::{RegionSet, polygon_area};

/// A round changes a region's value by at most this factor (or its inverse), so that a region
/// the map cannot resize further does not run away.
pub(crate) const MIN_CORRECTION: f64 = 0.5;

/// A polygon's rings (exterior first, then holes), each a list of positions without the
/// closing repetition.
pub type Polygon = Vec<Vec<[f64; 2]>>;

/// Cartogram settings.
#[derive(Debug, Clone, PartialEq)]
pub struct Config {
    /// About how many triangles the regions and their sea are cut into.
    pub target_faces: usize,
    /// DEM's iteration limit per round (`None`: DEM's default).
    pub max_iter: Option<usize>,
    /// At most this many DEM rounds (each starts from the map the previous one reached).
    pub rounds: usize,
    /// No further round once every region's area/value is within this fraction of the mean.
    pub tolerance: f64,
    /// DEM's stationary test: a round ends when its density error has improved by less than
    /// 2% over this many iterations. Sharp steps of density between regions make DEM's
    /// progress slow but steady, so the default waits longer than DEM's own 5.
    pub patience: usize,
}

impl Default for Config {
    fn default() -> Self {
        Self {
            target_faces: 20_000,
            max_iter: None,
            rounds: 10,
            tolerance: 0.01,
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
    /// Its area before.
    pub input_area: f64,
    /// Its area after.
    pub output_area: f64,
    /// (output area / value) / mean over the regions of (output area / value) − 1.
    pub ratio_error: f64,
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
    /// See `mesh_vertices`.
    pub mesh_faces: usize,
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

/// Assembles the result with planar areas.
fn finish(set: &RegionSet, coordinates: Vec<Vec<Polygon>>, run: Run) -> Cartogram {
    let input = set.coordinates();
    let area = |c: &Vec<Polygon>| c.iter().map(|p| polygon_area(p)).sum::<f64>();
    let out_areas: Vec<f64> = coordinates.iter().map(area).collect();
    let in_areas: Vec<f64> = input.iter().map(area).collect();
    figures(set, coordinates, &in_areas, &out_areas, run)
}

/// Assembles the result from the regions' areas before and after.
pub(crate) fn figures(
    set: &RegionSet,
    coordinates: Vec<Vec<Polygon>>,
    in_areas: &[f64],
    out_areas: &[f64],
    run: Run,
) -> Cartogram {
    let values: Vec<f64> = set.regions.iter().map(|r| r.value).collect();
    let errors = ratio_errors_of_areas(&values, out_areas);
    let (median_error, worst_error) = median_and_worst(&errors);
    let regions = set
        .regions
        .iter()
        .enumerate()
        .map(|(i, r)| RegionFigures {
            label: r.label.clone(),
            value: r.value,
            input_area: in_areas[i],
            output_area: out_areas[i],
            ratio_error: errors[i],
        })
        .collect();
    Cartogram {
        coordinates,
        regions,
        median_error,
        worst_error,
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
