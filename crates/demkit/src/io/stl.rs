//! STL, ascii and binary. STL stores every triangle with its own three corners; the reader
//! welds corners with exactly equal coordinates into shared vertices.

use super::{Lines, format_error, parse_error, parse_vertex, tokens};
use crate::mesh::weld;
use crate::{Result, TriMesh};

/// Parses an STL file and welds identical corners ([`fn@weld`] with tolerance 0). `path` only
/// labels error messages.
///
/// The file is binary when its size is 84 + 50 × (the triangle count stored at byte 80), whatever
/// its first bytes say (many binary files start with `solid` too); otherwise it must be ascii
/// (`solid ... facet ... outer loop ... vertex x y z ... endloop ... endfacet ... endsolid`).
/// Facet normals are ignored. Triangles that become degenerate after welding are dropped.
///
/// Errors: a facet without exactly 3 vertices, an unreadable number or a non-finite coordinate
/// ([`crate::Error::Parse`] with the line for ascii, [`crate::Error::Format`] naming the triangle
/// for binary), a file that is neither, no (non-degenerate) triangles.
pub fn parse_stl(data: &[u8], path: &str) -> Result<TriMesh> {
    let soup = if let Some(n) = binary_count(data) {
        parse_binary(data, n, path)?
    } else if is_ascii_stl(data) && !data.contains(&0) {
        // (A file starting with "solid" that holds NUL bytes is a binary file of the wrong size.)
        parse_ascii(data, path)?
    } else {
        let msg = match data.get(80..84) {
            Some(b) => {
                let n = u32::from_le_bytes([b[0], b[1], b[2], b[3]]) as u64;
                format!(
                    "not a valid STL file: not ascii (no 'solid' at the start) and not binary \
                     (the header announces {n} triangles, i.e. {} bytes, but the file has {})",
                    84 + 50 * n,
                    data.len()
                )
            }
            None => "not a valid STL file (too short for binary STL, no 'solid' at the start)"
                .to_string(),
        };
        return Err(format_error(path, &msg));
    };
    let n_triangles = soup.faces.len();
    if n_triangles == 0 {
        return Err(format_error(path, "no faces"));
    }
    let mesh = weld(&soup, 0.0);
    if mesh.faces.is_empty() {
        return Err(format_error(
            path,
            &format!("no faces (all {n_triangles} triangles are degenerate)"),
        ));
    }
    Ok(mesh)
}

/// The triangle count if `data` has exactly the size of a binary STL file.
fn binary_count(data: &[u8]) -> Option<usize> {
    let b = data.get(80..84)?;
    let n = u32::from_le_bytes([b[0], b[1], b[2], b[3]]) as u64;
    (84 + 50 * n == data.len() as u64).then_some(n as usize)
}

fn is_ascii_stl(data: &[u8]) -> bool {
    let start = data
        .iter()
        .position(|b| !b.is_ascii_whitespace())
        .unwrap_or(data.len());
    data[start..].starts_with(b"solid")
}

fn parse_binary(data: &[u8], n: usize, path: &str) -> Result<TriMesh> {
    let mut positions = Vec::with_capacity(3 * n);
    let mut faces = Vec::with_capacity(n);
    for (t, record) in data[84..].chunks_exact(50).enumerate() {
        for c in 0..3 {
            let mut p = [0.0; 3];
            for (k, x) in p.iter_mut().enumerate() {
                let o = 12 + 12 * c + 4 * k;
                *x = f32::from_le_bytes([record[o], record[o + 1], record[o + 2], record[o + 3]])
                    as f64;
            }
            if !p.iter().all(|x| x.is_finite()) {
                return Err(format_error(
                    path,
                    &format!("triangle {t} has a non-finite coordinate"),
                ));
            }
            positions.push(p);
        }
        let v = 3 * t as u32;
        faces.push([v, v + 1, v + 2]);
    }
    Ok(TriMesh::new(positions, faces))
}

fn parse_ascii(data: &[u8], path: &str) -> Result<TriMesh> {
    let mut positions: Vec<[f64; 3]> = Vec::new();
    let mut faces = Vec::new();
    // Corners of the facet being read, and the line where it started.
    let mut corners: Vec<[f64; 3]> = Vec::with_capacity(3);
    let mut facet_line = 0;
    let mut close = |corners: &mut Vec<[f64; 3]>, line: usize| -> Result<()> {
        if corners.len() != 3 {
            let k = corners.len();
            let msg = if k > 3 {
                format!(
                    "facet with {k} vertices: only triangles are supported (triangulate the mesh first)"
                )
            } else {
                format!("facet with {k} vertices: a facet needs 3")
            };
            return Err(parse_error(path, line, msg));
        }
        let v = positions.len() as u32;
        positions.append(corners);
        faces.push([v, v + 1, v + 2]);
        Ok(())
    };
    for (line_no, line) in Lines::new(data) {
        let mut toks = tokens(line);
        match toks.next() {
            Some(b"facet") => facet_line = line_no,
            Some(b"vertex") => {
                let p = parse_vertex(&mut toks, path, line_no, "vertex")?;
                if corners.is_empty() && facet_line == 0 {
                    facet_line = line_no;
                }
                corners.push(p);
            }
            Some(b"endloop") | Some(b"endfacet") if !corners.is_empty() => {
                close(&mut corners, facet_line)?;
                facet_line = 0;
            }
            _ => {}
        }
    }
    if !corners.is_empty() {
        return Err(format_error(path, "file ends inside a facet"));
    }
    Ok(TriMesh::new(positions, faces))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Error;

    /// Binary STL of the given triangles (normals zero), with an optional misleading header.
    fn binary(triangles: &[[[f32; 3]; 3]], header: &[u8]) -> Vec<u8> {
        let mut out = vec![0u8; 80];
        out[..header.len()].copy_from_slice(header);
        out.extend((triangles.len() as u32).to_le_bytes());
        for t in triangles {
            out.extend([0u8; 12]);
            for p in t {
                for x in p {
                    out.extend(x.to_le_bytes());
                }
            }
            out.extend([0u8; 2]);
        }
        out
    }

    fn ascii(triangles: &[[[f32; 3]; 3]]) -> String {
        let mut s = "solid test\n".to_string();
        for t in triangles {
            s += "  facet normal 0 0 1\n    outer loop\n";
            for p in t {
                s += &format!("      vertex {} {} {}\n", p[0], p[1], p[2]);
            }
            s += "    endloop\n  endfacet\n";
        }
        s + "endsolid test\n"
    }

    const SQUARE: [[[f32; 3]; 3]; 2] = [
        [[0., 0., 0.], [1., 0., 0.], [1., 1., 0.]],
        [[0., 0., 0.], [1., 1., 0.], [0., 1., 0.]],
    ];

    fn expected_square() -> TriMesh {
        TriMesh::new(
            vec![[0., 0., 0.], [1., 0., 0.], [1., 1., 0.], [0., 1., 0.]],
            vec![[0, 1, 2], [0, 2, 3]],
        )
    }

    #[test]
    fn two_triangles_weld_into_four_vertices() {
        for data in [
            binary(&SQUARE, b""),
            binary(&SQUARE, b"solid but binary"),
            ascii(&SQUARE).into_bytes(),
        ] {
            let m = parse_stl(&data, "t.stl").unwrap();
            assert_eq!(m, expected_square());
        }
    }

    #[test]
    fn single_precision_values_are_kept_exactly() {
        let t = [[[0.1f32, 0.2, 0.3], [1.1, 0.2, 0.3], [0.1, 1.7, 0.3]]];
        let m = parse_stl(&binary(&t, b""), "t.stl").unwrap();
        assert_eq!(
            m.positions[2],
            [0.1f32 as f64, 1.7f32 as f64, 0.3f32 as f64]
        );
    }

    fn format_msg(data: &[u8]) -> String {
        match parse_stl(data, "t.stl") {
            Err(Error::Format { msg, .. }) => msg,
            other => panic!("expected a format error, got {other:?}"),
        }
    }

    fn parse_msg(data: &str) -> (usize, String) {
        match parse_stl(data.as_bytes(), "t.stl") {
            Err(Error::Parse { line, msg, .. }) => (line, msg),
            other => panic!("expected a parse error, got {other:?}"),
        }
    }

    #[test]
    fn malformed_files() {
        let mut data = binary(&SQUARE, b"");
        data.pop();
        assert!(format_msg(&data).contains("announces 2 triangles"));
        assert!(format_msg(b"hello").contains("not a valid STL file"));
        let mut data = binary(&SQUARE, b"solid but binary");
        data.push(0);
        assert!(format_msg(&data).contains("announces 2 triangles"));
        assert_eq!(format_msg(&binary(&[], b"")), "no faces");
        assert_eq!(format_msg(b"solid empty\nendsolid empty\n"), "no faces");
        let flat = [[[0., 0., 0.], [1., 0., 0.], [1., 0., 0.]]];
        assert!(format_msg(&binary(&flat, b"")).contains("all 1 triangles are degenerate"));
        let nan = [[[0., 0., 0.], [1., f32::NAN, 0.], [1., 1., 0.]]];
        assert_eq!(
            format_msg(&binary(&nan, b"")),
            "triangle 0 has a non-finite coordinate"
        );
        let text = ascii(&SQUARE);
        let cut = text.rfind("    endloop").unwrap();
        assert_eq!(
            format_msg(&text.as_bytes()[..cut]),
            "file ends inside a facet"
        );
    }

    #[test]
    fn ascii_errors_name_the_line() {
        let text = ascii(&SQUARE).replace("vertex 1 0 0", "vertex 1 zero 0");
        assert_eq!(
            parse_msg(&text),
            (5, "cannot read 'zero' as a number".to_string())
        );
        let text = ascii(&SQUARE).replace("vertex 1 0 0", "vertex 1 inf 0");
        assert_eq!(
            parse_msg(&text),
            (5, "vertex has a non-finite coordinate".to_string())
        );
        let text = ascii(&SQUARE).replacen(
            "      vertex 1 1 0\n",
            "      vertex 1 1 0\n      vertex 2 2 0\n",
            1,
        );
        let (line, msg) = parse_msg(&text);
        assert_eq!(line, 2);
        assert!(
            msg.starts_with("facet with 4 vertices: only triangles"),
            "{msg}"
        );
        let text = ascii(&SQUARE).replacen("      vertex 1 1 0\n", "", 1);
        assert_eq!(
            parse_msg(&text),
            (2, "facet with 2 vertices: a facet needs 3".to_string())
        );
    }
}
