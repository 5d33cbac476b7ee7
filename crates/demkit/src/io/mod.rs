//! Reading and writing files: meshes (OBJ, PLY, OFF, STL, chosen by extension) and landmarks.
//!
//! Readers parse bytes with small hand-written scanners (no regular expressions) and report
//! problems as [`Error::Parse`] (with the 1-based line) or [`Error::Format`] (the file as a
//! whole). They check that indices are in range and coordinates finite, but not the topology:
//! that is [`fn@crate::mesh::validate`]'s job.

pub mod atomic;
pub mod landmarks;
pub mod obj;
pub mod off;
pub mod ply;
pub mod stl;

pub use atomic::{write_atomically, write_bytes_atomically};
pub use landmarks::{Landmark, read_landmarks};

use crate::{Error, Result, TriMesh};
use std::path::Path;

/// Mesh file extensions [`read_mesh`] understands (compared case-insensitively).
pub const READ_EXTENSIONS: &[&str] = &["obj", "ply", "off", "stl"];

/// Mesh file extensions [`write_mesh`] understands (compared case-insensitively).
pub const WRITE_EXTENSIONS: &[&str] = &["obj", "ply"];

/// Reads a triangle mesh, choosing the format by the file's extension (`.obj`, `.ply`, `.off`,
/// `.stl`, case-insensitive).
///
/// Errors: an unsupported extension ([`Error::Format`]), a missing or unreadable file
/// ([`Error::Io`]), an empty file or one without faces ([`Error::Format`]), and the format's own
/// errors (see [`obj::parse_obj`], [`ply::parse_ply`], [`off::parse_off`], [`stl::parse_stl`]).
pub fn read_mesh(path: &Path) -> Result<TriMesh> {
    let ext = extension(path, READ_EXTENSIONS, "input")?;
    let data = read_file(path)?;
    let label = path_label(path);
    if data.iter().all(u8::is_ascii_whitespace) {
        return Err(format_error(&label, "empty file"));
    }
    match ext.as_str() {
        "obj" => obj::parse_obj(&data, &label),
        "ply" => ply::parse_ply(&data, &label),
        "off" => off::parse_off(&data, &label),
        _ => stl::parse_stl(&data, &label),
    }
}

/// Writes a triangle mesh as `.obj` (text, full `f64` precision, 1-based faces) or `.ply`
/// (binary little-endian, double coordinates, int indices), chosen by the extension
/// (case-insensitive).
///
/// The file is written atomically ([`atomic`]): a failure leaves no partial file and an older
/// file of that name intact.
///
/// Errors: another extension ([`Error::Format`], before anything is created), or a failure to
/// create or write the file ([`Error::Io`]).
pub fn write_mesh(path: &Path, mesh: &TriMesh) -> Result<()> {
    let ext = extension(path, WRITE_EXTENSIONS, "output")?;
    write_atomically(path, |w| match ext.as_str() {
        "obj" => obj::write_obj(w, mesh),
        _ => ply::write_ply(w, mesh),
    })
    .map_err(|source| Error::Io {
        path: path_label(path),
        source,
    })
}

/// Writes `mesh` as `.obj` with texture coordinates (`vt` lines and `f a/ta b/tb c/tc`),
/// atomically.
///
/// Errors: another extension than `.obj` ([`Error::Format`], before anything is created), or a
/// failure to create or write the file ([`Error::Io`]).
pub fn write_textured_obj(
    path: &Path,
    mesh: &TriMesh,
    texture: &obj::TextureCoordinates,
) -> Result<()> {
    extension(path, &["obj"], "texture output")?;
    write_atomically(path, |w| obj::write_obj_textured(w, mesh, Some(texture))).map_err(|source| {
        Error::Io {
            path: path_label(path),
            source,
        }
    })
}

/// The lower-cased extension of `path` if it is one of `supported`, else [`Error::Format`].
fn extension(path: &Path, supported: &[&str], what: &str) -> Result<String> {
    let ext = path
        .extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase())
        .unwrap_or_default();
    if supported.contains(&ext.as_str()) {
        return Ok(ext);
    }
    let list = supported
        .iter()
        .map(|e| format!(".{e}"))
        .collect::<Vec<_>>()
        .join(", ");
    let found = if ext.is_empty() {
        "no extension".to_string()
    } else {
        format!("extension '.{ext}'")
    };
    Err(format_error(
        &path_label(path),
        &format!("unsupported {what} mesh format ({found}); supported: {list}"),
    ))
}

/// Reads a whole file, mapping failures to [`Error::Io`] with the path.
pub(crate) fn read_file(path: &Path) -> Result<Vec<u8>> {
    std::fs::read(path).map_err(|source| Error::Io {
        path: path_label(path),
        source,
    })
}

/// How a path is shown in error messages.
pub(crate) fn path_label(path: &Path) -> String {
    path.display().to_string()
}

/// An [`Error::Format`] for `path`.
pub(crate) fn format_error(path: &str, msg: &str) -> Error {
    Error::Format {
        path: path.to_string(),
        msg: msg.to_string(),
    }
}

/// An [`Error::Parse`] for `path` at 1-based `line`.
pub(crate) fn parse_error(path: &str, line: usize, msg: impl Into<String>) -> Error {
    Error::Parse {
        path: path.to_string(),
        line,
        msg: msg.into(),
    }
}

/// The [`Error::Parse`] for a token that is not a number.
pub(crate) fn number_error(path: &str, line: usize, token: &[u8]) -> Error {
    unreadable_error(path, line, token, "a number")
}

/// The [`Error::Parse`] for a token that cannot be read as `what` ("a number", "a count", ...).
pub(crate) fn unreadable_error(path: &str, line: usize, token: &[u8], what: &str) -> Error {
    parse_error(
        path,
        line,
        format!("cannot read '{}' as {what}", show(token)),
    )
}

/// The [`Error::Parse`] for a face of `count` vertices in a text format: only triangles are read.
pub(crate) fn face_size_error(path: &str, line: usize, count: i64) -> Error {
    let msg = if count > 3 {
        format!(
            "face with {count} vertices: only triangles are supported (triangulate the mesh \
             first)"
        )
    } else {
        format!("face with {count} vertices: a face needs 3")
    };
    parse_error(path, line, msg)
}

/// A token for an error message: lossy UTF-8, shortened to 40 characters.
pub(crate) fn show(token: &[u8]) -> String {
    let s = String::from_utf8_lossy(token);
    if s.chars().count() > 40 {
        format!("{}...", s.chars().take(40).collect::<String>())
    } else {
        s.into_owned()
    }
}

/// Lines of a byte buffer as `(1-based line number, line without "\n" or "\r\n")`.
pub(crate) struct Lines<'a> {
    data: &'a [u8],
    pos: usize,
    line: usize,
}

impl<'a> Lines<'a> {
    /// Iterates over the lines of `data`.
    pub(crate) fn new(data: &'a [u8]) -> Self {
        Self {
            data,
            pos: 0,
            line: 0,
        }
    }
}

impl<'a> Iterator for Lines<'a> {
    type Item = (usize, &'a [u8]);

    fn next(&mut self) -> Option<Self::Item> {
        if self.pos >= self.data.len() {
            return None;
        }
        let rest = &self.data[self.pos..];
        let end = rest.iter().position(|&b| b == b'\n').unwrap_or(rest.len());
        self.pos += end + 1;
        self.line += 1;
        let mut line = &rest[..end];
        if let [head @ .., b'\r'] = line {
            line = head;
        }
        Some((self.line, line))
    }
}

/// The whitespace-separated tokens of a line.
pub(crate) fn tokens(line: &[u8]) -> impl Iterator<Item = &[u8]> {
    line.split(u8::is_ascii_whitespace)
        .filter(|t| !t.is_empty())
}

/// The part of a line before a `#` comment.
pub(crate) fn strip_comment(line: &[u8]) -> &[u8] {
    match line.iter().position(|&b| b == b'#') {
        Some(i) => &line[..i],
        None => line,
    }
}

/// Reads the three coordinates of a vertex from the remaining tokens of a text line; errors
/// name the file and line (`what` names the vertex in the non-finite message).
pub(crate) fn parse_vertex<'a>(
    toks: &mut impl Iterator<Item = &'a [u8]>,
    path: &str,
    line_no: usize,
    what: &str,
) -> Result<[f64; 3]> {
    let mut p = [0.0; 3];
    for (k, x) in p.iter_mut().enumerate() {
        let t = toks.next().ok_or_else(|| {
            parse_error(
                path,
                line_no,
                format!("vertex with {k} coordinates: 3 are needed"),
            )
        })?;
        *x = parse_f64(t).ok_or_else(|| number_error(path, line_no, t))?;
    }
    if !p.iter().all(|x| x.is_finite()) {
        return Err(parse_error(
            path,
            line_no,
            format!("{what} has a non-finite coordinate"),
        ));
    }
    Ok(p)
}

/// Parses a decimal floating-point number (also accepts `inf` and `nan`: callers check).
pub(crate) fn parse_f64(token: &[u8]) -> Option<f64> {
    std::str::from_utf8(token).ok()?.parse().ok()
}

/// Parses a decimal integer with an optional sign.
pub(crate) fn parse_int(token: &[u8]) -> Option<i64> {
    let (negative, digits) = match token {
        [b'-', rest @ ..] => (true, rest),
        [b'+', rest @ ..] => (false, rest),
        _ => (false, token),
    };
    if digits.is_empty() {
        return None;
    }
    let mut value: i64 = 0;
    for &b in digits {
        if !b.is_ascii_digit() {
            return None;
        }
        value = value.checked_mul(10)?.checked_add((b - b'0') as i64)?;
    }
    Some(if negative { -value } else { value })
}

#[cfg(test)]
pub(crate) mod test_util {
    //! Temporary files for the readers' and writers' tests.

    use std::path::PathBuf;
    use std::sync::atomic::{AtomicUsize, Ordering};

    /// A fresh path in a per-process temporary folder, with the given file name suffix.
    pub(crate) fn temp_path(name: &str) -> PathBuf {
        static COUNTER: AtomicUsize = AtomicUsize::new(0);
        let dir = std::env::temp_dir().join(format!("demkit-io-tests-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let k = COUNTER.fetch_add(1, Ordering::Relaxed);
        dir.join(format!("{k}-{name}"))
    }

    /// Writes `data` to a fresh temporary file named `name` and returns its path.
    pub(crate) fn temp_file(name: &str, data: &[u8]) -> PathBuf {
        let path = temp_path(name);
        std::fs::write(&path, data).unwrap();
        path
    }

    /// The folder of the real meshes: `DEMKIT_DATA`, or `../shared/data` beside the checkout.
    pub(crate) fn data_dir() -> PathBuf {
        match std::env::var_os("DEMKIT_DATA") {
            Some(dir) => PathBuf::from(dir),
            None => PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../../shared/data"),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::test_util::*;
    use super::*;

    use crate::generate_fixtures::unit_square as square;

    #[test]
    fn lines_strip_line_endings() {
        let lines: Vec<_> = Lines::new(b"a\r\nb\n\nc").collect();
        assert_eq!(
            lines,
            vec![
                (1, &b"a"[..]),
                (2, &b"b"[..]),
                (3, &b""[..]),
                (4, &b"c"[..])
            ]
        );
        assert_eq!(Lines::new(b"").count(), 0);
        assert_eq!(Lines::new(b"x\n").count(), 1);
    }

    #[test]
    fn tokens_and_numbers() {
        let t: Vec<_> = tokens(b"  v 1.5\t-2e3  x ").collect();
        assert_eq!(t, vec![&b"v"[..], b"1.5", b"-2e3", b"x"]);
        assert_eq!(parse_f64(b"-2e3"), Some(-2000.0));
        assert_eq!(parse_f64(b"abc"), None);
        assert_eq!(parse_int(b"-17"), Some(-17));
        assert_eq!(parse_int(b"+3"), Some(3));
        assert_eq!(parse_int(b"3.0"), None);
        assert_eq!(parse_int(b"-"), None);
        assert_eq!(parse_int(b"99999999999999999999"), None);
        assert_eq!(strip_comment(b"f 1 2 3 # c"), b"f 1 2 3 ");
    }

    #[test]
    fn round_trip_through_files_by_extension() {
        let m = square();
        for name in ["m.obj", "m.ply", "M.OBJ", "M.Ply"] {
            let path = temp_path(name);
            write_mesh(&path, &m).unwrap();
            assert_eq!(read_mesh(&path).unwrap(), m, "{name}");
        }
    }

    #[test]
    fn unsupported_extensions() {
        let path = temp_file("m.xyz", b"v 0 0 0\n");
        match read_mesh(&path) {
            Err(Error::Format { msg, .. }) => {
                assert!(msg.contains("'.xyz'"), "{msg}");
                assert!(msg.contains(".obj, .ply, .off, .stl"), "{msg}");
            }
            other => panic!("{other:?}"),
        }
        let path = temp_path("noext");
        assert!(
            matches!(read_mesh(&path), Err(Error::Format { msg, .. }) if msg.contains("no extension"))
        );
        let path = temp_path("m.stl");
        match write_mesh(&path, &square()) {
            Err(Error::Format { msg, .. }) => assert!(msg.contains(".obj, .ply"), "{msg}"),
            other => panic!("{other:?}"),
        }
        assert!(!path.exists());
    }

    #[test]
    fn missing_file_is_io_error_with_path() {
        let path = temp_path("missing.obj");
        match read_mesh(&path) {
            Err(Error::Io { path: p, source }) => {
                assert_eq!(p, path.display().to_string());
                assert_eq!(source.kind(), std::io::ErrorKind::NotFound);
            }
            other => panic!("{other:?}"),
        }
        let bad = temp_path("no-such-dir").join("out.obj");
        assert!(matches!(write_mesh(&bad, &square()), Err(Error::Io { .. })));
    }

    #[test]
    fn empty_files() {
        for name in ["e.obj", "e.ply", "e.off", "e.stl"] {
            for data in [&b""[..], b" \n\n"] {
                let path = temp_file(name, data);
                match read_mesh(&path) {
                    Err(Error::Format { msg, .. }) => assert_eq!(msg, "empty file"),
                    other => panic!("{name}: {other:?}"),
                }
            }
        }
    }

    #[test]
    fn files_without_faces() {
        let cases: [(&str, &[u8]); 4] = [
            ("n.obj", b"v 0 0 0\nv 1 0 0\n"),
            ("n.off", b"OFF\n1 0 0\n0 0 0\n"),
            (
                "n.ply",
                b"ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n\
                  property float z\nend_header\n0 0 0\n",
            ),
            ("n.stl", b"solid x\nendsolid x\n"),
        ];
        for (name, data) in cases {
            let path = temp_file(name, data);
            match read_mesh(&path) {
                Err(Error::Format { msg, .. }) => {
                    assert!(msg.contains("no faces"), "{name}: {msg}")
                }
                other => panic!("{name}: {other:?}"),
            }
        }
    }

    #[test]
    fn all_readers_by_extension() {
        let off = b"OFF\n4 2 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n3 0 1 2\n3 0 2 3\n";
        let obj = b"v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3\nf 1 3 4\n";
        let stl = b"solid s\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\n\
                    vertex 1 1 0\nendloop\nendfacet\nfacet normal 0 0 1\nouter loop\n\
                    vertex 0 0 0\nvertex 1 1 0\nvertex 0 1 0\nendloop\nendfacet\nendsolid s\n";
        for (name, data) in [("a.off", &off[..]), ("a.obj", obj), ("a.STL", stl)] {
            assert_eq!(
                read_mesh(&temp_file(name, data)).unwrap(),
                square(),
                "{name}"
            );
        }
    }

    #[test]
    fn a_million_vertices_round_trip() {
        let n = 1000u32;
        let mut positions = Vec::with_capacity((n * n) as usize);
        for i in 0..n {
            for j in 0..n {
                positions.push([i as f64 / 7.0, j as f64 / 3.0, 0.1 * (i + j) as f64]);
            }
        }
        let mut faces = Vec::new();
        for i in 0..n - 1 {
            for j in 0..n - 1 {
                faces.push([i * n + j, (i + 1) * n + j, (i + 1) * n + j + 1]);
            }
        }
        let m = TriMesh::new(positions, faces);
        for name in ["big.ply", "big.obj"] {
            let path = temp_path(name);
            let t = std::time::Instant::now();
            write_mesh(&path, &m).unwrap();
            let written = t.elapsed();
            let back = read_mesh(&path).unwrap();
            assert_eq!(back, m, "{name}");
            std::fs::remove_file(&path).unwrap();
            eprintln!("{name}: wrote 1M vertices in {written:?}");
        }
    }
}
