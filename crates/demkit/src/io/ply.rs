//! Stanford PLY 1.0: ascii, binary little-endian and binary big-endian.
//!
//! Reads the `vertex` element's `x`, `y`, `z` (any scalar type) and the `face` element's list
//! `vertex_indices` (or `vertex_index`, any count and index types); every other property and
//! element is skipped, list properties included. Writes binary little-endian.

use super::{Lines, format_error, number_error, parse_error, parse_f64, show, tokens};
use crate::{Result, TriMesh};
use std::io::Write;

/// Parses a PLY file. `path` only labels error messages.
///
/// Errors: a malformed header or body ([`crate::Error::Parse`] with the line for ascii text,
/// [`crate::Error::Format`] for binary data), a missing `x`/`y`/`z` or `vertex_indices` property, a
/// face that is not a triangle, a negative or out-of-range vertex index, a non-finite
/// coordinate, truncated data, no faces.
pub fn parse_ply(data: &[u8], path: &str) -> Result<TriMesh> {
    let header = Header::parse(data, path)?;
    let body = &data[header.body_start..];
    match header.encoding {
        Encoding::Ascii => {
            let mut src = AsciiSource {
                data: body,
                pos: 0,
                line: header.body_first_line,
                token_line: header.body_first_line,
            };
            read_body(&header, &mut src, body.len(), path)
        }
        Encoding::Binary { big_endian } => {
            let mut src = BinarySource {
                data: body,
                pos: 0,
                big_endian,
            };
            read_body(&header, &mut src, body.len(), path)
        }
    }
}

/// Writes `mesh` as binary little-endian PLY with `double` x, y, z and a `uchar int`
/// `vertex_indices` list per face. Flushes `w` at the end.
pub fn write_ply<W: Write>(mut w: W, mesh: &TriMesh) -> std::io::Result<()> {
    write!(
        w,
        "ply\nformat binary_little_endian 1.0\ncomment written by demkit\n\
         element vertex {}\nproperty double x\nproperty double y\nproperty double z\n\
         element face {}\nproperty list uchar int vertex_indices\nend_header\n",
        mesh.positions.len(),
        mesh.faces.len()
    )?;
    let mut buf = [0u8; 24];
    for p in &mesh.positions {
        for k in 0..3 {
            buf[8 * k..8 * k + 8].copy_from_slice(&p[k].to_le_bytes());
        }
        w.write_all(&buf)?;
    }
    let mut buf = [0u8; 13];
    buf[0] = 3;
    for f in &mesh.faces {
        for k in 0..3 {
            buf[1 + 4 * k..5 + 4 * k].copy_from_slice(&(f[k] as i32).to_le_bytes());
        }
        w.write_all(&buf)?;
    }
    w.flush()
}

/// PLY scalar types.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Scalar {
    I8,
    U8,
    I16,
    U16,
    I32,
    U32,
    F32,
    F64,
}

impl Scalar {
    fn from_name(name: &[u8]) -> Option<Self> {
        Some(match name {
            b"char" | b"int8" => Self::I8,
            b"uchar" | b"uint8" => Self::U8,
            b"short" | b"int16" => Self::I16,
            b"ushort" | b"uint16" => Self::U16,
            b"int" | b"int32" => Self::I32,
            b"uint" | b"uint32" => Self::U32,
            b"float" | b"float32" => Self::F32,
            b"double" | b"float64" => Self::F64,
            _ => return None,
        })
    }

    fn size(self) -> usize {
        match self {
            Self::I8 | Self::U8 => 1,
            Self::I16 | Self::U16 => 2,
            Self::I32 | Self::U32 | Self::F32 => 4,
            Self::F64 => 8,
        }
    }
}

#[derive(Debug)]
enum Property {
    Scalar(Scalar, String),
    List(Scalar, Scalar, String),
}

impl Property {
    fn name(&self) -> &str {
        match self {
            Self::Scalar(_, n) | Self::List(_, _, n) => n,
        }
    }
}

#[derive(Debug)]
struct Element {
    name: String,
    count: usize,
    properties: Vec<Property>,
}

#[derive(Debug, Clone, Copy)]
enum Encoding {
    Ascii,
    Binary { big_endian: bool },
}

#[derive(Debug)]
struct Header {
    encoding: Encoding,
    elements: Vec<Element>,
    /// Byte offset of the body (just after the `end_header` line).
    body_start: usize,
    /// Line number of the body's first line.
    body_first_line: usize,
}

impl Header {
    fn parse(data: &[u8], path: &str) -> Result<Self> {
        let mut encoding = None;
        let mut elements: Vec<Element> = Vec::new();
        let mut offset = 0usize;
        for (line_no, line) in Lines::new(data) {
            // Lines yields lines in order; track the byte offset of the next line.
            offset += line.len() + 1;
            if data.get(offset - 1) == Some(&b'\r') {
                offset += 1;
            }
            let mut toks = tokens(line);
            let Some(key) = toks.next() else {
                if line_no == 1 {
                    return Err(format_error(
                        path,
                        "not a PLY file (no 'ply' on the first line)",
                    ));
                }
                continue;
            };
            if line_no == 1 {
                if key != b"ply" || toks.next().is_some() {
                    return Err(format_error(
                        path,
                        "not a PLY file (no 'ply' on the first line)",
                    ));
                }
                continue;
            }
            let err = |msg: String| parse_error(path, line_no, msg);
            let rest: Vec<&[u8]> = toks.collect();
            match key {
                b"comment" | b"obj_info" => {}
                b"format" => {
                    let enc = match rest.first().copied() {
                        Some(b"ascii") => Encoding::Ascii,
                        Some(b"binary_little_endian") => Encoding::Binary { big_endian: false },
                        Some(b"binary_big_endian") => Encoding::Binary { big_endian: true },
                        _ => return Err(err(format!("unknown PLY format line '{}'", show(line)))),
                    };
                    if rest.get(1).copied() != Some(&b"1.0"[..]) || rest.len() != 2 {
                        return Err(err(format!(
                            "unsupported PLY format line '{}' (version 1.0 expected)",
                            show(line)
                        )));
                    }
                    encoding = Some(enc);
                }
                b"element" => {
                    let count = match rest.as_slice() {
                        [_, count] => super::parse_int(count).and_then(|c| usize::try_from(c).ok()),
                        _ => None,
                    };
                    let Some(count) = count else {
                        return Err(err(format!(
                            "expected 'element NAME COUNT', found '{}'",
                            show(line)
                        )));
                    };
                    elements.push(Element {
                        name: String::from_utf8_lossy(rest[0]).into_owned(),
                        count,
                        properties: Vec::new(),
                    });
                }
                b"property" => {
                    let Some(element) = elements.last_mut() else {
                        return Err(err("property before any element".to_string()));
                    };
                    let name = |t: &[u8]| String::from_utf8_lossy(t).into_owned();
                    let ty = |t: &[u8]| {
                        Scalar::from_name(t)
                            .ok_or_else(|| err(format!("unknown PLY property type '{}'", show(t))))
                    };
                    let property = match rest.as_slice() {
                        [b"list", count, item, n] => Property::List(ty(count)?, ty(item)?, name(n)),
                        [t, n] if *t != b"list" => Property::Scalar(ty(t)?, name(n)),
                        _ => {
                            return Err(err(format!(
                                "expected 'property TYPE NAME' or 'property list COUNT_TYPE \
                                 ITEM_TYPE NAME', found '{}'",
                                show(line)
                            )));
                        }
                    };
                    element.properties.push(property);
                }
                b"end_header" => {
                    let Some(encoding) = encoding else {
                        return Err(format_error(path, "PLY header has no 'format' line"));
                    };
                    return Ok(Header {
                        encoding,
                        elements,
                        body_start: offset.min(data.len()),
                        body_first_line: line_no + 1,
                    });
                }
                _ => {
                    return Err(err(format!("unexpected PLY header line '{}'", show(line))));
                }
            }
        }
        Err(format_error(path, "PLY header has no 'end_header' line"))
    }
}

/// Why a value could not be read.
enum ReadError {
    /// The data ended.
    End,
    /// (ascii) a token that is not a number.
    Bad(Vec<u8>),
}

/// A stream of scalar values (ascii tokens or binary data).
trait Source {
    /// The next value, converted to `f64` (exact for every PLY integer type).
    fn next(&mut self, ty: Scalar) -> std::result::Result<f64, ReadError>;
    /// The line of the last value (ascii) or `None` (binary).
    fn line(&self) -> Option<usize>;
    /// The fewest bytes a value of type `ty` takes in the data.
    fn min_bytes(&self, ty: Scalar) -> usize;
    /// Skips `n` values of type `ty`.
    fn skip(&mut self, ty: Scalar, n: usize) -> std::result::Result<(), ReadError> {
        for _ in 0..n {
            self.next(ty)?;
        }
        Ok(())
    }
    /// Whether anything but whitespace (ascii) or any byte (binary) follows the last element,
    /// with the line where it starts (ascii).
    fn trailing(&mut self) -> Option<Option<usize>>;
}

struct AsciiSource<'a> {
    data: &'a [u8],
    pos: usize,
    /// Line at `pos`.
    line: usize,
    /// Line of the last token returned.
    token_line: usize,
}

impl Source for AsciiSource<'_> {
    fn next(&mut self, _ty: Scalar) -> std::result::Result<f64, ReadError> {
        let d = self.data;
        while self.pos < d.len() && d[self.pos].is_ascii_whitespace() {
            if d[self.pos] == b'\n' {
                self.line += 1;
            }
            self.pos += 1;
        }
        if self.pos >= d.len() {
            return Err(ReadError::End);
        }
        let start = self.pos;
        while self.pos < d.len() && !d[self.pos].is_ascii_whitespace() {
            self.pos += 1;
        }
        self.token_line = self.line;
        let token = &d[start..self.pos];
        parse_f64(token).ok_or_else(|| ReadError::Bad(token.to_vec()))
    }

    fn line(&self) -> Option<usize> {
        Some(self.token_line)
    }
    fn min_bytes(&self, _ty: Scalar) -> usize {
        1
    }

    fn trailing(&mut self) -> Option<Option<usize>> {
        let d = self.data;
        while self.pos < d.len() && d[self.pos].is_ascii_whitespace() {
            if d[self.pos] == b'\n' {
                self.line += 1;
            }
            self.pos += 1;
        }
        (self.pos < d.len()).then_some(Some(self.line))
    }
}

struct BinarySource<'a> {
    data: &'a [u8],
    pos: usize,
    big_endian: bool,
}

impl BinarySource<'_> {
    fn take<const N: usize>(&mut self) -> std::result::Result<[u8; N], ReadError> {
        let bytes = self
            .data
            .get(self.pos..self.pos + N)
            .ok_or(ReadError::End)?;
        self.pos += N;
        let mut out = [0u8; N];
        out.copy_from_slice(bytes);
        if self.big_endian {
            out.reverse();
        }
        Ok(out)
    }
}

impl Source for BinarySource<'_> {
    fn next(&mut self, ty: Scalar) -> std::result::Result<f64, ReadError> {
        // Bytes are brought to little-endian order by `take`.
        Ok(match ty {
            Scalar::I8 => i8::from_le_bytes(self.take()?) as f64,
            Scalar::U8 => u8::from_le_bytes(self.take()?) as f64,
            Scalar::I16 => i16::from_le_bytes(self.take()?) as f64,
            Scalar::U16 => u16::from_le_bytes(self.take()?) as f64,
            Scalar::I32 => i32::from_le_bytes(self.take()?) as f64,
            Scalar::U32 => u32::from_le_bytes(self.take()?) as f64,
            Scalar::F32 => f32::from_le_bytes(self.take()?) as f64,
            Scalar::F64 => f64::from_le_bytes(self.take()?),
        })
    }

    fn line(&self) -> Option<usize> {
        None
    }
    fn min_bytes(&self, ty: Scalar) -> usize {
        ty.size()
    }

    fn trailing(&mut self) -> Option<Option<usize>> {
        (self.pos < self.data.len()).then_some(None)
    }

    fn skip(&mut self, ty: Scalar, n: usize) -> std::result::Result<(), ReadError> {
        let end = n
            .checked_mul(ty.size())
            .and_then(|len| self.pos.checked_add(len))
            .filter(|&end| end <= self.data.len())
            .ok_or(ReadError::End)?;
        self.pos = end;
        Ok(())
    }
}

/// What the reader does with each property of an element.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Role {
    Coordinate(usize),
    Indices,
    Skip,
}

fn read_body<S: Source>(
    header: &Header,
    src: &mut S,
    body_len: usize,
    path: &str,
) -> Result<TriMesh> {
    let vertex_elements = header
        .elements
        .iter()
        .filter(|e| e.name == "vertex")
        .count();
    let face_elements = header.elements.iter().filter(|e| e.name == "face").count();
    if vertex_elements != 1 || face_elements > 1 {
        return Err(format_error(
            path,
            &format!(
                "a PLY mesh needs one 'vertex' element and at most one 'face' element (found \
                 {vertex_elements} and {face_elements})"
            ),
        ));
    }
    // Error at the current position: with the line for ascii, for the file otherwise.
    let located = |src: &S, msg: String| match src.line() {
        Some(line) => parse_error(path, line, msg),
        None => format_error(path, &msg),
    };
    let read_error = |src: &S, e: ReadError, element: &Element, item: usize| match e {
        ReadError::End => format_error(
            path,
            &format!(
                "file is truncated: it ends in {} {item} of {}",
                element.name, element.count
            ),
        ),
        ReadError::Bad(token) => number_error(path, src.line().unwrap_or(0), &token),
    };

    let mut positions: Vec<[f64; 3]> = Vec::new();
    let mut faces: Vec<[u32; 3]> = Vec::new();
    // (largest index, its face, its line) to check against the vertex count at the end.
    let mut max_index: Option<(u32, usize, Option<usize>)> = None;
    for element in &header.elements {
        let roles: Vec<Role> = roles(element, path)?;
        let is_vertex = element.name == "vertex";
        let is_face = element.name == "face";
        // An element without properties takes no bytes: there is nothing to read, however
        // many items it declares (and counting up to a huge count would never end).
        if element.properties.is_empty() {
            continue;
        }
        // Never trust the count for allocation beyond what the data could hold: every item
        // takes at least `item_bytes`.
        let item_bytes: usize = element
            .properties
            .iter()
            .map(|p| match p {
                Property::Scalar(ty, _) | Property::List(ty, _, _) => src.min_bytes(*ty),
            })
            .sum();
        let capacity = element.count.min(body_len / item_bytes.max(1));
        if is_vertex {
            positions.reserve(capacity);
        } else if is_face {
            faces.reserve(capacity);
        }
        for item in 0..element.count {
            let mut p = [0.0f64; 3];
            let mut face = [0u32; 3];
            for (property, &role) in element.properties.iter().zip(&roles) {
                match property {
                    Property::Scalar(ty, _) => {
                        let x = src
                            .next(*ty)
                            .map_err(|e| read_error(src, e, element, item))?;
                        if let Role::Coordinate(k) = role {
                            p[k] = x;
                        }
                    }
                    Property::List(count_ty, item_ty, _) => {
                        let n = src
                            .next(*count_ty)
                            .map_err(|e| read_error(src, e, element, item))?;
                        if !(n >= 0.0 && n.fract() == 0.0) {
                            return Err(located(
                                src,
                                format!("{} {item}: invalid list length {n}", element.name),
                            ));
                        }
                        let n = n as usize;
                        if role != Role::Indices {
                            src.skip(*item_ty, n)
                                .map_err(|e| read_error(src, e, element, item))?;
                            continue;
                        }
                        if n != 3 {
                            return Err(located(
                                src,
                                format!(
                                    "face {item} has {n} vertices: only triangles are \
                                     supported (triangulate the mesh first)"
                                ),
                            ));
                        }
                        for slot in &mut face {
                            let v = src
                                .next(*item_ty)
                                .map_err(|e| read_error(src, e, element, item))?;
                            if !(v >= 0.0 && v.fract() == 0.0 && v <= u32::MAX as f64) {
                                return Err(located(
                                    src,
                                    format!("face {item} has an invalid vertex index {v}"),
                                ));
                            }
                            *slot = v as u32;
                            if max_index.is_none_or(|(m, _, _)| *slot > m) {
                                max_index = Some((*slot, item, src.line()));
                            }
                        }
                    }
                }
            }
            if is_vertex {
                if !p.iter().all(|x| x.is_finite()) {
                    return Err(located(
                        src,
                        format!("vertex {item} has a non-finite coordinate"),
                    ));
                }
                positions.push(p);
            } else if is_face {
                faces.push(face);
            }
        }
    }
    if let Some((m, face, line)) = max_index
        && m as usize >= positions.len()
    {
        let msg = format!(
            "face {face} uses vertex {m}, which is out of range (the file has {} vertices)",
            positions.len()
        );
        return Err(match line {
            Some(line) => parse_error(path, line, msg),
            None => format_error(path, &msg),
        });
    }
    if let Some(line) = src.trailing() {
        let msg = "data after the elements the header declares (is a count wrong?)";
        return Err(match line {
            Some(line) => parse_error(path, line, msg),
            None => format_error(path, msg),
        });
    }
    if faces.is_empty() {
        return Err(format_error(path, "no faces"));
    }
    Ok(TriMesh::new(positions, faces))
}

/// The role of every property of `element`; checks the vertex and face elements have what
/// the reader needs.
fn roles(element: &Element, path: &str) -> Result<Vec<Role>> {
    let props = &element.properties;
    let mut roles = vec![Role::Skip; props.len()];
    if element.name == "vertex" {
        for (k, axis) in ["x", "y", "z"].iter().enumerate() {
            let found = props.iter().position(|p| p.name() == *axis);
            match found.map(|i| (i, &props[i])) {
                Some((i, Property::Scalar(..))) => roles[i] = Role::Coordinate(k),
                Some((_, Property::List(..))) => {
                    return Err(format_error(
                        path,
                        &format!("PLY vertex property '{axis}' is a list, not a number"),
                    ));
                }
                None => {
                    return Err(format_error(
                        path,
                        &format!("PLY vertex element has no property '{axis}'"),
                    ));
                }
            }
        }
    } else if element.name == "face" {
        let found = props
            .iter()
            .position(|p| matches!(p, Property::List(..)) && p.name() == "vertex_indices")
            .or_else(|| {
                props
                    .iter()
                    .position(|p| matches!(p, Property::List(..)) && p.name() == "vertex_index")
            });
        match found {
            Some(i) => roles[i] = Role::Indices,
            None => {
                return Err(format_error(
                    path,
                    "PLY face element has no list property 'vertex_indices' (or 'vertex_index')",
                ));
            }
        }
    }
    Ok(roles)
}

impl std::fmt::Debug for ReadError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::End => write!(f, "End"),
            Self::Bad(t) => write!(f, "Bad({})", show(t)),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Error;

    #[test]
    fn data_beyond_the_declared_elements_is_an_error_naming_its_line() {
        let text = "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n\
                    property float z\nelement face 1\nproperty list uchar int vertex_indices\n\
                    end_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n3 0 2 1\n";
        match parse_ply(text.as_bytes(), "t.ply") {
            Err(Error::Parse { line, msg, .. }) => {
                assert_eq!(line, 14, "{msg}");
                assert!(msg.contains("after the elements"), "{msg}");
            }
            other => panic!("{other:?}"),
        }
    }
    use crate::io::test_util::data_dir;

    /// A value of a given PLY type, for building test files.
    #[derive(Clone, Copy)]
    enum V {
        I8(i8),
        U8(u8),
        I16(i16),
        U16(u16),
        I32(i32),
        U32(u32),
        F32(f32),
        F64(f64),
    }

    #[derive(Clone, Copy, PartialEq)]
    enum Enc {
        Ascii,
        Le,
        Be,
    }

    impl Enc {
        fn name(self) -> &'static str {
            match self {
                Enc::Ascii => "ascii",
                Enc::Le => "binary_little_endian",
                Enc::Be => "binary_big_endian",
            }
        }
    }

    const ALL: [Enc; 3] = [Enc::Ascii, Enc::Le, Enc::Be];

    /// A PLY file from header lines (between `format` and `end_header`) and items of values.
    fn build(enc: Enc, header: &str, items: &[Vec<V>]) -> Vec<u8> {
        let mut out = format!("ply\nformat {} 1.0\n{header}end_header\n", enc.name()).into_bytes();
        for item in items {
            let mut text = Vec::new();
            for &v in item {
                if enc == Enc::Ascii {
                    text.push(match v {
                        V::I8(x) => x.to_string(),
                        V::U8(x) => x.to_string(),
                        V::I16(x) => x.to_string(),
                        V::U16(x) => x.to_string(),
                        V::I32(x) => x.to_string(),
                        V::U32(x) => x.to_string(),
                        V::F32(x) => x.to_string(),
                        V::F64(x) => x.to_string(),
                    });
                    continue;
                }
                let le = enc == Enc::Le;
                macro_rules! bytes {
                    ($x:expr) => {
                        if le {
                            $x.to_le_bytes().to_vec()
                        } else {
                            $x.to_be_bytes().to_vec()
                        }
                    };
                }
                out.extend(match v {
                    V::I8(x) => bytes!(x),
                    V::U8(x) => bytes!(x),
                    V::I16(x) => bytes!(x),
                    V::U16(x) => bytes!(x),
                    V::I32(x) => bytes!(x),
                    V::U32(x) => bytes!(x),
                    V::F32(x) => bytes!(x),
                    V::F64(x) => bytes!(x),
                });
            }
            if enc == Enc::Ascii {
                out.extend(text.join(" ").into_bytes());
                out.push(b'\n');
            }
        }
        out
    }

    /// The test writer: `mesh` in any encoding, with the same layout as [`write_ply`].
    fn write_with(enc: Enc, mesh: &TriMesh) -> Vec<u8> {
        let header = format!(
            "element vertex {}\nproperty double x\nproperty double y\nproperty double z\n\
             element face {}\nproperty list uchar int vertex_indices\n",
            mesh.positions.len(),
            mesh.faces.len()
        );
        let mut items: Vec<Vec<V>> = mesh
            .positions
            .iter()
            .map(|p| p.map(V::F64).to_vec())
            .collect();
        for f in &mesh.faces {
            items.push(vec![
                V::U8(3),
                V::I32(f[0] as i32),
                V::I32(f[1] as i32),
                V::I32(f[2] as i32),
            ]);
        }
        build(enc, &header, &items)
    }

    fn sample() -> TriMesh {
        TriMesh::new(
            vec![
                [0.1, -2.0 / 3.0, 1e-300],
                [std::f64::consts::PI, 1e300, -0.0],
                [123_456_789.123_456_79, 5e-324, 7.0],
                [1.0, 2.0, 3.0],
            ],
            vec![[0, 1, 2], [2, 1, 3]],
        )
    }

    fn parse(data: &[u8]) -> Result<TriMesh> {
        parse_ply(data, "t.ply")
    }

    fn bits(m: &TriMesh) -> Vec<[u64; 3]> {
        m.positions.iter().map(|p| p.map(f64::to_bits)).collect()
    }

    #[test]
    fn round_trip_binary_little_endian() {
        let m = sample();
        let mut buf = Vec::new();
        write_ply(&mut buf, &m).unwrap();
        let back = parse(&buf).unwrap();
        assert_eq!(back.faces, m.faces);
        assert_eq!(bits(&back), bits(&m));
        // The writer and the test writer agree byte for byte (apart from the comment).
        let comment = b"comment written by demkit\n";
        let at = buf
            .windows(comment.len())
            .position(|w| w == comment)
            .unwrap();
        buf.drain(at..at + comment.len());
        assert_eq!(buf, write_with(Enc::Le, &m));
    }

    #[test]
    fn round_trip_all_encodings() {
        let m = sample();
        for enc in ALL {
            let back = parse(&write_with(enc, &m)).unwrap();
            assert_eq!(back.faces, m.faces, "{}", enc.name());
            assert_eq!(bits(&back), bits(&m), "{}", enc.name());
        }
    }

    /// A unit square with extra properties and elements of every kind to skip.
    fn decorated(enc: Enc, face_list: &str) -> Vec<u8> {
        let header = format!(
            "comment made by hand\nobj_info test\n\
             element material 1\nproperty list uchar float weights\nproperty uchar id\n\
             element vertex 4\nproperty float nx\nproperty float x\nproperty list ushort short \
             tags\nproperty float y\nproperty uchar red\nproperty float z\nproperty int8 flag\n\
             element face 2\nproperty uchar kind\nproperty {face_list}\n\
             property list uint uint16 extra\n\
             element edge 1\nproperty int vertex1\nproperty int vertex2\n"
        );
        let vertex = |x: f32, y: f32, tags: &[i16]| {
            let mut v = vec![V::F32(0.5), V::F32(x), V::U16(tags.len() as u16)];
            v.extend(tags.iter().map(|&t| V::I16(t)));
            v.extend([V::F32(y), V::U8(200), V::F32(0.0), V::I8(-1)]);
            v
        };
        let face = |f: [u32; 3]| {
            let mut v = vec![V::U8(7)];
            v.push(match face_list {
                l if l.contains("uint8 ") => V::U8(3),
                _ => V::I32(3),
            });
            for i in f {
                v.push(if face_list.ends_with("uint16 vertex_index") {
                    V::U16(i as u16)
                } else {
                    V::U32(i)
                });
            }
            v.extend([V::U32(2), V::U16(9), V::U16(9)]);
            v
        };
        let items = vec![
            vec![V::U8(2), V::F32(1.0), V::F32(2.0), V::U8(5)],
            vertex(0.0, 0.0, &[]),
            vertex(1.0, 0.0, &[1, 2, 3]),
            vertex(1.0, 1.0, &[4]),
            vertex(0.0, 1.0, &[]),
            face([0, 1, 2]),
            face([0, 2, 3]),
            vec![V::I32(0), V::I32(1)],
        ];
        build(enc, &header, &items)
    }

    #[test]
    fn skips_other_properties_and_elements() {
        let square = TriMesh::new(
            vec![[0., 0., 0.], [1., 0., 0.], [1., 1., 0.], [0., 1., 0.]],
            vec![[0, 1, 2], [0, 2, 3]],
        );
        for enc in ALL {
            for list in [
                "list int uint vertex_indices",
                "list uint8 uint16 vertex_index",
            ] {
                let m = parse(&decorated(enc, list)).unwrap_or_else(|e| panic!("{list}: {e}"));
                assert_eq!(m, square, "{} {list}", enc.name());
            }
        }
    }

    #[test]
    fn crlf_header_and_ascii_body() {
        let text = "ply\r\nformat ascii 1.0\r\nelement vertex 3\r\nproperty float x\r\n\
                    property float y\r\nproperty float z\r\nelement face 1\r\n\
                    property list uchar int vertex_indices\r\nend_header\r\n\
                    0 0 0\r\n1 0 0\r\n0 1 0\r\n3 0 1 2\r\n";
        assert_eq!(parse(text.as_bytes()).unwrap().faces, vec![[0, 1, 2]]);
    }

    fn format_msg(r: Result<TriMesh>) -> String {
        match r {
            Err(Error::Format { msg, .. }) => msg,
            other => panic!("expected a format error, got {other:?}"),
        }
    }

    fn parse_msg(r: Result<TriMesh>) -> (usize, String) {
        match r {
            Err(Error::Parse { line, msg, .. }) => (line, msg),
            other => panic!("expected a parse error, got {other:?}"),
        }
    }

    #[test]
    fn truncated_binary() {
        for enc in [Enc::Le, Enc::Be] {
            let full = write_with(enc, &sample());
            for (cut, place) in [
                (1, "face 1 of 2"),
                (13, "face 1 of 2"),
                (14, "face 0 of 2"),
                (60, "vertex 2 of 4"),
            ] {
                let msg = format_msg(parse(&full[..full.len() - cut]));
                assert_eq!(msg, format!("file is truncated: it ends in {place}"));
            }
            let header_end = full.windows(11).position(|w| w == b"end_header\n").unwrap() + 11;
            let msg = format_msg(parse(&full[..header_end + 30]));
            assert!(msg.contains("vertex 1 of 4"), "{msg}");
        }
        let ascii = write_with(Enc::Ascii, &sample());
        let msg = format_msg(parse(&ascii[..ascii.len() - 5]));
        assert_eq!(msg, "file is truncated: it ends in face 1 of 2");
    }

    #[test]
    fn quads_are_rejected_naming_the_face() {
        let header = "element vertex 4\nproperty float x\nproperty float y\nproperty float z\n\
                      element face 2\nproperty list uchar int vertex_indices\n";
        let mut items: Vec<Vec<V>> = (0..4)
            .map(|i| vec![V::F32(i as f32), V::F32(0.5 * i as f32), V::F32(0.0)])
            .collect();
        items.push(vec![V::U8(3), V::I32(0), V::I32(1), V::I32(2)]);
        items.push(vec![V::U8(4), V::I32(0), V::I32(1), V::I32(2), V::I32(3)]);
        let expected =
            "face 1 has 4 vertices: only triangles are supported (triangulate the mesh first)";
        assert_eq!(format_msg(parse(&build(Enc::Le, header, &items))), expected);
        assert_eq!(format_msg(parse(&build(Enc::Be, header, &items))), expected);
        assert_eq!(
            parse_msg(parse(&build(Enc::Ascii, header, &items))),
            (15, expected.to_string())
        );
    }

    #[test]
    fn bad_indices_and_coordinates() {
        let header = "element vertex 3\nproperty float x\nproperty float y\nproperty float z\n\
                      element face 1\nproperty list uchar int vertex_indices\n";
        let verts: Vec<Vec<V>> = (0..3)
            .map(|i| vec![V::F32(i as f32), V::F32((i % 2) as f32), V::F32(0.0)])
            .collect();
        let with_face = |f: [i32; 3]| {
            let mut items = verts.clone();
            items.push(vec![V::U8(3), V::I32(f[0]), V::I32(f[1]), V::I32(f[2])]);
            items
        };
        let msg = format_msg(parse(&build(Enc::Le, header, &with_face([0, 1, 3]))));
        assert_eq!(
            msg,
            "face 0 uses vertex 3, which is out of range (the file has 3 vertices)"
        );
        let (line, msg) = parse_msg(parse(&build(Enc::Ascii, header, &with_face([0, 5, 1]))));
        assert_eq!(line, 13);
        assert!(msg.contains("vertex 5, which is out of range"), "{msg}");
        let msg = format_msg(parse(&build(Enc::Be, header, &with_face([0, -1, 1]))));
        assert_eq!(msg, "face 0 has an invalid vertex index -1");

        let mut items = with_face([0, 1, 2]);
        items[1][1] = V::F32(f32::NAN);
        assert_eq!(
            format_msg(parse(&build(Enc::Le, header, &items))),
            "vertex 1 has a non-finite coordinate"
        );
        let (line, msg) = parse_msg(parse(&build(Enc::Ascii, header, &items)));
        assert_eq!(
            (line, msg.as_str()),
            (11, "vertex 1 has a non-finite coordinate")
        );

        let text = String::from_utf8(build(Enc::Ascii, header, &with_face([0, 1, 2])))
            .unwrap()
            .replace("\n2 0 0\n", "\n2 abc 0\n");
        let (line, msg) = parse_msg(parse(text.as_bytes()));
        assert_eq!((line, msg.as_str()), (12, "cannot read 'abc' as a number"));
    }

    #[test]
    fn malformed_headers() {
        assert!(format_msg(parse(b"plx\n")).contains("not a PLY file"));
        assert!(
            format_msg(parse(b"ply\nformat ascii 1.0\nelement vertex 0\n")).contains("end_header")
        );
        assert!(format_msg(parse(b"ply\nelement vertex 0\nend_header\n")).contains("'format'"));
        let (line, msg) = parse_msg(parse(b"ply\nformat ascii 2.0\nend_header\n"));
        assert_eq!(line, 2);
        assert!(msg.contains("version 1.0"), "{msg}");
        let (line, msg) = parse_msg(parse(
            b"ply\nformat ascii 1.0\nelement vertex 1\nproperty float128 x\nend_header\n",
        ));
        assert_eq!(line, 4);
        assert!(msg.contains("'float128'"), "{msg}");
        let (line, _) = parse_msg(parse(
            b"ply\nformat ascii 1.0\nproperty float x\nend_header\n",
        ));
        assert_eq!(line, 3);
        let (line, _) = parse_msg(parse(
            b"ply\nformat ascii 1.0\nelement vertex many\nend_header\n",
        ));
        assert_eq!(line, 3);
        let (line, _) = parse_msg(parse(b"ply\nformat ascii 1.0\nbogus\nend_header\n"));
        assert_eq!(line, 3);
        let msg = format_msg(parse(
            b"ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nend_header\n0 0\n",
        ));
        assert!(msg.contains("no property 'z'"), "{msg}");
        let msg = format_msg(parse(
            b"ply\nformat ascii 1.0\nelement vertex 0\nproperty float x\nproperty float y\n\
              property float z\nelement face 0\nproperty int vertex_indices\nend_header\n",
        ));
        assert!(msg.contains("no list property 'vertex_indices'"), "{msg}");
        let msg = format_msg(parse(
            b"ply\nformat ascii 1.0\nelement face 0\nend_header\n",
        ));
        assert!(msg.contains("one 'vertex' element"), "{msg}");
    }

    #[test]
    fn huge_counts_do_not_allocate() {
        let data = b"ply\nformat binary_little_endian 1.0\nelement vertex 4000000000\n\
                     property float x\nproperty float y\nproperty float z\nelement face 1\n\
                     property list uchar int vertex_indices\nend_header\n";
        assert!(format_msg(parse(data)).starts_with("file is truncated"));
    }

    #[test]
    #[ignore = "needs real meshes (DEMKIT_DATA)"]
    fn real_mesh_round_trip() {
        let m = crate::io::read_mesh(&data_dir().join("open/human_face.obj")).unwrap();
        let mut buf = Vec::new();
        write_ply(&mut buf, &m).unwrap();
        assert_eq!(parse(&buf).unwrap(), m);
        assert_eq!(parse(&write_with(Enc::Ascii, &m)).unwrap(), m);
    }
}
