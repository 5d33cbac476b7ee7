//! Stanford PLY 1.0: ascii, binary little-endian and binary big-endian.
//!
//! Reads the `vertex` element's `x`, `y`, `z` (any scalar type) and the `face` element's list
//! `vertex_indices` (or `vertex_index`, any count and index types); every other property and
//! element is skipped, list properties included. Writes binary little-endian.

mod body;
mod header;
mod source;
#[cfg(test)]
mod tests;
mod write;

pub use write::write_ply;

use crate::{Result, TriMesh};
use body::read_body;
use header::{Encoding, Header};
use source::{AsciiSource, BinarySource};

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
