//! Object File Format (OFF), text only: header, counts, vertex lines, face lines.

use super::{Lines, face_size_error, format_error, parse_error, parse_int, show};
use super::{parse_vertex, strip_comment, tokens, unreadable_error};
use crate::{Result, TriMesh};

/// Parses OFF text. `path` only labels error messages.
///
/// Accepts an `OFF` header (also `COFF`, `NOFF`, `STOFF`, ...: extra per-vertex values are
/// ignored; the header may be missing or carry the counts on the same line), `#` comments and
/// blank lines anywhere, a counts line `vertices faces [edges]`, one vertex per line (`x y z`)
/// and one face per line (`3 a b c`, 0-based, optional trailing colour values).
///
/// Errors: a face that is not a triangle, an unreadable number, a non-finite coordinate, an index
/// out of range ([`crate::Error::Parse`] with the line); an unsupported variant (`4OFF`, `nOFF`,
/// binary), fewer lines than announced, no faces ([`crate::Error::Format`]).
pub fn parse_off(data: &[u8], path: &str) -> Result<TriMesh> {
    let mut lines = Lines::new(data)
        .map(|(n, l)| (n, strip_comment(l)))
        .filter(|(_, l)| tokens(l).next().is_some());
    let Some((first_no, first)) = lines.next() else {
        return Err(format_error(path, "empty file"));
    };
    let mut first_toks = tokens(first);
    let key = first_toks.next().unwrap_or_default();
    let (counts_no, counts): (usize, Vec<&[u8]>) = if let Some(prefix) = key.strip_suffix(b"OFF") {
        if !prefix.iter().all(|b| b"STCN".contains(b)) {
            return Err(format_error(
                path,
                &format!(
                    "unsupported OFF variant '{}' (only 3D OFF files are supported)",
                    show(key)
                ),
            ));
        }
        let rest: Vec<&[u8]> = first_toks.collect();
        if rest
            .first()
            .is_some_and(|t| t.eq_ignore_ascii_case(b"BINARY"))
        {
            return Err(format_error(path, "binary OFF files are not supported"));
        }
        if rest.is_empty() {
            let (n, l) = lines
                .next()
                .ok_or_else(|| format_error(path, "file ends before the counts line"))?;
            (n, tokens(l).collect())
        } else {
            (first_no, rest)
        }
    } else if parse_int(key).is_some() {
        (first_no, tokens(first).collect())
    } else {
        return Err(format_error(
            path,
            &format!("not an OFF file (it starts with '{}')", show(key)),
        ));
    };
    let count = |i: usize| -> Result<usize> {
        let t = counts.get(i).ok_or_else(|| {
            parse_error(
                path,
                counts_no,
                "expected the counts line 'vertices faces [edges]'",
            )
        })?;
        parse_int(t)
            .and_then(|c| usize::try_from(c).ok())
            .ok_or_else(|| unreadable_error(path, counts_no, t, "a count"))
    };
    let (nv, nf) = (count(0)?, count(1)?);

    // The counts are not trusted for allocation beyond what the data could hold: a vertex
    // line takes at least 6 bytes ("0 0 0\n"), a face line at least 8 ("3 0 1 2\n").
    let mut positions = Vec::with_capacity(nv.min(data.len() / 6));
    for v in 0..nv {
        let (line_no, line) = next_line(&mut lines, path, v, nv, "vertices")?;
        let mut toks = tokens(line);
        let p = parse_vertex(&mut toks, path, line_no, &format!("vertex {v}"))?;
        positions.push(p);
    }

    let mut faces = Vec::with_capacity(nf.min(data.len() / 8));
    for f in 0..nf {
        let (line_no, line) = next_line(&mut lines, path, f, nf, "faces")?;
        let mut toks = tokens(line);
        let t = toks.next().unwrap_or_default();
        let k = parse_int(t).ok_or_else(|| unreadable_error(path, line_no, t, "a vertex count"))?;
        if k != 3 {
            return Err(face_size_error(path, line_no, k));
        }
        let mut face = [0u32; 3];
        for slot in &mut face {
            let t = toks.next().ok_or_else(|| {
                parse_error(path, line_no, "face announces 3 vertices but lists fewer")
            })?;
            let i =
                parse_int(t).ok_or_else(|| unreadable_error(path, line_no, t, "a vertex index"))?;
            if i < 0 || i as u64 >= nv as u64 {
                return Err(parse_error(
                    path,
                    line_no,
                    format!("vertex index {i} is out of range (the file has {nv} vertices)"),
                ));
            }
            *slot = i as u32;
        }
        faces.push(face);
    }
    if let Some((line_no, _)) = lines.next() {
        return Err(parse_error(
            path,
            line_no,
            format!("data after the {nf} faces the header declares (is the face count wrong?)"),
        ));
    }
    if faces.is_empty() {
        return Err(format_error(path, "no faces"));
    }
    Ok(TriMesh::new(positions, faces))
}

/// The next line of `lines`, or the error for a file that ends after `done` of `total`
/// `what` ("vertices", "faces").
fn next_line<'a>(
    lines: &mut impl Iterator<Item = (usize, &'a [u8])>,
    path: &str,
    done: usize,
    total: usize,
    what: &str,
) -> Result<(usize, &'a [u8])> {
    lines
        .next()
        .ok_or_else(|| format_error(path, &format!("file ends after {done} of {total} {what}")))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Error;

    #[test]
    fn faces_beyond_the_declared_count_are_an_error_naming_their_line() {
        let text = "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n3 0 2 1\n";
        match parse_off(text.as_bytes(), "t.off") {
            Err(Error::Parse { line, msg, .. }) => {
                assert_eq!(line, 7, "{msg}");
                assert!(msg.contains("after the 1 faces"), "{msg}");
            }
            other => panic!("{other:?}"),
        }
    }

    fn square() -> TriMesh {
        TriMesh::new(
            vec![[0., 0., 0.], [1., 0., 0.], [1., 1., 0.], [0., 1., 0.]],
            vec![[0, 1, 2], [0, 2, 3]],
        )
    }

    fn parse(text: &str) -> Result<TriMesh> {
        parse_off(text.as_bytes(), "t.off")
    }

    fn parse_msg(text: &str) -> (usize, String) {
        match parse(text) {
            Err(Error::Parse { line, msg, .. }) => (line, msg),
            other => panic!("expected a parse error, got {other:?}"),
        }
    }

    fn format_msg(text: &str) -> String {
        match parse(text) {
            Err(Error::Format { msg, .. }) => msg,
            other => panic!("expected a format error, got {other:?}"),
        }
    }

    const BODY: &str = "0 0 0\n1 0 0\n1 1 0\n0 1 0\n3 0 1 2\n3 0 2 3\n";

    #[test]
    fn standard_and_variants() {
        for head in [
            "OFF\n4 2 0\n",
            "OFF\n4 2\n",
            "OFF 4 2 0\n",
            "4 2 0\n",
            "COFF\n4 2 5\n",
        ] {
            assert_eq!(
                parse(&format!("{head}{BODY}")).unwrap(),
                square(),
                "{head:?}"
            );
        }
        let text = "# made by hand\nOFF # header\n\n# counts\n4 2 0\r\n0 0 0 255 0 0\n\
                    1 0 0\n# a comment between vertices\n1 1 0\n0 1 0\n3 0 1 2 1.0 0.5 0.5\n\
                    3 0 2 3\n";
        assert_eq!(parse(text).unwrap(), square());
    }

    #[test]
    fn quads_are_rejected() {
        let (line, msg) = parse_msg("OFF\n4 1 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n4 0 1 2 3\n");
        assert_eq!(line, 7);
        assert_eq!(
            msg,
            "face with 4 vertices: only triangles are supported (triangulate the mesh first)"
        );
    }

    #[test]
    fn errors_name_the_line() {
        let (line, msg) = parse_msg("OFF\n4 2 0\n0 0 0\n1 x 0\n1 1 0\n0 1 0\n3 0 1 2\n3 0 2 3\n");
        assert_eq!((line, msg.as_str()), (4, "cannot read 'x' as a number"));
        let (line, msg) = parse_msg("OFF\n4 2 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n3 0 1 2\n3 0 2 4\n");
        assert_eq!(
            (line, msg.as_str()),
            (
                8,
                "vertex index 4 is out of range (the file has 4 vertices)"
            )
        );
        let (line, _) = parse_msg("OFF\n4 2 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n3 0 1 2\n3 0 -2 3\n");
        assert_eq!(line, 8);
        let (line, msg) = parse_msg("OFF\n4 2 0\n0 0 0\n1 0 nan\n1 1 0\n0 1 0\n3 0 1 2\n");
        assert_eq!(
            (line, msg.as_str()),
            (4, "vertex 1 has a non-finite coordinate")
        );
        let (line, _) = parse_msg("OFF\nfour 2 0\n");
        assert_eq!(line, 2);
        let (line, _) = parse_msg("OFF\n4\n");
        assert_eq!(line, 2);
        let (line, msg) = parse_msg("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1\n");
        assert_eq!(line, 6);
        assert!(msg.contains("lists fewer"), "{msg}");
    }

    #[test]
    fn whole_file_errors() {
        assert_eq!(
            format_msg("OFF\n4 2 0\n0 0 0\n1 0 0\n"),
            "file ends after 2 of 4 vertices"
        );
        assert_eq!(
            format_msg("OFF\n4 2 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n3 0 1 2\n"),
            "file ends after 1 of 2 faces"
        );
        assert!(format_msg("4OFF\n1 0 0\n0 0 0 0\n").contains("unsupported OFF variant '4OFF'"));
        assert!(format_msg("nOFF\n3\n").contains("unsupported"));
        assert!(format_msg("OFF BINARY\n").contains("binary"));
        assert!(format_msg("ply\n").contains("not an OFF file"));
        assert_eq!(format_msg("OFF\n3 0 0\n0 0 0\n1 0 0\n0 1 0\n"), "no faces");
        assert!(format_msg("OFF\n").contains("counts"));
        assert_eq!(format_msg("# only a comment\n"), "empty file");
    }
}
