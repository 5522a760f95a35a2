//! Observers: code that watches a search (logs, progress bars, live history
//! files) without living inside the loop.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use super::SearchError;
use super::genes::GeneSpec;
use super::polish::PolishIteration;
use super::report::{GenerationReport, SearchOutcome};
use crate::base::fsutil::atomic_write;

/// Watches a search, one generation at a time.
pub trait Observer {
    /// Called after each generation the observer's [`ObserverMode`] selects.
    fn observe(&mut self, report: &GenerationReport) -> Result<(), SearchError>;

    /// Called after every iteration of the polish that follows the GA
    /// (whatever the [`ObserverMode`], except [`ObserverMode::Never`]).
    fn polished(&mut self, _iteration: &PolishIteration) -> Result<(), SearchError> {
        Ok(())
    }

    /// Called once when a search resumes from a checkpoint, with the history
    /// so far (so a history writer can start from it).
    fn resumed(&mut self, _history: &[GenerationReport]) -> Result<(), SearchError> {
        Ok(())
    }

    /// Called once when the search (and its polish, if any) ends without error.
    fn finish(&mut self, _outcome: &SearchOutcome) -> Result<(), SearchError> {
        Ok(())
    }
}

/// A boxed observer observes as the observer inside (a caller's list of
/// observers of different types).
impl<O: Observer + ?Sized> Observer for Box<O> {
    fn observe(&mut self, report: &GenerationReport) -> Result<(), SearchError> {
        (**self).observe(report)
    }

    fn polished(&mut self, iteration: &PolishIteration) -> Result<(), SearchError> {
        (**self).polished(iteration)
    }

    fn resumed(&mut self, history: &[GenerationReport]) -> Result<(), SearchError> {
        (**self).resumed(history)
    }

    fn finish(&mut self, outcome: &SearchOutcome) -> Result<(), SearchError> {
        (**self).finish(outcome)
    }
}

/// When an observer is called.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ObserverMode {
    /// Every generation.
    Always,
    /// Every `n`-th generation (generation index divisible by `n`) and the last.
    Every(usize),
    /// When the best cost improved (and the first generation).
    NewBest,
    /// Only [`Observer::resumed`] and [`Observer::finish`].
    Never,
}

impl ObserverMode {
    /// Whether `report` should be shown; `last` marks the final generation.
    pub fn selects(self, report: &GenerationReport, last: bool) -> bool {
        match self {
            Self::Always => true,
            Self::Every(n) => last || report.generation.is_multiple_of(n.max(1)),
            Self::NewBest => report.improved || report.generation == 0,
            Self::Never => false,
        }
    }
}

/// Rewrites `history.csv` (atomically) each time it is called, so a crashed
/// run still leaves the history up to its last call.
#[derive(Debug)]
pub struct HistoryCsvObserver {
    path: PathBuf,
    genes: Vec<GeneSpec>,
    rows: Vec<GenerationReport>,
}

impl HistoryCsvObserver {
    /// Writes to `path`, one column per gene for the best genome.
    pub fn new(path: impl Into<PathBuf>, genes: &[GeneSpec]) -> Self {
        Self {
            path: path.into(),
            genes: genes.to_vec(),
            rows: Vec::new(),
        }
    }

    fn write(&self) -> Result<(), SearchError> {
        write_history_csv(&self.path, &self.rows, &self.genes)
    }
}

impl Observer for HistoryCsvObserver {
    fn observe(&mut self, report: &GenerationReport) -> Result<(), SearchError> {
        self.rows.push(report.clone());
        self.write()
    }

    fn resumed(&mut self, history: &[GenerationReport]) -> Result<(), SearchError> {
        self.rows = history.to_vec();
        Ok(())
    }

    fn finish(&mut self, outcome: &SearchOutcome) -> Result<(), SearchError> {
        // With `Every(n)` the file may lag; the outcome has every generation.
        self.rows = outcome.history.clone();
        self.write()
    }
}

/// Column names of [`history_csv`], before the per-gene `best_<name>` columns.
pub const HISTORY_COLUMNS: [&str; 11] = [
    "generation",
    "best_cost",
    "best_r2",
    "median_cost",
    "diversity",
    "evaluations",
    "evaluated",
    "evals_per_s",
    "diverged",
    "diverged_runs",
    "elapsed_s",
];

/// The history as CSV text: [`HISTORY_COLUMNS`], then `best_<gene>` per gene.
/// Floats use Rust's shortest round-trip formatting.
pub fn history_csv(reports: &[GenerationReport], genes: &[GeneSpec]) -> String {
    let mut out = HISTORY_COLUMNS.join(",");
    for g in genes {
        let _ = write!(out, ",best_{}", g.name);
    }
    out.push('\n');
    for r in reports {
        let _ = write!(
            out,
            "{},{},{},{},{},{},{},{},{},{},{}",
            r.generation,
            r.best_cost,
            1.0 - r.best_cost,
            r.median_cost,
            r.diversity,
            r.evaluations,
            r.evaluated,
            r.evals_per_s,
            r.diverged,
            r.diverged_runs,
            r.elapsed_s
        );
        for x in &r.best_genome {
            let _ = write!(out, ",{x}");
        }
        out.push('\n');
    }
    out
}

/// Writes [`history_csv`] to `path` atomically.
pub fn write_history_csv(
    path: &Path,
    reports: &[GenerationReport],
    genes: &[GeneSpec],
) -> Result<(), SearchError> {
    atomic_write(path, history_csv(reports, genes).as_bytes()).map_err(|source| SearchError::Io {
        action: "writing history",
        path: path.into(),
        source,
    })
}
