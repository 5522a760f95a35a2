//! The series' folder: its manifest (`series.json`), and each test's status
//! file (`status/<test>.json`), both written atomically by rigfit alone.

use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use super::SeriesError;
use crate::base::fsutil::atomic_write;

/// The manifest in a series' folder.
pub const MANIFEST_FILE: &str = "series.json";
/// The folder of the tests' campaigns.
pub const CAMPAIGNS_DIR: &str = "campaigns";
/// The folder of the tests' job folders.
pub const TESTS_DIR: &str = "tests";
/// The folder of the tests' status files.
pub const STATUS_DIR: &str = "status";
/// The summary table.
pub const SUMMARY_CSV: &str = "summary.csv";
/// The summary page.
pub const SUMMARY_HTML: &str = "summary.html";

/// What a manifest's `generator` says: a folder without it is not a
/// series rigfit wrote.
pub const GENERATOR: &str = "rigfit series";

/// A series as prepared: every test with its campaign, seed, covariates and
/// output folder, and the tasks a Slurm array runs them in. Paths are
/// relative to the series' folder, so that the folder may move.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Manifest {
    /// Always [`GENERATOR`].
    pub generator: String,
    /// The series' name (its file's `name`).
    pub name: String,
    /// The series file it was prepared from (absolute).
    pub series_file: PathBuf,
    /// The covariate columns of the table, in its order.
    pub covariates: Vec<String>,
    /// The tests, in the table's (or the campaign list's) order.
    pub tests: Vec<TestEntry>,
    /// The tests of each task of a Slurm array (indices into `tests`); one
    /// test per task unless a plan packed several short ones.
    pub tasks: Vec<Vec<usize>>,
}

/// One test of a series.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TestEntry {
    /// Its name: the table's `test`, or the campaign file's stem. Names its
    /// campaign, job folder and status file.
    pub id: String,
    /// Its campaign file, relative to the series' folder
    /// (`campaigns/<id>.json`); `rigfit run` on it runs the same job.
    pub campaign: PathBuf,
    /// Its job folder, relative to the series' folder (`tests/<id>`).
    pub out: PathBuf,
    /// The search's seed.
    pub seed: u64,
    /// Its value of each covariate (`""` where the table leaves it empty),
    /// in [`Manifest::covariates`]' order.
    pub covariates: Vec<String>,
    /// Where it was read from (`tests.csv line 4`, or a campaign file).
    pub source: String,
    /// Why it could not be prepared, if so (a record that is missing): the
    /// test is kept, and fails with this error when it runs.
    pub error: Option<String>,
    /// The estimated steps of its search (population × generations × steps
    /// per candidate), by which a plan packs short tests into one task; 0
    /// where unknown.
    #[serde(default)]
    pub work: f64,
}

/// How a test ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum TestState {
    /// Its job wrote its results.
    Done,
    /// It could not run, or its job failed: the status says why.
    Failed,
    /// Interrupted (Ctrl-C, SIGTERM, Slurm's SIGUSR1) with its checkpoint
    /// kept: running it again resumes it.
    Interrupted,
}

/// A test's status file (`status/<id>.json`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct TestStatus {
    /// The test.
    pub id: String,
    /// How it ended.
    pub state: TestState,
    /// The error, with its causes, where it failed.
    pub error: Option<String>,
    /// The SHA-256 of the campaign file it ran: a status of another
    /// campaign (the series prepared again with changes) does not count.
    pub campaign_sha256: String,
    /// Wall time of this run of the test (s).
    pub wall_time_s: f64,
    /// `"cpu"` or `"gpu"`, where an evaluator was opened.
    pub backend: Option<String>,
    /// The device or threads.
    pub device: Option<String>,
    /// The GPU adapter the scheduler gave the task, and how it was matched
    /// (`SLURM_JOB_GPUS=1 → PCI 0000:3b:00.0`), where one was.
    pub adapter: Option<String>,
    /// The machine it ran on.
    pub host: String,
    /// The Slurm task that ran it (`--task`), if one did.
    pub task: Option<usize>,
    /// The Slurm job (`SLURM_ARRAY_JOB_ID_SLURM_ARRAY_TASK_ID`, or
    /// `SLURM_JOB_ID`) and its restart count, where Slurm ran it.
    pub slurm_job: Option<String>,
    /// `SLURM_RESTART_COUNT`: how often Slurm requeued the task.
    pub restarts: u32,
}

impl Manifest {
    /// Reads the manifest of the series' folder `root`.
    pub fn read(root: &Path) -> Result<Manifest, SeriesError> {
        let path = root.join(MANIFEST_FILE);
        let text = crate::base::fsutil::read_description(&path).map_err(|e| {
            if e.kind() == std::io::ErrorKind::NotFound {
                SeriesError::Folder {
                    path: root.to_path_buf(),
                    reason: format!("it holds no {MANIFEST_FILE}: not a series rigfit prepared"),
                }
            } else {
                SeriesError::io(&path, e)
            }
        })?;
        let manifest: Manifest = serde_json::from_str(&text)
            .map_err(|e| SeriesError::input(&path, "(file)", e.to_string()))?;
        if manifest.generator != GENERATOR {
            return Err(SeriesError::Folder {
                path: root.to_path_buf(),
                reason: format!("its {MANIFEST_FILE} was not written by {GENERATOR}"),
            });
        }
        Ok(manifest)
    }

    /// Writes it into `root`, atomically.
    pub fn write(&self, root: &Path) -> Result<(), SeriesError> {
        let path = root.join(MANIFEST_FILE);
        let mut text = serde_json::to_string_pretty(self).expect("a manifest serialises");
        text.push('\n');
        atomic_write(&path, text.as_bytes()).map_err(|e| SeriesError::io(&path, e))
    }

    /// The test called `id`.
    pub fn test(&self, id: &str) -> Option<&TestEntry> {
        self.tests.iter().find(|t| t.id == id)
    }

    /// The tests of task `task`, or an error naming the tasks there are.
    pub fn task(&self, task: usize) -> Result<&[usize], SeriesError> {
        self.tasks.get(task).map(Vec::as_slice).ok_or_else(|| {
            SeriesError::Task(format!(
                "task {task}: the series `{}` has tasks 0 to {} ({} tests)",
                self.name,
                self.tasks.len().saturating_sub(1),
                self.tests.len()
            ))
        })
    }
}

impl TestStatus {
    /// The status file of test `id` in the series' folder `root`.
    pub fn path(root: &Path, id: &str) -> PathBuf {
        root.join(STATUS_DIR).join(format!("{id}.json"))
    }

    /// The status of test `id`, if it has one that can be read.
    pub fn read(root: &Path, id: &str) -> Option<TestStatus> {
        let text = std::fs::read_to_string(Self::path(root, id)).ok()?;
        serde_json::from_str(&text).ok()
    }

    /// Writes it into `root`, atomically.
    pub fn write(&self, root: &Path) -> Result<(), SeriesError> {
        let path = Self::path(root, &self.id);
        let mut text = serde_json::to_string_pretty(self).expect("a status serialises");
        text.push('\n');
        atomic_write(&path, text.as_bytes()).map_err(|e| SeriesError::io(&path, e))
    }
}

/// The SHA-256 of a file's bytes, in hex.
pub(crate) fn file_sha256(path: &Path) -> Result<String, SeriesError> {
    use sha2::Digest as _;
    let bytes = std::fs::read(path).map_err(|e| SeriesError::io(path, e))?;
    let digest = sha2::Sha256::digest(&bytes);
    Ok(digest.iter().map(|b| format!("{b:02x}")).collect())
}
