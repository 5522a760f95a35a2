//! The universal file format's dataset 58 (function at nodal DOF), ASCII and
//! binary (`58b`), as the "Universal File Format" specification describes
//! it: a file is a run of datasets, each opened and closed by a line `-1`;
//! every dataset 58 becomes one or more channels, and the other datasets
//! (151, 164, 2411, 55, …) are skipped.
//!
//! Channels, one group per dataset 58 in file order. The name is ID line 1
//! (record 1) trimmed, where it is non-empty, not `NONE` and unique among the
//! file's datasets 58; a shared ID line 1 gets ` (N)` added, and an empty one
//! becomes `dataset N`, N counting the file's datasets 58 from 1. The unit is
//! the ordinate's units label (record 9) unless empty or `NONE`. An evenly
//! spaced function over time (abscissa specific data type 17, or abscissa
//! units label `s`) gets the timing `start` = abscissa minimum, `increment`
//! = abscissa increment (record 7); other abscissae give no timing. An
//! unevenly spaced function puts its abscissa values in a channel
//! `<name>/abscissa` (unit from record 8) right before the ordinate. A
//! complex ordinate becomes `<name>/real` and `<name>/imag`.
//!
//! ASCII data lines are read field by field as the record's fixed widths
//! lay them out (E13.5 for single precision, E20.12 for double, E13.5
//! abscissae when uneven), or as whitespace-separated numbers; Fortran
//! exponents written with `D` or without a letter (`1.5-100`) are read too.
//! Binary data is as many values as record 7 calls for (single or double
//! IEEE 754, in the byte order the `58b` line states), straight after the
//! eleven header records and followed by the line `-1`; the `58b` line's
//! byte count is not relied on, since some writers state points × 8 there
//! whatever the data holds.

use std::collections::{HashMap, HashSet};

use super::{Channel, Format, FormatError, Record, Waveform, bytes::Cursor};

/// The specific data type that marks an axis as time (records 8–11).
const TIME: i64 = 17;

/// Whether `bytes` look like a universal file holding a dataset 58: the
/// first non-blank line is `-1`, and a line right after a `-1` line opens a
/// dataset 58 or 58b.
pub fn is_uff(bytes: &[u8]) -> bool {
    let mut lines = Lines { bytes, pos: 0 };
    match lines.next_non_blank() {
        Some(line) if line.text.trim_ascii() == b"-1" => {}
        _ => return false,
    }
    let mut after_delimiter = true;
    while let Some(line) = lines.next_line() {
        if after_delimiter && matches!(dataset_header(line.text), Some((58, _, _))) {
            return true;
        }
        after_delimiter = line.text.trim_ascii() == b"-1";
    }
    false
}

/// Reads every dataset 58 of a universal file into a [`Record`] (see the
/// module docs for the channels it makes).
pub fn read(bytes: &[u8]) -> Result<Record, FormatError> {
    let mut reader = Reader {
        bytes,
        lines: Lines { bytes, pos: 0 },
    };
    let mut functions = Vec::new();
    let mut others = Vec::new();
    while let Some(open) = reader.lines.next_non_blank() {
        if open.text.trim_ascii() != b"-1" {
            return Err(reader.error(open, "`    -1` opening a dataset", shown(open.text)));
        }
        let Some(head) = reader.lines.next_line() else {
            return Err(reader.error_at_end("a dataset number after `-1`"));
        };
        let Some((number, binary, fields)) = dataset_header(head.text) else {
            return Err(reader.error(head, "a dataset number after `-1`", shown(head.text)));
        };
        if number == 58 {
            let fields = binary.then_some(fields);
            functions.push(reader.dataset58(head, fields)?);
        } else {
            reader.skip_dataset(head, number, binary.then_some(fields))?;
            if !others.contains(&number) {
                others.push(number);
            }
        }
    }
    if functions.is_empty() {
        let found = if others.is_empty() {
            "no dataset, so no numeric channel".to_string()
        } else {
            let others: Vec<String> = others.iter().map(u64::to_string).collect();
            format!("only datasets {}, so no numeric channel", others.join(", "))
        };
        return Err(FormatError {
            format: Format::Uff,
            at: "end of file".into(),
            expected: "a dataset 58 (function at nodal DOF)".into(),
            found,
        });
    }
    Ok(Record {
        format: Format::Uff,
        channels: channels(functions),
    })
}

/// One line of the file: where it starts and its bytes, without the line
/// ending (`\n` or `\r\n`).
#[derive(Debug, Clone, Copy)]
struct Line<'a> {
    start: usize,
    text: &'a [u8],
}

/// The file's lines from a byte position on.
struct Lines<'a> {
    bytes: &'a [u8],
    pos: usize,
}

impl<'a> Lines<'a> {
    fn next_line(&mut self) -> Option<Line<'a>> {
        let rest = self.bytes.get(self.pos..).filter(|rest| !rest.is_empty())?;
        let start = self.pos;
        let (text, used) = match rest.iter().position(|&b| b == b'\n') {
            Some(end) => (rest.split_at(end).0, end + 1),
            None => (rest, rest.len()),
        };
        self.pos += used;
        let text = text.strip_suffix(b"\r").unwrap_or(text);
        Some(Line { start, text })
    }

    fn next_non_blank(&mut self) -> Option<Line<'a>> {
        std::iter::from_fn(|| self.next_line()).find(|line| !line.text.trim_ascii().is_empty())
    }
}

/// A dataset's number, whether it is binary (`58b`), and the fields after
/// the number on its header line; `None` if the line does not start with a
/// number.
fn dataset_header(text: &[u8]) -> Option<(u64, bool, &str)> {
    let text = std::str::from_utf8(text).ok()?.trim_start();
    let digits = text
        .find(|c: char| !c.is_ascii_digit())
        .unwrap_or(text.len());
    let (number, rest) = text.split_at(digits);
    let number = number.parse().ok()?;
    let binary = rest.starts_with(['b', 'B']);
    let rest = rest.get(usize::from(binary)..)?;
    if !rest.is_empty() && !rest.starts_with(char::is_whitespace) {
        return None;
    }
    Some((number, binary, rest))
}

/// `text` quoted for an error message, cut after 60 characters.
fn shown(text: &[u8]) -> String {
    let text = String::from_utf8_lossy(text);
    let text = text.trim_end();
    if text.is_empty() {
        return "an empty line".into();
    }
    let cut: String = text.chars().take(60).collect();
    let more = if cut.len() < text.len() { "…" } else { "" };
    format!("`{cut}{more}`")
}

/// Reads a number field: E-format, plain, Fortran `D` exponent, or a
/// Fortran exponent without its letter (`-1.23456-100`).
fn number(field: &str) -> Option<f64> {
    let field = field.trim();
    if field.is_empty() {
        return None;
    }
    if let Ok(value) = field.parse() {
        return Some(value);
    }
    let mut fixed = field.replace(['D', 'd'], "E");
    if let Ok(value) = fixed.parse() {
        return Some(value);
    }
    let sign = fixed.rfind(['+', '-']).filter(|&at| {
        at > 0
            && fixed
                .get(..at)
                .is_some_and(|head| head.ends_with(|c: char| c.is_ascii_digit() || c == '.'))
    })?;
    fixed.insert(sign, 'E');
    fixed.parse().ok()
}

/// An integer field, trimmed.
fn integer(field: &str) -> Option<i64> {
    field.trim().parse().ok()
}

/// Characters `from..to` of an ASCII line (fewer where it is shorter).
fn columns(text: &[u8], from: usize, to: usize) -> &str {
    let end = to.min(text.len());
    text.get(from.min(end)..end)
        .and_then(|field| std::str::from_utf8(field).ok())
        .unwrap_or("")
}

/// Record 7: ordinate data type, number of points, abscissa spacing,
/// abscissa minimum, abscissa increment — read as whitespace-separated
/// fields, or else by the specification's columns (3I10, 3E13.5).
fn record7(text: &[u8]) -> Option<(i64, i64, i64, f64, f64)> {
    let free = || {
        let line = std::str::from_utf8(text).ok()?;
        let fields: Vec<&str> = line.split_whitespace().collect();
        match fields.as_slice() {
            [kind, points, spacing, min, increment]
            | [kind, points, spacing, min, increment, _] => Some((
                integer(kind)?,
                integer(points)?,
                integer(spacing)?,
                number(min)?,
                number(increment)?,
            )),
            _ => None,
        }
    };
    free().or_else(|| {
        Some((
            integer(columns(text, 0, 10))?,
            integer(columns(text, 10, 20))?,
            integer(columns(text, 20, 30))?,
            number(columns(text, 30, 43))?,
            number(columns(text, 43, 56))?,
        ))
    })
}

/// Records 8–11: the axis's specific data type (I10, or the line's first
/// field) and its units label (columns 48–67, after the axis label).
fn axis(text: &[u8]) -> Option<(i64, Option<String>)> {
    let kind = integer(columns(text, 0, 10)).or_else(|| {
        let line = std::str::from_utf8(text).ok()?;
        integer(line.split_whitespace().next()?)
    })?;
    let line = String::from_utf8_lossy(text);
    let label: String = line.chars().skip(47).take(20).collect();
    Some((kind, unit(&label)))
}

/// A units label, unless empty or `NONE`.
fn unit(label: &str) -> Option<String> {
    let label = label.trim();
    (!label.is_empty() && !label.eq_ignore_ascii_case("none")).then(|| label.to_string())
}

/// Whether an axis with this specific data type and unit is time.
fn is_time(kind: i64, unit: Option<&str>) -> bool {
    kind == TIME || unit.is_some_and(|u| u == "s" || u.eq_ignore_ascii_case("sec"))
}

/// One dataset 58 as read.
#[derive(Debug)]
struct Function {
    id: String,
    layout: Layout,
    start: f64,
    increment: f64,
    abscissa_time: bool,
    abscissa_unit: Option<String>,
    ordinate_unit: Option<String>,
    /// The data values, interleaved as the file holds them.
    values: Vec<f64>,
}

/// Layout of record 7's data: ordinate type, precision and spacing.
#[derive(Debug, Clone, Copy)]
struct Layout {
    complex: bool,
    double: bool,
    even: bool,
}

impl Layout {
    /// Values per point: abscissa (when uneven), real, imaginary (when complex).
    fn stride(self) -> usize {
        1 + usize::from(self.complex) + usize::from(!self.even)
    }

    /// The fixed field widths of one ASCII data line, repeating.
    fn widths(self) -> &'static [usize] {
        match (self.double, self.even, self.complex) {
            (false, _, _) => &[13],
            (true, true, _) => &[20],
            (true, false, false) => &[13, 20],
            (true, false, true) => &[13, 20, 20],
        }
    }
}

/// Reads numbers from one ASCII data line into `out`: whitespace-separated
/// fields, or else fixed-width fields; false (and `out` unchanged) if
/// neither reading works.
fn data_line(text: &[u8], widths: &[usize], out: &mut Vec<f64>) -> bool {
    let Ok(line) = std::str::from_utf8(text) else {
        return false;
    };
    let mark = out.len();
    if line
        .split_whitespace()
        .all(|field| number(field).map(|v| out.push(v)).is_some())
    {
        return true;
    }
    out.truncate(mark);
    if !line.is_ascii() {
        return false;
    }
    let mut rest = line;
    for &width in widths.iter().cycle() {
        if rest.trim().is_empty() {
            return true;
        }
        let (field, tail) = rest.split_at(width.min(rest.len()));
        let Some(value) = number(field) else {
            out.truncate(mark);
            return false;
        };
        out.push(value);
        rest = tail;
    }
    true
}

/// Walks a file's datasets, naming lines and bytes in its errors.
struct Reader<'a> {
    bytes: &'a [u8],
    lines: Lines<'a>,
}

impl<'a> Reader<'a> {
    fn line_number(&self, start: usize) -> usize {
        self.bytes
            .iter()
            .take(start)
            .filter(|&&b| b == b'\n')
            .count()
            + 1
    }

    fn error(
        &self,
        line: Line,
        expected: impl Into<String>,
        found: impl Into<String>,
    ) -> FormatError {
        self.error_at(line.start, expected.into(), found.into())
    }

    fn error_at_end(&self, expected: impl Into<String>) -> FormatError {
        self.error_at(
            self.bytes.len(),
            expected.into(),
            "the end of the file".into(),
        )
    }

    fn error_at(&self, start: usize, expected: String, found: String) -> FormatError {
        let at = format!("line {}", self.line_number(start));
        FormatError {
            format: Format::Uff,
            at,
            expected,
            found,
        }
    }

    /// The next line, which record `what` of dataset 58 must be.
    fn record(&mut self, what: &str) -> Result<Line<'a>, FormatError> {
        self.lines
            .next_line()
            .ok_or_else(|| self.error_at_end(format!("{what} of dataset 58")))
    }

    /// The next line as axis record `what`: specific data type and unit.
    fn axis_record(&mut self, what: &str) -> Result<(i64, Option<String>), FormatError> {
        let line = self.record(what)?;
        let expected = || format!("{what} starting with its specific data type");
        axis(line.text).ok_or_else(|| self.error(line, expected(), shown(line.text)))
    }

    /// Reads one dataset 58 after its header line; `binary` holds the
    /// `58b` line's fields after `58b`.
    fn dataset58(&mut self, head: Line, binary: Option<&str>) -> Result<Function, FormatError> {
        let id_line = self.record("record 1 (ID line 1)")?;
        for what in [
            "record 2 (ID line 2)",
            "record 3 (ID line 3)",
            "record 4 (ID line 4)",
            "record 5 (ID line 5)",
            "record 6 (DOF identification)",
        ] {
            self.record(what)?;
        }
        let form = self.record("record 7 (data form)")?;
        let (kind, points, spacing, start, increment) = record7(form.text).ok_or_else(|| {
            self.error(
                form,
                "record 7 of dataset 58: ordinate data type, number of points, abscissa spacing, \
                 minimum and increment (3I10, 3E13.5)",
                shown(form.text),
            )
        })?;
        let (complex, double) = match kind {
            2 => (false, false),
            4 => (false, true),
            5 => (true, false),
            6 => (true, true),
            _ => {
                return Err(self.error(
                    form,
                    "ordinate data type 2, 4 (real single, double) or 5, 6 (complex single, double)",
                    format!("{kind}"),
                ));
            }
        };
        let even = match spacing {
            1 => true,
            0 => false,
            _ => {
                return Err(self.error(
                    form,
                    "abscissa spacing 1 (even) or 0 (uneven)",
                    format!("{spacing}"),
                ));
            }
        };
        let layout = Layout {
            complex,
            double,
            even,
        };
        let points = usize::try_from(points).map_err(|_| {
            self.error(form, "a number of points of 0 or more", format!("{points}"))
        })?;
        let total = points.checked_mul(layout.stride()).ok_or_else(|| {
            self.error(
                form,
                "a number of points the file can hold",
                format!("{points}"),
            )
        })?;
        let (abscissa_kind, abscissa_unit) = self.axis_record("record 8 (abscissa axis)")?;
        let (_, ordinate_unit) = self.axis_record("record 9 (ordinate numerator axis)")?;
        self.record("record 10 (ordinate denominator axis)")?;
        self.record("record 11 (z axis)")?;
        let values = match binary {
            None => self.ascii_data(layout, total, points)?,
            Some(fields) => self.binary_data(head, fields, layout, total)?,
        };
        Ok(Function {
            id: String::from_utf8_lossy(id_line.text).trim().to_string(),
            layout,
            start,
            increment,
            abscissa_time: is_time(abscissa_kind, abscissa_unit.as_deref()),
            abscissa_unit,
            ordinate_unit,
            values,
        })
    }

    /// ASCII data lines up to the closing `-1`: exactly `total` values.
    fn ascii_data(
        &mut self,
        layout: Layout,
        total: usize,
        points: usize,
    ) -> Result<Vec<f64>, FormatError> {
        let mut values = Vec::new();
        let widths = layout.widths();
        loop {
            let Some(line) = self.lines.next_line() else {
                return Err(self.error_at_end(format!(
                    "{total} data values ({points} points) and `-1` closing dataset 58"
                )));
            };
            if line.text.trim_ascii() == b"-1" {
                if values.len() != total {
                    return Err(self.error(
                        line,
                        format!(
                            "{total} data values ({points} points) before `-1` closing dataset 58"
                        ),
                        format!("{} values", values.len()),
                    ));
                }
                return Ok(values);
            }
            if !data_line(line.text, widths, &mut values) {
                let layout: Vec<String> = widths.iter().map(|w| format!("E{w}")).collect();
                return Err(self.error(
                    line,
                    format!(
                        "data values (fields {}) or `-1` closing dataset 58",
                        layout.join(", ")
                    ),
                    shown(line.text),
                ));
            }
            if values.len() > total {
                return Err(self.error(
                    line,
                    format!("{total} data values ({points} points) in dataset 58"),
                    format!("{} by this line", values.len()),
                ));
            }
        }
    }

    /// Binary data after a `58b` header: `total` values, then `-1`.
    fn binary_data(
        &mut self,
        head: Line,
        fields: &str,
        layout: Layout,
        total: usize,
    ) -> Result<Vec<f64>, FormatError> {
        let fields: Vec<&str> = fields.split_whitespace().collect();
        let field = |k: usize| fields.get(k).and_then(|f| integer(f));
        let big_endian = match field(0) {
            Some(1) => false,
            Some(2) => true,
            _ => {
                let found = fields
                    .first()
                    .map_or("nothing".into(), |f| format!("`{f}`"));
                return Err(self.error(
                    head,
                    "58b byte ordering 1 (little endian) or 2 (big endian)",
                    found,
                ));
            }
        };
        if field(1) != Some(2) {
            let found = fields.get(1).map_or("nothing".into(), |f| format!("`{f}`"));
            return Err(self.error(head, "58b floating-point format 2 (IEEE 754)", found));
        }
        let size = if layout.double { 8 } else { 4 };
        let mut cursor = Cursor::new(self.bytes, Format::Uff);
        cursor.seek(self.lines.pos, "58b data")?;
        cursor.set_big_endian(big_endian);
        let length = total
            .checked_mul(size)
            .ok_or_else(|| cursor.error("58b data the file can hold", format!("{total} values")))?;
        cursor.clone().take(length, "58b data")?;
        let mut values = Vec::with_capacity(total);
        for _ in 0..total {
            values.push(if layout.double {
                cursor.f64("a 58b value")?
            } else {
                f64::from(cursor.f32("a 58b value")?)
            });
        }
        self.lines.pos = cursor.pos();
        match self.lines.next_non_blank() {
            Some(line) if line.text.trim_ascii() == b"-1" => Ok(values),
            other => {
                let stated =
                    field(3).map_or(String::new(), |n| format!("; its 58b line states {n}"));
                Err(cursor.error(
                    format!(
                        "`-1` closing dataset 58b after {length} bytes of data \
                         ({total} values of {size} bytes{stated})"
                    ),
                    other.map_or("the end of the file".into(), |line| shown(line.text)),
                ))
            }
        }
    }

    /// Skips a dataset other than 58 up to its closing `-1`; a binary one
    /// by its header's ASCII line and byte counts where it states them.
    fn skip_dataset(
        &mut self,
        head: Line,
        number: u64,
        binary: Option<&str>,
    ) -> Result<(), FormatError> {
        let counts = binary.and_then(|fields| {
            let mut fields = fields.split_whitespace().skip(2);
            Some((fields.next()?.parse().ok()?, fields.next()?.parse().ok()?))
        });
        if let Some((ascii_lines, bytes)) = counts {
            for _ in 0..ascii_lines {
                self.lines.next_line().ok_or_else(|| {
                    self.error_at_end(format!("{ascii_lines} ASCII lines of dataset {number}b"))
                })?;
            }
            let mut cursor = Cursor::new(self.bytes, Format::Uff);
            cursor.seek(self.lines.pos, "binary data")?;
            cursor.take(bytes, &format!("binary data of dataset {number}b"))?;
            self.lines.pos = cursor.pos();
        }
        let closing = |reader: &Self| {
            let binary = if counts.is_some() { "b" } else { "" };
            let opened = reader.line_number(head.start);
            format!("`-1` closing dataset {number}{binary} opened at line {opened}")
        };
        if counts.is_some() {
            return match self.lines.next_non_blank() {
                Some(line) if line.text.trim_ascii() == b"-1" => Ok(()),
                Some(line) => Err(self.error(line, closing(self), shown(line.text))),
                None => Err(self.error_at_end(closing(self))),
            };
        }
        loop {
            match self.lines.next_line() {
                Some(line) if line.text.trim_ascii() == b"-1" => return Ok(()),
                Some(_) => {}
                None => return Err(self.error_at_end(closing(self))),
            }
        }
    }
}

/// The channels of the file's datasets 58, named as the module docs say.
fn channels(functions: Vec<Function>) -> Vec<Channel> {
    let mut uses: HashMap<&str, usize> = HashMap::new();
    for function in &functions {
        *uses.entry(function.id.as_str()).or_default() += 1;
    }
    let mut taken = HashSet::new();
    let mut names: Vec<String> = Vec::with_capacity(functions.len());
    for (k, function) in functions.iter().enumerate() {
        let n = k + 1;
        let id = function.id.as_str();
        let mut name = if id.is_empty() || id.eq_ignore_ascii_case("none") {
            format!("dataset {n}")
        } else if uses.get(id).copied().unwrap_or(0) > 1 {
            format!("{id} ({n})")
        } else {
            id.to_string()
        };
        while !taken.insert(name.clone()) {
            name = format!("{name} ({n})");
        }
        names.push(name);
    }
    let mut out = Vec::new();
    for (function, name) in functions.into_iter().zip(names) {
        let stride = function.layout.stride();
        let column = |offset: usize| -> Vec<f64> {
            function
                .values
                .iter()
                .skip(offset)
                .step_by(stride)
                .copied()
                .collect()
        };
        let mut offset = 0;
        if !function.layout.even {
            out.push(Channel {
                name: format!("{name}/abscissa"),
                unit: function.abscissa_unit.clone(),
                values: column(0),
                timing: None,
            });
            offset = 1;
        }
        let timing = (function.layout.even && function.abscissa_time).then_some(Waveform {
            start: function.start,
            increment: function.increment,
        });
        let parts: &[(&str, usize)] = if function.layout.complex {
            &[("/real", 0), ("/imag", 1)]
        } else {
            &[("", 0)]
        };
        for &(suffix, part) in parts {
            out.push(Channel {
                name: format!("{name}{suffix}"),
                unit: function.ordinate_unit.clone(),
                values: column(offset + part),
                timing,
            });
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    const EVEN: &[u8] = include_bytes!("../../tests/data/records/uff_even_double.uff");
    const UNEVEN: &[u8] = include_bytes!("../../tests/data/records/uff_uneven.uff");
    const MIXED: &[u8] = include_bytes!("../../tests/data/records/uff_mixed.uff");
    const BINARY: &[u8] = include_bytes!("../../tests/data/records/uff_binary.uff");
    const BINARY_BE32: &[u8] = include_bytes!("../../tests/data/records/uff_binary_be32.uff");

    /// The channels `make_uff.py` wrote beside each file: name, unit or `-`,
    /// `start,increment` or `-`, and the values as Python's shortest decimals.
    fn expected(listing: &str) -> Vec<Channel> {
        listing
            .lines()
            .map(|line| {
                let fields: Vec<&str> = line.split('\t').collect();
                assert_eq!(fields.len(), 4, "{line}");
                let timing = (fields[2] != "-").then(|| {
                    let (start, increment) = fields[2].split_once(',').unwrap();
                    Waveform {
                        start: start.parse().unwrap(),
                        increment: increment.parse().unwrap(),
                    }
                });
                Channel {
                    name: fields[0].to_string(),
                    unit: (fields[1] != "-").then(|| fields[1].to_string()),
                    values: fields[3].split(' ').map(|v| v.parse().unwrap()).collect(),
                    timing,
                }
            })
            .collect()
    }

    /// Reads `file` and compares it with its listing, values bit for bit.
    fn check(file: &[u8], listing: &str) {
        assert!(is_uff(file));
        let record = read(file).unwrap();
        assert_eq!(record.format, Format::Uff);
        let want = expected(listing);
        let names: Vec<&str> = record.channels.iter().map(|c| c.name.as_str()).collect();
        let want_names: Vec<&str> = want.iter().map(|c| c.name.as_str()).collect();
        assert_eq!(names, want_names);
        for (got, want) in record.channels.iter().zip(&want) {
            assert_eq!(got.unit, want.unit, "{}", got.name);
            assert_eq!(got.timing, want.timing, "{}", got.name);
            let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
            assert_eq!(bits(&got.values), bits(&want.values), "{}", got.name);
        }
    }

    #[test]
    fn ascii_even_double_gives_timed_channels_equal_to_the_written_decimals() {
        check(
            EVEN,
            include_str!("../../tests/data/records/uff_even_double.expected"),
        );
    }

    #[test]
    fn ascii_uneven_gives_abscissa_channels_and_numbers_shared_names() {
        check(
            UNEVEN,
            include_str!("../../tests/data/records/uff_uneven.expected"),
        );
    }

    #[test]
    fn a_dataset_151_is_skipped_and_a_complex_ordinate_splits() {
        check(
            MIXED,
            include_str!("../../tests/data/records/uff_mixed.expected"),
        );
    }

    #[test]
    fn binary_58b_as_pyuff_writes_it_is_read_whatever_its_byte_count_says() {
        check(
            BINARY,
            include_str!("../../tests/data/records/uff_binary.expected"),
        );
    }

    #[test]
    fn binary_58b_big_endian_single_precision_is_read() {
        check(
            BINARY_BE32,
            include_str!("../../tests/data/records/uff_binary_be32.expected"),
        );
    }

    #[test]
    fn crlf_line_endings_read_the_same() {
        let text = std::str::from_utf8(EVEN).unwrap().replace('\n', "\r\n");
        assert_eq!(read(text.as_bytes()).unwrap(), read(EVEN).unwrap());
    }

    /// A minimal ASCII dataset 58 with record 7 `form`, axis lines and data.
    fn dataset(id: &str, form: &str, abscissa: &str, data: &str) -> String {
        let axis = |kind: i32, label: &str, unit: &str| {
            format!(
                "{kind:>10}{:>5}{:>5}{:>5} {label:<20} {unit:<20}\n",
                0, 0, 0
            )
        };
        format!(
            "    -1\n    58\n{id}\nNONE\nNONE\nNONE\nNONE\n    1         0    0         0       NONE         1   3       NONE         0   0\n{form}\n{}{}{}{}{data}    -1\n",
            axis(0, "Time", abscissa),
            axis(8, "Displacement", "mm"),
            axis(0, "NONE", "NONE"),
            axis(0, "NONE", "NONE"),
        )
    }

    #[test]
    fn fixed_width_fields_that_run_together_and_fortran_exponents_are_read() {
        let data = "  1.00000e+00-1.00000e-100  3.00000D+00\n -2.50000-100\n";
        let file = dataset(
            "",
            "         2         4         1  1.00000e+00  2.00000e+00  0.00000e+00",
            "Hz",
            data,
        );
        let record = read(file.as_bytes()).unwrap();
        let [channel] = record.channels.as_slice() else {
            panic!("{record:?}")
        };
        assert_eq!(channel.name, "dataset 1");
        assert_eq!(channel.unit.as_deref(), Some("mm"));
        assert_eq!(channel.timing, None, "a frequency abscissa has no timing");
        assert_eq!(channel.values, vec![1.0, -1.0e-100, 3.0, -2.5e-100]);
    }

    #[test]
    fn free_format_record_7_and_a_seconds_label_give_timing() {
        let file = dataset("x", "4 2 1 0.5 0.25 0", "s", "1.0 2.0\n");
        let record = read(file.as_bytes()).unwrap();
        assert_eq!(
            record.channels[0].timing,
            Some(Waveform {
                start: 0.5,
                increment: 0.25
            })
        );
        assert_eq!(record.channels[0].values, vec![1.0, 2.0]);
    }

    #[test]
    fn abscissa_type_17_is_time_whatever_its_units_label() {
        let form = "4 2 1 0.5 0.25 0";
        let file = dataset("x", form, "ms", "1.0 2.0\n");
        assert_eq!(read(file.as_bytes()).unwrap().channels[0].timing, None);
        let file = file.replacen(
            "         0    0    0    0 Time",
            "        17    0    0    0 Time",
            1,
        );
        let timing = read(file.as_bytes()).unwrap().channels[0].timing;
        assert_eq!(
            timing,
            Some(Waveform {
                start: 0.5,
                increment: 0.25
            })
        );
    }

    #[test]
    fn other_datasets_ascii_and_binary_are_skipped() {
        let binary =
            b"    -1\n  2414b     1     2           2           5\nA\nB\n-1\n\x00\xff    -1\n";
        let ascii = b"    -1\n   164\nSI\n    -1\n";
        let function = dataset("x", "4 1 1 0 1 0", "s", "7.0\n");
        let file = [&binary[..], &ascii[..], function.as_bytes()].concat();
        assert!(is_uff(&file));
        let record = read(&file).unwrap();
        assert_eq!(record.channels.len(), 1);
        assert_eq!(record.channels[0].values, vec![7.0]);
        let e = read(&file[..binary.len() - 3]).unwrap_err();
        assert!(
            e.expected
                .contains("`-1` closing dataset 2414b opened at line 2"),
            "{e}"
        );
    }

    #[test]
    fn binary_data_not_followed_by_minus_one_names_the_byte_after_it() {
        let text = String::from_utf8_lossy(BINARY_BE32).replace(
            "         2         7         1",
            "         2         6         1",
        );
        let data_at = BINARY_BE32.len() - 7 - 28;
        let file = [
            text.as_bytes().get(..data_at).unwrap(),
            &BINARY_BE32[data_at..],
        ]
        .concat();
        let e = read(&file).unwrap_err();
        assert_eq!(e.at, format!("byte {}", data_at + 24));
        assert!(
            e.expected
                .contains("after 24 bytes of data (6 values of 4 bytes; its 58b line states 28)"),
            "{e}"
        );
    }

    #[test]
    fn names_stay_unique_when_an_id_line_reads_like_a_made_up_name() {
        let form = "4 1 1 0 1 0";
        let file = [
            dataset("", form, "s", "1.0\n"),
            dataset("dataset 1", form, "s", "2.0\n"),
        ]
        .concat();
        let record = read(file.as_bytes()).unwrap();
        let names: Vec<&str> = record.channels.iter().map(|c| c.name.as_str()).collect();
        assert_eq!(names, ["dataset 1", "dataset 1 (2)"]);
    }

    #[test]
    fn too_few_values_name_the_closing_line() {
        let file = dataset(
            "x",
            "         4         3         1  0.00000e+00  1.00000e+00  0.00000e+00",
            "s",
            "   1.0e+00   2.0e+00\n",
        );
        let e = read(file.as_bytes()).unwrap_err();
        assert_eq!(e.at, "line 15");
        assert!(e.expected.contains("3 data values (3 points)"), "{e}");
        assert_eq!(e.found, "2 values");
    }

    #[test]
    fn an_unknown_ordinate_type_names_record_7() {
        let file = dataset(
            "x",
            "         3         1         1  0.00000e+00  1.00000e+00  0.00000e+00",
            "s",
            "1.0\n",
        );
        let e = read(file.as_bytes()).unwrap_err();
        assert_eq!(e.at, "line 9");
        assert!(e.expected.contains("ordinate data type"), "{e}");
        assert_eq!(e.found, "3");
    }

    #[test]
    fn a_bad_data_field_names_its_line() {
        let file = dataset(
            "x",
            "         4         2         1  0.00000e+00  1.00000e+00  0.00000e+00",
            "s",
            "1.0 abc\n",
        );
        let e = read(file.as_bytes()).unwrap_err();
        assert_eq!(e.at, "line 14");
        assert!(e.found.contains("abc"), "{e}");
    }

    #[test]
    fn truncated_binary_data_names_the_byte() {
        let data_at = BINARY_BE32.len() - 7 - 28;
        let e = read(&BINARY_BE32[..data_at + 10]).unwrap_err();
        assert_eq!(e.at, format!("byte {data_at}"));
        assert!(e.expected.contains("28 bytes of 58b data"), "{e}");
    }

    #[test]
    fn a_file_without_dataset_58_says_it_has_no_numeric_channel() {
        let only_151 = &MIXED[..MIXED.len() - dataset_58_length(MIXED)];
        assert!(!is_uff(only_151));
        let e = read(only_151).unwrap_err();
        assert!(
            e.found.contains("only datasets 151") && e.found.contains("no numeric channel"),
            "{e}"
        );
    }

    /// Bytes from the last `    -1\n    58` to the end.
    fn dataset_58_length(file: &[u8]) -> usize {
        let text = std::str::from_utf8(file).unwrap();
        text.len() - text.rfind("    -1\n    58").unwrap()
    }

    #[test]
    fn other_files_are_not_uff() {
        assert!(!is_uff(b"time,force\n0,1\n"));
        assert!(!is_uff(b""));
        assert!(!is_uff(b"    -1\n   151\n    -1\n"));
        assert!(read(b"time,force\n0,1\n").unwrap_err().at == "line 1");
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(256))]

        #[test]
        fn truncated_or_flipped_files_never_panic(
            which in 0usize..5,
            cut in any::<prop::sample::Index>(),
            flips in prop::collection::vec((any::<prop::sample::Index>(), any::<u8>()), 0..6),
        ) {
            let file = [EVEN, UNEVEN, MIXED, BINARY, BINARY_BE32][which];
            let mut bytes = file[..cut.index(file.len() + 1)].to_vec();
            for (at, value) in flips {
                if !bytes.is_empty() {
                    let at = at.index(bytes.len());
                    bytes[at] ^= value;
                }
            }
            let _ = is_uff(&bytes);
            let _ = read(&bytes);
        }
    }
}
