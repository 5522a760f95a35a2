//! MATLAB MAT-files, level 5 (as MATLAB's v5, v6 and v7 write them), read
//! after the "MAT-File Format" specification: a 128-byte header, then data
//! elements, each a `miMATRIX` variable or a `miCOMPRESSED` zlib stream
//! holding one.
//!
//! Channels: a real numeric vector (1×N or N×1) `v` is channel `v`; an N×M
//! matrix (both above 1) gives one channel per column, `v(:,1)`, `v(:,2)`, …
//! (data is column-major); a 1×1 struct's numeric fields are `s.field`
//! (nested structs `s.a.b`). Scalars, empty and N-dimensional arrays, char,
//! cell, sparse, logical, complex, function-handle and object arrays, and
//! struct arrays other than 1×1 are skipped. Values of every storage type are
//! converted to `f64` (64-bit integers beyond 2^53 round to the nearest).
//!
//! Units: a struct's char field `units` (or `unit`) is the unit of each of
//! its numeric fields; a struct field `units` whose char fields are named like
//! the numeric fields gives each its own. Timing: a struct with a scalar
//! field `dt` (or `increment`, s) and optionally `t0` (or `start`, s; else 0)
//! gives that timing to its other vector fields. MAT-files state no other
//! timing.

use std::collections::HashMap;
use std::io::Read;

use super::{Channel, Format, FormatError, Record, Waveform, bytes::Cursor};

/// The header's length (bytes).
const HEADER_LEN: usize = 128;
/// Data type of a variable.
const MI_MATRIX: u32 = 14;
/// Data type of a zlib-compressed element.
const MI_COMPRESSED: u32 = 15;
/// Most struct levels a variable may nest.
const MAX_DEPTH: usize = 32;
/// Most bytes a compressed element may inflate to, per compressed byte.
const MAX_INFLATE_RATIO: u64 = 64;
/// Most bytes a compressed element may inflate to (4 GiB).
const MAX_INFLATED: u64 = 4 << 30;
/// The HDF5 signature, at byte 512 of a v7.3 MAT-file.
const HDF5_SIGNATURE: &[u8] = b"\x89HDF\r\n\x1a\n";

/// Whether `bytes` start with a level-5 MAT-file header (v5, v6 or v7): four
/// non-zero text bytes, version 0x0100 and the endian indicator `IM` or `MI`.
pub fn is_mat5(bytes: &[u8]) -> bool {
    !is_mat73(bytes) && header_byte_order(bytes).is_ok()
}

/// Whether `bytes` are a MAT-file v7.3 (HDF5 underneath): its header text
/// starts `MATLAB 7.3 MAT-file`, or the HDF5 signature sits at byte 512.
pub fn is_mat73(bytes: &[u8]) -> bool {
    bytes.starts_with(b"MATLAB 7.3 MAT-file") || bytes.get(512..520) == Some(HDF5_SIGNATURE)
}

/// Reads a level-5 MAT-file's numeric variables as a record (see the module
/// docs for which variables become which channels).
pub fn read(bytes: &[u8]) -> Result<Record, FormatError> {
    if is_mat73(bytes) {
        return Err(error_at(
            0,
            "a level-5 MAT-file (v7.3 files are HDF5 and read by the HDF5 reader)",
            "a v7.3 MAT-file (its header text or the HDF5 signature at byte 512)",
        ));
    }
    let big_endian = header_byte_order(bytes)?;
    let mut cursor = Cursor::new(bytes, Format::Mat);
    cursor.set_big_endian(big_endian);
    cursor.seek(HEADER_LEN, "the first data element")?;
    let mut variables = Vec::new();
    while cursor.remaining() > 0 {
        let tag_pos = cursor.pos();
        let element = element(&mut cursor, bytes.len(), "a data element")?;
        match element.kind {
            MI_MATRIX => variables.push(matrix_at(&cursor, &element, 0)?),
            MI_COMPRESSED => {
                let inflated = inflate(element.data, tag_pos)?;
                let variable = compressed_variable(&inflated, big_endian).map_err(|mut e| {
                    e.at = format!(
                        "{} of the data decompressed from the element at byte {tag_pos}",
                        e.at
                    );
                    e
                })?;
                variables.extend(variable);
            }
            _ => {}
        }
    }
    let mut channels = Vec::new();
    let count = variables.len();
    for (name, value) in variables {
        if !name.is_empty() {
            push_channels(&name, value, None, None, &mut channels)?;
        }
    }
    if channels.is_empty() {
        return Err(FormatError {
            format: Format::Mat,
            at: "the whole file".into(),
            expected: "a numeric vector or matrix variable (or struct field) with more than one \
                       sample"
                .into(),
            found: format!("{count} variables, none of them one"),
        });
    }
    Ok(Record {
        format: Format::Mat,
        channels,
    })
}

/// Checks the 128-byte header; whether the file is big-endian.
fn header_byte_order(bytes: &[u8]) -> Result<bool, FormatError> {
    let header = bytes.get(..HEADER_LEN).ok_or_else(|| {
        error_at(
            0,
            "a 128-byte level-5 MAT-file header",
            format!("{} bytes", bytes.len()),
        )
    })?;
    if header.iter().take(4).any(|&b| b == 0) {
        return Err(error_at(
            0,
            "the header text of a level-5 MAT-file (a level-4 file starts with a zero byte)",
            "a zero byte in the first four",
        ));
    }
    let big_endian = match header.get(126..128) {
        Some(b"IM") => false,
        Some(b"MI") => true,
        found => {
            return Err(error_at(
                126,
                "the endian indicator IM or MI of a level-5 MAT-file",
                format!("{:?}", found.unwrap_or_default()),
            ));
        }
    };
    let raw = [header.get(124).copied(), header.get(125).copied()];
    let [Some(a), Some(b)] = raw else {
        return Err(error_at(124, "a version", "the end of the header"));
    };
    let version = if big_endian {
        u16::from_be_bytes([a, b])
    } else {
        u16::from_le_bytes([a, b])
    };
    if version != 0x0100 {
        return Err(error_at(
            124,
            "version 0x0100 of a level-5 MAT-file",
            format!("version {version:#06x}"),
        ));
    }
    Ok(big_endian)
}

/// A data element: its type, its bytes and where they start in the buffer.
struct Element<'a> {
    kind: u32,
    data: &'a [u8],
    data_pos: usize,
}

/// Reads the element at the cursor, which must end by `end`, and moves past
/// it and its padding to the next 8-byte boundary (a compressed element has
/// none).
fn element<'a>(c: &mut Cursor<'a>, end: usize, what: &str) -> Result<Element<'a>, FormatError> {
    let tag_pos = c.pos();
    let left = end.saturating_sub(tag_pos);
    if left < 8 {
        return Err(error_at(
            tag_pos,
            format!("the 8-byte tag of {what}"),
            format!("{left} bytes left in the enclosing element"),
        ));
    }
    let word = c.u32(what)?;
    if word >> 16 != 0 {
        // The small form: type and byte count packed in 4 bytes, data in 4.
        let (kind, n) = (word & 0xFFFF, (word >> 16) as usize);
        let data = c.take(4, what)?.get(..n).ok_or_else(|| {
            error_at(
                tag_pos,
                format!("{what} in the small form of at most 4 bytes"),
                format!("{n} bytes"),
            )
        })?;
        return Ok(Element {
            kind,
            data,
            data_pos: tag_pos + 4,
        });
    }
    let n = c.u32(what)? as usize;
    let data_pos = c.pos();
    let left = end.saturating_sub(data_pos);
    if n > left {
        return Err(error_at(
            tag_pos,
            format!("{what} of {n} bytes within the enclosing element, which ends at byte {end}"),
            format!("{left} bytes left"),
        ));
    }
    let data = c.take(n, what)?;
    if word != MI_COMPRESSED {
        let padded = data_pos + n.next_multiple_of(8);
        c.seek(padded.min(end), what)?;
    }
    Ok(Element {
        kind: word,
        data,
        data_pos,
    })
}

/// The one element a compressed element holds: a named variable, or none
/// where it holds something else.
fn compressed_variable(
    inflated: &[u8],
    big_endian: bool,
) -> Result<Option<(String, Value)>, FormatError> {
    let mut c = Cursor::new(inflated, Format::Mat);
    c.set_big_endian(big_endian);
    let element = element(&mut c, inflated.len(), "the compressed data element")?;
    match element.kind {
        MI_MATRIX => Ok(Some(matrix_at(&c, &element, 0)?)),
        MI_COMPRESSED => Err(error_at(
            0,
            "an uncompressed element inside a compressed one",
            "another compressed element",
        )),
        _ => Ok(None),
    }
}

/// Inflates a compressed element's zlib stream (at `at`), refusing one that
/// inflates beyond 64 times its size or 4 GiB.
fn inflate(data: &[u8], at: usize) -> Result<Vec<u8>, FormatError> {
    let limit = (data.len() as u64)
        .saturating_mul(MAX_INFLATE_RATIO)
        .min(MAX_INFLATED);
    let mut out = Vec::new();
    flate2::read::ZlibDecoder::new(data)
        .take(limit.saturating_add(1))
        .read_to_end(&mut out)
        .map_err(|e| error_at(at, "a zlib stream in the compressed element", e.to_string()))?;
    if out.len() as u64 > limit {
        return Err(error_at(
            at,
            format!(
                "a compressed element inflating to at most {limit} bytes ({MAX_INFLATE_RATIO} \
                 times its {} compressed bytes, at most 4 GiB)",
                data.len()
            ),
            "more",
        ));
    }
    Ok(out)
}

/// A variable's contents, as far as channels need them.
#[derive(Debug)]
enum Value {
    /// A real, non-logical, 2-D numeric array, column-major.
    Numeric {
        rows: usize,
        cols: usize,
        values: Vec<f64>,
    },
    /// A char array of one row.
    Text(String),
    /// A 1×1 struct's fields, in file order.
    Struct(Vec<(String, Value)>),
    /// Anything else: skipped.
    Other,
}

/// Reads the `miMATRIX` element `matrix` of the buffer `c` reads: its name
/// and its value. `depth` counts the structs around it.
fn matrix_at(
    c: &Cursor<'_>,
    matrix: &Element<'_>,
    depth: usize,
) -> Result<(String, Value), FormatError> {
    if matrix.data.is_empty() {
        return Ok((String::new(), Value::Other));
    }
    if depth > MAX_DEPTH {
        return Err(error_at(
            matrix.data_pos,
            format!("structs nested at most {MAX_DEPTH} deep"),
            "deeper nesting",
        ));
    }
    let mut c = c.clone();
    c.seek(matrix.data_pos, "a matrix")?;
    let end = matrix.data_pos + matrix.data.len();
    let big = c.big_endian();
    let flags = element_of(&mut c, end, "the array flags", &[6], Some(8))?;
    let flags = u32_at(flags.data, 0, big).unwrap_or_default();
    let dims_at = c.pos();
    let dims = element_of(&mut c, end, "the dimensions", &[5], None)?;
    let dims = dimensions(dims.data, big, dims_at)?;
    let name = element_of(&mut c, end, "the array name", &[1, 2, 16], None)?;
    let name = String::from_utf8_lossy(name.data).into_owned();
    let count = dims.iter().try_fold(1usize, |n, &d| n.checked_mul(d));
    let (class, complex, logical) = (flags & 0xFF, flags & 0x800 != 0, flags & 0x200 != 0);
    let value = match (class, dims.as_slice()) {
        (6..=15, &[rows, cols]) if !complex && !logical => {
            let at = c.pos();
            let real = element(&mut c, end, "the real part")?;
            let values = numbers(real.kind, real.data, big).ok_or_else(|| {
                error_at(
                    at,
                    "a numeric data type (1–7, 9, 12 or 13)",
                    real.kind.to_string(),
                )
            })?;
            if count != Some(values.len()) {
                return Err(error_at(
                    at,
                    format!("{rows}×{cols} = {} values", rows.saturating_mul(cols)),
                    format!("{} values", values.len()),
                ));
            }
            Value::Numeric { rows, cols, values }
        }
        (4, &[0 | 1, _]) => {
            let text = element(&mut c, end, "the characters")?;
            text_of(text.kind, text.data, big).map_or(Value::Other, Value::Text)
        }
        (2, _) if count == Some(1) => Value::Struct(fields(&mut c, end, depth)?),
        _ => Value::Other,
    };
    Ok((name, value))
}

/// A 1×1 struct's fields, read after its name.
fn fields(
    c: &mut Cursor<'_>,
    end: usize,
    depth: usize,
) -> Result<Vec<(String, Value)>, FormatError> {
    let big = c.big_endian();
    let at = c.pos();
    let len = element_of(c, end, "the field name length", &[5], Some(4))?;
    let len = u32_at(len.data, 0, big).unwrap_or_default() as usize;
    let names = element_of(c, end, "the field names", &[1, 2, 16], None)?;
    if len == 0 && !names.data.is_empty() || len != 0 && !names.data.len().is_multiple_of(len) {
        return Err(error_at(
            at,
            format!("field names of {len} bytes each"),
            format!("{} bytes of names", names.data.len()),
        ));
    }
    let mut fields = Vec::new();
    for raw in names.data.chunks(len.max(1)) {
        let name = raw.split(|&b| b == 0).next().unwrap_or_default();
        let tag_pos = c.pos();
        let element = element(c, end, "a struct field")?;
        if element.kind != MI_MATRIX {
            return Err(error_at(
                tag_pos,
                "a struct field's matrix (type 14)",
                format!("type {}", element.kind),
            ));
        }
        let (_, value) = matrix_at(c, &element, depth + 1)?;
        fields.push((String::from_utf8_lossy(name).into_owned(), value));
    }
    Ok(fields)
}

/// Reads an element that must have one of the types `kinds` (and, where
/// given, `len` bytes).
fn element_of<'a>(
    c: &mut Cursor<'a>,
    end: usize,
    what: &str,
    kinds: &[u32],
    len: Option<usize>,
) -> Result<Element<'a>, FormatError> {
    let tag_pos = c.pos();
    let element = element(c, end, what)?;
    if !kinds.contains(&element.kind) || len.is_some_and(|n| n != element.data.len()) {
        return Err(error_at(
            tag_pos,
            format!(
                "{what} as type {kinds:?}{}",
                len.map_or(String::new(), |n| format!(" of {n} bytes"))
            ),
            format!("type {} of {} bytes", element.kind, element.data.len()),
        ));
    }
    Ok(element)
}

/// A dimensions element's sizes (each at least 0; at least two of them).
fn dimensions(data: &[u8], big: bool, at: usize) -> Result<Vec<usize>, FormatError> {
    if data.len() < 8 || !data.len().is_multiple_of(4) {
        return Err(error_at(
            at,
            "at least two 4-byte dimensions",
            format!("{} bytes", data.len()),
        ));
    }
    data.chunks_exact(4)
        .map(|raw| {
            let d = u32_at(raw, 0, big).unwrap_or_default() as i32;
            usize::try_from(d)
                .map_err(|_| error_at(at, "dimensions of 0 or more", format!("dimension {d}")))
        })
        .collect()
}

/// The `u32` at `pos` of `data` in the file's byte order.
fn u32_at(data: &[u8], pos: usize, big: bool) -> Option<u32> {
    let raw: [u8; 4] = data.get(pos..pos.checked_add(4)?)?.try_into().ok()?;
    Some(if big {
        u32::from_be_bytes(raw)
    } else {
        u32::from_le_bytes(raw)
    })
}

/// Decodes numeric data of MAT type `kind` to `f64`; `None` for a type that
/// is not numeric. A trailing partial value is ignored (the caller checks
/// the count).
fn numbers(kind: u32, data: &[u8], big: bool) -> Option<Vec<f64>> {
    macro_rules! convert {
        ($ty:ty) => {{
            const N: usize = std::mem::size_of::<$ty>();
            data.chunks_exact(N)
                .map(|raw| {
                    let mut array = [0u8; N];
                    array.copy_from_slice(raw);
                    let v = if big {
                        <$ty>::from_be_bytes(array)
                    } else {
                        <$ty>::from_le_bytes(array)
                    };
                    v as f64
                })
                .collect()
        }};
    }
    Some(match kind {
        1 => convert!(i8),
        2 => convert!(u8),
        3 => convert!(i16),
        4 => convert!(u16),
        5 => convert!(i32),
        6 => convert!(u32),
        7 => convert!(f32),
        9 => convert!(f64),
        12 => convert!(i64),
        13 => convert!(u64),
        _ => return None,
    })
}

/// Decodes a char array's data of MAT type `kind` (8-bit, UTF-8, UTF-16 or
/// UTF-32); `None` for another type.
fn text_of(kind: u32, data: &[u8], big: bool) -> Option<String> {
    match kind {
        1 | 2 | 16 => Some(String::from_utf8_lossy(data).into_owned()),
        3 | 4 | 17 => {
            let units: Vec<u16> = data
                .chunks_exact(2)
                .map(|r| {
                    let raw = [r.first().copied()?, r.get(1).copied()?];
                    Some(if big {
                        u16::from_be_bytes(raw)
                    } else {
                        u16::from_le_bytes(raw)
                    })
                })
                .collect::<Option<_>>()?;
            Some(String::from_utf16_lossy(&units))
        }
        5 | 6 | 18 => Some(
            data.chunks_exact(4)
                .filter_map(|r| char::from_u32(u32_at(r, 0, big)?))
                .collect(),
        ),
        _ => None,
    }
}

/// Appends the channels of variable (or field) `name`.
fn push_channels(
    name: &str,
    value: Value,
    unit: Option<&str>,
    timing: Option<Waveform>,
    out: &mut Vec<Channel>,
) -> Result<(), FormatError> {
    match value {
        Value::Numeric { rows, cols, values } if rows.saturating_mul(cols) > 1 => {
            let channel = |name: String, values: Vec<f64>| Channel {
                name,
                unit: unit.map(str::to_owned),
                values,
                timing,
            };
            if rows == 1 || cols == 1 {
                out.push(channel(name.to_owned(), values));
            } else {
                for (j, column) in values.chunks_exact(rows).enumerate() {
                    out.push(channel(format!("{name}(:,{})", j + 1), column.to_vec()));
                }
            }
        }
        Value::Struct(fields) => push_struct(name, fields, out)?,
        _ => {}
    }
    Ok(())
}

/// Appends the channels of struct `name`'s fields, with the units and the
/// timing its fields state.
fn push_struct(
    name: &str,
    fields: Vec<(String, Value)>,
    out: &mut Vec<Channel>,
) -> Result<(), FormatError> {
    let field = |names: &[&str]| fields.iter().find(|(n, _)| names.contains(&n.as_str()));
    let is_units = |n: &str| n == "units" || n == "unit";
    let (common, by_field): (Option<String>, HashMap<String, String>) =
        match field(&["units", "unit"]) {
            Some((_, Value::Text(unit))) => (Some(unit.clone()), HashMap::new()),
            Some((_, Value::Struct(units))) => (
                None,
                units
                    .iter()
                    .filter_map(|(n, v)| match v {
                        Value::Text(unit) => Some((n.clone(), unit.clone())),
                        _ => None,
                    })
                    .collect(),
            ),
            _ => (None, HashMap::new()),
        };
    let scalar = |names: &[&str]| match field(names) {
        Some((n, Value::Numeric { values, .. })) if values.len() == 1 => {
            Some((n.clone(), values.first().copied().unwrap_or_default()))
        }
        _ => None,
    };
    let timing = match scalar(&["dt", "increment"]) {
        Some((field_name, increment)) => {
            let start = scalar(&["t0", "start"]).map_or(0.0, |(_, start)| start);
            if !(increment.is_finite() && increment > 0.0 && start.is_finite()) {
                return Err(FormatError {
                    format: Format::Mat,
                    at: format!("variable {name}.{field_name}"),
                    expected: "a finite sample interval above 0 s and a finite start".into(),
                    found: format!("interval {increment} s, start {start} s"),
                });
            }
            Some(Waveform { start, increment })
        }
        None => None,
    };
    for (field_name, value) in fields {
        if is_units(&field_name) && matches!(value, Value::Text(_) | Value::Struct(_)) {
            continue;
        }
        let full = format!("{name}.{field_name}");
        match value {
            Value::Struct(inner) => push_struct(&full, inner, out)?,
            _ => {
                let unit = by_field.get(&field_name).or(common.as_ref());
                push_channels(&full, value, unit.map(String::as_str), timing, out)?;
            }
        }
    }
    Ok(())
}

/// A format error at byte `pos`.
fn error_at(pos: usize, expected: impl Into<String>, found: impl Into<String>) -> FormatError {
    FormatError {
        format: Format::Mat,
        at: format!("byte {pos}"),
        expected: expected.into(),
        found: found.into(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    const V5: &[u8] = include_bytes!("../../tests/data/records/mat_v5.mat");
    const BE: &[u8] = include_bytes!("../../tests/data/records/mat_be.mat");
    const COMPRESSED: &[u8] = include_bytes!("../../tests/data/records/mat_compressed.mat");
    const STRUCT: &[u8] = include_bytes!("../../tests/data/records/mat_struct.mat");

    /// `0, 1, …, 15` as the generating script's `k`.
    fn k() -> impl Iterator<Item = f64> {
        (0..16).map(f64::from)
    }

    fn bits(values: &[f64]) -> Vec<u64> {
        values.iter().map(|v| v.to_bits()).collect()
    }

    fn expect(values: impl Iterator<Item = f64>) -> Vec<u64> {
        values.map(f64::to_bits).collect()
    }

    fn names(record: &Record) -> Vec<&str> {
        record.channels.iter().map(|c| c.name.as_str()).collect()
    }

    fn channel<'a>(record: &'a Record, name: &str) -> &'a Channel {
        record.channels.iter().find(|c| c.name == name).unwrap()
    }

    fn check_v5(record: &Record) {
        assert_eq!(record.format, Format::Mat);
        // `gain` (scalar), `notes` (cell) and `label` (char) are skipped.
        assert_eq!(names(record), ["t_s", "force_N"]);
        let t = channel(record, "t_s");
        assert_eq!(bits(&t.values), expect(k().map(|k| k * 1e-3)));
        let f = channel(record, "force_N");
        let force = k().map(|k| k * 0.5 - 2.25 + k * k * 1e-2);
        assert_eq!(bits(&f.values), expect(force));
        assert!(
            record
                .channels
                .iter()
                .all(|c| c.unit.is_none() && c.timing.is_none())
        );
    }

    #[test]
    fn reads_an_uncompressed_v5_file_bit_for_bit() {
        assert!(is_mat5(V5) && !is_mat73(V5));
        check_v5(&read(V5).unwrap());
    }

    #[test]
    fn reads_a_big_endian_file_as_its_little_endian_twin() {
        assert!(is_mat5(BE));
        assert_eq!(BE.get(126..128), Some(&b"MI"[..]));
        check_v5(&read(BE).unwrap());
    }

    #[test]
    fn reads_compressed_variables_and_matrix_columns() {
        let record = read(COMPRESSED).unwrap();
        // Logical `flag`, complex `z` and sparse `sp` are skipped.
        assert_eq!(
            names(&record),
            ["t_s", "counts(:,1)", "counts(:,2)", "v32", "big"]
        );
        let t = channel(&record, "t_s");
        assert_eq!(bits(&t.values), expect(k().map(|k| k * 1e-3)));
        let c1 = channel(&record, "counts(:,1)");
        assert_eq!(bits(&c1.values), expect(k().map(|k| k * 3.0 - 20.0)));
        let c2 = channel(&record, "counts(:,2)");
        assert_eq!(bits(&c2.values), expect(k().map(|k| 0.0 - k * 1000.0)));
        let v32 = channel(&record, "v32");
        assert_eq!(bits(&v32.values), expect(k().map(|k| k * 0.25)));
        let big = channel(&record, "big");
        assert_eq!(bits(&big.values), expect(k().map(|k| k * 2f64.powi(40))));
    }

    #[test]
    fn reads_struct_fields_with_their_units_and_timing() {
        let record = read(STRUCT).unwrap();
        assert_eq!(
            names(&record),
            ["rec.t", "rec.force", "wave.x", "s.a", "s.b", "s.inner.y"]
        );
        let unit = |name| channel(&record, name).unit.as_deref();
        assert_eq!(unit("rec.t"), Some("N"));
        assert_eq!(unit("rec.force"), Some("N"));
        assert_eq!(unit("wave.x"), None);
        assert_eq!(unit("s.a"), Some("N"));
        assert_eq!(unit("s.b"), Some("mm"));
        assert_eq!(unit("s.inner.y"), Some("V"));
        let wave = channel(&record, "wave.x");
        let timing = Waveform {
            start: 0.5,
            increment: 1e-3,
        };
        assert_eq!(wave.timing, Some(timing));
        assert_eq!(bits(&wave.values), expect(k().map(|k| k * 2.0)));
        assert!(channel(&record, "rec.t").timing.is_none());
        let y = channel(&record, "s.inner.y");
        assert_eq!(bits(&y.values), expect(k().map(|k| k * 3.0)));
        let force = channel(&record, "rec.force");
        let expected = k().map(|k| k * 0.5 - 2.25 + k * k * 1e-2);
        assert_eq!(bits(&force.values), expect(expected));
    }

    /// A little-endian element: tag, data, padding to 8 bytes.
    fn el(kind: u32, data: &[u8]) -> Vec<u8> {
        let mut out = kind.to_le_bytes().to_vec();
        out.extend((data.len() as u32).to_le_bytes());
        out.extend(data);
        out.resize(out.len().next_multiple_of(8), 0);
        out
    }

    /// A little-endian `miMATRIX` of class `class` holding `body` after its
    /// flags, dimensions and name (the name in the small form).
    fn matrix(class: u32, dims: &[i32], name: &str, body: &[u8]) -> Vec<u8> {
        let mut inner = el(6, &[class.to_le_bytes(), [0; 4]].concat());
        let dims: Vec<u8> = dims.iter().flat_map(|d| d.to_le_bytes()).collect();
        inner.extend(el(5, &dims));
        if name.len() <= 4 {
            let mut small = (1u32 | (name.len() as u32) << 16).to_le_bytes().to_vec();
            small.extend(name.as_bytes());
            small.resize(8, 0);
            inner.extend(small);
        } else {
            inner.extend(el(1, name.as_bytes()));
        }
        inner.extend(body);
        el(MI_MATRIX, &inner)
    }

    fn file(elements: &[Vec<u8>]) -> Vec<u8> {
        let mut out = b"MATLAB 5.0 MAT-file, written by a unit test".to_vec();
        out.resize(116, b' ');
        out.extend([0; 8]);
        out.extend([0x00, 0x01, b'I', b'M']);
        out.extend(elements.concat());
        out
    }

    #[test]
    fn reads_doubles_stored_in_a_smaller_type() {
        // MATLAB stores a double array of small integers as miUINT8.
        let v = matrix(6, &[1, 3], "v", &el(2, &[7, 0, 255]));
        let record = read(&file(&[v])).unwrap();
        assert_eq!(record.channels[0].values, [7.0, 0.0, 255.0]);
    }

    #[test]
    fn a_count_that_disagrees_with_the_dimensions_is_an_error() {
        let v = matrix(6, &[1, 4], "v", &el(9, &[0; 24]));
        let e = read(&file(&[v])).unwrap_err();
        assert_eq!(e.at, format!("byte {}", 128 + 8 + 16 + 16 + 8));
        assert_eq!(e.expected, "1×4 = 4 values");
        assert_eq!(e.found, "3 values");
    }

    #[test]
    fn a_file_without_numeric_vectors_is_an_error_saying_so() {
        let scalar = matrix(6, &[1, 1], "g", &el(9, &2f64.to_le_bytes()));
        let text = matrix(4, &[1, 2], "c", &el(16, b"hi"));
        let e = read(&file(&[scalar, text])).unwrap_err();
        assert_eq!(e.at, "the whole file");
        assert!(e.expected.contains("numeric vector or matrix"), "{e}");
        assert_eq!(e.found, "2 variables, none of them one");
    }

    #[test]
    fn truncation_and_a_bad_header_are_errors_naming_the_byte() {
        let e = read(V5.get(..300).unwrap()).unwrap_err();
        // `t_s`: a 176-byte element whose tag is at byte 128.
        assert_eq!(e.at, "byte 128");
        assert!(e.expected.contains("of 176 bytes within"), "{e}");
        assert_eq!(e.found, "164 bytes left");
        let mut bad = V5.to_vec();
        bad[126..128].copy_from_slice(b"XX");
        let e = read(&bad).unwrap_err();
        assert_eq!(e.at, "byte 126");
        assert!(e.expected.contains("endian indicator IM or MI"), "{e}");
        assert!(!is_mat5(&bad));
        let e = read(b"MATLAB").unwrap_err();
        assert_eq!((e.at.as_str(), e.found.as_str()), ("byte 0", "6 bytes"));
    }

    #[test]
    fn v73_files_are_told_apart_and_refused() {
        let mut header = b"MATLAB 7.3 MAT-file, Platform: GLNXA64".to_vec();
        header.resize(128, 0);
        assert!(is_mat73(&header) && !is_mat5(&header));
        let e = read(&header).unwrap_err();
        assert!(e.expected.contains("v7.3 files are HDF5"), "{e}");
        let mut userblock = vec![b' '; 512];
        userblock.extend(HDF5_SIGNATURE);
        assert!(is_mat73(&userblock));
        assert!(!is_mat73(V5));
    }

    #[test]
    fn a_compression_bomb_is_refused_before_inflating_it() {
        use std::io::Write;
        let inner = matrix(6, &[1, 1 << 17], "v", &el(9, &vec![0; 8 << 17]));
        let mut z = flate2::write::ZlibEncoder::new(Vec::new(), flate2::Compression::best());
        z.write_all(&inner).unwrap();
        let compressed = z.finish().unwrap();
        assert!(compressed.len() * 64 < inner.len());
        let mut zel = MI_COMPRESSED.to_le_bytes().to_vec();
        zel.extend((compressed.len() as u32).to_le_bytes());
        zel.extend(&compressed);
        let e = read(&file(&[zel])).unwrap_err();
        assert_eq!(e.at, "byte 128");
        assert!(e.expected.contains("64 times"), "{e}");
    }

    #[test]
    fn deep_nesting_is_an_error_not_a_stack_overflow() {
        let mut v = matrix(6, &[1, 2], "", &el(9, &[0; 16]));
        for _ in 0..40 {
            let mut body = el(5, &4u32.to_le_bytes());
            body.extend(el(1, b"a\0\0\0"));
            body.extend(v);
            v = matrix(2, &[1, 1], "", &body);
        }
        let named = {
            let mut body = el(5, &4u32.to_le_bytes());
            body.extend(el(1, b"a\0\0\0"));
            body.extend(v);
            matrix(2, &[1, 1], "s", &body)
        };
        let e = read(&file(&[named])).unwrap_err();
        assert!(e.expected.contains("nested at most 32 deep"), "{e}");
    }

    #[test]
    fn a_bad_sample_interval_is_an_error() {
        let mut body = el(5, &4u32.to_le_bytes());
        body.extend(el(1, b"dt\0\0x\0\0\0"));
        body.extend(matrix(6, &[1, 1], "", &el(9, &(-1f64).to_le_bytes())));
        body.extend(matrix(6, &[1, 2], "", &el(9, &[0; 16])));
        let e = read(&file(&[matrix(2, &[1, 1], "w", &body)])).unwrap_err();
        assert_eq!(e.at, "variable w.dt");
        assert!(e.found.contains("interval -1 s"), "{e}");
    }

    /// A struct `s` of an int16 2×2 field `m` and a char field `units`.
    fn int16_struct() -> Vec<u8> {
        let body = el(5, &8u32.to_le_bytes());
        let names = el(1, b"m\0\0\0\0\0\0\0units\0\0\0");
        let field = matrix(6, &[2, 2], "", &el(3, &[1, 0, 2, 0, 3, 0, 0xfc, 0xff]));
        let units = matrix(4, &[1, 1], "", &el(16, b"N"));
        matrix(2, &[1, 1], "s", &[body, names, field, units].concat())
    }

    #[test]
    fn reads_a_struct_of_an_int16_matrix_with_its_unit() {
        let record = read(&file(&[int16_struct()])).unwrap();
        assert_eq!(names(&record), ["s.m(:,1)", "s.m(:,2)"]);
        assert_eq!(record.channels[1].values, [3.0, -4.0]);
        assert_eq!(record.channels[1].unit.as_deref(), Some("N"));
        let (kind, inflated) = (MI_MATRIX, int16_struct());
        assert_eq!(inflated[..4], kind.to_le_bytes());
        assert!(compressed_variable(&inflated, false).unwrap().is_some());
    }

    proptest! {
        #[test]
        fn truncated_or_flipped_files_never_panic(
            file in 0usize..4,
            cut in 0usize..4096,
            flips in proptest::collection::vec((0usize..4096, any::<u8>()), 0..8),
        ) {
            let mut bytes = [V5, BE, COMPRESSED, STRUCT][file].to_vec();
            for (at, x) in flips {
                let n = bytes.len();
                bytes[at % n] ^= x;
            }
            bytes.truncate(cut);
            let _ = read(&bytes);
            let _ = (is_mat5(&bytes), is_mat73(&bytes));
        }

        #[test]
        fn flipped_decompressed_elements_never_panic(
            flips in proptest::collection::vec((0usize..1024, any::<u8>()), 1..8),
            big_endian in any::<bool>(),
        ) {
            let mut inflated = int16_struct();
            for (at, x) in flips {
                let n = inflated.len();
                inflated[at % n] ^= x;
            }
            let _ = compressed_variable(&inflated, big_endian);
        }
    }
}
