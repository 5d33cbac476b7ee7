//! The header: format, elements and their properties.

use crate::Result;
use crate::io::{Lines, format_error, parse_error, parse_int, show, tokens};

/// PLY scalar types.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Scalar {
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

    pub(super) fn size(self) -> usize {
        match self {
            Self::I8 | Self::U8 => 1,
            Self::I16 | Self::U16 => 2,
            Self::I32 | Self::U32 | Self::F32 => 4,
            Self::F64 => 8,
        }
    }
}

/// A property of an element: a scalar or a list (count type, item type), with its name.
#[derive(Debug)]
pub(super) enum Property {
    Scalar(Scalar, String),
    List(Scalar, Scalar, String),
}

impl Property {
    pub(super) fn name(&self) -> &str {
        match self {
            Self::Scalar(_, n) | Self::List(_, _, n) => n,
        }
    }
}

/// An element of the header: its name, item count and properties.
#[derive(Debug)]
pub(super) struct Element {
    pub(super) name: String,
    pub(super) count: usize,
    pub(super) properties: Vec<Property>,
}

/// How the body is encoded.
#[derive(Debug, Clone, Copy)]
pub(super) enum Encoding {
    Ascii,
    Binary { big_endian: bool },
}

/// A parsed header.
#[derive(Debug)]
pub(super) struct Header {
    pub(super) encoding: Encoding,
    pub(super) elements: Vec<Element>,
    /// Byte offset of the body (just after the `end_header` line).
    pub(super) body_start: usize,
    /// Line number of the body's first line.
    pub(super) body_first_line: usize,
}

impl Header {
    /// Parses the header at the start of `data`; `path` only labels error messages.
    pub(super) fn parse(data: &[u8], path: &str) -> Result<Self> {
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
                        [_, count] => parse_int(count).and_then(|c| usize::try_from(c).ok()),
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
