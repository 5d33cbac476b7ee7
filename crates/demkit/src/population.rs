//! Populations: one positive value per face, from a name, a file or an expression.
//!
//! A population is named ([`PopulationSpec::Area`], [`PopulationSpec::Uniform`]), read from a
//! file ([`PopulationSpec::File`]) or written as an expression ([`PopulationSpec::Expr`]); text
//! is read with [`parse`], which never touches the file system (whether an argument names a file
//! is the caller's decision). [`face_populations`] turns a spec into values and always ends with
//! [`check_population`], so every population a method receives is finite and positive, one per
//! face.

use std::path::{Path, PathBuf};

use crate::expr::{Expr, ExprErrorKind};
use crate::mesh::scale::ldexp;
use crate::{Error, Result, TriMesh};

/// Where a population comes from.
#[derive(Debug, Clone, PartialEq)]
pub enum PopulationSpec {
    /// Each face's area on the input surface (an area-preserving map).
    Area,
    /// 1 on every face.
    Uniform,
    /// A text file with one value per face, in face order (blank lines and `#` comments ignored).
    File(PathBuf),
    /// An expression of the face centroid `x`, `y`, `z` and the face `area`, both in input
    /// coordinates; syntax in [`crate::expr`].
    Expr(String),
}

impl PopulationSpec {
    /// Reads a population written as text; the same as the free function [`parse`].
    pub fn parse(s: &str) -> PopulationSpec {
        parse(s)
    }
}

/// The variables of a population expression, in the order their values are passed.
pub const EXPR_VARIABLES: [&str; 4] = ["x", "y", "z", "area"];

/// Reads a population written as text: `"area"` and `"uniform"` (surrounding white space
/// ignored) are the named populations, anything else is a [`PopulationSpec::Expr`] (compiled,
/// and possibly refused, by [`face_populations`]). Text is never taken for a file name: a file
/// is given as [`PopulationSpec::File`].
pub fn parse(s: &str) -> PopulationSpec {
    match s.trim() {
        "area" => PopulationSpec::Area,
        "uniform" => PopulationSpec::Uniform,
        _ => PopulationSpec::Expr(s.to_string()),
    }
}

/// The population of every face of `mesh`, in face order, checked by [`check_population`].
///
/// Errors: an unreadable file ([`Error::Io`]); a value that is not a number
/// ([`Error::Parse`] with the file and 1-based line); a wrong count, a bad expression, or a
/// value that is not finite and positive ([`Error::Population`], naming the face).
pub fn face_populations(spec: &PopulationSpec, mesh: &TriMesh) -> Result<Vec<f64>> {
    face_populations_at_scale(spec, mesh, 0)
}

/// [`face_populations`] of an input that was scaled by 2^`exponent` into `mesh`
/// ([`crate::mesh::scale`]): an expression's `x`, `y`, `z` are still in input units, its
/// `area` is measured on `mesh` (an input that needed scaling has areas beyond floating point,
/// 1e600 or 1e-400).
pub fn face_populations_at_scale(
    spec: &PopulationSpec,
    mesh: &TriMesh,
    exponent: i32,
) -> Result<Vec<f64>> {
    let n = mesh.n_faces();
    let values = match spec {
        PopulationSpec::Area => (0..n).map(|f| triangle_area(&mesh.corners(f))).collect(),
        PopulationSpec::Uniform => vec![1.0; n],
        PopulationSpec::File(path) => read_face_values(path, n, "population file")?,
        PopulationSpec::Expr(source) => {
            let values = expression_populations(source, mesh, exponent)?;
            // Name the face *and* where it is: the user wrote a function of position.
            if let Some((f, msg)) = first_bad_value(&values) {
                let [x, y, z] = centroid(&mesh.corners(f)).map(|c| ldexp(c, -exponent));
                let area = triangle_area(&mesh.corners(f));
                return Err(Error::Population(format!(
                    "{msg} (expression '{source}' at x={x}, y={y}, z={z}, area={area})"
                )));
            }
            values
        }
    };
    check_population(&values, n)?;
    Ok(values)
}

/// `values` scaled by the power of two that brings their largest into [0.5, 1): every method
/// and metric depends on population ratios only, and at unit scale the sums over a mesh cannot
/// overflow (a population of 1e306 per face) nor underflow. A power of two scales exactly, so
/// a map of the scaled values is the map of the values as given, to the last bit.
pub fn unit_scale(values: &[f64]) -> Vec<f64> {
    let max = values.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    if !(max > 0.0 && max.is_finite()) {
        return values.to_vec();
    }
    // A power of two: the scaling is exact, so the map is the one of the values as given.
    let k = crate::mesh::scale::unit_exponent(&[[max, 0.0, 0.0]]);
    values.iter().map(|&v| ldexp(v, k)).collect()
}

/// Refuses a population that no method can use: a length other than `n_faces`, an empty mesh,
/// a value that is NaN or infinite, every value zero, or a value that is zero or negative.
/// Faces are named by their 0-based index.
pub fn check_population(values: &[f64], n_faces: usize) -> Result<()> {
    if values.len() != n_faces {
        return Err(Error::Population(format!(
            "population has {} values but the mesh has {} faces",
            values.len(),
            n_faces
        )));
    }
    if n_faces == 0 {
        return Err(Error::Population("the mesh has no faces".into()));
    }
    if values.iter().all(|&v| v == 0.0) {
        return Err(Error::Population("every population is zero".into()));
    }
    match first_bad_value(values) {
        Some((_, msg)) => Err(Error::Population(msg)),
        None => Ok(()),
    }
}

/// The first face whose value is not finite and positive, with the message naming it.
fn first_bad_value(values: &[f64]) -> Option<(usize, String)> {
    values.iter().enumerate().find_map(|(f, &v)| {
        if !v.is_finite() {
            Some((f, format!("population of face {f} is {v}")))
        } else if v <= 0.0 {
            Some((
                f,
                format!("population of face {f} is {v}: populations must be positive"),
            ))
        } else {
            None
        }
    })
}

/// One value per face of a mesh with `n_faces` faces, from a file in the population-file
/// format ([`read_population_file`]); `what` names the file in the error when the count is
/// wrong ("population file x.txt has 3 values but the mesh has 2 faces", [`Error::Population`]).
/// The values are not checked.
pub fn read_face_values(path: &Path, n_faces: usize, what: &str) -> Result<Vec<f64>> {
    let values = read_population_file(path)?;
    if values.len() != n_faces {
        return Err(Error::Population(format!(
            "{what} {} has {} values but the mesh has {n_faces} faces",
            path.display(),
            values.len(),
        )));
    }
    Ok(values)
}

/// Reads a population file: one number per line, in face order; blank lines and everything
/// after a `#` are ignored. The values are not checked (see [`check_population`]).
pub fn read_population_file(path: &Path) -> Result<Vec<f64>> {
    let text = std::fs::read_to_string(path).map_err(|source| Error::Io {
        path: path.display().to_string(),
        source,
    })?;
    let mut values = Vec::new();
    for (i, line) in text.lines().enumerate() {
        let content = line.split('#').next().unwrap_or("").trim();
        if content.is_empty() {
            continue;
        }
        let parse_error = |msg: String| Error::Parse {
            path: path.display().to_string(),
            line: i + 1,
            msg,
        };
        let mut words = content.split_whitespace();
        let word = words.next().unwrap_or("");
        if words.next().is_some() {
            return Err(parse_error(format!(
                "expected one number per line, found '{content}'"
            )));
        }
        let value = word
            .parse::<f64>()
            .map_err(|_| parse_error(format!("'{word}' is not a number")))?;
        values.push(value);
    }
    Ok(values)
}

/// Evaluates a population expression on every face (values unchecked).
/// True for a `--population` argument that reads like a file name rather than a formula: no
/// spaces, and a path separator or a final `.ext` of letters.
fn looks_like_a_file_name(s: &str) -> bool {
    let s = s.trim();
    if s.is_empty() || s.contains(char::is_whitespace) {
        return false;
    }
    if s.contains('/') || s.contains('\\') {
        return true;
    }
    match s.rsplit_once('.') {
        Some((stem, ext)) => {
            !stem.is_empty() && !ext.is_empty() && ext.chars().all(|c| c.is_ascii_alphabetic())
        }
        None => false,
    }
}

fn expression_populations(source: &str, mesh: &TriMesh, exponent: i32) -> Result<Vec<f64>> {
    let expr = Expr::compile(source, &EXPR_VARIABLES).map_err(|e| {
        let hint = match e.kind {
            ExprErrorKind::UnknownVariable(_) => "; the variables are x, y, z and area",
            _ => "",
        };
        if looks_like_a_file_name(source) {
            return Error::Population(format!(
                "no such population file '{source}', and it is not a valid expression either ({} at column {})",
                e.kind, e.column
            ));
        }
        Error::Population(format!(
            "{} in population expression '{source}' (column {}){hint}",
            e.kind, e.column
        ))
    })?;
    Ok((0..mesh.n_faces())
        .map(|f| {
            let corners = mesh.corners(f);
            let [x, y, z] = centroid(&corners).map(|c| ldexp(c, -exponent));
            expr.eval(&[x, y, z, triangle_area(&corners)])
        })
        .collect())
}

fn centroid(c: &[[f64; 3]; 3]) -> [f64; 3] {
    std::array::from_fn(|k| (c[0][k] + c[1][k] + c[2][k]) / 3.0)
}

/// Area of a triangle in R^3 given by its corners ([`crate::geometry::triangle_area`]).
fn triangle_area(c: &[[f64; 3]; 3]) -> f64 {
    crate::geometry::triangle_area(c[0], c[1], c[2])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_missing_file_is_named_as_such() {
        let e = face_populations(&PopulationSpec::parse("pop_typo.txt"), &mesh()).unwrap_err();
        let text = e.to_string();
        assert!(
            text.contains("no such population file 'pop_typo.txt'"),
            "{text}"
        );
        assert!(text.contains("not a valid expression"), "{text}");
        assert!(looks_like_a_file_name("data/pop"));
        assert!(!looks_like_a_file_name("2.5*area"));
        assert!(!looks_like_a_file_name("area * 2"));
    }

    #[test]
    fn unit_scale_keeps_ratios_and_avoids_overflow() {
        let huge = vec![0.5e308, 1.5e308, 1.0e308];
        let u = unit_scale(&huge);
        assert!((0.5..1.0).contains(&u[1]), "{u:?}");
        for (a, b) in u.iter().zip([1.0 / 3.0, 1.0, 2.0 / 3.0]) {
            assert!((a / u[1] - b).abs() < 1e-15, "{u:?}");
        }
        // Exact: scaling back gives the values as they were.
        let k = crate::mesh::scale::unit_exponent(&[[1.5e308, 0.0, 0.0]]);
        assert!(u.iter().zip(&huge).all(|(a, b)| ldexp(*a, -k) == *b));
        assert!(u.iter().sum::<f64>().is_finite());
        assert!(huge.iter().sum::<f64>().is_infinite());
    }

    /// Two faces: a right triangle of area 2 in the plane z = 0 with centroid (2/3, 2/3, 0), and
    /// a tilted one, (0,0,0), (1,0,0), (0,1,1), of area sqrt(2)/2 with centroid (1/3, 1/3, 1/3).
    fn mesh() -> TriMesh {
        TriMesh::new(
            vec![
                [0.0, 0.0, 0.0],
                [2.0, 0.0, 0.0],
                [0.0, 2.0, 0.0],
                [1.0, 0.0, 0.0],
                [0.0, 1.0, 1.0],
            ],
            vec![[0, 1, 2], [0, 3, 4]],
        )
    }

    fn population_message(r: Result<Vec<f64>>) -> String {
        match r {
            Err(Error::Population(msg)) => msg,
            other => panic!("expected a population error, got {other:?}"),
        }
    }

    /// A temporary file that removes itself.
    struct TempFile(PathBuf);
    impl TempFile {
        fn new(name: &str, content: &str) -> Self {
            let path = std::env::temp_dir()
                .join(format!("demkit-population-{}-{name}", std::process::id()));
            std::fs::write(&path, content).unwrap();
            TempFile(path)
        }
    }
    impl Drop for TempFile {
        fn drop(&mut self) {
            let _ = std::fs::remove_file(&self.0);
        }
    }

    #[test]
    fn parse_names_and_expressions_without_touching_files() {
        assert_eq!(parse("area"), PopulationSpec::Area);
        assert_eq!(parse("uniform"), PopulationSpec::Uniform);
        assert_eq!(PopulationSpec::parse(" area "), PopulationSpec::Area);
        assert_eq!(
            parse("area*(1+3*(x>0))"),
            PopulationSpec::Expr("area*(1+3*(x>0))".into())
        );
        // The name of an existing file is text like any other: files are the caller's to name.
        let file = TempFile::new("parse.txt", "1\n");
        let name = file.0.to_str().unwrap();
        assert_eq!(parse(name), PopulationSpec::Expr(name.into()));
    }

    #[test]
    fn area_and_uniform() {
        let m = mesh();
        let a = face_populations(&PopulationSpec::Area, &m).unwrap();
        assert_eq!(a[0], 2.0);
        assert!((a[1] - 0.5 * 2f64.sqrt()).abs() < 1e-15);
        let u = face_populations(&PopulationSpec::Uniform, &m).unwrap();
        assert_eq!(u, vec![1.0, 1.0]);
    }

    #[test]
    fn expressions_see_centroid_and_area() {
        let m = mesh();
        let spec = PopulationSpec::Expr("1 + x + 10*y + 100*z + 1000*area".into());
        let p = face_populations(&spec, &m).unwrap();
        let want0 = 1.0 + 2.0 / 3.0 + 20.0 / 3.0 + 2000.0;
        let want1 = 1.0 + 1.0 / 3.0 + 10.0 / 3.0 + 100.0 / 3.0 + 1000.0 * 0.5 * 2f64.sqrt();
        assert!((p[0] - want0).abs() < 1e-12, "{}", p[0]);
        assert!((p[1] - want1).abs() < 1e-12, "{}", p[1]);
        let spec = PopulationSpec::Expr("area*(1+3*(z>0))".into());
        let p = face_populations(&spec, &m).unwrap();
        assert_eq!(p[0], 2.0);
        assert!((p[1] - 2.0 * 2f64.sqrt()).abs() < 1e-15);
    }

    #[test]
    fn expression_errors() {
        let m = mesh();
        let msg = population_message(face_populations(&PopulationSpec::Expr("q+1".into()), &m));
        assert!(
            msg.starts_with("unknown variable 'q' in population expression 'q+1' (column 1)"),
            "{msg}"
        );
        let msg = population_message(face_populations(&PopulationSpec::Expr("x+".into()), &m));
        assert!(
            msg.contains("syntax error") && msg.contains("column 3"),
            "{msg}"
        );
        let msg = population_message(face_populations(
            &PopulationSpec::Expr("nope(x)".into()),
            &m,
        ));
        assert!(msg.starts_with("unknown function 'nope'"), "{msg}");
        // Positive on face 0 (z = 0), negative on face 1 (z = 1/3).
        let msg = population_message(face_populations(&PopulationSpec::Expr("1-6*z".into()), &m));
        assert!(
            msg.starts_with("population of face 1 is -1: populations must be positive"),
            "{msg}"
        );
        assert!(msg.contains("(expression '1-6*z' at x="), "{msg}");
        let msg = population_message(face_populations(&PopulationSpec::Expr("log(z)".into()), &m));
        assert!(msg.starts_with("population of face 0 is -inf"), "{msg}");
        let msg = population_message(face_populations(
            &PopulationSpec::Expr("sqrt(-x)".into()),
            &m,
        ));
        assert!(msg.starts_with("population of face 0 is NaN"), "{msg}");
    }

    #[test]
    fn files() {
        let m = mesh();
        let ok = TempFile::new("ok.txt", "# populations\n\n 2.5 \n1e-3  # second face\n");
        let p = face_populations(&PopulationSpec::File(ok.0.clone()), &m).unwrap();
        assert_eq!(p, vec![2.5, 1e-3]);

        let bad = TempFile::new("bad.txt", "1\n\n# c\nabc\n");
        match face_populations(&PopulationSpec::File(bad.0.clone()), &m) {
            Err(Error::Parse { path, line, msg }) => {
                assert_eq!(path, bad.0.display().to_string());
                assert_eq!(line, 4);
                assert!(msg.contains("'abc'"), "{msg}");
            }
            other => panic!("{other:?}"),
        }
        let two = TempFile::new("two.txt", "1 2\n");
        assert!(matches!(
            face_populations(&PopulationSpec::File(two.0.clone()), &m),
            Err(Error::Parse { line: 1, .. })
        ));

        let short = TempFile::new("p.txt", "1\n2\n3\n");
        let msg = population_message(face_populations(&PopulationSpec::File(short.0.clone()), &m));
        assert_eq!(
            msg,
            format!(
                "population file {} has 3 values but the mesh has 2 faces",
                short.0.display()
            )
        );
        let neg = TempFile::new("neg.txt", "1\n-1\n");
        let msg = population_message(face_populations(&PopulationSpec::File(neg.0.clone()), &m));
        assert_eq!(
            msg,
            "population of face 1 is -1: populations must be positive"
        );

        let missing = std::env::temp_dir().join("demkit-population-does-not-exist.txt");
        assert!(matches!(
            face_populations(&PopulationSpec::File(missing), &m),
            Err(Error::Io { .. })
        ));
    }

    #[test]
    fn check_population_refusals() {
        let msg = |v: &[f64], n| match check_population(v, n) {
            Err(Error::Population(m)) => m,
            other => panic!("{other:?}"),
        };
        assert!(check_population(&[1.0, 0.5, 1e-300], 3).is_ok());
        assert_eq!(
            msg(&[1.0; 100], 200),
            "population has 100 values but the mesh has 200 faces"
        );
        let mut v = vec![1.0; 20];
        v[17] = f64::NAN;
        assert_eq!(msg(&v, 20), "population of face 17 is NaN");
        v[17] = f64::INFINITY;
        assert_eq!(msg(&v, 20), "population of face 17 is inf");
        v[17] = 1.0;
        v[3] = -1.0;
        assert_eq!(
            msg(&v, 20),
            "population of face 3 is -1: populations must be positive"
        );
        v[3] = 0.0;
        assert_eq!(
            msg(&v, 20),
            "population of face 3 is 0: populations must be positive"
        );
        assert_eq!(msg(&[0.0; 4], 4), "every population is zero");
        assert_eq!(msg(&[], 0), "the mesh has no faces");
    }
}
