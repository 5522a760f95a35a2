//! A bounds-checked reader over a binary record file's bytes: every read
//! past the end, and every count larger than the bytes left, is a
//! [`FormatError`] naming the byte offset, never a panic or an allocation
//! sized by an untrusted count.

use super::{Format, FormatError};

/// A position in a binary file's bytes, reading little- or big-endian values.
#[derive(Debug, Clone)]
pub(crate) struct Cursor<'a> {
    bytes: &'a [u8],
    pos: usize,
    format: Format,
    big_endian: bool,
}

macro_rules! read_number {
    ($name:ident, $ty:ty) => {
        /// Reads one value in the cursor's byte order; `what` names it in errors.
        pub(crate) fn $name(&mut self, what: &str) -> Result<$ty, FormatError> {
            let raw = self.take(std::mem::size_of::<$ty>(), what)?;
            let mut array = [0u8; std::mem::size_of::<$ty>()];
            array.copy_from_slice(raw);
            Ok(if self.big_endian {
                <$ty>::from_be_bytes(array)
            } else {
                <$ty>::from_le_bytes(array)
            })
        }
    };
}

impl<'a> Cursor<'a> {
    /// A little-endian cursor at the start of `bytes`.
    pub(crate) fn new(bytes: &'a [u8], format: Format) -> Self {
        Self {
            bytes,
            pos: 0,
            format,
            big_endian: false,
        }
    }

    /// Sets the byte order of the reads that follow.
    pub(crate) fn set_big_endian(&mut self, big_endian: bool) {
        self.big_endian = big_endian;
    }

    /// Whether reads are big-endian.
    pub(crate) fn big_endian(&self) -> bool {
        self.big_endian
    }

    /// The offset of the next read.
    pub(crate) fn pos(&self) -> usize {
        self.pos
    }

    /// Bytes left after the position.
    pub(crate) fn remaining(&self) -> usize {
        self.bytes.len() - self.pos
    }

    /// Moves to `pos`, which must lie within the file (its end included).
    pub(crate) fn seek(&mut self, pos: usize, what: &str) -> Result<(), FormatError> {
        if pos > self.bytes.len() {
            return Err(self.error(
                format!("{what} within the file's {} bytes", self.bytes.len()),
                format!("offset {pos}"),
            ));
        }
        self.pos = pos;
        Ok(())
    }

    /// The next `n` bytes; `what` names them in the error when fewer are left.
    pub(crate) fn take(&mut self, n: usize, what: &str) -> Result<&'a [u8], FormatError> {
        if n > self.remaining() {
            return Err(self.error(
                format!("{n} bytes of {what}"),
                format!("{} bytes before the end of the file", self.remaining()),
            ));
        }
        let out = &self.bytes[self.pos..self.pos + n];
        self.pos += n;
        Ok(out)
    }

    read_number!(u32, u32);
    read_number!(u64, u64);
    read_number!(f32, f32);
    read_number!(f64, f64);

    /// An error at the cursor's position.
    pub(crate) fn error(
        &self,
        expected: impl Into<String>,
        found: impl Into<String>,
    ) -> FormatError {
        FormatError {
            format: self.format,
            at: format!("byte {}", self.pos),
            expected: expected.into(),
            found: found.into(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reads_past_the_end_are_errors_naming_the_offset() {
        let mut c = Cursor::new(&[1, 0, 0, 0, 2], Format::Tdms);
        assert_eq!(c.u32("a count").unwrap(), 1);
        let e = c.u32("a count").unwrap_err();
        assert_eq!(e.at, "byte 4");
        assert!(e.expected.contains("4 bytes of a count"), "{e}");
        c.set_big_endian(true);
        assert!(c.u32("a flag").is_err());
        assert_eq!(c.take(1, "a flag").unwrap(), [2]);
        assert!(c.seek(6, "a segment").is_err());
    }
}
