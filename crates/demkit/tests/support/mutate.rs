//! Mutations of files: damage of the kinds real files suffer (cut short, lines lost or
//! repeated, numbers replaced by extreme or unreadable ones, bytes flipped), as proptest
//! strategies.

#![allow(dead_code)]

use proptest::prelude::*;
use proptest::sample::Index;

/// Tokens a number or keyword may be replaced with: extremes, non-finite values, values out of
/// every integer type's range, garbage, and keywords of the formats in the wrong place.
pub const TOKENS: &[&str] = &[
    "nan",
    "NaN",
    "inf",
    "-inf",
    "infinity",
    "1e309",
    "-1e309",
    "1e308",
    "-1e308",
    "4.9e-324",
    "-1e-320",
    "0",
    "-0",
    "-1",
    "1",
    "2",
    "3",
    "4",
    "255",
    "256",
    "65536",
    "2147483647",
    "2147483648",
    "-2147483649",
    "4294967295",
    "4294967296",
    "18446744073709551615",
    "99999999999999999999999",
    "1.5",
    "-3.25",
    "1e3",
    "0x10",
    "abc",
    "",
    "#",
    "/",
    "1/2/3",
    "1//2",
    "-1/-1/-1",
    "\u{feff}",
    "\u{e9}",
    "\0",
    "ply",
    "format",
    "ascii",
    "binary_little_endian",
    "1.0",
    "element",
    "property",
    "list",
    "uchar",
    "int",
    "double",
    "vertex",
    "face",
    "vertex_indices",
    "end_header",
    "OFF",
    "COFF",
    "4OFF",
    "BINARY",
    "solid",
    "facet",
    "normal",
    "outer",
    "loop",
    "endloop",
    "endfacet",
    "endsolid",
    "v",
    "f",
    "vt",
];

/// Numbers a coordinate or index may be replaced with, mild and extreme: files damaged by
/// these still read, so what follows the reader (validation, the methods) sees them.
pub const NUMBERS: &[&str] = &[
    "0",
    "-0",
    "1",
    "2",
    "3",
    "0.5",
    "-0.5",
    "1.5",
    "-3.25",
    "1e3",
    "-1e3",
    "1e-7",
    "1e-300",
    "4.9e-324",
    "1e150",
    "1e300",
    "-1e300",
    "1.7976931348623157e308",
];

/// Lines that may be inserted: statements of every format, some of them malformed.
pub const LINES: &[&str] = &[
    "",
    "# a comment",
    "v 0 0 0",
    "v 1e308 -1e308 1e308",
    "v nan 0 0",
    "v 1 2",
    "f 1 2 3",
    "f 1 2 3 4",
    "f -1 -2 -3",
    "f 0 1 2",
    "f 4294967296 1 2",
    "f 1/1/1 2//2 3/3",
    "3 0 1 2",
    "4 0 1 2 3",
    "3 0 0 0",
    "3 -1 0 1",
    "0 0 0",
    "1 2 3 4 5 6",
    "OFF",
    "OFF BINARY",
    "element vertex 3",
    "element face 4294967296",
    "element face 1000000000000",
    "element junk 1000000000",
    "property float x",
    "property list uchar int vertex_indices",
    "property list int int vertex_indices",
    "property list uchar float junk",
    "end_header",
    "format ascii 1.0",
    "format binary_big_endian 1.0",
    "solid x",
    "facet normal 0 0 1",
    "outer loop",
    "vertex 0 0 0",
    "vertex 1 0 0",
    "vertex inf 0 0",
    "endloop",
    "endfacet",
    "endsolid x",
];

/// 32-bit words a binary position may be overwritten with: counts, and the bit patterns of
/// NaN, ±∞, the largest and the smallest `f32` values.
pub const WORDS: &[u32] = &[
    0,
    1,
    3,
    4,
    255,
    0xFFFF,
    0x7FFF_FFFF,
    0x8000_0000,
    0xFFFF_FFFF,
    0x7FC0_0000,
    0x7F80_0000,
    0xFF80_0000,
    0x7F7F_FFFF,
    0x0000_0001,
    0x4040_0000,
];

/// One change to a file.
#[derive(Debug, Clone)]
pub enum Mutation {
    /// Cut the file at this fraction of its length.
    Truncate(Index),
    /// Delete a line.
    DeleteLine(Index),
    /// Repeat a line.
    DuplicateLine(Index),
    /// Exchange two lines.
    SwapLines(Index, Index),
    /// Insert one of [`LINES`] before a line.
    InsertLine(Index, &'static str),
    /// Replace a whitespace-separated token by one of [`TOKENS`].
    ReplaceToken(Index, &'static str),
    /// Flip some bits of a byte.
    FlipByte(Index, u8),
    /// Overwrite four bytes with one of [`WORDS`] (little- or big-endian).
    SetWord(Index, u32, bool),
    /// Delete a run of bytes.
    DeleteBytes(Index, u8),
}

/// Any [`Mutation`].
pub fn mutation() -> impl Strategy<Value = Mutation> {
    let index = any::<Index>;
    prop_oneof![
        index().prop_map(Mutation::Truncate),
        index().prop_map(Mutation::DeleteLine),
        index().prop_map(Mutation::DuplicateLine),
        (index(), index()).prop_map(|(a, b)| Mutation::SwapLines(a, b)),
        (index(), prop::sample::select(LINES)).prop_map(|(i, l)| Mutation::InsertLine(i, l)),
        (index(), prop::sample::select(TOKENS)).prop_map(|(i, t)| Mutation::ReplaceToken(i, t)),
        (index(), 1u8..=255).prop_map(|(i, m)| Mutation::FlipByte(i, m)),
        (index(), prop::sample::select(WORDS), any::<bool>())
            .prop_map(|(i, w, big)| Mutation::SetWord(i, w, big)),
        (index(), 1u8..=16).prop_map(|(i, n)| Mutation::DeleteBytes(i, n)),
    ]
}

/// The byte ranges of the lines of `data` (without their `\n`).
fn line_ranges(data: &[u8]) -> Vec<(usize, usize)> {
    let mut out = Vec::new();
    let mut start = 0;
    for (i, &b) in data.iter().enumerate() {
        if b == b'\n' {
            out.push((start, i));
            start = i + 1;
        }
    }
    if start < data.len() {
        out.push((start, data.len()));
    }
    out
}

/// The byte ranges of the whitespace-separated tokens of `data`.
fn token_ranges(data: &[u8]) -> Vec<(usize, usize)> {
    let mut out = Vec::new();
    let mut start = None;
    for (i, &b) in data.iter().enumerate() {
        match (b.is_ascii_whitespace(), start) {
            (true, Some(s)) => {
                out.push((s, i));
                start = None;
            }
            (false, None) => start = Some(i),
            _ => {}
        }
    }
    if let Some(s) = start {
        out.push((s, data.len()));
    }
    out
}

/// Applies `m` to `data` (a no-op where the file is too short for it).
pub fn apply(data: &mut Vec<u8>, m: &Mutation) {
    match m {
        Mutation::Truncate(i) => {
            let at = i.index(data.len() + 1);
            data.truncate(at);
        }
        Mutation::DeleteLine(i) => {
            let lines = line_ranges(data);
            if !lines.is_empty() {
                let (s, e) = lines[i.index(lines.len())];
                let e = (e + 1).min(data.len());
                data.drain(s..e);
            }
        }
        Mutation::DuplicateLine(i) => {
            let lines = line_ranges(data);
            if !lines.is_empty() {
                let (s, e) = lines[i.index(lines.len())];
                let mut copy = data[s..e].to_vec();
                copy.push(b'\n');
                data.splice(s..s, copy);
            }
        }
        Mutation::SwapLines(a, b) => {
            let lines = line_ranges(data);
            if lines.len() >= 2 {
                let (mut x, mut y) = (a.index(lines.len()), b.index(lines.len()));
                if x > y {
                    std::mem::swap(&mut x, &mut y);
                }
                if x != y {
                    let (xs, xe) = lines[x];
                    let (ys, ye) = lines[y];
                    let mut out = data[..xs].to_vec();
                    out.extend_from_slice(&data[ys..ye]);
                    out.extend_from_slice(&data[xe..ys]);
                    out.extend_from_slice(&data[xs..xe]);
                    out.extend_from_slice(&data[ye..]);
                    *data = out;
                }
            }
        }
        Mutation::InsertLine(i, line) => {
            let lines = line_ranges(data);
            let at = if lines.is_empty() {
                0
            } else {
                lines[i.index(lines.len())].0
            };
            let mut text = line.as_bytes().to_vec();
            text.push(b'\n');
            data.splice(at..at, text);
        }
        Mutation::ReplaceToken(i, token) => {
            let tokens = token_ranges(data);
            if !tokens.is_empty() {
                let (s, e) = tokens[i.index(tokens.len())];
                data.splice(s..e, token.as_bytes().iter().copied());
            }
        }
        Mutation::FlipByte(i, mask) => {
            if !data.is_empty() {
                let at = i.index(data.len());
                data[at] ^= mask;
            }
        }
        Mutation::SetWord(i, word, big) => {
            if data.len() >= 4 {
                let at = i.index(data.len() - 3);
                let bytes = if *big {
                    word.to_be_bytes()
                } else {
                    word.to_le_bytes()
                };
                data[at..at + 4].copy_from_slice(&bytes);
            }
        }
        Mutation::DeleteBytes(i, n) => {
            if !data.is_empty() {
                let at = i.index(data.len());
                let end = (at + *n as usize).min(data.len());
                data.drain(at..end);
            }
        }
    }
}
