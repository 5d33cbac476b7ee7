//! Landmark files: one landmark per line, `vertex_index target_x target_y [target_z]`; and
//! landmark vertex files (registration): one vertex index per line.

use super::{Lines, format_error, number_error, parse_error, parse_f64, parse_int, read_file};
use super::{path_label, strip_comment, tokens, unreadable_error};
use crate::{Error, Result};
use std::path::Path;

/// A landmark: a mesh vertex and where the map must send it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Landmark {
    /// 0-based vertex index.
    pub vertex: usize,
    /// Target position (z = 0 when the file gives two coordinates).
    pub target: [f64; 3],
}

/// Reads a landmark file for a mesh with `n_vertices` vertices.
///
/// One landmark per line: `vertex_index target_x target_y [target_z]` (0-based index; z defaults
/// to 0). Blank lines and `#` comments are ignored.
///
/// Errors: a missing or unreadable file ([`Error::Io`]); an unreadable number or a wrong number
/// of fields ([`Error::Parse`] with the line); an index out of range, a vertex given twice, a
/// non-finite target ([`Error::Landmarks`], naming the line); a file without any landmark
/// ([`Error::Format`]).
pub fn read_landmarks(path: &Path, n_vertices: usize) -> Result<Vec<Landmark>> {
    let data = read_file(path)?;
    parse_landmarks(&data, &path_label(path), n_vertices)
}

/// Parses landmark text (see [`read_landmarks`]); `path` only labels error messages.
pub fn parse_landmarks(data: &[u8], path: &str, n_vertices: usize) -> Result<Vec<Landmark>> {
    let rows = parse_rows(
        data,
        path,
        n_vertices,
        "'vertex_index target_x target_y [target_z]'",
        &[3, 4],
        |vertex, rest, line_no| {
            let mut target = [0.0; 3];
            for (x, t) in target.iter_mut().zip(rest) {
                *x = parse_f64(t).ok_or_else(|| number_error(path, line_no, t))?;
            }
            if !target.iter().all(|x| x.is_finite()) {
                return Err(Error::Landmarks(format!(
                    "{path}: landmark on line {line_no}: the target of vertex {vertex} is not finite"
                )));
            }
            Ok(target)
        },
    )?;
    Ok(rows
        .into_iter()
        .map(|(vertex, target)| Landmark { vertex, target })
        .collect())
}

/// Reads a file of landmark vertices for a mesh with `n_vertices` vertices: one 0-based
/// vertex index per line (registration's landmark files); blank lines and `#` comments are
/// ignored.
///
/// Errors: as [`read_landmarks`] — a missing file, a line that is not one integer, an index
/// out of range or given twice (naming the line), a file without any index.
pub fn read_landmark_vertices(path: &Path, n_vertices: usize) -> Result<Vec<usize>> {
    let data = read_file(path)?;
    parse_landmark_vertices(&data, &path_label(path), n_vertices)
}

/// Parses landmark vertex text (see [`read_landmark_vertices`]); `path` labels errors.
pub fn parse_landmark_vertices(data: &[u8], path: &str, n_vertices: usize) -> Result<Vec<usize>> {
    let rows = parse_rows(
        data,
        path,
        n_vertices,
        "one vertex index",
        &[1],
        |_, _, _| Ok(()),
    )?;
    Ok(rows.into_iter().map(|(v, _)| v).collect())
}

/// The lines of a landmark file: each non-blank line has a vertex index (0-based, in range,
/// each vertex once) followed by fields that `rest` reads; `allowed` are the accepted field
/// counts and `expected` describes a line for the error message.
fn parse_rows<T>(
    data: &[u8],
    path: &str,
    n_vertices: usize,
    expected: &str,
    allowed: &[usize],
    rest: impl Fn(usize, &[&[u8]], usize) -> Result<T>,
) -> Result<Vec<(usize, T)>> {
    let mut rows = Vec::new();
    // Line of the landmark on each vertex, to report duplicates.
    let mut seen: Vec<(usize, usize)> = Vec::new();
    for (line_no, line) in Lines::new(data) {
        let fields: Vec<&[u8]> = tokens(strip_comment(line)).collect();
        if fields.is_empty() {
            continue;
        }
        if !allowed.contains(&fields.len()) {
            return Err(parse_error(
                path,
                line_no,
                format!("expected {expected}, found {} fields", fields.len()),
            ));
        }
        let index = parse_int(fields[0])
            .ok_or_else(|| unreadable_error(path, line_no, fields[0], "a vertex index"))?;
        if index < 0 || index as u64 >= n_vertices as u64 {
            return Err(Error::Landmarks(format!(
                "{path}: landmark on line {line_no}: vertex {index} is out of range (mesh has \
                 {n_vertices} vertices)"
            )));
        }
        let vertex = index as usize;
        let value = rest(vertex, &fields[1..], line_no)?;
        seen.push((vertex, line_no));
        rows.push((vertex, value));
    }
    if rows.is_empty() {
        return Err(format_error(path, "no landmarks in the file"));
    }
    seen.sort_unstable();
    if let Some(w) = seen
        .windows(2)
        .filter(|w| w[0].0 == w[1].0)
        .min_by_key(|w| w[1].1)
    {
        return Err(Error::Landmarks(format!(
            "{path}: landmark on line {}: vertex {} already has a landmark (line {})",
            w[1].1, w[1].0, w[0].1
        )));
    }
    Ok(rows)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::io::test_util::{data_dir, temp_file, temp_path};

    #[test]
    fn reads_landmark_vertices_and_refuses_bad_lines() {
        let v = parse_landmark_vertices(b"# eyes\n3\n\n 7 # nose\n0\n", "a.txt", 8).unwrap();
        assert_eq!(v, vec![3, 7, 0]);
        let e = parse_landmark_vertices(b"3\n8\n", "a.txt", 8).unwrap_err();
        assert!(
            e.to_string().contains("line 2") && e.to_string().contains('8'),
            "{e}"
        );
        let e = parse_landmark_vertices(b"3\n4\n3\n", "a.txt", 8).unwrap_err();
        assert!(e.to_string().contains("line 3"), "{e}");
        let e = parse_landmark_vertices(b"3 1.0\n", "a.txt", 8).unwrap_err();
        assert!(matches!(e, Error::Parse { line: 1, .. }), "{e}");
        assert!(parse_landmark_vertices(b"# none\n", "a.txt", 8).is_err());
        assert!(parse_landmark_vertices(b"x\n", "a.txt", 8).is_err());
    }

    fn parse(text: &str, n: usize) -> Result<Vec<Landmark>> {
        parse_landmarks(text.as_bytes(), "l.txt", n)
    }

    fn landmarks_msg(text: &str, n: usize) -> String {
        match parse(text, n) {
            Err(Error::Landmarks(msg)) => msg,
            other => panic!("expected a landmark error, got {other:?}"),
        }
    }

    fn parse_msg(text: &str) -> (usize, String) {
        match parse(text, 100) {
            Err(Error::Parse { line, msg, .. }) => (line, msg),
            other => panic!("expected a parse error, got {other:?}"),
        }
    }

    #[test]
    fn reads_landmarks_with_comments_and_default_z() {
        let text = "# vertex x y z\n\n3 0.5 -1 2 # with z\r\n  7\t1e-3 4\n";
        let path = temp_file("l.txt", text.as_bytes());
        let l = read_landmarks(&path, 8).unwrap();
        assert_eq!(
            l,
            vec![
                Landmark {
                    vertex: 3,
                    target: [0.5, -1.0, 2.0]
                },
                Landmark {
                    vertex: 7,
                    target: [1e-3, 4.0, 0.0]
                },
            ]
        );
    }

    #[test]
    fn out_of_range() {
        assert_eq!(
            landmarks_msg("1 0 0\n\n9999 0 0\n", 500),
            "l.txt: landmark on line 3: vertex 9999 is out of range (mesh has 500 vertices)"
        );
        assert_eq!(
            landmarks_msg("-1 0 0\n", 500),
            "l.txt: landmark on line 1: vertex -1 is out of range (mesh has 500 vertices)"
        );
        assert!(landmarks_msg("3 0 0\n", 3).contains("vertex 3 is out of range"));
    }

    #[test]
    fn duplicates() {
        assert_eq!(
            landmarks_msg("5 0 0\n2 1 1\n2 0 1\n5 1 0\n", 10),
            "l.txt: landmark on line 3: vertex 2 already has a landmark (line 2)"
        );
    }

    #[test]
    fn non_finite_target() {
        assert_eq!(
            landmarks_msg("1 0 0\n2 nan 0\n", 10),
            "l.txt: landmark on line 2: the target of vertex 2 is not finite"
        );
        assert!(landmarks_msg("2 0 0 inf\n", 10).contains("line 1"));
    }

    #[test]
    fn syntax_errors() {
        assert_eq!(
            parse_msg("1 0 0\n2 0 abc\n"),
            (2, "cannot read 'abc' as a number".into())
        );
        assert_eq!(
            parse_msg("1 0\n"),
            (
                1,
                "expected 'vertex_index target_x target_y [target_z]', found 2 fields".into()
            )
        );
        assert_eq!(parse_msg("\n1 0 0 0 0\n").0, 2);
        assert_eq!(
            parse_msg("1.5 0 0\n"),
            (1, "cannot read '1.5' as a vertex index".into())
        );
    }

    #[test]
    fn empty_and_missing_files() {
        assert!(matches!(
            parse("# nothing\n\n", 10),
            Err(Error::Format { .. })
        ));
        assert!(matches!(
            read_landmarks(&temp_path("missing.txt"), 10),
            Err(Error::Io { .. })
        ));
    }

    #[test]
    #[ignore = "needs real meshes (DEMKIT_DATA)"]
    fn real_landmark_files() {
        let dir = data_dir().join("genus0");
        for name in ["sphere_with_landmark", "brain_with_landmark"] {
            let mesh = crate::io::read_mesh(&dir.join(format!("{name}.obj"))).unwrap();
            let l = read_landmarks(
                &dir.join(format!("{name}.landmarks.txt")),
                mesh.n_vertices(),
            )
            .unwrap();
            assert!(!l.is_empty());
            for lm in &l {
                let r = lm.target.iter().map(|x| x * x).sum::<f64>().sqrt();
                assert!(
                    (r - 1.0).abs() < 1e-3,
                    "{name}: target off the unit sphere: {r}"
                );
            }
        }
    }
}
