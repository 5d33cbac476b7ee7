//! Streams of scalar values: ascii tokens or binary data in either byte order.

use super::header::Scalar;
use crate::io::{parse_f64, show};

/// Why a value could not be read.
pub(super) enum ReadError {
    /// The data ended.
    End,
    /// (ascii) a token that is not a number.
    Bad(Vec<u8>),
}

/// A stream of scalar values (ascii tokens or binary data).
pub(super) trait Source {
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

/// Whitespace-separated ascii tokens, tracking lines.
pub(super) struct AsciiSource<'a> {
    pub(super) data: &'a [u8],
    pub(super) pos: usize,
    /// Line at `pos`.
    pub(super) line: usize,
    /// Line of the last token returned.
    pub(super) token_line: usize,
}

impl AsciiSource<'_> {
    /// Moves past whitespace, counting the lines it ends.
    fn skip_whitespace(&mut self) {
        let d = self.data;
        while self.pos < d.len() && d[self.pos].is_ascii_whitespace() {
            if d[self.pos] == b'\n' {
                self.line += 1;
            }
            self.pos += 1;
        }
    }
}

impl Source for AsciiSource<'_> {
    fn next(&mut self, _ty: Scalar) -> std::result::Result<f64, ReadError> {
        self.skip_whitespace();
        let d = self.data;
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
        self.skip_whitespace();
        (self.pos < self.data.len()).then_some(Some(self.line))
    }
}

/// Binary data in either byte order.
pub(super) struct BinarySource<'a> {
    pub(super) data: &'a [u8],
    pub(super) pos: usize,
    pub(super) big_endian: bool,
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

impl std::fmt::Debug for ReadError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::End => write!(f, "End"),
            Self::Bad(t) => write!(f, "Bad({})", show(t)),
        }
    }
}
