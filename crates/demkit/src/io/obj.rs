//! Wavefront OBJ: `v` and `f` statements (triangles only); everything else is ignored.

use super::{Lines, face_size_error, format_error, parse_error, parse_int};
use super::{parse_vertex, strip_comment, tokens, unreadable_error};
use crate::{Result, TriMesh};
use std::io::Write;

/// Parses OBJ text. `path` only labels error messages.
///
/// Reads `v x y z` (a fourth coordinate or colors are ignored) and `f` with corners `a`, `a/b`,
/// `a//c` or `a/b/c`, 1-based or negative (relative to the last vertex defined so far); ignores
/// `vt`, `vn`, `g`, `o`, `s`, `usemtl`, `mtllib`, other statements and `#` comments.
///
/// Errors ([`crate::Error::Parse`] with the line): a face that is not a triangle, an unreadable
/// number or index, a non-finite coordinate, an index out of range; [`crate::Error::Format`] if
/// there are no faces.
pub fn parse_obj(data: &[u8], path: &str) -> Result<TriMesh> {
    let mut positions: Vec<[f64; 3]> = Vec::with_capacity(data.len() / 64);
    let mut faces: Vec<[u32; 3]> = Vec::with_capacity(data.len() / 64);
    // Largest positive index seen (1-based) and the first line where it appears: positive
    // indices may refer to vertices defined later in the file, so they are checked at the end.
    let mut max_index: (u64, usize) = (0, 0);
    for (line_no, line) in Lines::new(data) {
        let line = strip_comment(line);
        let mut toks = tokens(line);
        match toks.next() {
            Some(b"v") => {
                let what = format!("vertex {}", positions.len());
                let p = parse_vertex(&mut toks, path, line_no, &what)?;
                positions.push(p);
            }
            Some(b"f") => {
                let mut face = [0u32; 3];
                let mut count = 0;
                for t in toks {
                    if count < 3 {
                        let (index, positive) = corner(t, positions.len(), path, line_no)?;
                        if positive && index as u64 + 1 > max_index.0 {
                            max_index = (index as u64 + 1, line_no);
                        }
                        face[count] = index;
                    }
                    count += 1;
                }
                if count != 3 {
                    return Err(face_size_error(path, line_no, count as i64));
                }
                faces.push(face);
            }
            _ => {}
        }
    }
    if max_index.0 > positions.len() as u64 {
        return Err(parse_error(
            path,
            max_index.1,
            format!(
                "vertex index {} is out of range (the file has {} vertices)",
                max_index.0,
                positions.len()
            ),
        ));
    }
    if faces.is_empty() {
        return Err(format_error(path, "no faces"));
    }
    Ok(TriMesh::new(positions, faces))
}

/// The 0-based vertex index of a face corner `a`, `a/b`, `a//c` or `a/b/c`, and whether it was
/// given as a positive (absolute, to be range-checked later) index.
fn corner(token: &[u8], n_so_far: usize, path: &str, line: usize) -> Result<(u32, bool)> {
    let index = token.split(|&b| b == b'/').next().unwrap_or(token);
    let value =
        parse_int(index).ok_or_else(|| unreadable_error(path, line, token, "a vertex index"))?;
    if value > 0 {
        return u32::try_from(value - 1)
            .map(|i| (i, true))
            .map_err(|_| parse_error(path, line, format!("vertex index {value} is out of range")));
    }
    if value == 0 {
        return Err(parse_error(
            path,
            line,
            "vertex index 0 is invalid (OBJ indices start at 1)",
        ));
    }
    let resolved = n_so_far as i64 + value;
    if resolved < 0 {
        return Err(parse_error(
            path,
            line,
            format!(
                "relative vertex index {value} is out of range ({n_so_far} vertices defined so \
                 far)"
            ),
        ));
    }
    Ok((resolved as u32, false))
}

/// Writes `mesh` as OBJ: a comment, `v x y z` lines with the shortest representation that reads
/// back to the same `f64`, and 1-based `f a b c` lines. Flushes `w` at the end.
pub fn write_obj<W: Write>(w: W, mesh: &TriMesh) -> std::io::Result<()> {
    write_obj_textured(w, mesh, None)
}

/// Texture coordinates for [`write_obj_textured`]: `vt` points and, per face corner, the index
/// of its point (a vertex may have several, one per side of a seam).
#[derive(Debug, Clone, PartialEq)]
pub struct TextureCoordinates {
    /// The `vt u v` points.
    pub points: Vec<[f64; 2]>,
    /// Per face, the 0-based `vt` index of each corner.
    pub corners: Vec<[u32; 3]>,
}

/// As [`write_obj`], with `vt` lines and `f a/ta b/tb c/tc` faces when `texture` is given.
pub fn write_obj_textured<W: Write>(
    mut w: W,
    mesh: &TriMesh,
    texture: Option<&TextureCoordinates>,
) -> std::io::Result<()> {
    const BLOCK: usize = 1 << 16;
    // Lines are assembled in a reusable buffer and written in blocks: much faster than
    // formatting each number through the writer.
    let mut buf: Vec<u8> = Vec::with_capacity(BLOCK + 256);
    writeln!(
        buf,
        "# demkit: {} vertices, {} faces",
        mesh.positions.len(),
        mesh.faces.len()
    )?;
    let flush = |buf: &mut Vec<u8>, w: &mut W| -> std::io::Result<()> {
        if buf.len() > BLOCK {
            w.write_all(buf)?;
            buf.clear();
        }
        Ok(())
    };
    for [x, y, z] in &mesh.positions {
        writeln!(buf, "v {} {} {}", Real(*x), Real(*y), Real(*z))?;
        flush(&mut buf, &mut w)?;
    }
    if let Some(t) = texture {
        for [u, v] in &t.points {
            writeln!(buf, "vt {} {}", Real(*u), Real(*v))?;
            flush(&mut buf, &mut w)?;
        }
    }
    for (i, f) in mesh.faces.iter().enumerate() {
        buf.push(b'f');
        for (k, &v) in f.iter().enumerate() {
            buf.push(b' ');
            push_decimal(&mut buf, v as u64 + 1);
            if let Some(t) = texture {
                buf.push(b'/');
                push_decimal(&mut buf, t.corners[i][k] as u64 + 1);
            }
        }
        buf.push(b'\n');
        flush(&mut buf, &mut w)?;
    }
    w.write_all(&buf)?;
    w.flush()
}

/// Appends the decimal digits of `n`.
fn push_decimal(out: &mut Vec<u8>, mut n: u64) {
    let mut digits = [0u8; 20];
    let mut i = digits.len();
    loop {
        i -= 1;
        digits[i] = b'0' + (n % 10) as u8;
        n /= 10;
        if n == 0 {
            break;
        }
    }
    out.extend_from_slice(&digits[i..]);
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Error;
    use crate::io::test_util::data_dir;

    fn parse(text: &str) -> Result<TriMesh> {
        parse_obj(text.as_bytes(), "t.obj")
    }

    /// (line, message) of a parse error.
    fn parse_err(text: &str) -> (usize, String) {
        match parse(text) {
            Err(Error::Parse { path, line, msg }) => {
                assert_eq!(path, "t.obj");
                (line, msg)
            }
            other => panic!("expected a parse error, got {other:?}"),
        }
    }

    const SQUARE: &str = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n";

    #[test]
    fn reads_vertices_faces_and_ignores_the_rest() {
        let text = "# comment\r\nmtllib a.mtl\no thing\ng group\ns off\nusemtl m\n\
                    v 0 0 0 1\nv 1 0 0 0.5 0.5 0.5\nv 1 1 0\nv 0 1 0 # trailing comment\n\
                    vt 0 0\nvn 0 0 1\n\nf 1/1 2/2/1 3//1\r\nf 1 3 4 # c\nl 1 2\n";
        let m = parse(text).unwrap();
        assert_eq!(m.positions.len(), 4);
        assert_eq!(m.positions[1], [1., 0., 0.]);
        assert_eq!(m.faces, vec![[0, 1, 2], [0, 2, 3]]);
    }

    #[test]
    fn relative_indices() {
        let m = parse(&format!("{SQUARE}f -4 -3 -2\nv 2 2 0\nf -5 -3 -2\n")).unwrap();
        assert_eq!(m.faces, vec![[0, 1, 2], [0, 2, 3]]);
        let (line, msg) = parse_err("v 0 0 0\nv 1 0 0\nf -1 -2 -3\n");
        assert_eq!(line, 3);
        assert!(
            msg.contains("relative vertex index -3 is out of range"),
            "{msg}"
        );
    }

    #[test]
    fn forward_references_are_allowed() {
        let m = parse(&format!("f 1 2 3\n{SQUARE}")).unwrap();
        assert_eq!(m.faces, vec![[0, 1, 2]]);
    }

    #[test]
    fn quads_are_rejected_with_the_line() {
        let (line, msg) = parse_err(&format!("{SQUARE}f 1 2 3 4\n"));
        assert_eq!(line, 5);
        assert_eq!(
            msg,
            "face with 4 vertices: only triangles are supported (triangulate the mesh first)"
        );
        let (line, msg) = parse_err(&format!("{SQUARE}f 1 2\n"));
        assert_eq!(
            (line, msg.as_str()),
            (5, "face with 2 vertices: a face needs 3")
        );
    }

    #[test]
    fn unreadable_numbers() {
        let (line, msg) = parse_err("v 0 0 0\nv 1 abc 0\n");
        assert_eq!((line, msg.as_str()), (2, "cannot read 'abc' as a number"));
        let (line, msg) = parse_err("v 0 0\n");
        assert_eq!(
            (line, msg.as_str()),
            (1, "vertex with 2 coordinates: 3 are needed")
        );
        let (line, msg) = parse_err(&format!("{SQUARE}f 1 x/2 3\n"));
        assert_eq!(
            (line, msg.as_str()),
            (5, "cannot read 'x/2' as a vertex index")
        );
        let (line, msg) = parse_err(&format!("{SQUARE}f 0 1 2\n"));
        assert_eq!(line, 5);
        assert!(msg.contains("index 0 is invalid"), "{msg}");
    }

    #[test]
    fn non_finite_coordinates() {
        for bad in ["nan", "inf", "-inf", "1e999"] {
            let (line, msg) = parse_err(&format!("v 0 0 0\nv 0 {bad} 0\n"));
            assert_eq!(line, 2);
            assert_eq!(msg, "vertex 1 has a non-finite coordinate");
        }
    }

    #[test]
    fn indices_out_of_range() {
        let (line, msg) = parse_err(&format!("{SQUARE}f 1 2 3\nf 1 9 3\nf 1 2 4\n"));
        assert_eq!(line, 6);
        assert_eq!(
            msg,
            "vertex index 9 is out of range (the file has 4 vertices)"
        );
        let (line, _) = parse_err(&format!("{SQUARE}f 1 2 99999999999\n"));
        assert_eq!(line, 5);
    }

    #[test]
    fn no_faces() {
        assert!(matches!(parse(SQUARE), Err(Error::Format { msg, .. }) if msg == "no faces"));
    }

    #[test]
    fn round_trip_is_exact() {
        let positions = vec![
            [0.1, -2.0 / 3.0, 1e-300],
            [std::f64::consts::PI, 1e300, -0.0],
            [123_456_789.123_456_79, 5e-324, f64::MAX],
        ];
        let m = TriMesh::new(positions, vec![[0, 1, 2], [2, 1, 0]]);
        let mut buf = Vec::new();
        write_obj(&mut buf, &m).unwrap();
        let back = parse_obj(&buf, "mem").unwrap();
        assert_eq!(back.faces, m.faces);
        for (a, b) in back.positions.iter().zip(&m.positions) {
            assert_eq!(a.map(f64::to_bits), b.map(f64::to_bits));
        }
        let text = String::from_utf8(buf).unwrap();
        assert!(text.contains("\nf 1 2 3\nf 3 2 1\n"), "{text}");
    }

    #[test]
    #[ignore = "needs real meshes (DEMKIT_DATA)"]
    fn reads_hand() {
        let path = data_dir().join("open/hand.obj");
        let data = std::fs::read(&path).unwrap();
        let t = std::time::Instant::now();
        let m = parse_obj(&data, "hand.obj").unwrap();
        let elapsed = t.elapsed();
        eprintln!("hand.obj: {} faces parsed in {elapsed:?}", m.faces.len());
        assert_eq!(m.faces.len(), 105860);
    }
}

/// A coordinate as the shortest decimal that reads back to the same number: plain digits for
/// ordinary magnitudes, an exponent beyond them (1e300 rather than three hundred digits).
struct Real(f64);

impl std::fmt::Display for Real {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let a = self.0.abs();
        if a == 0.0 || (1e-5..1e16).contains(&a) || !a.is_finite() {
            write!(f, "{}", self.0)
        } else {
            write!(f, "{:e}", self.0)
        }
    }
}

#[cfg(test)]
mod real_tests {
    use super::Real;

    #[test]
    fn coordinates_are_written_short_and_read_back_exactly() {
        for x in [
            0.0,
            -0.5,
            1.0 / 3.0,
            12345.678,
            4e300,
            -2.5e-200,
            1e-5,
            9.99e15,
            1e16,
        ] {
            let text = Real(x).to_string();
            assert!(text.len() <= 24, "{text}");
            assert_eq!(text.parse::<f64>().unwrap(), x, "{text}");
        }
        assert_eq!(Real(4e300).to_string(), "4e300");
        assert_eq!(Real(0.25).to_string(), "0.25");
    }
}
