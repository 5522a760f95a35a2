//! The table of tests: one row per test (CSV, with a header).
//!
//! | column | meaning |
//! | --- | --- |
//! | `test` | the test's name (required): letters, digits, `.`, `_`, `-` |
//! | `record` | its record file, relative to the table (a campaign of one experiment) |
//! | `record.<experiment>` | the record of one experiment of the campaign |
//! | `seed` | its search's seed (default: the campaign's plus the row's index) |
//! | `value.<param>` | a fixed value in place of the campaign's |
//! | `min.<param>`, `max.<param>` | a free parameter's bounds in place of the campaign's |
//! | anything else | a covariate (rate, temperature, specimen), kept for the summary |
//!
//! `<param>` is a shared parameter's name (`k1`) or an experiment's own
//! (`v2.k_lin`). An empty cell leaves the campaign's value.

use std::path::{Path, PathBuf};

use super::SeriesError;
use super::file::check_name;

/// A test's changes to the campaign's parameters.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Overrides {
    /// Fixed values, by parameter (`k1`, `v2.k_lin`).
    pub values: Vec<(String, f64)>,
    /// Lower bounds.
    pub mins: Vec<(String, f64)>,
    /// Upper bounds.
    pub maxs: Vec<(String, f64)>,
}

/// One row of the table.
#[derive(Debug, Clone, PartialEq)]
pub struct TestRow {
    /// The row's line in the file (1 is the header).
    pub line: usize,
    /// The test's name.
    pub id: String,
    /// Its records: `(None, file)` for `record`, `(Some(experiment), file)`
    /// for `record.<experiment>`; absolute.
    pub records: Vec<(Option<String>, PathBuf)>,
    /// Its seed, where the table gives one.
    pub seed: Option<u64>,
    /// Its parameters' changes.
    pub overrides: Overrides,
    /// Its value of each covariate, in the table's column order.
    pub covariates: Vec<String>,
}

enum Column {
    Test,
    Record(Option<String>),
    Seed,
    Value(String),
    Min(String),
    Max(String),
    Covariate,
}

fn column(name: &str) -> Column {
    let name = name.trim();
    match name {
        "test" => return Column::Test,
        "record" => return Column::Record(None),
        "seed" => return Column::Seed,
        _ => {}
    }
    if let Some((kind, rest)) = name.split_once('.') {
        let rest = rest.to_string();
        match kind {
            "record" => return Column::Record(Some(rest)),
            "value" => return Column::Value(rest),
            "min" => return Column::Min(rest),
            "max" => return Column::Max(rest),
            _ => {}
        }
    }
    Column::Covariate
}

/// Reads the table: its covariate columns and its rows, every cell checked.
pub fn read_table(path: &Path) -> Result<(Vec<String>, Vec<TestRow>), SeriesError> {
    let bytes =
        crate::base::fsutil::read_description(path).map_err(|e| SeriesError::io(path, e))?;
    let dir = path.parent().unwrap_or(Path::new("/"));
    let text = bytes.strip_prefix('\u{feff}').unwrap_or(&bytes);
    let mut reader = csv::ReaderBuilder::new()
        .has_headers(true)
        .flexible(false)
        .from_reader(text.as_bytes());
    let bad = |place: String, reason: String| SeriesError::input(path, place, reason);
    let header: Vec<String> = reader
        .headers()
        .map_err(|e| bad("line 1".into(), e.to_string()))?
        .iter()
        .map(|h| h.trim().to_string())
        .collect();
    let columns: Vec<Column> = header.iter().map(|h| column(h)).collect();
    if !columns.iter().any(|c| matches!(c, Column::Test)) {
        return Err(bad(
            "line 1".into(),
            format!(
                "expected a column \"test\" (each test's name); the columns are: {}",
                header.join(", ")
            ),
        ));
    }
    for (i, h) in header.iter().enumerate() {
        if header[..i].contains(h) {
            return Err(bad(
                "line 1".into(),
                format!("column \"{h}\" is given twice"),
            ));
        }
    }
    let covariates: Vec<String> = header
        .iter()
        .zip(&columns)
        .filter(|(_, c)| matches!(c, Column::Covariate))
        .map(|(h, _)| h.clone())
        .collect();
    let mut rows: Vec<TestRow> = Vec::new();
    for record in reader.records() {
        let record = record.map_err(|e| {
            let line = e.position().map_or(0, |p| p.line());
            bad(format!("line {line}"), e.to_string())
        })?;
        let line = record.position().map_or(0, |p| p.line() as usize);
        if record.iter().all(|c| c.trim().is_empty()) {
            continue;
        }
        let mut row = TestRow {
            line,
            id: String::new(),
            records: Vec::new(),
            seed: None,
            overrides: Overrides::default(),
            covariates: Vec::new(),
        };
        for ((cell, col), name) in record.iter().zip(&columns).zip(&header) {
            let cell = cell.trim();
            let place = || format!("line {line}, column \"{name}\"");
            let number = || {
                cell.parse::<f64>()
                    .ok()
                    .filter(|x| x.is_finite())
                    .ok_or_else(|| {
                        bad(
                            place(),
                            format!(
                                "expected a finite number, found {}",
                                crate::base::text::echo(cell)
                            ),
                        )
                    })
            };
            match col {
                Column::Covariate => row.covariates.push(cell.to_string()),
                _ if cell.is_empty() => {}
                Column::Test => {
                    check_name(cell).map_err(|r| bad(place(), r))?;
                    row.id = cell.to_string();
                }
                Column::Record(exp) => row.records.push((exp.clone(), dir.join(cell))),
                Column::Seed => {
                    row.seed = Some(cell.parse::<u64>().map_err(|_| {
                        bad(
                            place(),
                            format!(
                                "expected a whole number ≥ 0, found {}",
                                crate::base::text::echo(cell)
                            ),
                        )
                    })?);
                }
                Column::Value(p) => row.overrides.values.push((p.clone(), number()?)),
                Column::Min(p) => row.overrides.mins.push((p.clone(), number()?)),
                Column::Max(p) => row.overrides.maxs.push((p.clone(), number()?)),
            }
        }
        if row.id.is_empty() {
            return Err(bad(
                format!("line {line}, column \"test\""),
                "empty: every test needs a name".into(),
            ));
        }
        if let Some(first) = rows.iter().find(|r| r.id == row.id) {
            return Err(bad(
                format!("line {line}, column \"test\""),
                format!(
                    "test \"{}\" is also on line {}; each test needs a name of its own",
                    row.id, first.line
                ),
            ));
        }
        rows.push(row);
    }
    if rows.is_empty() {
        return Err(bad(
            "(file)".into(),
            "no tests: expected a header and at least one row".into(),
        ));
    }
    Ok((covariates, rows))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn table(text: &str) -> Result<(Vec<String>, Vec<TestRow>), SeriesError> {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("tests.csv");
        std::fs::write(&path, text).unwrap();
        read_table(&path)
    }

    #[test]
    fn columns_are_read_by_their_names() {
        let (cov, rows) = table(
            "test,record,rate_mps,seed,value.k1,min.v2.k_lin,max.v2.k_lin\n\
             t1,a.csv,2.0,5,8e9,1e7,1e9\n\
             t2,b.csv,4.0,,,,\n",
        )
        .unwrap();
        assert_eq!(cov, ["rate_mps"]);
        assert_eq!(rows.len(), 2);
        assert_eq!(rows[0].seed, Some(5));
        assert_eq!(rows[0].overrides.values, [("k1".to_string(), 8e9)]);
        assert_eq!(rows[0].overrides.mins, [("v2.k_lin".to_string(), 1e7)]);
        assert_eq!(rows[1].covariates, ["4.0"]);
        assert!(rows[1].overrides.values.is_empty());
        assert_eq!(rows[1].line, 3);
    }

    #[test]
    fn bad_cells_name_their_line_and_column() {
        let e = table("test,value.k1\nt1,abc\n").unwrap_err().to_string();
        assert!(e.contains("line 2, column \"value.k1\""), "{e}");
        let e = table("test\nt1\nt1\n").unwrap_err().to_string();
        assert!(e.contains("also on line 2"), "{e}");
        let e = table("rate\n1\n").unwrap_err().to_string();
        assert!(e.contains("expected a column \"test\""), "{e}");
        let e = table("test,rate\nt1,1,2\n").unwrap_err().to_string();
        assert!(e.contains("line 2"), "{e}");
    }
}
