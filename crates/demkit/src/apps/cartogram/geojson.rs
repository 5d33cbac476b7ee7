//! Reading the regions of a cartogram from a GeoJSON FeatureCollection (RFC 7946) and writing
//! the transformed collection back: every feature, its properties and its ring structure kept,
//! only the coordinates replaced.

use super::Polygon;
use crate::{Error, Result};
use geojson::{Feature, FeatureCollection, GeoJson, GeometryValue, JsonValue, Position};

/// One feature's geometry and value, as read.
#[derive(Debug, Clone, PartialEq)]
pub struct RawRegion {
    /// How messages name the feature: its 0-based index and, if present, its name or id.
    pub label: String,
    /// The value the region's area is to be proportional to (finite, > 0).
    pub value: f64,
    /// True for a MultiPolygon (written back as one), false for a Polygon.
    pub multi: bool,
    /// The polygons (one for a Polygon): rings, exterior first, each without its closing point.
    pub polygons: Vec<Polygon>,
}

/// One feature's geometry, as read, before its value is known.
#[derive(Debug, Clone, PartialEq)]
pub struct Shape {
    /// How messages name the feature (see [`feature_label`]).
    pub label: String,
    /// True for a MultiPolygon (written back as one), false for a Polygon.
    pub multi: bool,
    /// The polygons (one for a Polygon): rings, exterior first, each without its closing point.
    pub polygons: Vec<Polygon>,
}

impl Shape {
    /// The region of this shape with `value`.
    pub fn with_value(self, value: f64) -> RawRegion {
        RawRegion {
            label: self.label,
            value,
            multi: self.multi,
            polygons: self.polygons,
        }
    }
}

/// Parses `text` as a FeatureCollection whose every feature is a Polygon or MultiPolygon with
/// a positive numeric property `field`; `path` names the file in messages.
///
/// Errors ([`Error::Format`], naming the feature): those of [`parse_shapes`], and a missing,
/// non-numeric, non-finite or non-positive value.
pub fn parse_regions(
    text: &str,
    field: &str,
    path: &str,
) -> Result<(FeatureCollection, Vec<RawRegion>)> {
    let (fc, shapes) = parse_shapes(text, path)?;
    let mut regions = Vec::with_capacity(shapes.len());
    for (shape, f) in shapes.into_iter().zip(&fc.features) {
        let value = read_value(f, field).map_err(|msg| Error::Format {
            path: path.to_string(),
            msg: format!("{}: {msg}", shape.label),
        })?;
        regions.push(shape.with_value(value));
    }
    Ok((fc, regions))
}

/// Parses `text` as a FeatureCollection whose every feature is a Polygon or MultiPolygon, and
/// returns the features' shapes in order; `path` names the file in messages.
///
/// Errors ([`Error::Format`], naming the feature): not GeoJSON, not a FeatureCollection, no
/// features, a feature without geometry or with another geometry type, an empty polygon, a
/// position with fewer than two or non-finite coordinates.
pub fn parse_shapes(text: &str, path: &str) -> Result<(FeatureCollection, Vec<Shape>)> {
    let err = |msg: String| Error::Format {
        path: path.to_string(),
        msg,
    };
    let gj: GeoJson = text
        .parse()
        .map_err(|e| err(format!("not valid GeoJSON: {e}")))?;
    let fc = match gj {
        GeoJson::FeatureCollection(fc) => fc,
        GeoJson::Feature(_) => return Err(err("not a FeatureCollection (found a Feature)".into())),
        GeoJson::Geometry(_) => {
            return Err(err("not a FeatureCollection (found a Geometry)".into()));
        }
    };
    if fc.features.is_empty() {
        return Err(err("the FeatureCollection has no features".into()));
    }
    let mut shapes = Vec::with_capacity(fc.features.len());
    for (i, f) in fc.features.iter().enumerate() {
        let label = feature_label(i, f);
        let ferr = |msg: String| err(format!("{label}: {msg}"));
        let geometry = f
            .geometry
            .as_ref()
            .ok_or_else(|| ferr("has no geometry".into()))?;
        let (multi, raw) = match &geometry.value {
            GeometryValue::Polygon { coordinates } => (false, vec![coordinates]),
            GeometryValue::MultiPolygon { coordinates } => (true, coordinates.iter().collect()),
            other => {
                return Err(ferr(format!(
                    "its geometry is a {}, not a Polygon or MultiPolygon",
                    other.type_name()
                )));
            }
        };
        if raw.is_empty() {
            return Err(ferr("its MultiPolygon has no polygons".into()));
        }
        let mut polygons = Vec::with_capacity(raw.len());
        for (k, rings) in raw.into_iter().enumerate() {
            if rings.is_empty() {
                return Err(ferr(format!("polygon {k} has no rings")));
            }
            let mut out = Vec::with_capacity(rings.len());
            for (j, ring) in rings.iter().enumerate() {
                let mut pts = Vec::with_capacity(ring.len());
                for p in ring {
                    let s = p.as_slice();
                    if s.len() < 2 || !s[0].is_finite() || !s[1].is_finite() {
                        return Err(ferr(format!(
                            "ring {j} of polygon {k} has a position without two finite coordinates"
                        )));
                    }
                    pts.push([s[0], s[1]]);
                }
                out.push(pts);
            }
            polygons.push(out);
        }
        shapes.push(Shape {
            label,
            multi,
            polygons,
        });
    }
    Ok((fc, shapes))
}

/// `feature I` followed by the feature's `name` (or `NAME`, `Name`) property or its id, if any.
pub fn feature_label(index: usize, f: &Feature) -> String {
    let props = f.properties.as_ref();
    let name = ["name", "NAME", "Name"]
        .iter()
        .find_map(|k| props.and_then(|p| p.get(*k)))
        .and_then(json_text);
    let id = || match &f.id {
        Some(geojson::feature::Id::String(s)) => Some(s.clone()),
        Some(geojson::feature::Id::Number(n)) => Some(n.to_string()),
        None => props.and_then(|p| p.get("id")).and_then(json_text),
    };
    match (name, id()) {
        (Some(n), _) => format!("feature {index} (name '{n}')"),
        (None, Some(id)) => format!("feature {index} (id '{id}')"),
        (None, None) => format!("feature {index}"),
    }
}

/// A JSON string or number as text (how a join key is compared).
pub fn json_text(v: &JsonValue) -> Option<String> {
    match v {
        JsonValue::String(s) => Some(s.clone()),
        JsonValue::Number(n) => Some(n.to_string()),
        _ => None,
    }
}

/// The value in property `field`, allowing it to be missing: `None` when the property is
/// absent, null or an empty string, else a finite number ≥ 0 (a JSON number, or a string
/// holding one).
///
/// Errors (the message, without the feature's label): a value that is not a number, not
/// finite, or negative.
pub fn optional_value(f: &Feature, field: &str) -> std::result::Result<Option<f64>, String> {
    let v = match f.properties.as_ref().and_then(|p| p.get(field)) {
        None | Some(JsonValue::Null) => return Ok(None),
        Some(JsonValue::String(s)) if s.trim().is_empty() => return Ok(None),
        Some(v) => v,
    };
    let x = match v {
        JsonValue::Number(n) => n.as_f64(),
        JsonValue::String(s) => s.trim().parse::<f64>().ok(),
        _ => None,
    }
    .ok_or_else(|| format!("its value '{field}' = {v} is not a number"))?;
    if !x.is_finite() {
        return Err(format!("its value '{field}' = {v} is not finite"));
    }
    if x < 0.0 {
        return Err(format!("its value '{field}' = {v} is negative"));
    }
    Ok(Some(x))
}

/// The positive finite number in property `field` (a JSON number, or a string holding one).
fn read_value(f: &Feature, field: &str) -> std::result::Result<f64, String> {
    let v = f
        .properties
        .as_ref()
        .and_then(|p| p.get(field))
        .ok_or_else(|| format!("has no value '{field}'"))?;
    let x = match v {
        JsonValue::Number(n) => n.as_f64(),
        JsonValue::String(s) => s.trim().parse::<f64>().ok(),
        JsonValue::Null => return Err(format!("its value '{field}' is null")),
        _ => None,
    }
    .ok_or_else(|| format!("its value '{field}' = {v} is not a number"))?;
    if !x.is_finite() {
        return Err(format!("its value '{field}' = {v} is not finite"));
    }
    if x <= 0.0 {
        return Err(format!("its value '{field}' = {v} is not positive"));
    }
    Ok(x)
}

/// The collection `fc` with every feature's coordinates replaced by `polygons[i]` (rings
/// without closing point, in the feature's ring structure), Polygon stays Polygon and
/// MultiPolygon MultiPolygon; rings are closed and oriented as RFC 7946 §3.1.6 asks
/// (exteriors counter-clockwise, holes clockwise). Properties and ids are kept.
pub fn replace_coordinates(fc: &FeatureCollection, polygons: &[Vec<Polygon>]) -> FeatureCollection {
    let mut out = fc.clone();
    out.bbox = None;
    for (f, polys) in out.features.iter_mut().zip(polygons) {
        f.bbox = None;
        let rings_of = |p: &Polygon| -> Vec<Vec<Position>> {
            p.iter()
                .enumerate()
                .map(|(j, ring)| closed_ring(ring, j == 0))
                .collect()
        };
        if let Some(g) = f.geometry.as_mut() {
            g.bbox = None;
            g.value = match g.value {
                GeometryValue::MultiPolygon { .. } => GeometryValue::MultiPolygon {
                    coordinates: polys.iter().map(rings_of).collect(),
                },
                _ => GeometryValue::Polygon {
                    coordinates: polys.first().map(rings_of).unwrap_or_default(),
                },
            };
        }
    }
    out
}

/// A GeoJSON ring: closed, counter-clockwise when `exterior`, clockwise otherwise.
fn closed_ring(ring: &[[f64; 2]], exterior: bool) -> Vec<Position> {
    let mut pts: Vec<[f64; 2]> = ring.to_vec();
    if (super::rings::ring_orientation(&pts) > 0.0) != exterior {
        pts.reverse();
    }
    if let Some(&first) = pts.first() {
        pts.push(first);
    }
    pts.into_iter().map(Position::from).collect()
}

/// The collection as GeoJSON text.
pub fn to_text(fc: FeatureCollection) -> String {
    GeoJson::from(fc).to_string()
}

#[cfg(test)]
mod tests {
    use super::*;

    const FC: &str = r#"{"type":"FeatureCollection","features":[
      {"type":"Feature","properties":{"name":"A","pop":3},"geometry":{"type":"Polygon",
       "coordinates":[[[0,0],[1,0],[1,1],[0,1],[0,0]]]}},
      {"type":"Feature","id":7,"properties":{"pop":"2.5"},"geometry":{"type":"MultiPolygon",
       "coordinates":[[[[2,0],[3,0],[3,1],[2,0]]],[[[4,0],[5,0],[5,1],[4,0]]]]}}]}"#;

    #[test]
    fn reads_polygons_multipolygons_and_values() {
        let (fc, r) = parse_regions(FC, "pop", "x.geojson").unwrap();
        assert_eq!(fc.features.len(), 2);
        assert_eq!(r[0].label, "feature 0 (name 'A')");
        assert_eq!(r[1].label, "feature 1 (id '7')");
        assert_eq!((r[0].value, r[1].value), (3.0, 2.5));
        assert!(!r[0].multi && r[1].multi);
        assert_eq!(r[0].polygons[0][0].len(), 5);
        assert_eq!(r[1].polygons.len(), 2);
    }

    #[test]
    fn refusals_name_the_feature() {
        let cases = [
            (FC.replace("\"pop\":3", "\"pop\":0"), "feature 0 (name 'A'): its value 'pop' = 0 is not positive"),
            (FC.replace("\"pop\":3", "\"pop\":-1"), "is not positive"),
            (FC.replace("\"pop\":3", "\"pop\":\"abc\""), "is not a number"),
            (FC.replace("\"pop\":3", "\"pop\":null"), "is null"),
            (FC.replace("\"pop\":\"2.5\"", "\"x\":1"), "feature 1 (id '7'): has no value 'pop'"),
            (FC.replace("\"type\":\"Polygon\",\n       \"coordinates\":[[[0,0],[1,0],[1,1],[0,1],[0,0]]]", "\"type\":\"Point\",\"coordinates\":[0,0]"), "is a Point"),
            (r#"{"type":"Feature","properties":{},"geometry":null}"#.to_string(), "not a FeatureCollection"),
            ("[1,2".to_string(), "not valid GeoJSON"),
        ];
        for (text, want) in cases {
            let e = parse_regions(&text, "pop", "x.geojson")
                .unwrap_err()
                .to_string();
            assert!(e.starts_with("x.geojson: "), "{e}");
            assert!(e.contains(want), "{e} does not contain {want}");
        }
    }

    #[test]
    fn written_rings_are_closed_and_oriented() {
        let (fc, _) = parse_regions(FC, "pop", "x").unwrap();
        // Exterior given clockwise, hole given counter-clockwise: both are turned around.
        let square = vec![[0.0, 0.0], [0.0, 4.0], [4.0, 4.0], [4.0, 0.0]];
        let hole = vec![[1.0, 1.0], [2.0, 1.0], [2.0, 2.0], [1.0, 2.0]];
        let tri = vec![[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]];
        let out = replace_coordinates(
            &fc,
            &[vec![vec![square, hole]], vec![vec![tri.clone()], vec![tri]]],
        );
        let text = to_text(out);
        let (back, r) = parse_regions(&text, "pop", "x").unwrap();
        assert_eq!(back.features[0].properties, fc.features[0].properties);
        let rings = &r[0].polygons[0];
        assert_eq!(rings[0].first(), rings[0].last());
        assert!(super::super::rings::ring_area(&rings[0][..4]) > 0.0);
        assert!(super::super::rings::ring_area(&rings[1][..4]) < 0.0);
        assert!(r[1].multi && r[1].polygons.len() == 2);
    }
}
