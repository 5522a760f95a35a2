//! The NI TDMS reader: a [`Record`] from the segments a LabVIEW, DIAdem or
//! DAQmx logger writes, as "TDMS File Format Internal Structure" describes
//! them.
//!
//! A file is a run of segments. Each starts with a 28-byte lead-in (tag
//! `TDSm`, a table of contents, version 4712 or 4713, the offsets of the next
//! segment and of the raw data, both counted from the lead-in's end), then
//! optional metadata (objects `/`, `/'group'` and `/'group'/'channel'`, each
//! with its raw data index and properties), then raw data written as one or
//! more chunks of the same layout, contiguous or interleaved, little- or
//! big-endian. The object list and each object's index carry over from one
//! segment to the next unless a segment starts a new list.
//!
//! Every channel of integer or float values becomes a [`Channel`] named
//! `group/channel`, its values appended across segments and converted to
//! `f64`. Its unit is the `unit_string` property; its timing comes from the
//! `wf_increment` and `wf_start_offset` properties (seconds) when the increment
//! is positive and `wf_xunit_string` is `s` or absent. Strings, booleans,
//! timestamps, complex values and DAQmx raw data are skipped. A segment cut
//! short by a crash (next-segment offset all ones) is read as far as its
//! chunks are complete.

use std::collections::HashMap;

use super::{Channel, Format, FormatError, Record, Waveform, bytes::Cursor};

/// Bytes in a segment's lead-in.
const LEAD_IN_BYTES: usize = 28;
/// Table-of-contents bit: the segment holds metadata.
const TOC_META_DATA: u32 = 1 << 1;
/// Table-of-contents bit: the segment's metadata starts a new object list.
const TOC_NEW_OBJ_LIST: u32 = 1 << 2;
/// Table-of-contents bit: the segment holds raw data.
const TOC_RAW_DATA: u32 = 1 << 3;
/// Table-of-contents bit: the raw data is interleaved (one value of each
/// channel after another) rather than contiguous.
const TOC_INTERLEAVED_DATA: u32 = 1 << 5;
/// Table-of-contents bit: the segment's numbers (lead-in after the table of
/// contents, metadata, raw data) are big-endian.
const TOC_BIG_ENDIAN: u32 = 1 << 6;
/// Table-of-contents bit: the segment holds DAQmx raw data.
const TOC_DAQMX_RAW_DATA: u32 = 1 << 7;
/// Raw data index: the object has no raw data in this segment.
const NO_RAW_DATA: u32 = 0xFFFF_FFFF;
/// Raw data index: the object's index is the one it had before.
const SAME_INDEX: u32 = 0;
/// Raw data index headers of DAQmx data: format-changing scalers, and
/// digital-line scalers (as written, and as the specification gives them).
const DAQMX_INDEXES: [u32; 3] = [0x1269, 0x126A, 0x1369];
/// Next-segment offset of a segment its writer never finished.
const CUT_SHORT: u64 = u64::MAX;
/// Characters of a path quoted in an error.
const QUOTE_CHARS: usize = 60;

/// Whether `bytes` start as a TDMS file does (the segment tag `TDSm`).
pub fn is_tdms(bytes: &[u8]) -> bool {
    bytes.starts_with(b"TDSm")
}

/// Reads a TDMS file's numeric channels, in the order the file first names
/// them.
pub fn read(bytes: &[u8]) -> Result<Record, FormatError> {
    let mut file = Reader::default();
    let mut cursor = Cursor::new(bytes, Format::Tdms);
    let mut number = 0usize;
    // A segment cut short runs to the end of the file, so nothing follows it.
    while cursor.remaining() > 0 {
        number += 1;
        file.segment(&mut cursor, number)?;
    }
    file.into_record()
}

/// A TDMS data type, of raw data or of a property value.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum DataType {
    I8,
    I16,
    I32,
    I64,
    U8,
    U16,
    U32,
    U64,
    F32,
    F64,
    Text,
    /// Values of this many bytes that are not read: void (0), booleans (1),
    /// complex numbers (8, 16) and timestamps (16).
    Skipped(u64),
    DaqMx,
}

impl DataType {
    /// The type a data type code stands for, if this reader knows it.
    fn from_code(code: u32) -> Option<Self> {
        Some(match code {
            1 => Self::I8,
            2 => Self::I16,
            3 => Self::I32,
            4 => Self::I64,
            5 => Self::U8,
            6 => Self::U16,
            7 => Self::U32,
            8 => Self::U64,
            // Floats, and floats with a unit (the same bytes).
            9 | 0x19 => Self::F32,
            10 | 0x1A => Self::F64,
            0x20 => Self::Text,
            0 => Self::Skipped(0),
            0x21 => Self::Skipped(1),
            0x08_000C => Self::Skipped(8),
            0x44 | 0x10_000D => Self::Skipped(16),
            0xFFFF_FFFF => Self::DaqMx,
            _ => return None,
        })
    }

    /// Bytes per value; `None` for strings (their sizes vary) and DAQmx data.
    fn size(self) -> Option<u64> {
        Some(match self {
            Self::I8 | Self::U8 => 1,
            Self::I16 | Self::U16 => 2,
            Self::I32 | Self::U32 | Self::F32 => 4,
            Self::I64 | Self::U64 | Self::F64 => 8,
            Self::Skipped(size) => size,
            Self::Text | Self::DaqMx => return None,
        })
    }

    /// Whether values of this type become a channel.
    fn is_numeric(self) -> bool {
        !matches!(self, Self::Text | Self::Skipped(_) | Self::DaqMx)
    }
}

/// Appends the values in `raw` (whole values of a numeric `ty`) to `out`.
fn decode(raw: &[u8], ty: DataType, big_endian: bool, out: &mut Vec<f64>) {
    macro_rules! push_all {
        ($t:ty) => {
            for bytes in raw.chunks_exact(std::mem::size_of::<$t>()) {
                if let Ok(array) = bytes.try_into() {
                    let value = if big_endian {
                        <$t>::from_be_bytes(array)
                    } else {
                        <$t>::from_le_bytes(array)
                    };
                    // Integers past 2^53 round to the nearest f64, as intended.
                    out.push(value as f64);
                }
            }
        };
    }
    match ty {
        DataType::I8 => push_all!(i8),
        DataType::I16 => push_all!(i16),
        DataType::I32 => push_all!(i32),
        DataType::I64 => push_all!(i64),
        DataType::U8 => push_all!(u8),
        DataType::U16 => push_all!(u16),
        DataType::U32 => push_all!(u32),
        DataType::U64 => push_all!(u64),
        DataType::F32 => push_all!(f32),
        DataType::F64 => push_all!(f64),
        _ => {}
    }
}

/// An object's raw data index: what it holds in each chunk of a segment.
#[derive(Debug, Clone, Copy)]
enum Index {
    /// `count` values of `ty`, `bytes` bytes in all.
    Values {
        ty: DataType,
        count: u64,
        bytes: u64,
    },
    /// DAQmx raw data, which this reader does not read.
    DaqMx,
}

/// A property value, as far as this reader uses it.
enum Property {
    Number(f64),
    Text(String),
    Other,
}

/// One object of the file (root, group or channel), across its segments.
#[derive(Debug, Default)]
struct Object {
    /// `group/channel` for a channel; `None` for the root and groups.
    name: Option<String>,
    /// The `unit_string` property, when not empty.
    unit: Option<String>,
    /// The `wf_increment` property (s).
    increment: Option<f64>,
    /// The `wf_start_offset` property (s).
    start: Option<f64>,
    /// The `wf_xunit_string` property.
    x_unit: Option<String>,
    /// Whether it has had numeric raw data.
    numeric: bool,
    /// Its values so far.
    values: Vec<f64>,
    /// Its last raw data index that had data.
    index: Option<Index>,
    /// Its place in the current object list, if it is on it.
    slot: Option<usize>,
}

impl Object {
    /// Takes note of a property the reader uses; others are skipped.
    fn set(&mut self, name: &str, value: Property) {
        match (name, value) {
            ("unit_string", Property::Text(unit)) => {
                self.unit = Some(unit).filter(|u| !u.trim().is_empty());
            }
            ("wf_increment", Property::Number(x)) => self.increment = Some(x),
            ("wf_start_offset", Property::Number(x)) => self.start = Some(x),
            ("wf_xunit_string", Property::Text(unit)) => self.x_unit = Some(unit),
            _ => {}
        }
    }

    /// The sample timing its waveform properties state, in seconds.
    fn timing(&self) -> Option<Waveform> {
        let increment = self.increment.filter(|x| x.is_finite() && *x > 0.0)?;
        let x_unit = self.x_unit.as_deref().map(str::trim).unwrap_or("");
        if !(x_unit.is_empty() || x_unit == "s") {
            return None;
        }
        let start = self.start.unwrap_or(0.0);
        start.is_finite().then_some(Waveform { start, increment })
    }
}

/// The state carried from segment to segment.
#[derive(Default)]
struct Reader {
    objects: Vec<Object>,
    by_path: HashMap<String, usize>,
    /// The current object list: each object and its index in this segment
    /// (`None`: no raw data).
    list: Vec<(usize, Option<Index>)>,
    /// Whether DAQmx raw data was skipped.
    daqmx: bool,
}

/// An error at `at` (see [`FormatError::at`]).
fn error(
    at: impl Into<String>,
    expected: impl Into<String>,
    found: impl Into<String>,
) -> FormatError {
    FormatError {
        format: Format::Tdms,
        at: at.into(),
        expected: expected.into(),
        found: found.into(),
    }
}

/// A path or name as quoted in an error: at most [`QUOTE_CHARS`] characters.
fn quote(text: &str) -> String {
    let mut out: String = text.chars().take(QUOTE_CHARS).collect();
    if text.chars().nth(QUOTE_CHARS).is_some() {
        out.push('…');
    }
    format!("{out:?}")
}

/// Reads a string: its byte length (`u32`), then its UTF-8 bytes.
fn string(c: &mut Cursor, what: &str) -> Result<String, FormatError> {
    let length = c.u32(what)?;
    let raw = c.take(usize::try_from(length).unwrap_or(usize::MAX), what)?;
    Ok(String::from_utf8_lossy(raw).into_owned())
}

/// The names in an object path: none for the root `/`, then the group's and
/// the channel's, each quoted with `'` and with `''` standing for a quote.
fn path_names(path: &str) -> Option<Vec<String>> {
    if path == "/" {
        return Some(Vec::new());
    }
    let mut names = Vec::new();
    let mut chars = path.chars().peekable();
    while let Some(slash) = chars.next() {
        if slash != '/' || chars.next() != Some('\'') {
            return None;
        }
        let mut name = String::new();
        loop {
            match chars.next()? {
                '\'' if chars.peek() == Some(&'\'') => {
                    chars.next();
                    name.push('\'');
                }
                '\'' => break,
                other => name.push(other),
            }
        }
        names.push(name);
    }
    (!names.is_empty()).then_some(names)
}

/// Reads a data type code; `what` names its place in errors.
fn data_type(c: &mut Cursor, what: &str) -> Result<DataType, FormatError> {
    let code = c.u32(what)?;
    DataType::from_code(code).ok_or_else(|| {
        error(
            format!("byte {}", c.pos() - 4),
            format!("a TDMS data type code for {what}"),
            format!("{code:#x}"),
        )
    })
}

/// Reads a raw data index after its length field (`path` names the object).
fn raw_data_index(c: &mut Cursor, path: &str) -> Result<Index, FormatError> {
    let ty = data_type(c, "the raw data")?;
    let dimension = c.u32("an array dimension")?;
    if dimension != 1 {
        return Err(error(
            format!("byte {}", c.pos() - 4),
            format!("array dimension 1 in the raw data index of {}", quote(path)),
            format!("{dimension}"),
        ));
    }
    let count = c.u64("a value count")?;
    let bytes = match ty.size() {
        Some(size) => count.checked_mul(size).ok_or_else(|| {
            c.error(
                format!("raw data of fewer than 2^64 bytes for {}", quote(path)),
                format!("{count} values of {size} bytes"),
            )
        })?,
        None if ty == DataType::Text => c.u64("the strings' total size")?,
        None => {
            return Err(c.error(
                format!(
                    "a DAQmx raw data index for the DAQmx data of {}",
                    quote(path)
                ),
                "a plain raw data index",
            ));
        }
    };
    Ok(Index::Values { ty, count, bytes })
}

/// Skips a DAQmx raw data index after its header, whose value gives the
/// size of each scaler (20 bytes format-changing, 17 digital-line).
fn skip_daqmx_index(c: &mut Cursor, header: u32) -> Result<(), FormatError> {
    c.u32("a DAQmx data type")?;
    c.u32("an array dimension")?;
    c.u64("a DAQmx chunk size")?;
    let scalers = u64::from(c.u32("a DAQmx scaler count")?);
    let scaler_bytes = if header == 0x1269 { 20 } else { 17 };
    let n = usize::try_from(scalers * scaler_bytes).unwrap_or(usize::MAX);
    c.take(n, "DAQmx scalers")?;
    let widths = u64::from(c.u32("a DAQmx raw data width count")?);
    c.take(
        usize::try_from(widths * 4).unwrap_or(usize::MAX),
        "DAQmx raw data widths",
    )?;
    Ok(())
}

/// Reads a property's type and value.
fn property(c: &mut Cursor) -> Result<Property, FormatError> {
    let ty = data_type(c, "a property value")?;
    if ty == DataType::Text {
        return string(c, "a string property value").map(Property::Text);
    }
    let size = ty.size().ok_or_else(|| {
        c.error(
            "a property value of a fixed-size type",
            "DAQmx raw data type",
        )
    })?;
    let raw = c.take(
        usize::try_from(size).unwrap_or(usize::MAX),
        "a property value",
    )?;
    let mut value = Vec::new();
    decode(raw, ty, c.big_endian(), &mut value);
    Ok(value
        .first()
        .map_or(Property::Other, |x| Property::Number(*x)))
}

impl Reader {
    /// Reads the segment at the cursor (the `number`th), leaving the cursor
    /// at its end.
    fn segment(&mut self, c: &mut Cursor, number: usize) -> Result<(), FormatError> {
        let start = c.pos();
        let at = format!("segment {number} (byte {start})");
        if c.remaining() < LEAD_IN_BYTES {
            return Err(error(
                at,
                format!("a {LEAD_IN_BYTES}-byte segment lead-in"),
                format!("{} bytes before the end of the file", c.remaining()),
            ));
        }
        let tag = c.take(4, "the segment tag")?;
        if tag != b"TDSm" {
            return Err(error(
                at,
                "the segment tag \"TDSm\"",
                format!("{:?}", String::from_utf8_lossy(tag)),
            ));
        }
        c.set_big_endian(false);
        let toc = c.u32("the table of contents")?;
        c.set_big_endian(toc & TOC_BIG_ENDIAN != 0);
        let version = c.u32("the version")?;
        if version != 4712 && version != 4713 {
            return Err(error(at, "version 4712 or 4713", format!("{version}")));
        }
        let next = c.u64("the next segment offset")?;
        let raw_offset = c.u64("the raw data offset")?;
        let body = c.pos();
        let left = c.remaining() as u64;
        let length = match next {
            CUT_SHORT => left,
            next if next > left => {
                return Err(error(
                    at,
                    format!("the segment's {next} bytes (its next segment offset)"),
                    format!("{left} bytes before the end of the file"),
                ));
            }
            next => next,
        };
        if raw_offset > length {
            return Err(error(
                at,
                format!("a raw data offset within the segment's {length} bytes"),
                format!("{raw_offset}"),
            ));
        }
        // Both fit: they are at most the bytes left.
        let end = body + length as usize;
        let raw_start = body + raw_offset as usize;
        if toc & TOC_NEW_OBJ_LIST != 0 {
            self.clear_list();
        }
        if toc & TOC_META_DATA != 0 {
            self.metadata(c)?;
            if c.pos() > raw_start {
                return Err(error(
                    at,
                    format!("metadata ending by byte {raw_start} (the raw data offset)"),
                    format!("metadata ending at byte {}", c.pos()),
                ));
            }
        }
        if toc & TOC_RAW_DATA != 0 {
            let daqmx = self
                .list
                .iter()
                .any(|(_, i)| matches!(i, Some(Index::DaqMx)));
            if daqmx || toc & TOC_DAQMX_RAW_DATA != 0 {
                self.daqmx = true;
            } else {
                c.seek(raw_start, "the raw data")?;
                self.raw_data(c, end, toc & TOC_INTERLEAVED_DATA != 0, &at)?;
            }
        }
        c.seek(end, "the next segment")
    }

    /// Empties the object list.
    fn clear_list(&mut self) {
        for (id, _) in self.list.drain(..) {
            if let Some(object) = self.objects.get_mut(id) {
                object.slot = None;
            }
        }
    }

    /// The object at `path` (read at byte `at`), made on first sight.
    fn object(&mut self, path: &str, at: usize) -> Result<usize, FormatError> {
        let id = match self.by_path.get(path) {
            Some(&id) => id,
            None => {
                let names = path_names(path).ok_or_else(|| {
                    error(
                        format!("byte {at}"),
                        "an object path /, /'group' or /'group'/'channel'",
                        quote(path),
                    )
                })?;
                let name = match names.as_slice() {
                    [] | [_] => None,
                    [group, channel] => Some(format!("{group}/{channel}")),
                    _ => {
                        return Err(error(
                            format!("byte {at}"),
                            "an object path of at most a group and a channel",
                            quote(path),
                        ));
                    }
                };
                self.objects.push(Object {
                    name,
                    ..Object::default()
                });
                self.by_path.insert(path.to_owned(), self.objects.len() - 1);
                self.objects.len() - 1
            }
        };
        Ok(id)
    }

    /// Reads a segment's metadata: its objects, their raw data indexes and
    /// properties, updating the object list.
    fn metadata(&mut self, c: &mut Cursor) -> Result<(), FormatError> {
        let count = c.u32("the object count")?;
        for _ in 0..count {
            let path_at = c.pos();
            let path = string(c, "an object path")?;
            let id = self.object(&path, path_at)?;
            let object = self.objects.get_mut(id).ok_or_else(|| {
                error(
                    format!("byte {path_at}"),
                    "an object read before",
                    quote(&path),
                )
            })?;
            let header = c.u32("a raw data index length")?;
            let index = match header {
                NO_RAW_DATA => None,
                SAME_INDEX => Some(object.index.ok_or_else(|| {
                    error(
                        format!("byte {}", c.pos() - 4),
                        format!("a raw data index for {}", quote(&path)),
                        "0x00000000 (the same index as before) for an object that had none",
                    )
                })?),
                header if DAQMX_INDEXES.contains(&header) => {
                    skip_daqmx_index(c, header)?;
                    Some(Index::DaqMx)
                }
                _ => Some(raw_data_index(c, &path)?),
            };
            if let Some(index) = index {
                object.index = Some(index);
                if let Index::Values { ty, .. } = index {
                    object.numeric |= ty.is_numeric() && object.name.is_some();
                }
            }
            let properties = c.u32("a property count")?;
            for _ in 0..properties {
                let name = string(c, "a property name")?;
                let value = property(c)?;
                object.set(&name, value);
            }
            match object.slot {
                Some(slot) => {
                    if let Some(entry) = self.list.get_mut(slot) {
                        entry.1 = index;
                    }
                }
                None => {
                    object.slot = Some(self.list.len());
                    self.list.push((id, index));
                }
            }
        }
        Ok(())
    }

    /// Reads a segment's raw data, from the cursor to byte `end`: as many
    /// whole chunks as it holds (`at` names the segment in errors).
    fn raw_data(
        &mut self,
        c: &mut Cursor,
        end: usize,
        interleaved: bool,
        at: &str,
    ) -> Result<(), FormatError> {
        let mut chunk = 0u64;
        for (_, index) in &self.list {
            if let Some(Index::Values { bytes, .. }) = index {
                chunk = chunk.checked_add(*bytes).ok_or_else(|| {
                    error(at, "a raw data chunk of fewer than 2^64 bytes", "more")
                })?;
            }
        }
        if chunk == 0 {
            return Ok(());
        }
        let row = if interleaved {
            self.interleaved_row(at)?
        } else {
            0
        };
        let length = end.saturating_sub(c.pos()) as u64;
        // Taken only while a whole chunk is left, so it fits.
        let chunk_bytes = chunk as usize;
        let big_endian = c.big_endian();
        for _ in 0..length / chunk {
            let raw = c.take(chunk_bytes, "a raw data chunk")?;
            if interleaved {
                self.interleaved_chunk(raw, row, big_endian);
            } else {
                self.contiguous_chunk(raw, big_endian);
            }
        }
        Ok(())
    }

    /// Reads one chunk of contiguous data: each object's values in turn.
    fn contiguous_chunk(&mut self, raw: &[u8], big_endian: bool) {
        let mut offset = 0usize;
        for (id, index) in &self.list {
            let Some(Index::Values { ty, bytes, .. }) = index else {
                continue;
            };
            // Each object's bytes are part of the chunk, so they fit.
            let next = offset + *bytes as usize;
            if let (Some(values), Some(object)) = (raw.get(offset..next), self.objects.get_mut(*id))
            {
                // Strings and other non-numeric values are skipped.
                decode(values, *ty, big_endian, &mut object.values);
            }
            offset = next;
        }
    }

    /// The bytes of one row of interleaved data, checking it can be read:
    /// values of fixed size, the same count of each object.
    fn interleaved_row(&self, at: &str) -> Result<u64, FormatError> {
        let mut row = 0;
        let mut first = None;
        for (id, index) in &self.list {
            let Some(Index::Values { ty, count, .. }) = index else {
                continue;
            };
            let name = self.objects.get(*id).and_then(|o| o.name.as_deref());
            let name = quote(name.unwrap_or("/"));
            let Some(size) = ty.size() else {
                let found = format!("strings in {name}");
                return Err(error(at, "interleaved values of fixed size", found));
            };
            let first = *first.get_or_insert(*count);
            if *count != first {
                let expected = format!("interleaved channels of {first} values each");
                return Err(error(at, expected, format!("{count} values in {name}")));
            }
            row += size;
        }
        Ok(row)
    }

    /// Reads one chunk of interleaved data: rows of `row` bytes, one value of
    /// each object.
    fn interleaved_chunk(&mut self, raw: &[u8], row: u64, big_endian: bool) {
        if row == 0 {
            return;
        }
        for values in raw.chunks_exact(row as usize) {
            let mut offset = 0usize;
            for (id, index) in &self.list {
                let Some(Index::Values { ty, .. }) = index else {
                    continue;
                };
                let next = offset + ty.size().unwrap_or(0) as usize;
                if let (Some(value), Some(object)) =
                    (values.get(offset..next), self.objects.get_mut(*id))
                {
                    decode(value, *ty, big_endian, &mut object.values);
                }
                offset = next;
            }
        }
    }

    /// The record: every channel that had numeric data.
    fn into_record(self) -> Result<Record, FormatError> {
        let channels: Vec<Channel> = self
            .objects
            .into_iter()
            .filter(|o| o.numeric)
            .filter_map(|o| {
                let timing = o.timing();
                Some(Channel {
                    name: o.name?,
                    unit: o.unit,
                    values: o.values,
                    timing,
                })
            })
            .collect();
        if channels.is_empty() {
            let found = if self.daqmx {
                "DAQmx raw data only; DAQmx raw data is not read; export the channels as scaled data"
            } else {
                "none (only strings, booleans, timestamps, complex values or objects without data)"
            };
            return Err(error(
                "the whole file",
                "a channel of integer or float values",
                found,
            ));
        }
        Ok(Record {
            format: Format::Tdms,
            channels,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    const TENSILE: &[u8] =
        include_bytes!("../../tests/data/records/tdms_tensile_two_segments.tdms");
    const MIXED: &[u8] = include_bytes!("../../tests/data/records/tdms_mixed_types.tdms");
    const INTERLEAVED: &[u8] = include_bytes!("../../tests/data/records/tdms_interleaved_be.tdms");

    /// The channel named `name`.
    fn channel<'r>(record: &'r Record, name: &str) -> &'r Channel {
        record
            .channels
            .iter()
            .find(|c| c.name == name)
            .unwrap_or_else(|| panic!("no channel {name} in {:?}", names(record)))
    }

    fn names(record: &Record) -> Vec<&str> {
        record.channels.iter().map(|c| c.name.as_str()).collect()
    }

    /// Asserts `values` equal `expected(k)` bit for bit, for k = 0..n.
    fn assert_bits(values: &[f64], n: usize, expected: impl Fn(f64) -> f64) {
        assert_eq!(values.len(), n);
        for (k, v) in values.iter().enumerate() {
            let want = expected(k as f64);
            assert_eq!(v.to_bits(), want.to_bits(), "value {k}: {v} against {want}");
        }
    }

    /// A string as TDMS writes it (little-endian length).
    fn s(text: &str) -> Vec<u8> {
        let mut out = (text.len() as u32).to_le_bytes().to_vec();
        out.extend_from_slice(text.as_bytes());
        out
    }

    /// A little-endian segment.
    fn segment(toc: u32, meta: &[u8], raw: &[u8]) -> Vec<u8> {
        let mut out = b"TDSm".to_vec();
        out.extend_from_slice(&toc.to_le_bytes());
        out.extend_from_slice(&4713u32.to_le_bytes());
        out.extend_from_slice(&((meta.len() + raw.len()) as u64).to_le_bytes());
        out.extend_from_slice(&(meta.len() as u64).to_le_bytes());
        out.extend_from_slice(meta);
        out.extend_from_slice(raw);
        out
    }

    /// Metadata: objects of (path, raw data index bytes), no properties.
    fn meta(objects: &[(&str, Vec<u8>)]) -> Vec<u8> {
        let mut out = (objects.len() as u32).to_le_bytes().to_vec();
        for (path, index) in objects {
            out.extend(s(path));
            out.extend_from_slice(index);
            out.extend_from_slice(&0u32.to_le_bytes());
        }
        out
    }

    /// A raw data index of `count` values of type `code`.
    fn index(code: u32, count: u64) -> Vec<u8> {
        let mut out = 20u32.to_le_bytes().to_vec();
        out.extend_from_slice(&code.to_le_bytes());
        out.extend_from_slice(&1u32.to_le_bytes());
        out.extend_from_slice(&count.to_le_bytes());
        out
    }

    fn i16s(values: &[i16]) -> Vec<u8> {
        values.iter().flat_map(|v| v.to_le_bytes()).collect()
    }

    const ALL: u32 = TOC_META_DATA | TOC_NEW_OBJ_LIST | TOC_RAW_DATA;

    #[test]
    fn two_segments_are_concatenated_with_units_and_timing() {
        let record = read(TENSILE).unwrap();
        assert_eq!(record.format, Format::Tdms);
        assert_eq!(names(&record), ["tensile/t_s", "tensile/force_N"]);
        let t = channel(&record, "tensile/t_s");
        assert_eq!(t.unit.as_deref(), Some("s"));
        assert_eq!(t.timing, None);
        assert_bits(&t.values, 80, |k| k * 1e-6);
        let force = channel(&record, "tensile/force_N");
        assert_eq!(force.unit.as_deref(), Some("N"));
        assert_eq!(
            force.timing,
            Some(Waveform {
                start: 0.0,
                increment: 1e-6
            })
        );
        assert_bits(&force.values, 80, |k| 250.0 + 0.75 * k - k * k / 64.0);
        assert!(is_tdms(TENSILE));
        assert!(!is_tdms(b"time,force\n"));
    }

    #[test]
    fn every_integer_and_float_type_is_read_and_strings_and_timestamps_skipped() {
        let record = read(MIXED).unwrap();
        let want = [
            "i8", "i16", "i32", "i64", "u8", "u16", "u32", "u64", "f32", "f64",
        ];
        let want: Vec<String> = want.iter().map(|n| format!("rig/{n}")).collect();
        assert_eq!(names(&record), want);
        let n = 12;
        assert_bits(&channel(&record, "rig/i8").values, n, |k| k * 11.0 - 64.0);
        assert_bits(&channel(&record, "rig/i16").values, n, |k| {
            k * 2500.0 - 20000.0
        });
        assert_bits(&channel(&record, "rig/i32").values, n, |k| {
            k * 100000.0 - 7.0
        });
        assert_bits(&channel(&record, "rig/i64").values, n, |k| k * 3e9 - 5.0);
        assert_bits(&channel(&record, "rig/u8").values, n, |k| k * 20.0 + 3.0);
        assert_bits(&channel(&record, "rig/u16").values, n, |k| k * 5000.0 + 1.0);
        assert_bits(&channel(&record, "rig/u32").values, n, |k| k * 3e8 + 9.0);
        assert_bits(&channel(&record, "rig/u64").values, n, |k| k * 1e12 + 1.0);
        let f32s = |k: f64| f64::from(k as f32 * 0.125 - 1.5);
        assert_bits(&channel(&record, "rig/f32").values, n, f32s);
        assert_bits(&channel(&record, "rig/f64").values, n, |k| k / 3.0);
        let i16s = channel(&record, "rig/i16");
        assert_eq!(i16s.unit.as_deref(), Some("mV"));
        assert_eq!(
            i16s.timing,
            Some(Waveform {
                start: 2.0,
                increment: 0.5
            })
        );
        // An empty unit is no unit; an increment in Hz or of zero is no timing.
        let u16s = channel(&record, "rig/u16");
        assert_eq!((u16s.unit.as_deref(), u16s.timing), (None, None));
        assert_eq!(channel(&record, "rig/f32").timing, None);
    }

    #[test]
    fn interleaved_big_endian_carried_over_and_cut_short_segments_are_read() {
        let record = read(INTERLEAVED).unwrap();
        assert_eq!(names(&record), ["rig/disp 'mm'", "rig/load"]);
        let disp = channel(&record, "rig/disp 'mm'");
        assert_eq!(disp.unit.as_deref(), Some("mm"));
        assert_bits(&disp.values, 12, |k| 3.0 * k - 7.0);
        let load = channel(&record, "rig/load");
        assert_eq!(load.unit.as_deref(), Some("kN"), "the third segment's unit");
        assert_bits(&load.values, 12, |k| k / 4.0);
    }

    #[test]
    fn a_new_object_list_drops_the_objects_it_does_not_name() {
        let a = "/'g'/'a'";
        let b = "/'g'/'b'";
        let mut file = segment(
            ALL,
            &meta(&[(a, index(2, 2)), (b, index(2, 2))]),
            &i16s(&[1, 2, 3, 4]),
        );
        // Only b, with the index it had (0x00000000), and two chunks.
        let second = meta(&[(b, 0u32.to_le_bytes().to_vec())]);
        file.extend(segment(ALL, &second, &i16s(&[5, 6, 7, 8])));
        // No metadata: the same list, b alone.
        file.extend(segment(TOC_RAW_DATA, &[], &i16s(&[9, 10])));
        let record = read(&file).unwrap();
        assert_eq!(channel(&record, "g/a").values, [1.0, 2.0]);
        assert_eq!(
            channel(&record, "g/b").values,
            [3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.0, 10.0]
        );
    }

    #[test]
    fn an_object_without_data_in_a_later_segment_keeps_its_place() {
        let a = "/'g'/'a'";
        let b = "/'g'/'b'";
        let mut file = segment(
            ALL,
            &meta(&[(a, index(2, 1)), (b, index(2, 1))]),
            &i16s(&[1, 2]),
        );
        let no_data = NO_RAW_DATA.to_le_bytes().to_vec();
        file.extend(segment(
            TOC_META_DATA | TOC_RAW_DATA,
            &meta(&[(a, no_data)]),
            &i16s(&[3]),
        ));
        let record = read(&file).unwrap();
        assert_eq!(channel(&record, "g/a").values, [1.0]);
        assert_eq!(channel(&record, "g/b").values, [2.0, 3.0]);
    }

    #[test]
    fn a_file_of_strings_only_is_refused_saying_so() {
        let mut strings = 28u32.to_le_bytes().to_vec();
        for word in [0x20u32, 1] {
            strings.extend_from_slice(&word.to_le_bytes());
        }
        strings.extend_from_slice(&1u64.to_le_bytes());
        strings.extend_from_slice(&6u64.to_le_bytes());
        let mut raw = 2u32.to_le_bytes().to_vec();
        raw.extend_from_slice(b"ok");
        let file = segment(ALL, &meta(&[("/'g'/'note'", strings)]), &raw);
        let e = read(&file).unwrap_err();
        assert_eq!(e.at, "the whole file");
        assert!(e.expected.contains("integer or float"), "{e}");
        assert!(e.found.contains("strings"), "{e}");
    }

    #[test]
    fn a_daqmx_file_is_refused_with_the_advice_to_export_scaled_data() {
        let mut daqmx = 0x1269u32.to_le_bytes().to_vec();
        for word in [0xFFFF_FFFFu32, 1] {
            daqmx.extend_from_slice(&word.to_le_bytes());
        }
        daqmx.extend_from_slice(&4u64.to_le_bytes());
        daqmx.extend_from_slice(&1u32.to_le_bytes());
        daqmx.extend_from_slice(&[0; 20]);
        daqmx.extend_from_slice(&1u32.to_le_bytes());
        daqmx.extend_from_slice(&2u32.to_le_bytes());
        let toc = ALL | TOC_DAQMX_RAW_DATA;
        let file = segment(toc, &meta(&[("/'dev'/'ai0'", daqmx)]), &i16s(&[1, 2, 3, 4]));
        let e = read(&file).unwrap_err();
        assert!(
            e.to_string()
                .contains("DAQmx raw data is not read; export the channels as scaled data"),
            "{e}"
        );
        // Its metadata was skipped whole: a numeric channel after it is read.
        let next = segment(ALL, &meta(&[("/'g'/'x'", index(2, 1))]), &i16s(&[7]));
        let record = read(&[file, next].concat()).unwrap();
        assert_eq!(names(&record), ["g/x"]);
        assert_eq!(record.channels[0].values, [7.0]);
    }

    #[test]
    fn a_wrong_tag_or_version_is_refused_naming_the_segment() {
        let mut file = TENSILE.to_vec();
        file[0] = b'X';
        let e = read(&file).unwrap_err();
        assert_eq!(e.at, "segment 1 (byte 0)");
        assert!(
            e.expected.contains("TDSm") && e.found.contains("XDSm"),
            "{e}"
        );
        // The second segment's version (bytes 8..12 of its lead-in).
        let second =
            usize::try_from(u64::from_le_bytes(TENSILE[12..20].try_into().unwrap())).unwrap() + 28;
        let mut file = TENSILE.to_vec();
        file[second + 8..second + 12].copy_from_slice(&4711u32.to_le_bytes());
        let e = read(&file).unwrap_err();
        assert_eq!(e.at, format!("segment 2 (byte {second})"));
        assert_eq!(
            (e.expected.as_str(), e.found.as_str()),
            ("version 4712 or 4713", "4711")
        );
    }

    #[test]
    fn a_file_cut_inside_a_segment_is_refused_naming_its_size() {
        let e = read(&TENSILE[..TENSILE.len() - 5]).unwrap_err();
        assert!(e.at.starts_with("segment 2 "), "{e}");
        assert!(e.expected.contains("next segment offset"), "{e}");
        assert!(e.found.ends_with("bytes before the end of the file"), "{e}");
        let e = read(&TENSILE[..20]).unwrap_err();
        assert!(
            e.expected.contains("28-byte segment lead-in") && e.found.starts_with("20 bytes"),
            "{e}"
        );
    }

    #[test]
    fn malformed_metadata_is_refused_naming_the_byte_and_object() {
        let file = segment(ALL, &meta(&[("/'g'/'a'/'b'", index(2, 1))]), &i16s(&[1]));
        let e = read(&file).unwrap_err();
        assert_eq!(e.at, "byte 32");
        assert!(
            e.expected.contains("at most a group and a channel")
                && e.found.contains("/'g'/'a'/'b'"),
            "{e}"
        );
        let file = segment(ALL, &meta(&[("g/a", index(2, 1))]), &i16s(&[1]));
        assert!(
            read(&file)
                .unwrap_err()
                .expected
                .contains("an object path /")
        );
        let same = 0u32.to_le_bytes().to_vec();
        let e = read(&segment(ALL, &meta(&[("/'g'/'a'", same)]), &[])).unwrap_err();
        assert!(
            e.found.contains("had none") && e.expected.contains("/'g'/'a'"),
            "{e}"
        );
        let e = read(&segment(ALL, &meta(&[("/'g'/'a'", index(0x4F, 1))]), &[])).unwrap_err();
        assert_eq!((e.at.as_str(), e.found.as_str()), ("byte 48", "0x4f"));
        // Metadata running past the raw data offset.
        let mut file = segment(ALL, &meta(&[("/'g'/'a'", index(2, 1))]), &i16s(&[1]));
        file[20] -= 1;
        assert!(
            read(&file)
                .unwrap_err()
                .expected
                .contains("the raw data offset")
        );
    }

    #[test]
    fn interleaved_strings_or_unequal_counts_are_refused() {
        let toc = ALL | TOC_INTERLEAVED_DATA;
        let file = segment(
            toc,
            &meta(&[("/'g'/'a'", index(2, 1)), ("/'g'/'b'", index(2, 2))]),
            &i16s(&[1, 2, 3]),
        );
        let e = read(&file).unwrap_err();
        assert!(
            e.expected.contains("of 1 values each") && e.found.contains("\"g/b\""),
            "{e}"
        );
    }

    #[test]
    fn path_names_unescape_quotes() {
        assert_eq!(path_names("/"), Some(vec![]));
        assert_eq!(
            path_names("/'a''b'/'c'"),
            Some(vec!["a'b".to_owned(), "c".to_owned()])
        );
        assert_eq!(path_names("/'a"), None);
        assert_eq!(path_names(""), None);
        assert_eq!(path_names("/'a'x"), None);
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(300))]

        #[test]
        fn truncated_or_flipped_files_never_panic(
            which in 0usize..3,
            cut in 0.0f64..1.0,
            flips in proptest::collection::vec((0.0f64..1.0, any::<u8>()), 0..6),
        ) {
            let source = [TENSILE, MIXED, INTERLEAVED][which];
            let mut file = source[..(cut * source.len() as f64) as usize + 1].to_vec();
            for (at, byte) in flips {
                let i = (at * file.len() as f64) as usize;
                if let Some(b) = file.get_mut(i) {
                    *b ^= byte;
                }
            }
            let _ = read(&file);
        }
    }
}
