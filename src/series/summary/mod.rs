//! The summary of a series: one row per test of its manifest, with the
//! test's parameters and their intervals, its fit (R², the cost over the
//! noise floor), its warnings, where and how long it ran, and how it ended.
//! A test that failed, never ran, is still running or ran an earlier
//! campaign keeps its row, with the reason; no test is ever dropped.
//!
//! [`summarise`] reads the series' folder alone (the manifest, the status
//! files, each done test's `result.json`), so that a series run here and
//! the same series run as a Slurm array summarise to the same parameter
//! cells. [`write_summary`] writes the table ([`SUMMARY_CSV`], see
//! `table.rs`) and the page ([`SUMMARY_HTML`], see `page.rs`).

use std::path::Path;

use super::SeriesError;
use super::manifest::{
    Manifest, STATUS_DIR, SUMMARY_CSV, SUMMARY_HTML, TestEntry, TestState, TestStatus, file_sha256,
};
use crate::report::html::input::{self, ResultFile};
use crate::report::html::{REPORT_FILE, is_rigfit_report};

mod page;
mod table;

pub use table::CSV_MARK;

/// How a test stands in the summary.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SummaryState {
    /// Its status says done and its `result.json` reads.
    Done,
    /// Its job failed, it could not be prepared, or its status says done
    /// and its result does not read.
    Failed,
    /// Interrupted with its checkpoint kept: running it again resumes it.
    Interrupted,
    /// No status (never ran, or still running), or the status of an
    /// earlier campaign (stale).
    Missing,
}

impl SummaryState {
    /// The word the table writes.
    pub fn as_str(self) -> &'static str {
        match self {
            Self::Done => "done",
            Self::Failed => "failed",
            Self::Interrupted => "interrupted",
            Self::Missing => "missing",
        }
    }
}

/// Where a parameter's interval comes from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum IntervalKind {
    /// The profile likelihood's 95 % interval.
    Profile,
    /// The 95 % interval of the polish's covariance.
    Covariance,
}

impl IntervalKind {
    /// The word the table writes.
    pub fn as_str(self) -> &'static str {
        match self {
            Self::Profile => "profile",
            Self::Covariance => "covariance",
        }
    }
}

/// One parameter of one test, as its `result.json` gives it.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct ParamCell {
    /// The fitted (or fixed) value; `None` where the test lacks it.
    pub value: Option<f64>,
    /// The interval's lower end; `None` where open or absent.
    pub lower: Option<f64>,
    /// The interval's upper end; `None` where open or absent.
    pub upper: Option<f64>,
    /// Where the interval comes from; `None` without one.
    pub interval: Option<IntervalKind>,
}

/// A parameter column: a free parameter of some done test.
#[derive(Debug, Clone, PartialEq)]
pub struct SummaryParameter {
    /// Its name (`k1`, `v2.k_lin`).
    pub name: String,
    /// Its SI unit.
    pub unit: String,
    /// Whether searched on a log scale (in the first done test that fits it).
    pub log: bool,
    /// Its search bounds (in that test).
    pub bounds: Option<[Option<f64>; 2]>,
}

/// One test's row.
#[derive(Debug, Clone, PartialEq)]
pub struct SummaryRow {
    /// The test.
    pub id: String,
    /// Its covariates, in [`Summary::covariates`]' order.
    pub covariates: Vec<String>,
    /// How it stands.
    pub state: SummaryState,
    /// Why it is not done (failed, interrupted, missing, stale).
    pub error: Option<String>,
    /// Its parameters, in [`Summary::parameters`]' order (all `None` where
    /// it is not done).
    pub parameters: Vec<ParamCell>,
    /// R² (one experiment's; the weighted mean over several, `1 − fitness`).
    pub r2: Option<f64>,
    /// The fit's cost over the noise floor its record implies (about 1 at
    /// the floor).
    pub noise_floor_ratio: Option<f64>,
    /// The verdict's flags, briefly.
    pub flags: Vec<String>,
    /// The job's warnings, in words.
    pub warnings: Vec<String>,
    /// Wall time of the test's last run (s).
    pub wall_time_s: Option<f64>,
    /// `"cpu"` or `"gpu"`.
    pub backend: Option<String>,
    /// The device or threads.
    pub device: Option<String>,
    /// The GPU the scheduler gave it, and how it was matched.
    pub adapter: Option<String>,
    /// The machine it ran on.
    pub host: Option<String>,
    /// How often Slurm requeued its task.
    pub restarts: Option<u32>,
    /// Its report page, relative to the series' folder, where one exists.
    pub report: Option<String>,
}

/// The summary of a series' folder.
#[derive(Debug, Clone, PartialEq)]
pub struct Summary {
    /// The series' name.
    pub name: String,
    /// The covariate columns.
    pub covariates: Vec<String>,
    /// The parameter columns: the free parameters of the first done test in
    /// its result's order, then those only later tests fit.
    pub parameters: Vec<SummaryParameter>,
    /// Every test of the manifest, in its order.
    pub rows: Vec<SummaryRow>,
}

impl Summary {
    /// How many tests stand so.
    pub fn count(&self, state: SummaryState) -> usize {
        self.rows.iter().filter(|r| r.state == state).count()
    }

    /// `12 done, 1 failed, 0 missing` (and the interrupted, where any).
    pub fn counts(&self) -> String {
        let interrupted = self.count(SummaryState::Interrupted);
        let mut s = format!(
            "{} done, {} failed, ",
            self.count(SummaryState::Done),
            self.count(SummaryState::Failed)
        );
        if interrupted > 0 {
            s.push_str(&format!("{interrupted} interrupted, "));
        }
        s.push_str(&format!("{} missing", self.count(SummaryState::Missing)));
        s
    }

    /// The table as `summary.csv` holds it.
    pub fn to_csv(&self) -> String {
        table::csv(self)
    }

    /// The page as `summary.html` holds it.
    pub fn to_html(&self) -> String {
        page::html(self)
    }
}

/// What one test's files say, before the parameter columns are known.
struct Read {
    row: SummaryRow,
    result: Option<ResultFile>,
}

/// Reads the series' folder `root`: its manifest, each test's status and
/// each done test's `result.json`. Fails only where the manifest does not
/// read; a test's own files that do not read make its row failed or
/// missing, with the reason.
pub fn summarise(root: &Path) -> Result<Summary, SeriesError> {
    let manifest = Manifest::read(root)?;
    let reads: Vec<Read> = manifest.tests.iter().map(|t| read_test(root, t)).collect();
    let parameters = columns(reads.iter().filter_map(|r| r.result.as_ref()));
    let rows = reads
        .into_iter()
        .map(|Read { mut row, result }| {
            if let Some(r) = &result {
                row.parameters = parameters.iter().map(|p| cell(r, &p.name)).collect();
            } else {
                row.parameters = vec![ParamCell::default(); parameters.len()];
            }
            row
        })
        .collect();
    Ok(Summary {
        name: manifest.name,
        covariates: manifest.covariates,
        parameters,
        rows,
    })
}

/// [`summarise`], then writes `summary.csv` and `summary.html` into `root`
/// (each atomically). Refuses, before writing either, to replace a file
/// under either name that rigfit did not write, or a link.
pub fn write_summary(root: &Path) -> Result<Summary, SeriesError> {
    let summary = summarise(root)?;
    let csv_path = root.join(SUMMARY_CSV);
    let html_path = root.join(SUMMARY_HTML);
    if csv_path.symlink_metadata().is_ok() && !table::is_rigfit_summary(&csv_path) {
        return Err(foreign(&csv_path, &format!("a first line `{CSV_MARK} …`")));
    }
    if html_path.symlink_metadata().is_ok() && !is_rigfit_report(&html_path) {
        return Err(foreign(
            &html_path,
            "a page carrying rigfit's generator tag",
        ));
    }
    let write = |path: &Path, text: String| {
        crate::base::fsutil::atomic_write(path, text.as_bytes())
            .map_err(|e| SeriesError::io(path, e))
    };
    write(&csv_path, summary.to_csv())?;
    write(&html_path, summary.to_html())?;
    Ok(summary)
}

fn foreign(path: &Path, expected: &str) -> SeriesError {
    SeriesError::Folder {
        path: path.to_path_buf(),
        reason: format!(
            "this file exists and was not written by rigfit (expected {expected}, a regular file); \
             rigfit never replaces it: move it away"
        ),
    }
}

fn empty_row(t: &TestEntry, state: SummaryState, error: Option<String>) -> SummaryRow {
    SummaryRow {
        id: t.id.clone(),
        covariates: t.covariates.clone(),
        state,
        error,
        parameters: Vec::new(),
        r2: None,
        noise_floor_ratio: None,
        flags: Vec::new(),
        warnings: Vec::new(),
        wall_time_s: None,
        backend: None,
        device: None,
        adapter: None,
        host: None,
        restarts: None,
        report: None,
    }
}

/// One test's row from its status and result.
fn read_test(root: &Path, t: &TestEntry) -> Read {
    let status_name = format!("{STATUS_DIR}/{}.json", t.id);
    let Some(status) = TestStatus::read(root, &t.id) else {
        let row = match &t.error {
            Some(e) => empty_row(
                t,
                SummaryState::Failed,
                Some(format!("could not be prepared: {e}")),
            ),
            None => empty_row(
                t,
                SummaryState::Missing,
                Some(format!(
                    "no status ({status_name} is absent or does not read): not run yet, or still running"
                )),
            ),
        };
        return Read { row, result: None };
    };
    let campaign = t.campaign.display();
    let stale = match file_sha256(&root.join(&t.campaign)) {
        Ok(sha) if sha == status.campaign_sha256 => None,
        Ok(_) => Some(format!(
            "stale: {status_name} is of an earlier campaign; {campaign} changed since the test ran, so it must run again"
        )),
        Err(e) => Some(format!(
            "its campaign does not read, so its status cannot count: {e}"
        )),
    };
    let mut row = empty_row(t, SummaryState::Missing, stale.clone());
    row.wall_time_s = Some(status.wall_time_s);
    row.backend = status.backend.clone();
    row.device = status.device.clone();
    row.adapter = status.adapter.clone();
    row.host = Some(status.host.clone());
    row.restarts = Some(status.restarts);
    if stale.is_some() {
        return Read { row, result: None };
    }
    let known = || status.error.clone().or_else(|| t.error.clone());
    match status.state {
        TestState::Failed => {
            row.state = SummaryState::Failed;
            row.error =
                Some(known().unwrap_or_else(|| format!("failed ({status_name} gives no error)")));
            Read { row, result: None }
        }
        TestState::Interrupted => {
            row.state = SummaryState::Interrupted;
            row.error = Some(known().unwrap_or_else(|| {
                "interrupted with its checkpoint kept: running the test again resumes it".into()
            }));
            Read { row, result: None }
        }
        TestState::Done => {
            let dir = root.join(&t.out);
            let result = match input::read_result(&dir) {
                Ok(Some(r)) => r,
                Ok(None) => {
                    row.state = SummaryState::Failed;
                    row.error = Some(format!(
                        "{status_name} says done, but {} holds no result.json",
                        t.out.display()
                    ));
                    return Read { row, result: None };
                }
                Err(e) => {
                    row.state = SummaryState::Failed;
                    row.error = Some(format!(
                        "{status_name} says done, but its result does not read: {e}"
                    ));
                    return Read { row, result: None };
                }
            };
            row.state = SummaryState::Done;
            fill(&mut row, &result);
            if dir.join(REPORT_FILE).is_file() {
                let parts: Vec<String> = t
                    .out
                    .components()
                    .map(|c| c.as_os_str().to_string_lossy().into_owned())
                    .collect();
                row.report = Some(format!("{}/{REPORT_FILE}", parts.join("/")));
            }
            Read {
                row,
                result: Some(result),
            }
        }
    }
}

/// The fit's numbers and warnings of a done test; where the runner left no
/// backend or device, the result's.
fn fill(row: &mut SummaryRow, r: &ResultFile) {
    row.r2 = match r.experiments.as_slice() {
        [one] => one.r2,
        _ => r.fitness.map(|f| 1.0 - f),
    };
    row.noise_floor_ratio = r.verdict.as_ref().and_then(|v| v.cost_over_noise_floor).or(
        match r.experiments.as_slice() {
            [one] => one.cost_over_noise_floor,
            _ => None,
        },
    );
    row.flags = r
        .verdict
        .as_ref()
        .map(|v| v.flags.clone())
        .unwrap_or_default();
    row.warnings = r.warnings.clone();
    if row.backend.is_none() && !r.backend.is_empty() {
        row.backend = Some(r.backend.clone());
    }
    if row.device.is_none() && !r.device.is_empty() {
        row.device = Some(r.device.clone());
    }
}

/// The free parameters of the done tests' results, each once, in order of
/// first appearance.
fn columns<'a>(results: impl Iterator<Item = &'a ResultFile>) -> Vec<SummaryParameter> {
    let mut out: Vec<SummaryParameter> = Vec::new();
    for r in results {
        for p in r.parameters.iter().filter(|p| p.free) {
            if !out.iter().any(|c| c.name == p.name) {
                out.push(SummaryParameter {
                    name: p.name.clone(),
                    unit: p.unit.clone(),
                    log: p.scale.as_deref() == Some("log"),
                    bounds: p.bounds,
                });
            }
        }
    }
    out
}

/// Parameter `name` of a result: its value (free or fixed) and, for a free
/// one, the profile interval where the result has one, else the
/// covariance's.
fn cell(r: &ResultFile, name: &str) -> ParamCell {
    let Some(p) = r.parameters.iter().find(|p| p.name == name) else {
        return ParamCell::default();
    };
    let profile = r
        .profiles
        .as_ref()
        .and_then(|ps| ps.parameters.iter().find(|q| q.name == name))
        .and_then(|q| q.interval);
    let (interval, ends) = match (p.free, profile, p.interval_95) {
        (false, ..) => (None, None),
        (true, Some(i), _) => (Some(IntervalKind::Profile), Some(i)),
        (true, None, Some(i)) => (Some(IntervalKind::Covariance), Some(i)),
        (true, None, None) => (None, None),
    };
    ParamCell {
        value: p.value,
        lower: ends.and_then(|[lo, _]| lo),
        upper: ends.and_then(|[_, hi]| hi),
        interval,
    }
}

#[cfg(test)]
mod tests;
