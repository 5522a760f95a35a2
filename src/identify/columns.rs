//! The one CSV reader of the identification tools: records with one column per
//! channel, chosen by header name or by 1-based position ([`Table`]); the
//! two-column reader of `fit-specimen` and `ringdown`
//! ([`crate::identify::csv_input`]) is this reader held to two columns.
//!
//! Rules: the lines are those of the measured-record reader
//! ([`crate::base::data`]): blank lines and lines starting with `#` are skipped,
//! a byte-order mark is dropped. Fields are separated by commas, semicolons or
//! tabs when a line holds any (an empty field is a field), by blanks otherwise;
//! the first remaining line is a header when any of its fields is not a number;
//! every line must hold as many fields as the first (or as the caller asks) and
//! every data field a finite number. Errors name the 1-based line and column.

use std::path::Path;

use super::{IdentifyError, require_points};
use crate::base::data::content_lines;

/// A table of numeric columns.
#[derive(Debug, Clone, PartialEq)]
pub struct Table {
    /// Column names from the header row (empty when there was none).
    pub header: Vec<String>,
    /// The columns, each as long as the record.
    pub columns: Vec<Vec<f64>>,
}

impl Table {
    /// Reads a table from a file.
    ///
    /// # Errors
    /// [`IdentifyError::Io`] and the parsing errors of [`Table::parse`].
    pub fn read(path: &Path) -> Result<Self, IdentifyError> {
        Self::parse(&read_text(path)?)
    }

    /// Parses CSV text (see the module docs for the rules).
    ///
    /// # Errors
    /// [`IdentifyError::ColumnCount`], [`IdentifyError::NotNumeric`],
    /// [`IdentifyError::NotFinite`], and [`IdentifyError::TooFewPoints`] for a table
    /// without data rows.
    pub fn parse(text: &str) -> Result<Self, IdentifyError> {
        let table = parse_rows(text, None)?;
        require_points("data rows", 1, table.columns.first().map_or(0, Vec::len))?;
        Ok(table)
    }

    /// The column named `key` in the header, or at 1-based position `key`
    /// (the first column is 1, as a spreadsheet counts; a campaign's
    /// `time_column` counts from 0, and every message says which).
    ///
    /// # Errors
    /// [`IdentifyError::InvalidOption`] naming the columns there are.
    pub fn column(&self, key: &str) -> Result<&[f64], IdentifyError> {
        let by_name = self.header.iter().position(|h| h == key);
        let index = match by_name {
            Some(i) => Some(i),
            None => key
                .parse::<usize>()
                .ok()
                .and_then(|i| i.checked_sub(1))
                .filter(|&i| i < self.columns.len()),
        };
        index.map(|i| self.columns[i].as_slice()).ok_or_else(|| {
            let known = if self.header.is_empty() {
                format!("positions 1..={}", self.columns.len())
            } else {
                format!(
                    "{}, or positions 1..={}",
                    self.header.join(", "),
                    self.columns.len()
                )
            };
            IdentifyError::InvalidOption {
                name: "column",
                reason: format!(
                    "no column {key:?} (there are: {known}; on the command line a position \
                     counts from 1, the first column is 1, while a campaign's counts from 0)"
                ),
            }
        })
    }
}

/// The header (empty when there was none) and the numeric columns of CSV text
/// (see the module docs), every line `width` fields wide, or as wide as the
/// first when `None`. A text without data rows gives empty columns.
pub(crate) fn parse_rows(text: &str, width: Option<usize>) -> Result<Table, IdentifyError> {
    let mut header = Vec::new();
    let mut columns: Vec<Vec<f64>> = vec![Vec::new(); width.unwrap_or(0)];
    let mut rows = content_lines(text).peekable();
    if let Some(&(_, first)) = rows.peek() {
        let fields = split_fields(first);
        let expected = width.unwrap_or(fields.len());
        columns = vec![Vec::new(); expected];
        if fields.len() == expected && fields.iter().any(|f| f.parse::<f64>().is_err()) {
            header = fields.iter().map(|f| f.to_string()).collect();
            rows.next();
        }
    }
    for (line, row) in rows {
        let fields = split_fields(row);
        if fields.len() != columns.len() {
            return Err(IdentifyError::ColumnCount {
                line,
                expected: columns.len(),
                found: fields.len(),
            });
        }
        for (column, (field, col)) in fields.iter().zip(columns.iter_mut()).enumerate() {
            col.push(parse_field(field, line, column + 1)?);
        }
    }
    Ok(Table { header, columns })
}

/// The text of `path`, read and decoded as every measured record is
/// ([`crate::base::fsutil::read_record`]: a regular file of at most
/// [`crate::base::fsutil::MAX_RECORD_BYTES`]; UTF-8, UTF-16 with a byte-order
/// mark or Windows-1252, detected by [`crate::base::encoding::decode`]), or
/// [`IdentifyError::Io`] naming it.
pub(crate) fn read_text(path: &Path) -> Result<String, IdentifyError> {
    let io = |source| IdentifyError::Io {
        path: path.to_path_buf(),
        source,
    };
    let bytes = crate::base::fsutil::read_record(path).map_err(io)?;
    crate::base::encoding::decode(&bytes, None)
        .map(|(text, _)| text)
        .map_err(|e| io(std::io::Error::new(std::io::ErrorKind::InvalidData, e)))
}

/// A line's fields: split at commas, semicolons and tabs when it holds any,
/// else at blanks.
fn split_fields(line: &str) -> Vec<&str> {
    if line.contains([',', ';', '\t']) {
        line.split([',', ';', '\t']).map(str::trim).collect()
    } else {
        line.split_whitespace().collect()
    }
}

/// A field as a finite number, or the error naming its line and column.
fn parse_field(text: &str, line: usize, column: usize) -> Result<f64, IdentifyError> {
    let value: f64 = text.parse().map_err(|_| IdentifyError::NotNumeric {
        line,
        column,
        found: text.to_string(),
    })?;
    if !value.is_finite() {
        return Err(IdentifyError::NotFinite {
            line,
            column,
            found: text.to_string(),
        });
    }
    Ok(value)
}

/// The sample interval of uniformly spaced time stamps: the mean step, after
/// checking that no step strays from it by more than 1 %.
///
/// # Errors
/// [`IdentifyError::TooFewPoints`] for fewer than two samples and
/// [`IdentifyError::NonUniformTime`] for uneven spacing.
pub fn sample_interval(t: &[f64]) -> Result<f64, IdentifyError> {
    require_points("time stamps", 2, t.len())?;
    let dt = (t[t.len() - 1] - t[0]) / (t.len() - 1) as f64;
    for (index, w) in t.windows(2).enumerate() {
        let step = w[1] - w[0];
        if dt.is_nan() || dt <= 0.0 || (step - dt).abs() > 0.01 * dt {
            return Err(IdentifyError::NonUniformTime {
                index: index + 1,
                step,
                expected: dt,
            });
        }
    }
    Ok(dt)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn columns_by_name_and_position() {
        let t = Table::parse("# c\nt, x;y\n0 1 2\n1,3,4\n").unwrap();
        assert_eq!(t.column("x").unwrap(), &[1.0, 3.0]);
        assert_eq!(t.column("3").unwrap(), &[2.0, 4.0]);
        let e = t.column("z").unwrap_err().to_string();
        assert!(e.contains("t, x, y"), "{e}");
        assert!(matches!(
            Table::parse("0,1\n2\n"),
            Err(IdentifyError::ColumnCount { line: 2, .. })
        ));
        assert!(matches!(
            Table::parse("a,b\n1,nan\n"),
            Err(IdentifyError::NotFinite {
                line: 2,
                column: 2,
                ..
            })
        ));
    }

    #[test]
    fn sample_interval_checks_spacing() {
        assert!((sample_interval(&[0.0, 0.1, 0.2, 0.3]).unwrap() - 0.1).abs() < 1e-15);
        assert!(matches!(
            sample_interval(&[0.0, 0.1, 0.25, 0.3]),
            Err(IdentifyError::NonUniformTime { index: 2, .. })
        ));
    }
}
