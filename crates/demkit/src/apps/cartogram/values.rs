//! The regions' values: read from a feature property or from a CSV table joined on a key,
//! then made usable by the flow, as the cartogram programs of Gastner, Seguy & More do: a
//! missing value becomes the mean density times the region's area (the region keeps its
//! size), a zero value [`ZERO_FRACTION`] of the smallest positive value (the region shrinks
//! but keeps some area, so that its neighbours stay neighbours).

use super::geojson::{Shape, json_text, optional_value};
use crate::{Error, Result};
use geojson::FeatureCollection;
use std::collections::HashMap;
use std::path::Path;

/// A zero value becomes this fraction of the smallest positive value (the `MIN_POP_FAC` of
/// the reference implementation of Gastner, Seguy & More 2018).
pub const ZERO_FRACTION: f64 = 0.2;

/// Where the regions' values come from.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ValueSource<'a> {
    /// A numeric feature property.
    Property(&'a str),
    /// A CSV file whose first row is a header; column `key` holds the feature property `key`
    /// of the region a row is for, column `column` (default: the only other column) its value.
    Table {
        /// The CSV file.
        path: &'a Path,
        /// The join key: a column of the table and a property of the features.
        key: &'a str,
        /// The value column (`None`: the table has exactly one column besides the key).
        column: Option<&'a str>,
    },
}

/// A CSV table of values by key.
#[derive(Debug, Clone, PartialEq)]
pub struct Table {
    /// The value of each key (`None`: the cell is empty).
    pub values: HashMap<String, Option<f64>>,
    /// The keys in the table's order.
    pub keys: Vec<String>,
}

/// Reads a CSV table of values (see [`ValueSource::Table`]) from `text`; `path` names the file
/// in messages.
///
/// Errors ([`Error::Parse`] naming the line, or [`Error::Format`]): no header, the key or value
/// column missing from the header (or, without `column`, a header without exactly one other
/// column), a row without the columns, a value that is not a finite number ≥ 0, an empty or
/// duplicate key.
pub fn parse_table(text: &str, path: &str, key: &str, column: Option<&str>) -> Result<Table> {
    let parse_err = |line: u64, msg: String| Error::Parse {
        path: path.to_string(),
        line: line as usize,
        msg,
    };
    let mut reader = csv::ReaderBuilder::new()
        .flexible(true)
        .trim(csv::Trim::All)
        .from_reader(text.as_bytes());
    let header = reader
        .headers()
        .map_err(|e| parse_err(1, format!("not a CSV header: {e}")))?
        .clone();
    let names: Vec<&str> = header.iter().collect();
    if names.iter().all(|n| n.is_empty()) {
        return Err(parse_err(1, "the CSV file has no header row".into()));
    }
    let find = |name: &str| names.iter().position(|n| *n == name);
    let key_col = find(key).ok_or_else(|| {
        parse_err(
            1,
            format!(
                "no column '{key}' (`key`) in the header {}",
                names.join(",")
            ),
        )
    })?;
    let value_col = match column {
        Some(c) => find(c).ok_or_else(|| {
            parse_err(
                1,
                format!(
                    "no column '{c}' (`value`) in the header {}",
                    names.join(",")
                ),
            )
        })?,
        None => {
            let others: Vec<usize> = (0..names.len()).filter(|&i| i != key_col).collect();
            match others[..] {
                [only] => only,
                _ => {
                    return Err(parse_err(
                        1,
                        format!(
                            "{} columns besides '{key}': name the value column (`value`)",
                            others.len()
                        ),
                    ));
                }
            }
        }
    };
    let value_name = names[value_col].to_string();
    let mut table = Table {
        values: HashMap::new(),
        keys: Vec::new(),
    };
    let mut first_line: HashMap<String, u64> = HashMap::new();
    for record in reader.records() {
        let record = record.map_err(|e| {
            let line = e.position().map_or(0, |p| p.line());
            parse_err(line, format!("not CSV: {e}"))
        })?;
        let line = record.position().map_or(0, |p| p.line());
        if record.iter().all(str::is_empty) {
            continue;
        }
        let cell = |i: usize| {
            record.get(i).ok_or_else(|| {
                parse_err(
                    line,
                    format!("the row has {} fields, no column {}", record.len(), i + 1),
                )
            })
        };
        let k = cell(key_col)?.to_string();
        if k.is_empty() {
            return Err(parse_err(line, format!("the key '{key}' is empty")));
        }
        let text = cell(value_col)?;
        let value = if text.is_empty() {
            None
        } else {
            let x: f64 = text.parse().map_err(|_| {
                parse_err(
                    line,
                    format!("'{k}': the value '{value_name}' = '{text}' is not a number"),
                )
            })?;
            if !x.is_finite() || x < 0.0 {
                return Err(parse_err(
                    line,
                    format!(
                        "'{k}': the value '{value_name}' = '{text}' is {}",
                        if x.is_finite() {
                            "negative"
                        } else {
                            "not finite"
                        }
                    ),
                ));
            }
            Some(x)
        };
        if let Some(earlier) = first_line.get(&k) {
            return Err(parse_err(
                line,
                format!("the key '{k}' is repeated (first on line {earlier})"),
            ));
        }
        first_line.insert(k.clone(), line);
        table.keys.push(k.clone());
        table.values.insert(k, value);
    }
    Ok(table)
}

/// Every feature's value as read from `source` (`None`: missing), and warnings (table rows
/// that match no feature, features without a key). `path` names the GeoJSON file in messages.
///
/// Errors: those of [`parse_table`] and of reading the table's file; a property value that is
/// not a finite number ≥ 0 ([`Error::Format`] naming the feature).
pub fn read(
    fc: &FeatureCollection,
    shapes: &[Shape],
    source: &ValueSource,
    path: &str,
) -> Result<(Vec<Option<f64>>, Vec<String>)> {
    let feature_err = |label: &str, msg: String| Error::Format {
        path: path.to_string(),
        msg: format!("{label}: {msg}"),
    };
    match *source {
        ValueSource::Property(field) => {
            let mut values = Vec::with_capacity(shapes.len());
            for (f, s) in fc.features.iter().zip(shapes) {
                values.push(optional_value(f, field).map_err(|m| feature_err(&s.label, m))?);
            }
            Ok((values, Vec::new()))
        }
        ValueSource::Table {
            path: table_path,
            key,
            column,
        } => {
            let label = crate::io::path_label(table_path);
            let bytes = crate::io::read_file(table_path)?;
            let table = parse_table(&String::from_utf8_lossy(&bytes), &label, key, column)?;
            let mut used: HashMap<&str, ()> = HashMap::new();
            let mut values = Vec::with_capacity(shapes.len());
            let mut no_key = Vec::new();
            for (f, s) in fc.features.iter().zip(shapes) {
                let k = f
                    .properties
                    .as_ref()
                    .and_then(|p| p.get(key))
                    .and_then(json_text)
                    .map(|k| k.trim().to_string());
                match k {
                    Some(k) => match table.values.get_key_value(&k) {
                        Some((stored, v)) => {
                            used.insert(stored.as_str(), ());
                            values.push(*v);
                        }
                        None => values.push(None),
                    },
                    None => {
                        no_key.push(s.label.clone());
                        values.push(None);
                    }
                }
            }
            let mut warnings = Vec::new();
            if !no_key.is_empty() {
                warnings.push(format!(
                    "{} features have no property '{key}' to join on: {}",
                    no_key.len(),
                    list(&no_key)
                ));
            }
            let unused: Vec<String> = table
                .keys
                .iter()
                .filter(|k| !used.contains_key(k.as_str()))
                .map(|k| format!("'{k}'"))
                .collect();
            if !unused.is_empty() {
                warnings.push(format!(
                    "{label}: {} rows match no feature's '{key}': {}",
                    unused.len(),
                    list(&unused)
                ));
            }
            Ok((values, warnings))
        }
    }
}

/// At most this many names are listed in a warning.
const LISTED: usize = 10;

/// `names` joined by commas, the first [`LISTED`] of them and a count of the others.
fn list(names: &[String]) -> String {
    let mut s = names
        .iter()
        .take(LISTED)
        .cloned()
        .collect::<Vec<_>>()
        .join(", ");
    if names.len() > LISTED {
        s.push_str(&format!(" and {} more", names.len() - LISTED));
    }
    s
}

/// The values the flow uses, from the values as read (`None`: missing) and the regions'
/// areas (any unit): a missing value becomes the mean density of the regions with a positive
/// value times the region's area, a zero value (or a missing one of a region without area)
/// [`ZERO_FRACTION`] of the smallest positive value. Returns them with one warning per kind,
/// naming the regions.
///
/// Errors (the message): no region has a positive value.
pub fn complete(
    read: &[Option<f64>],
    areas: &[f64],
    labels: &[String],
) -> std::result::Result<(Vec<f64>, Vec<String>), String> {
    // Only ratios matter: scaled by the largest value, sums cannot overflow.
    let max = read.iter().flatten().fold(0.0f64, |m, &v| m.max(v));
    if !(max > 0.0) {
        return Err(if read.iter().all(Option::is_none) {
            "no region has a value".into()
        } else {
            "no region has a positive value".into()
        });
    }
    let (mut value_sum, mut area_sum, mut min_positive) = (0.0, 0.0, f64::INFINITY);
    for (v, a) in read.iter().zip(areas) {
        if let Some(v) = v
            && *v > 0.0
        {
            value_sum += v / max;
            area_sum += a.abs();
            min_positive = min_positive.min(*v);
        }
    }
    let density = if area_sum > 0.0 {
        value_sum / area_sum
    } else {
        0.0
    };
    let floor = ZERO_FRACTION * min_positive;
    let (mut missing, mut zero) = (Vec::new(), Vec::new());
    let mut values = Vec::with_capacity(read.len());
    for ((v, a), label) in read.iter().zip(areas).zip(labels) {
        let value = match v {
            Some(v) if *v > 0.0 => *v,
            Some(_) => {
                zero.push(label.clone());
                floor
            }
            None => {
                let filled = density * a.abs() * max;
                if filled > 0.0 && filled.is_finite() {
                    missing.push(label.clone());
                    filled
                } else {
                    zero.push(label.clone());
                    floor
                }
            }
        };
        values.push(value);
    }
    let mut warnings = Vec::new();
    if !missing.is_empty() {
        warnings.push(format!(
            "{} regions have no value and get the mean density (value per area) of the others: {}",
            missing.len(),
            list(&missing)
        ));
    }
    if !zero.is_empty() {
        warnings.push(format!(
            "{} regions have the value 0 and get {ZERO_FRACTION} times the smallest positive \
             value: {}",
            zero.len(),
            list(&zero)
        ));
    }
    Ok((values, warnings))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_table_is_read_by_key_and_its_errors_name_the_line() {
        let t = parse_table("id,pop\nA, 3\nB,\n\nC,1e2\n", "v.csv", "id", None).unwrap();
        assert_eq!(t.keys, ["A", "B", "C"]);
        assert_eq!(t.values["A"], Some(3.0));
        assert_eq!(t.values["B"], None);
        assert_eq!(t.values["C"], Some(100.0));
        let t = parse_table("name,id,gdp,pop\nx,A,1,2\n", "v.csv", "id", Some("pop")).unwrap();
        assert_eq!(t.values["A"], Some(2.0));
        let cases = [
            (
                "id,pop\nA,1\n",
                "code",
                None,
                "v.csv:1: no column 'code' (`key`)",
            ),
            (
                "id,pop\nA,1\n",
                "id",
                Some("gdp"),
                "v.csv:1: no column 'gdp' (`value`)",
            ),
            (
                "id,a,b\nA,1,2\n",
                "id",
                None,
                "v.csv:1: 2 columns besides 'id'",
            ),
            (
                "id,pop\nA,1\nB,many\n",
                "id",
                None,
                "v.csv:3: 'B': the value 'pop' = 'many' is not a number",
            ),
            (
                "id,pop\nA,-1\n",
                "id",
                None,
                "v.csv:2: 'A': the value 'pop' = '-1' is negative",
            ),
            ("id,pop\nA,NaN\n", "id", None, "is not finite"),
            (
                "id,pop\nA,1\nB,2\nA,3\n",
                "id",
                None,
                "v.csv:4: the key 'A' is repeated (first on line 2)",
            ),
            ("id,pop\nA\n", "id", None, "v.csv:2: the row has 1 fields"),
        ];
        for (text, key, column, want) in cases {
            let e = parse_table(text, "v.csv", key, column)
                .unwrap_err()
                .to_string();
            assert!(e.contains(want), "{e} does not contain {want}");
        }
    }

    #[test]
    fn missing_values_get_the_mean_density_and_zeros_a_fraction_of_the_least() {
        let labels: Vec<String> = ["a", "b", "c", "d"].iter().map(|s| s.to_string()).collect();
        // Densities 2 and 4 over areas 1 and 2: mean (2 + 8) / 3; d missing with area 3.
        let (v, w) = complete(
            &[Some(2.0), Some(8.0), Some(0.0), None],
            &[1.0, 2.0, 5.0, 3.0],
            &labels,
        )
        .unwrap();
        assert_eq!(v[..3], [2.0, 8.0, ZERO_FRACTION * 2.0]);
        assert!((v[3] - 10.0).abs() < 1e-12, "{v:?}");
        assert_eq!(w.len(), 2);
        assert!(
            w[0].contains("1 regions have no value") && w[0].ends_with(": d"),
            "{w:?}"
        );
        assert!(w[1].contains("value 0") && w[1].ends_with(": c"), "{w:?}");
        let e = complete(&[Some(0.0), None], &[1.0, 1.0], &labels[..2]).unwrap_err();
        assert_eq!(e, "no region has a positive value");
        assert_eq!(
            complete(&[None, None], &[1.0, 1.0], &labels[..2]).unwrap_err(),
            "no region has a value"
        );
        let (v, w) = complete(&[Some(1.0), Some(3.0)], &[1.0, 1.0], &labels[..2]).unwrap();
        assert_eq!((v, w.len()), (vec![1.0, 3.0], 0));
    }
}
