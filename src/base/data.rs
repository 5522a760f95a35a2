//! Measured force histories: a small CSV loader that returns uniformly sampled
//! data or an error naming the file, the line and what was expected.
//!
//! Accepted files:
//! - lines starting with `#` (after leading blanks) and blank lines are skipped
//!   anywhere;
//! - the text is decoded by [`decode_record`]: UTF-8, UTF-16 with a byte-order
//!   mark, or Windows-1252 (Latin-1), detected or as [`CsvSpec::encoding`]
//!   states;
//! - the separator is, of those found on the first row outside double quotes,
//!   `;`, else tab, else `,`; with `;` or tab a decimal comma (`1,5`) is also
//!   accepted unless [`CsvSpec::decimal`] says the decimal mark is `.`. A
//!   decimal comma with `,` as the separator cannot be read: a stated one is
//!   refused, and so is a data row that holds more fields than the header, all
//!   of digits (`0,001,12,5` under `t,F`), with a hint
//!   ([`DECIMAL_COMMA_HINT`]);
//! - a header row of column names is required when a column is chosen by name;
//!   when both columns are chosen by index the first row is a header unless every
//!   field of it is a number;
//! - time must increase strictly; cells must be finite numbers;
//! - sampling that is not uniform (interval jitter above [`JITTER_TOLERANCE`] of
//!   the median interval) is resampled to the median interval by linear
//!   interpolation, with a warning.

use std::fmt;
use std::path::{Path, PathBuf};

use crate::base::encoding::{Encoding, decode};
use crate::base::text::echo_bare;

/// Relative jitter of the sample interval (against the median interval) above
/// which a record is resampled.
pub const JITTER_TOLERANCE: f64 = 1.0e-3;

/// Most that resampling may multiply a record's sample count by; beyond that
/// the record has gaps and is refused.
pub const MAX_RESAMPLE_GROWTH: usize = 10;

/// Selects a CSV column.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Column {
    /// By header name.
    Name(String),
    /// By 0-based position (0 is the first column; the command line's
    /// `identify` counts from 1, and messages say which).
    Index(usize),
}

impl fmt::Display for Column {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Column::Name(n) => write!(f, "'{}'", crate::base::text::echo_bare(n)),
            Column::Index(i) => write!(f, "#{i} (0-based: #0 is the first column)"),
        }
    }
}

/// The decimal mark of a record's numbers.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Decimal {
    /// `1.5`; a comma is never a decimal mark.
    Point,
    /// `1,5`; the separator must then be `;` or tab, and a `.` in a number is
    /// refused (it may be a thousands separator).
    Comma,
}

impl<'de> serde::Deserialize<'de> for Decimal {
    /// `"."` or `","`.
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        let mark = String::deserialize(d)?;
        match mark.as_str() {
            "." => Ok(Decimal::Point),
            "," => Ok(Decimal::Comma),
            _ => Err(serde::de::Error::custom(format!(
                "expected the decimal mark \".\" or \",\", found {}",
                quote(&mark)
            ))),
        }
    }
}

/// The hint of a file whose decimal mark and separator are both `,`.
pub const DECIMAL_COMMA_HINT: &str = "the decimal mark and the separator are both ',' (a decimal \
     comma in a comma-separated file): export with ';' as the separator, or with '.' as the \
     decimal mark";

/// Which columns hold time and force, their unit conversions, and how the
/// file's text is encoded and its numbers written.
#[derive(Debug, Clone, PartialEq)]
pub struct CsvSpec {
    /// Time column (default: the first, index 0).
    pub time: Column,
    /// Force column (default: the second, index 1).
    pub force: Column,
    /// Multiplier turning the time column into seconds (1e-3 for ms).
    pub time_scale: f64,
    /// Multiplier turning the force column into newtons (1e3 for kN).
    pub force_scale: f64,
    /// The text encoding (default `None`: detected, see
    /// [`crate::base::encoding::decode`]).
    pub encoding: Option<Encoding>,
    /// The decimal mark (default `None`: a point, or a comma where the
    /// separator is `;` or tab).
    pub decimal: Option<Decimal>,
}

impl Default for CsvSpec {
    fn default() -> Self {
        Self {
            time: Column::Index(0),
            force: Column::Index(1),
            time_scale: 1.0,
            force_scale: 1.0,
            encoding: None,
            decimal: None,
        }
    }
}

/// A uniformly sampled force history.
#[derive(Debug, Clone, PartialEq)]
pub struct Series {
    /// Sample times (s), `t[k] = t[0] + k·dt`.
    pub t: Vec<f64>,
    /// Force at each sample (N).
    pub force: Vec<f64>,
    /// Sample interval (s).
    pub dt: f64,
    /// Set when the record was resampled; says by how much it jittered.
    pub warning: Option<String>,
}

/// Why a measured-data file was refused. Every message names the file and, where
/// there is one, the line (1-based, counting comment lines).
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum DataError {
    /// The file could not be read.
    #[error("{}: cannot read: {message}", file.display())]
    Io {
        /// The data file.
        file: PathBuf,
        /// The system's reason.
        message: String,
    },
    /// A cell or row is not what was expected.
    #[error("{}:{line}: {what}: expected {expected}, found {found}", file.display())]
    Cell {
        /// The data file.
        file: PathBuf,
        /// 1-based line number.
        line: usize,
        /// Which cell or row (e.g. `column 2 ('force_N')`).
        what: String,
        /// What was expected.
        expected: String,
        /// What was found.
        found: String,
    },
    /// A named column is not in the header, or an index is past the last column.
    #[error("{}:{line}: no column {column}; the header has {available}", file.display())]
    MissingColumn {
        /// The data file.
        file: PathBuf,
        /// Line of the header (or first data row).
        line: usize,
        /// The requested column.
        column: String,
        /// The columns present.
        available: String,
    },
    /// The sampling cannot be made uniform (a gap far longer than the median
    /// interval, or times beyond the range of `f64` arithmetic).
    #[error("{}: expected {expected}, found {found}", file.display())]
    Sampling {
        /// The data file.
        file: PathBuf,
        /// What was expected.
        expected: String,
        /// What was found.
        found: String,
    },
    /// The bytes contradict the stated encoding (or their own byte-order
    /// mark).
    #[error("{}: byte {offset}: expected {expected}, found {found}", file.display())]
    Encoding {
        /// The data file.
        file: PathBuf,
        /// 0-based byte offset of the first byte that does not fit.
        offset: usize,
        /// What was expected there.
        expected: String,
        /// What was found there.
        found: String,
    },
    /// The decimal mark and the separator are both `,`: the numbers cannot
    /// be told apart.
    #[error("{}:{line}: {found}; {DECIMAL_COMMA_HINT}", file.display())]
    DecimalComma {
        /// The data file.
        file: PathBuf,
        /// 1-based line number.
        line: usize,
        /// What shows the collision (a row, or the stated decimal mark).
        found: String,
    },
    /// The file holds fewer than two samples.
    #[error("{}: expected at least 2 samples, found {found}", file.display())]
    TooFewSamples {
        /// The data file.
        file: PathBuf,
        /// Number of samples found.
        found: usize,
    },
    /// A record file in another format than CSV (TDMS, HDF5, MAT, UFF 58)
    /// could not be read, or a channel of it is not what was expected.
    #[error("{}: {what}: expected {expected}, found {found}", file.display())]
    Record {
        /// The data file.
        file: PathBuf,
        /// Where in the file, or which channel (`TDMS byte 1234`,
        /// `channel 'tensile/force_N'`).
        what: String,
        /// What was expected.
        expected: String,
        /// What was found.
        found: String,
    },
}

/// Reads and parses a measured-data file (see the module docs for the format).
pub fn load_csv(path: &Path, spec: &CsvSpec) -> Result<Series, DataError> {
    let bytes = crate::base::fsutil::read_record(path).map_err(|e| DataError::Io {
        file: path.to_path_buf(),
        message: e.to_string(),
    })?;
    parse_csv(&decode_record(&bytes, path, spec)?, path, spec)
}

/// The text of a record's `bytes` in `spec`'s encoding (detected when it
/// states none; see [`crate::base::encoding::decode`]); `file` is only used in
/// messages.
///
/// # Errors
/// [`DataError::Encoding`] naming the byte where the bytes contradict the
/// encoding.
pub fn decode_record(bytes: &[u8], file: &Path, spec: &CsvSpec) -> Result<String, DataError> {
    decode(bytes, spec.encoding)
        .map(|(text, _)| text)
        .map_err(|e| DataError::Encoding {
            file: file.to_path_buf(),
            offset: e.offset,
            expected: e.expected,
            found: e.found,
        })
}

/// Steps per sample at or above which a record's sample interval reads as far
/// slower than the rig moves ([`slow_sampling_hint`]): 200 RK4 steps between
/// two samples of a record (every shipped campaign takes 1 to 3; a record in
/// milliseconds read as seconds takes a thousand times its own).
pub const SLOW_SAMPLING_STEPS: usize = 200;

/// Whether a time column's name says milliseconds: `t_ms`, `time_ms`,
/// `ms`, `time (ms)`, `Time [ms]`, `t_msec`, `millis`, … (any case).
pub fn names_milliseconds(column: &str) -> bool {
    let lower = column.trim().to_lowercase();
    let words: Vec<&str> = lower
        .split(|c: char| !c.is_ascii_alphanumeric())
        .filter(|w| !w.is_empty())
        .collect();
    words.iter().any(|w| {
        matches!(
            *w,
            "ms" | "msec" | "msecs" | "millis" | "millisecond" | "milliseconds"
        ) || w.ends_with("millis")
    }) || lower.ends_with("ms") && lower.len() > 2 && lower.starts_with('t') && {
        // `tms`, `timems`: a time word glued to `ms`.
        let head = &lower[..lower.len() - 2];
        matches!(head, "t" | "time")
    }
}

/// A hint for a time column whose name says milliseconds read at
/// `time_scale` 1 (seconds): its sample interval `dt` is then a thousand
/// times what the record means.
pub fn millisecond_column_hint(column: &str, time_scale: f64, dt: f64) -> Option<String> {
    (time_scale == 1.0 && names_milliseconds(column)).then(|| {
        format!(
            "the time column '{}' is named as milliseconds but read as seconds (a sample \
             interval of {dt:e} s); if it holds milliseconds, set \"time_scale\": 1e-3 in the \
             experiment's data",
            echo_bare(column)
        )
    })
}

/// A hint for a record whose sample interval `dt` (s) needs
/// `steps_per_sample` RK4 steps, at least [`SLOW_SAMPLING_STEPS`]: a record
/// sampled far slower than the rig moves, as one whose time column holds
/// milliseconds read as seconds is.
pub fn slow_sampling_hint(dt: f64, steps_per_sample: usize, time_scale: f64) -> Option<String> {
    (steps_per_sample >= SLOW_SAMPLING_STEPS).then(|| {
        let scale = if time_scale == 1.0 {
            "if its time column holds milliseconds, set \"time_scale\": 1e-3 in the experiment's \
             data"
                .to_string()
        } else {
            format!(
                "check its time column's scale (\"time_scale\": {time_scale:e}): 1e-3 reads \
                 milliseconds"
            )
        };
        format!(
            "the record's sample interval, {dt:e} s, takes {steps_per_sample} RK4 steps of the \
             rig: it is sampled far slower than the rig moves; {scale}"
        )
    })
}

/// The lines of CSV text that hold a header or data: each line neither blank
/// nor starting with `#` (after leading blanks), trimmed, with its 1-based line
/// number. A spreadsheet's "CSV UTF-8" starts with a byte-order mark; it is
/// dropped, not read as part of the first column's name. The one line walk of
/// every CSV reader in the crate (this file's and `crate::identify::columns`).
pub(crate) fn content_lines(text: &str) -> impl Iterator<Item = (usize, &str)> {
    text.strip_prefix('\u{feff}')
        .unwrap_or(text)
        .lines()
        .enumerate()
        .map(|(i, l)| (i + 1, l.trim()))
        .filter(|(_, l)| !l.is_empty() && !l.starts_with('#'))
}

fn cell_err(file: &Path, line: usize, what: String, expected: &str, found: String) -> DataError {
    DataError::Cell {
        file: file.to_path_buf(),
        line,
        what,
        expected: expected.into(),
        found,
    }
}

/// Parses CSV text; `file` is only used in messages.
pub fn parse_csv(text: &str, file: &Path, spec: &CsvSpec) -> Result<Series, DataError> {
    // Old Mac files end lines with CR alone.
    let cr_only;
    let text = if text.contains('\r') && !text.contains('\n') {
        cr_only = text.replace('\r', "\n");
        cr_only.as_str()
    } else {
        text
    };
    let mut rows = content_lines(text).peekable();
    let Some(&(first_line, first)) = rows.peek() else {
        return Err(DataError::TooFewSamples {
            file: file.into(),
            found: 0,
        });
    };
    let sep = separator(first);
    if sep == ',' && spec.decimal == Some(Decimal::Comma) && first.contains(',') {
        return Err(DataError::DecimalComma {
            file: file.into(),
            line: first_line,
            found: "the decimal mark is stated as ',' (\"decimal\": \",\") and the first row \
                    is separated by ','"
                .into(),
        });
    }
    let number = |s: &str| parse_number(s, sep, spec.decimal);
    let split = |l: &str| -> Vec<String> {
        split_fields(l, sep)
            .into_iter()
            .map(|f| f.trim().trim_matches('"').trim().to_string())
            .collect()
    };
    let first_fields = split(first);
    let by_name = matches!(spec.time, Column::Name(_)) || matches!(spec.force, Column::Name(_));
    let has_header = by_name || first_fields.iter().any(|f| number(f).is_none());
    let header: Vec<String> = if has_header {
        rows.next();
        first_fields
    } else {
        (0..first_fields.len()).map(|i| format!("#{i}")).collect()
    };
    let resolve = |c: &Column| -> Result<usize, DataError> {
        let found = match c {
            Column::Name(n) => header.iter().position(|h| h == n),
            Column::Index(i) => (*i < header.len()).then_some(*i),
        };
        found.ok_or_else(|| DataError::MissingColumn {
            file: file.into(),
            line: first_line,
            column: c.to_string(),
            available: columns_list(&header),
        })
    };
    let cols = [resolve(&spec.time)?, resolve(&spec.force)?];
    let scales = [spec.time_scale, spec.force_scale];
    let mut t: Vec<f64> = Vec::new();
    let mut force: Vec<f64> = Vec::new();
    for (line, row) in rows {
        let fields: Vec<&str> = split_fields(row, sep);
        if sep == ',' {
            decimal_comma_collision(&fields, header.len(), file, line)?;
        }
        let mut vals = [0.0; 2];
        for (j, &c) in cols.iter().enumerate() {
            let what = format!("column {} ('{}')", c + 1, echo_bare(&header[c]));
            let Some(raw) = fields.get(c) else {
                return Err(cell_err(
                    file,
                    line,
                    "row".into(),
                    &format!("at least {} fields", c + 1),
                    format!("{} field(s)", fields.len()),
                ));
            };
            let raw = raw.trim().trim_matches('"').trim();
            let expected = match spec.decimal {
                Some(Decimal::Comma) => "a number with a decimal comma (\"decimal\": \",\")",
                _ => "a number",
            };
            let v = number(raw)
                .ok_or_else(|| cell_err(file, line, what.clone(), expected, quote(raw)))?;
            if !v.is_finite() {
                return Err(cell_err(file, line, what, "a finite number", quote(raw)));
            }
            vals[j] = v * scales[j];
            if !vals[j].is_finite() {
                let found = format!("{} × {:e}", quote(raw), scales[j]);
                return Err(cell_err(
                    file,
                    line,
                    what,
                    "a finite number after scaling",
                    found,
                ));
            }
        }
        if let Some(&prev) = t.last()
            && vals[0] <= prev
        {
            let what = format!(
                "time column {} ('{}')",
                cols[0] + 1,
                echo_bare(&header[cols[0]])
            );
            let found = format!("{} s after {} s", vals[0], prev);
            return Err(cell_err(
                file,
                line,
                what,
                "a strictly increasing time",
                found,
            ));
        }
        t.push(vals[0]);
        force.push(vals[1]);
    }
    if t.len() < 2 {
        return Err(DataError::TooFewSamples {
            file: file.into(),
            found: t.len(),
        });
    }
    uniform(t, force, file)
}

/// The separator of a file whose first content line is `first`: of `;`, tab
/// and `,` outside double quotes, the first found in that order (`,` when
/// none is: a file of one column).
pub(crate) fn separator(first: &str) -> char {
    let mut quoted = false;
    let mut found = [false; 3];
    for c in first.chars() {
        match c {
            '"' => quoted = !quoted,
            ';' if !quoted => found[0] = true,
            '\t' if !quoted => found[1] = true,
            ',' if !quoted => found[2] = true,
            _ => {}
        }
    }
    [';', '\t', ',']
        .into_iter()
        .zip(found)
        .find_map(|(c, f)| f.then_some(c))
        .unwrap_or(',')
}

/// Refuses a row of a `,`-separated file that reads as decimal commas: more
/// fields than the header's `width` (trailing empty fields aside), every one
/// a run of digits (`0,001,12,5` under `t,F`).
fn decimal_comma_collision(
    fields: &[&str],
    width: usize,
    file: &Path,
    line: usize,
) -> Result<(), DataError> {
    if fields.len() <= width {
        return Ok(());
    }
    let cells: Vec<&str> = fields
        .iter()
        .map(|f| f.trim().trim_matches('"').trim())
        .collect();
    let used = cells
        .iter()
        .rposition(|c| !c.is_empty())
        .map_or(0, |i| i + 1);
    let digits = |c: &str| {
        let c = c.strip_prefix(['-', '+']).unwrap_or(c);
        let (mantissa, exponent) = c.split_once(['e', 'E']).unwrap_or((c, "0"));
        let exponent = exponent.strip_prefix(['-', '+']).unwrap_or(exponent);
        [mantissa, exponent]
            .iter()
            .all(|p| !p.is_empty() && p.bytes().all(|b| b.is_ascii_digit()))
    };
    let cells = cells.get(..used).unwrap_or_default();
    if used > width && cells.iter().all(|c| digits(c)) {
        return Err(DataError::DecimalComma {
            file: file.into(),
            line,
            found: format!(
                "a row of {used} fields of digits ({}) under a header of {width} column(s)",
                quote(&cells.join(","))
            ),
        });
    }
    Ok(())
}

/// The fields of one row: split at `sep`, except inside double quotes (a
/// header `"force, N"` is one field).
pub(crate) fn split_fields(row: &str, sep: char) -> Vec<&str> {
    let mut fields = Vec::new();
    let (mut start, mut quoted) = (0, false);
    for (i, c) in row.char_indices() {
        if c == '"' {
            quoted = !quoted;
        } else if c == sep && !quoted {
            fields.push(&row[start..i]);
            start = i + c.len_utf8();
        }
    }
    fields.push(&row[start..]);
    fields
}

/// The header's columns for a message (see [`names_shown`]).
fn columns_list(header: &[String]) -> String {
    format!(
        "{} column(s): {}",
        header.len(),
        names_shown(header.iter().map(String::as_str))
    )
}

/// Names for a message: each escaped and cut, at most twelve of them, then
/// how many more there are.
pub(crate) fn names_shown<'a>(names: impl ExactSizeIterator<Item = &'a str>) -> String {
    const SHOWN: usize = 12;
    let count = names.len();
    let mut shown: Vec<String> = names.take(SHOWN).map(echo_bare).collect();
    if count > SHOWN {
        shown.push(format!("… {} more", count - SHOWN));
    }
    shown.join(", ")
}

/// A cell as messages quote it: `'x'`, escaped and cut short.
fn quote(raw: &str) -> String {
    format!("'{}'", echo_bare(raw))
}

/// A number: with a decimal point, or with a decimal comma when the
/// separator is `;` or tab unless `decimal` says a point; with a stated
/// decimal comma a `.` is refused.
pub(crate) fn parse_number(s: &str, sep: char, decimal: Option<Decimal>) -> Option<f64> {
    let comma_ok = matches!(sep, ';' | '\t') && decimal != Some(Decimal::Point);
    if decimal == Some(Decimal::Comma) && s.contains('.') {
        return None;
    }
    s.parse::<f64>().ok().or_else(|| {
        (comma_ok && s.contains(','))
            .then(|| s.replace(',', ".").parse().ok())
            .flatten()
    })
}

/// Checks the sampling and resamples to the median interval when it jitters.
pub fn uniform(t: Vec<f64>, force: Vec<f64>, file: &Path) -> Result<Series, DataError> {
    let n = t.len();
    let mut d: Vec<f64> = t.windows(2).map(|w| w[1] - w[0]).collect();
    let median = super::stats::median(&mut d);
    let jitter = d
        .iter()
        .map(|x| (x - median).abs() / median)
        .fold(0.0, f64::max);
    if jitter <= JITTER_TOLERANCE {
        let dt = (t[n - 1] - t[0]) / (n - 1) as f64;
        let t = (0..n).map(|k| t[0] + k as f64 * dt).collect();
        if dt.is_finite() && dt > 0.0 {
            return Ok(Series {
                t,
                force,
                dt,
                warning: None,
            });
        }
    }
    let span = t[n - 1] - t[0];
    let m = (span / median * (1.0 + 1e-9)).floor();
    if !(m.is_finite() && m <= (MAX_RESAMPLE_GROWTH * n) as f64) {
        return Err(DataError::Sampling {
            file: file.into(),
            expected: format!(
                "a record without long gaps (resampling may at most multiply the sample \
                 count by {MAX_RESAMPLE_GROWTH})"
            ),
            found: format!("{n} samples spanning {span:e} s at a median interval of {median:e} s"),
        });
    }
    let m = m as usize + 1;
    let new_t: Vec<f64> = (0..m).map(|k| t[0] + k as f64 * median).collect();
    let mut j = 0;
    let new_f = new_t
        .iter()
        .map(|&x| {
            while j + 2 < n && t[j + 1] <= x {
                j += 1;
            }
            let w = ((x - t[j]) / (t[j + 1] - t[j])).clamp(0.0, 1.0);
            force[j] + w * (force[j + 1] - force[j])
        })
        .collect();
    let warning = format!(
        "{}: sampling is not uniform (interval jitter up to {:.3}% of the median \
         interval {:.4e} s); resampled {} samples to {} at the median interval by \
         linear interpolation",
        file.display(),
        jitter * 100.0,
        median,
        n,
        m
    );
    Ok(Series {
        t: new_t,
        force: new_f,
        dt: median,
        warning: Some(warning),
    })
}

#[cfg(test)]
mod ms_tests {
    use super::*;

    #[test]
    fn a_time_column_named_in_milliseconds_gets_a_hint_unless_scaled() {
        for name in [
            "t_ms",
            "time_ms",
            "ms",
            "Time (ms)",
            "time [ms]",
            "t_msec",
            "tms",
            "TimeMS",
        ] {
            assert!(names_milliseconds(name), "{name}");
            let hint = millisecond_column_hint(name, 1.0, 0.25).expect(name);
            assert!(hint.contains("\"time_scale\": 1e-3"), "{hint}");
        }
        for name in [
            "t_s", "time", "t", "seconds", "items", "terms", "systems", "t_us",
        ] {
            assert!(!names_milliseconds(name), "{name}");
        }
        assert_eq!(millisecond_column_hint("t_ms", 1e-3, 2.5e-4), None);
    }

    #[test]
    fn a_record_sampled_far_slower_than_the_rig_moves_gets_a_hint() {
        assert_eq!(slow_sampling_hint(1e-4, 12, 1.0), None);
        let hint = slow_sampling_hint(0.25, 2400, 1.0).unwrap();
        assert!(
            hint.contains("2400 RK4 steps") && hint.contains("1e-3"),
            "{hint}"
        );
        let scaled = slow_sampling_hint(0.25, 2400, 1e-3).unwrap();
        assert!(scaled.contains("\"time_scale\": 1e-3"), "{scaled}");
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quoted_fields_keep_their_separators() {
        assert_eq!(split_fields("\"force, N\",t", ','), ["\"force, N\"", "t"]);
        assert_eq!(split_fields("a;b;;", ';'), ["a", "b", "", ""]);
    }

    #[test]
    fn decimal_comma_only_with_semicolons_or_tabs() {
        assert_eq!(parse_number("1,5", ';', None), Some(1.5));
        assert_eq!(parse_number("1,5", '\t', None), Some(1.5));
        assert_eq!(parse_number("1,5", ',', None), None);
        assert_eq!(parse_number("-2.5e3", ',', None), Some(-2500.0));
        assert_eq!(parse_number("1,5", ';', Some(Decimal::Point)), None);
        assert_eq!(
            parse_number("1,5E-3", '\t', Some(Decimal::Comma)),
            Some(1.5e-3)
        );
        assert_eq!(parse_number("1.234", ';', Some(Decimal::Comma)), None);
        assert_eq!(parse_number("7", ';', Some(Decimal::Comma)), Some(7.0));
    }

    #[test]
    fn the_separator_prefers_semicolons_then_tabs_outside_quotes() {
        assert_eq!(separator("0,0;1,5"), ';');
        assert_eq!(separator("0,0\t1,5"), '\t');
        assert_eq!(separator("t,F"), ',');
        assert_eq!(separator("\"F; kN\",t"), ',');
        assert_eq!(separator("t"), ',');
    }

    #[test]
    fn a_row_of_digit_runs_wider_than_the_header_is_a_decimal_comma_collision() {
        let f = Path::new("x");
        let e = decimal_comma_collision(&["0", "001", "-12", "5"], 2, f, 3).unwrap_err();
        assert!(matches!(e, DataError::DecimalComma { line: 3, .. }), "{e}");
        let e = e.to_string();
        assert!(
            e.contains("'0,001,-12,5'") && e.contains(DECIMAL_COMMA_HINT),
            "{e}"
        );
        assert!(decimal_comma_collision(&["0", "001", "1", "5E-03"], 2, f, 3).is_err());
        // As wide as the header, a trailing empty field, or a point: no collision.
        assert!(decimal_comma_collision(&["0", "12"], 2, f, 3).is_ok());
        assert!(decimal_comma_collision(&["0", "12", ""], 2, f, 3).is_ok());
        assert!(decimal_comma_collision(&["0.5", "12", "3"], 2, f, 3).is_ok());
    }

    #[test]
    fn decoding_a_record_names_the_file_and_byte() {
        let spec = CsvSpec {
            encoding: Some(Encoding::Utf8),
            ..CsvSpec::default()
        };
        let e = decode_record(b"t,F\xB5", Path::new("r.csv"), &spec).unwrap_err();
        assert!(matches!(e, DataError::Encoding { offset: 3, .. }), "{e}");
        assert!(
            e.to_string().starts_with("r.csv: byte 3: expected UTF-8"),
            "{e}"
        );
        let text = decode_record(b"t,F\xB5", Path::new("r.csv"), &CsvSpec::default());
        assert_eq!(text.unwrap(), "t,Fµ");
    }

    #[test]
    fn median_of_an_even_count_is_the_mean_of_the_middle_two() {
        let s = uniform(vec![0.0, 1.0, 3.0], vec![0.0; 3], Path::new("x")).unwrap();
        assert_eq!(s.dt, 1.5);
        assert_eq!(s.t, [0.0, 1.5, 3.0]);
    }

    #[test]
    fn a_long_gap_is_refused_rather_than_resampled() {
        let t = vec![0.0, 1.0, 2.0, 1000.0];
        let e = uniform(t, vec![0.0; 4], Path::new("x")).unwrap_err();
        assert!(matches!(e, DataError::Sampling { .. }), "{e}");
    }
}
