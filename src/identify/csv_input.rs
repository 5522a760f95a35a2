//! The two-column CSV files of the pre-calibration tools:
//! `elongation (m), force (N)` for `fit-specimen`, `time (s), force (N)` for
//! `ringdown`, read by the identification tools' one reader
//! ([`crate::identify::columns`], whose rules apply) held to two columns: every
//! line, the header too, must hold exactly two fields.

use std::path::Path;

use serde::Serialize;

use super::IdentifyError;
use super::columns::{Table, parse_rows, read_text};

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
pub fn read_two_columns(path: &Path) -> Result<TwoColumns, IdentifyError> {
    parse_two_columns(&read_text(path)?)
}

/// Parses two-column CSV text (see the module docs for the rules).
pub fn parse_two_columns(text: &str) -> Result<TwoColumns, IdentifyError> {
    let Table {
        mut header,
        mut columns,
    } = parse_rows(text, Some(2))?;
    let y = columns.pop().unwrap_or_default();
    let x = columns.pop().unwrap_or_default();
    let header = (header.len() == 2).then(|| {
        let second = header.pop().unwrap_or_default();
        [header.pop().unwrap_or_default(), second]
    });
    Ok(TwoColumns { header, x, y })
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
        // Each message names the line (and the column) and quotes the field.
        let cases = [
            (
                "t,f\n0,1\n1,abc\n",
                "line 3, column 2: \"abc\" is not a number",
            ),
            (
                "# c\n0,1\nNaN,2\n",
                "line 3, column 1: \"NaN\" is not a finite number",
            ),
            ("0,1,2\n", "line 1: expected 2 columns, found 3"),
            (
                "0,1\ninf,2\n",
                "line 2, column 1: \"inf\" is not a finite number",
            ),
        ];
        for (text, message) in cases {
            let e = parse_two_columns(text).unwrap_err();
            assert_eq!(e.to_string(), message, "{text:?}");
        }
    }
}
