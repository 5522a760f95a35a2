//! A small reader for the two-column CSV files of the pre-calibration tools:
//! `elongation (m), force (N)` for `fit-specimen`, `time (s), force (N)` for
//! `ringdown`.
//!
//! Rules: fields separated by a comma, semicolon, tab or blanks; blank lines and
//! lines starting with `#` are skipped; the first remaining line is a header when
//! any of its fields is not a number; every other line must hold exactly two
//! finite numbers (NaN and infinities are refused). Errors name the 1-based line.

use std::path::Path;

use serde::Serialize;

use super::PrecalError;

/// Two numeric columns read from a file.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct TwoColumns {
    /// Column names from the header row, if there was one.
    pub header: Option<[String; 2]>,
    /// First column (elongation in m, or time in s).
    pub x: Vec<f64>,
    /// Second column (force in N).
    pub y: Vec<f64>,
}

/// Reads a two-column CSV file.
pub fn read_two_columns(path: &Path) -> Result<TwoColumns, PrecalError> {
    let text = std::fs::read_to_string(path).map_err(|source| PrecalError::Io {
        path: path.to_path_buf(),
        source,
    })?;
    parse_two_columns(&text)
}

/// Parses two-column CSV text (see the module docs for the rules).
pub fn parse_two_columns(text: &str) -> Result<TwoColumns, PrecalError> {
    let mut out = TwoColumns {
        header: None,
        x: Vec::new(),
        y: Vec::new(),
    };
    let mut first = true;
    for (index, raw) in text.lines().enumerate() {
        let line = index + 1;
        let trimmed = raw.trim();
        if trimmed.is_empty() || trimmed.starts_with('#') {
            continue;
        }
        let fields = split_fields(trimmed);
        if fields.len() != 2 {
            return Err(PrecalError::ColumnCount {
                line,
                expected: 2,
                found: fields.len(),
            });
        }
        let is_header = first && fields.iter().any(|f| f.parse::<f64>().is_err());
        first = false;
        if is_header {
            out.header = Some([fields[0].to_string(), fields[1].to_string()]);
            continue;
        }
        out.x.push(parse_field(fields[0], line, 1)?);
        out.y.push(parse_field(fields[1], line, 2)?);
    }
    Ok(out)
}

fn split_fields(line: &str) -> Vec<&str> {
    if line.contains([',', ';', '\t']) {
        line.split([',', ';', '\t']).map(str::trim).collect()
    } else {
        line.split_whitespace().collect()
    }
}

fn parse_field(text: &str, line: usize, column: usize) -> Result<f64, PrecalError> {
    let value: f64 = text.parse().map_err(|_| PrecalError::NotNumeric {
        line,
        column,
        found: text.to_string(),
    })?;
    if !value.is_finite() {
        return Err(PrecalError::NotFinite {
            line,
            column,
            found: text.to_string(),
        });
    }
    Ok(value)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn header_comments_and_separators() {
        let text = "# synthetic\n\nelongation_m, force_N\n0.0,0.0\n1e-6;86.3\n2e-6\t172.6\n 3e-6  258.9 \n";
        let c = parse_two_columns(text).unwrap();
        assert_eq!(c.header.as_ref().unwrap()[1], "force_N");
        assert_eq!(c.x, vec![0.0, 1e-6, 2e-6, 3e-6]);
        assert_eq!(c.y[3], 258.9);
    }

    #[test]
    fn no_header_is_fine() {
        let c = parse_two_columns("1,2\n3,4\n").unwrap();
        assert!(c.header.is_none());
        assert_eq!(c.y, vec![2.0, 4.0]);
    }

    #[test]
    fn errors_name_the_line() {
        let e = parse_two_columns("t,f\n0,1\n1,abc\n").unwrap_err();
        assert!(
            matches!(
                e,
                PrecalError::NotNumeric {
                    line: 3,
                    column: 2,
                    ..
                }
            ),
            "{e}"
        );
        let e = parse_two_columns("# c\n0,1\nNaN,2\n").unwrap_err();
        assert!(
            matches!(
                e,
                PrecalError::NotFinite {
                    line: 3,
                    column: 1,
                    ..
                }
            ),
            "{e}"
        );
        let e = parse_two_columns("0,1,2\n").unwrap_err();
        assert!(
            matches!(
                e,
                PrecalError::ColumnCount {
                    line: 1,
                    found: 3,
                    ..
                }
            ),
            "{e}"
        );
        let e = parse_two_columns("0,1\ninf,2\n").unwrap_err();
        assert!(matches!(e, PrecalError::NotFinite { line: 2, .. }), "{e}");
    }
}
