//! `summary.csv`, and the summary as a terminal shows it.
//!
//! Numbers are written with Rust's shortest round-trip form (`{}` of an
//! `f64`): a cell read back is the very `f64` of the test's `result.json`,
//! so two runs of a series that gave the same bits give the same cells.

use std::fmt;
use std::path::Path;

use super::{IntervalKind, Summary, SummaryRow, SummaryState};

/// How `summary.csv` begins: its first line is a comment starting so, and a
/// file under that name that does not is not rigfit's, and is never
/// replaced.
pub const CSV_MARK: &str = "# rigfit series summary";

/// What joins a test's warnings in one cell.
const JOIN: &str = " | ";

fn number(v: Option<f64>) -> String {
    v.map_or_else(String::new, |v| v.to_string())
}

/// The interval column: one word where every interval comes from one
/// place, else the profile and the parameters whose interval is the
/// covariance's.
fn interval_word(summary: &Summary, row: &SummaryRow) -> String {
    let kinds: Vec<(&str, IntervalKind)> = summary
        .parameters
        .iter()
        .zip(&row.parameters)
        .filter_map(|(p, c)| Some((p.name.as_str(), c.interval?)))
        .collect();
    let Some(&(_, first)) = kinds.first() else {
        return String::new();
    };
    if kinds.iter().all(|(_, k)| *k == first) {
        return first.as_str().into();
    }
    let covariance: Vec<&str> = kinds
        .iter()
        .filter(|(_, k)| *k == IntervalKind::Covariance)
        .map(|(n, _)| *n)
        .collect();
    format!("profile; covariance for {}", covariance.join(", "))
}

/// The header: `test`, the covariates, `status`, `error`, each parameter's
/// value and interval, `interval`, the fit, where it ran.
pub(super) fn header(summary: &Summary) -> Vec<String> {
    let mut h = vec!["test".to_string()];
    h.extend(summary.covariates.iter().cloned());
    h.extend(["status".into(), "error".into()]);
    for p in &summary.parameters {
        h.extend([
            p.name.clone(),
            format!("{}.lower", p.name),
            format!("{}.upper", p.name),
        ]);
    }
    h.extend(
        [
            "interval",
            "r2",
            "noise_floor_ratio",
            "warnings",
            "wall_time_s",
            "backend",
            "device",
            "adapter",
            "host",
            "restarts",
        ]
        .map(String::from),
    );
    h
}

/// One test's cells, in [`header`]'s order.
pub(super) fn cells(summary: &Summary, row: &SummaryRow) -> Vec<String> {
    let mut c = vec![row.id.clone()];
    c.extend(row.covariates.iter().cloned());
    // A manifest with fewer covariate cells than columns still gives a
    // rectangular table.
    c.resize(1 + summary.covariates.len(), String::new());
    c.push(row.state.as_str().into());
    c.push(row.error.clone().unwrap_or_default());
    for p in &row.parameters {
        c.extend([number(p.value), number(p.lower), number(p.upper)]);
    }
    let text = |s: &Option<String>| s.clone().unwrap_or_default();
    c.extend([
        interval_word(summary, row),
        number(row.r2),
        number(row.noise_floor_ratio),
        row.warnings.join(JOIN),
        number(row.wall_time_s),
        text(&row.backend),
        text(&row.device),
        text(&row.adapter),
        text(&row.host),
        row.restarts.map_or_else(String::new, |r| r.to_string()),
    ]);
    c
}

/// `summary.csv`: the mark line, the header, one row per test.
pub(super) fn csv(summary: &Summary) -> String {
    let name: String = summary
        .name
        .chars()
        .map(|c| if c.is_control() { ' ' } else { c })
        .collect();
    let mut text = format!(
        "{CSV_MARK} of \"{name}\": one row per test ({}); intervals are 95 %, from the profile or the covariance (column interval)\n",
        summary.counts()
    );
    let mut w = csv::WriterBuilder::new().from_writer(Vec::new());
    let write = |w: &mut csv::Writer<Vec<u8>>, record: Vec<String>| {
        w.write_record(&record)
            .expect("a CSV record writes to memory");
    };
    write(&mut w, header(summary));
    for row in &summary.rows {
        write(&mut w, cells(summary, row));
    }
    let bytes = w.into_inner().expect("a CSV writer into memory flushes");
    text.push_str(&String::from_utf8(bytes).expect("the cells are UTF-8"));
    text
}

/// Whether `path` is a regular file (not a link) whose first line starts
/// with [`CSV_MARK`].
pub(super) fn is_rigfit_summary(path: &Path) -> bool {
    use std::io::Read as _;
    let Ok(meta) = path.symlink_metadata() else {
        return false;
    };
    if !meta.file_type().is_file() {
        return false;
    }
    let mut head = Vec::new();
    let read = std::fs::File::open(path)
        .and_then(|f| f.take(CSV_MARK.len() as u64).read_to_end(&mut head));
    read.is_ok() && head == CSV_MARK.as_bytes()
}

/// `s` cut to `n` characters, on its first line.
fn short(s: &str, n: usize) -> String {
    let line = s.lines().next().unwrap_or_default();
    if line.chars().count() <= n && !s.contains('\n') {
        return line.to_string();
    }
    let mut t: String = line.chars().take(n.saturating_sub(1)).collect();
    t.push('…');
    t
}

impl fmt::Display for Summary {
    /// One line per test (status, R², cost over the noise floor, wall time,
    /// and its error or flags), then the counts.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let width = self
            .rows
            .iter()
            .map(|r| r.id.chars().count())
            .max()
            .unwrap_or(4)
            .max(4);
        let g = |v: Option<f64>, digits: usize| {
            v.map_or_else(|| "—".to_string(), |v| format!("{v:.digits$}"))
        };
        writeln!(
            f,
            "{:width$}  {:11}  {:>10}  {:>11}  {:>9}  note",
            "test", "status", "R²", "cost/floor", "wall (s)"
        )?;
        for r in &self.rows {
            let note = match (r.state, &r.error) {
                (SummaryState::Done, _) => r.flags.join("; "),
                (_, Some(e)) => e.clone(),
                (_, None) => String::new(),
            };
            writeln!(
                f,
                "{:width$}  {:11}  {:>10}  {:>11}  {:>9}  {}",
                r.id,
                r.state.as_str(),
                g(r.r2, 6),
                g(r.noise_floor_ratio, 3),
                g(r.wall_time_s, 1),
                short(&note, 100)
            )?;
        }
        write!(f, "{}", self.counts())
    }
}
