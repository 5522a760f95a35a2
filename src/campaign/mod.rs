//! Campaign files: the JSON a job is driven by, validated into a [`Campaign`]
//! before any work starts.
//!
//! The format, key by key (units in brackets):
//!
//! ```json
//! {
//!   "name": "aa2024-t3-synthetic",
//!   "description": "optional free text",
//!   "rig": "tensile4",
//!   "params": {
//!     "m1": 7.9,
//!     "k1": {"min": 2e9, "max": 3e10, "scale": "log", "init": 8e9},
//!     "c1": {"min": 1e4, "max": 3e6}
//!   },
//!   "experiments": [{
//!     "name": "v2",
//!     "data": {"file": "v2.csv", "time_column": "t_s", "force_column": "force_N"},
//!     "drive": "velocity",
//!     "fit_window": {"start": 0.0, "end": 2.5e-3},
//!     "offset": 0.0,
//!     "weight": 1.0,
//!     "params": {"velocity": 2.0, "k_lin": {"min": 3e7, "max": 3e8}}
//!   }],
//!   "solver": {"substeps": "auto", "backend": "auto", "precision": "auto"},
//!   "search": {"population": 1024, "generations": 150, "seed": 1},
//!   "output": "results/aa2024"
//! }
//! ```
//!
//! See [`raw`] for every key. Genes come in this order: the shared (top-level)
//! free parameters in model order, then for each experiment its own free
//! parameters in model order followed by its free offset.

mod build;
mod channels;
mod error;
mod initial;
mod integration_error;
mod names;
mod param_file;
mod plausible;
pub mod raw;
pub mod record_file;
mod resolve;
mod run_length;
mod simulation;
mod stability;
mod validation;
mod window;

use std::path::{Path, PathBuf};
use std::sync::Arc;

pub use error::CampaignError;
pub use integration_error::{
    ChannelStep, IntegrationError, SYNTHETIC_BIAS_SHARE, SYNTHETIC_CAP_FACTOR,
    SYNTHETIC_NOISE_FRACTION, SimulationStep,
};
pub use names::{MAX_NAME_CHARS, file_stem};
pub use plausible::{
    LATE_START_FACTOR, MAGNITUDE_FACTOR, MAGNITUDE_MAX_STEPS, MIN_WINDOW_SAMPLES, MIN_WINDOW_SHARE,
    UNIT_BAND,
};
pub use run_length::{
    CPU_STEPS_PER_S_PER_CORE, DEFAULT_MAX_STEPS, ExperimentRun, RunLength, human_duration,
};
pub use simulation::SimulationGrid;
pub use stability::{
    ACCURACY_CAP_FACTOR, ACCURACY_MARGIN, ESTIMATE_MAX_RUN_STEPS, ESTIMATE_REFERENCE_STATES,
    MAX_AUTO_SUBSTEPS, NOISE_FRACTION, SPREAD_FLOOR, STABILITY_LIMIT, SolverSettings,
    estimate_max_steps,
};

use crate::base::Scale;
use crate::eval::{Batch, DIVERGED, Problem, Scores};
use crate::model::CompiledRig;
use crate::record::lent::Lent;
use crate::search::SearchSettings;

/// What a gene sets.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum GeneTarget {
    /// The model parameter at this index.
    Param(usize),
    /// The experiment's clock offset.
    Offset,
}

/// One searched quantity.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Gene {
    /// `"k1"` (shared), `"v2.k_lin"` (experiment `v2`'s own) or `"v2.offset"`.
    pub name: String,
    /// `None` for a shared gene, else the experiment it belongs to.
    pub experiment: Option<usize>,
    /// What it sets.
    pub target: GeneTarget,
    /// Lower bound (unit below).
    pub lower: f64,
    /// Upper bound (unit below).
    pub upper: f64,
    /// Scale the search moves in.
    pub scale: Scale,
    /// Seed value for the initial population.
    pub init: Option<f64>,
    /// SI unit.
    pub unit: String,
}

/// Whether gene `g` acts in a run of campaign experiment `owner` whose
/// parameters come from `sources`: its own genes, and shared genes of
/// parameters the experiment does not override.
pub(crate) fn acts_in(g: &Gene, owner: usize, sources: &[Source]) -> bool {
    match (g.experiment, g.target) {
        (Some(x), _) => x == owner,
        (None, GeneTarget::Param(i)) => sources[i] == Source::Shared,
        (None, GeneTarget::Offset) => true,
    }
}

/// Where an experiment's value of a parameter comes from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Source {
    /// The model default.
    Default,
    /// The top-level `params`.
    Shared,
    /// The experiment's own `params`.
    Own,
}

/// A validated campaign: model, measured data, genes and settings.
#[derive(Debug, Clone)]
pub struct Campaign {
    /// The campaign file (as given).
    pub path: PathBuf,
    /// Campaign name.
    pub name: String,
    /// Free text from the file.
    pub description: Option<String>,
    /// The rig model.
    pub model: Arc<CompiledRig>,
    /// Model plus measured experiments; `problem.substeps` is `solver.substeps`.
    /// An experiment with `channels` is one problem experiment per channel
    /// (named `<experiment>.<output>`), each scoring its own output; they run
    /// with the same parameters ([`Campaign::owners`]).
    pub problem: Problem,
    /// For each problem experiment, the index of the campaign experiment it
    /// belongs to (itself, but for the channels of one experiment).
    pub owners: Vec<usize>,
    /// The searched quantities, in genome order; a gene's `experiment` is a
    /// campaign experiment ([`Campaign::owners`]).
    pub genes: Vec<Gene>,
    /// Per experiment, the full parameter vector: fixed values, free ones at
    /// their init or mid-range (geometric mid for log scale).
    pub base: Vec<Vec<f64>>,
    /// Per experiment, the clock offset (s), free ones at init or mid-range.
    pub base_offsets: Vec<f64>,
    /// Integration settings as chosen.
    pub solver: SolverSettings,
    /// Search settings (validated when given).
    pub search: SearchSettings,
    /// Whether the file has a `search` section; without one, `search` holds
    /// [`SearchSettings::unset`] and [`Campaign::require_search`] refuses a run.
    pub search_given: bool,
    /// Results folder (resolved against the campaign's folder).
    pub output: PathBuf,
    /// The files the campaign was read from (the campaign file, its rig file
    /// if it names one, then each experiment's data file): a job never writes
    /// over them.
    pub inputs: Vec<PathBuf>,
    /// What each problem experiment read of its record file (its format, the
    /// channel and the unit the file records), for result.json; none for an
    /// experiment simulated on a grid.
    pub records: Vec<record_file::RecordUse>,
    /// The campaign text as read.
    pub raw_json: String,
    /// FNV-1a hash of the campaign text and every data file's bytes; a resumed
    /// run refuses a different digest.
    pub digest: u64,
    /// Things the user should hear about (resampled data, unused genes).
    pub warnings: Vec<String>,
    /// The file's `"validation"` records, as a campaign of their own (read
    /// for a fit only): its experiments are those records, its genes the
    /// shared free parameters they take, never searched (a job simulates
    /// them at the fitted values, see [`Campaign::validation_genome`]).
    pub validation: Option<Box<Campaign>>,
    pub(crate) sources: Vec<Vec<Source>>,
}

impl Campaign {
    /// Index of the problem experiment called `name`; otherwise the list of
    /// the campaign's experiment names, for the message.
    pub fn experiment_index(&self, name: &str) -> Result<usize, String> {
        let exps = &self.problem.experiments;
        exps.iter().position(|x| x.name == name).ok_or_else(|| {
            let names: Vec<&str> = exps.iter().map(|x| x.name.as_str()).collect();
            names.join(", ")
        })
    }

    /// The campaign experiments' names, in the file's order: each one's first
    /// run's name up to its `.` (a channel's run is `<experiment>.<output>`,
    /// and an experiment's own name has none).
    pub fn experiment_names(&self) -> Vec<&str> {
        let exps = &self.problem.experiments;
        (0..self.owners.len())
            .filter(|&e| e == 0 || self.owners[e] != self.owners[e - 1])
            .map(|e| exps[e].name.split('.').next().unwrap_or_default())
            .collect()
    }

    /// The problem experiments of the campaign experiment called `name` (one,
    /// or one per channel); otherwise the list of the campaign's experiment
    /// names, for the message.
    pub fn runs_of(&self, name: &str) -> Result<Vec<usize>, String> {
        let names = self.experiment_names();
        let owner = names
            .iter()
            .position(|&x| x == name)
            .ok_or_else(|| names.join(", "))?;
        Ok((0..self.owners.len())
            .filter(|&e| self.owners[e] == owner)
            .collect())
    }

    /// Reads and validates a campaign file; data files are relative to its
    /// folder.
    pub fn load(path: &Path) -> Result<Campaign, CampaignError> {
        let text = crate::base::fsutil::read_description(path).map_err(|e| CampaignError::Io {
            file: path.to_path_buf(),
            message: e.to_string(),
        })?;
        let dir = path.parent().unwrap_or(Path::new("."));
        validation::build_fit(&text, dir, path, &Lent::none())
    }

    /// Reads and validates a campaign file for a simulation on `grid`: its
    /// records are not scored (a constant placeholder column is accepted), and
    /// with [`SimulationGrid::Uniform`] not read at all. The step is chosen for
    /// the grid as for a fit.
    pub fn load_for_simulation(
        path: &Path,
        grid: &SimulationGrid,
    ) -> Result<Campaign, CampaignError> {
        let text = crate::base::fsutil::read_description(path).map_err(|e| CampaignError::Io {
            file: path.to_path_buf(),
            message: e.to_string(),
        })?;
        let dir = path.parent().unwrap_or(Path::new("."));
        build::build(
            &text,
            dir,
            path,
            simulation::Reading::Simulate(grid),
            &Lent::none(),
        )
    }

    /// Validates campaign text; relative paths resolve against `base_dir` and
    /// messages name `origin` as the file.
    pub fn from_str(json: &str, base_dir: &Path, origin: &str) -> Result<Campaign, CampaignError> {
        validation::build_fit(json, base_dir, Path::new(origin), &Lent::none())
    }

    /// Validates campaign text as [`Campaign::from_str`] (`grid` `None`: for
    /// a fit) or [`Campaign::from_str_for_simulation`] does, with the records
    /// `lent` read in place of the files at those paths.
    pub fn from_str_lent(
        json: &str,
        base_dir: &Path,
        origin: &str,
        lent: &Lent,
        grid: Option<&SimulationGrid>,
    ) -> Result<Campaign, CampaignError> {
        let file = Path::new(origin);
        match grid {
            None => validation::build_fit(json, base_dir, file, lent),
            Some(grid) => build::build(
                json,
                base_dir,
                file,
                simulation::Reading::Simulate(grid),
                lent,
            ),
        }
    }

    /// Validates campaign text for a simulation on `grid`, as
    /// [`Campaign::load_for_simulation`] reads a file: relative paths resolve
    /// against `base_dir`, messages name `origin` as the file.
    pub fn from_str_for_simulation(
        json: &str,
        base_dir: &Path,
        origin: &str,
        grid: &SimulationGrid,
    ) -> Result<Campaign, CampaignError> {
        build::build(
            json,
            base_dir,
            Path::new(origin),
            simulation::Reading::Simulate(grid),
            &Lent::none(),
        )
    }

    /// Refuses a campaign with nothing to search (for `rigfit run`).
    pub fn require_genes(&self) -> Result<(), CampaignError> {
        if self.genes.is_empty() {
            return Err(CampaignError::NoFreeParameters {
                file: self.path.clone(),
            });
        }
        Ok(())
    }

    /// Refuses a campaign without a `search` section (for `rigfit run`;
    /// `simulate`, `modes` and `check` do not need one).
    pub fn require_search(&self) -> Result<(), CampaignError> {
        if self.search_given {
            return Ok(());
        }
        Err(error::invalid(
            &self.path,
            "search",
            "a search section {\"population\", \"generations\", …} to run a calibration",
            "none",
        ))
    }

    /// Full parameter vector and offset of each experiment for one genome (one
    /// value per gene, in gene order, physical units).
    pub fn full_params(&self, genome: &[f64]) -> Vec<(Vec<f64>, f64)> {
        assert_eq!(
            genome.len(),
            self.genes.len(),
            "genome length != gene count"
        );
        (0..self.base.len())
            .map(|e| {
                let mut p = self.base[e].clone();
                let mut offset = self.base_offsets[e];
                for (g, &v) in self.genes.iter().zip(genome) {
                    if acts_in(g, self.owners[e], &self.sources[e]) {
                        match g.target {
                            GeneTarget::Param(i) => p[i] = v,
                            GeneTarget::Offset => offset = v,
                        }
                    }
                }
                (p, offset)
            })
            .collect()
    }

    /// The evaluator batch for a population of genomes.
    pub fn batch(&self, genomes: &[Vec<f64>]) -> Batch {
        let n_exp = self.base.len();
        let mut batch = Batch {
            candidates: genomes.len(),
            params: vec![Vec::with_capacity(genomes.len() * self.model.params().len()); n_exp],
            offsets: vec![Vec::with_capacity(genomes.len()); n_exp],
        };
        for genome in genomes {
            for (e, (p, off)) in self.full_params(genome).into_iter().enumerate() {
                batch.params[e].extend_from_slice(&p);
                batch.offsets[e].push(off);
            }
        }
        batch
    }

    /// Joint fitness per candidate: the weighted mean of `1 − R²` over the
    /// experiments; [`DIVERGED`] if any experiment diverged.
    pub fn combine(&self, scores: &Scores) -> Vec<f64> {
        let weights = self.problem.relative_weights();
        let total: f64 = weights.iter().sum();
        let n = scores.values.len() / scores.experiments.max(1);
        (0..n)
            .map(|i| {
                let mut sum = 0.0;
                for (e, w) in weights.iter().enumerate() {
                    let s = scores.get(i, e);
                    if s.is_nan() || s >= DIVERGED {
                        return DIVERGED;
                    }
                    sum += w * s;
                }
                sum / total
            })
            .collect()
    }

    /// Sets values from a parameter file, `{"params": {"k1": 8.4e9,
    /// "v2.k_lin": 8.6e7, "v2.offset": 1.0e-5}}` (other top-level keys, as in a
    /// run's `result.json`, are ignored) or the same values as a flat object,
    /// `{"k1": 8.4e9, …}`. A plain name sets the parameter in
    /// every experiment that takes it from the top level or the model default;
    /// `<experiment>.<param>` sets one experiment's experiment-scope parameter;
    /// `<experiment>.offset` its offset (s). Genes of those names become fixed;
    /// the model's checks and the step size are applied again. A refused file
    /// leaves the campaign unchanged.
    pub fn apply_param_file(&mut self, path: &Path) -> Result<(), CampaignError> {
        param_file::apply(self, path)
    }

    /// Sets `values` by name as [`Campaign::apply_param_file`] sets a file's
    /// (`None`: +∞); refusals name `file` and the JSON path `under` followed
    /// by the name (`under`: `"variables."`, or `""` at the top level). For
    /// `rigfit sweep`, whose design points are values, not files.
    pub fn apply_values(
        &mut self,
        values: &std::collections::BTreeMap<String, Option<f64>>,
        file: &Path,
        under: &str,
    ) -> Result<(), CampaignError> {
        param_file::apply_values(self, values, file, under, true)
    }

    /// [`Campaign::apply_values`] without choosing the step again: for a
    /// caller that sets `problem.substeps` itself (`rigfit sweep` with a
    /// fixed step, as `rigfit simulate --substeps` runs).
    pub fn set_values(
        &mut self,
        values: &std::collections::BTreeMap<String, Option<f64>>,
        file: &Path,
        under: &str,
    ) -> Result<(), CampaignError> {
        param_file::apply_values(self, values, file, under, false)
    }

    /// Whether gene `g` (an index into [`Campaign::genes`]) acts in experiment
    /// `e`: a shared gene does not act where the experiment sets the parameter
    /// itself.
    pub fn gene_acts_in(&self, g: usize, e: usize) -> bool {
        acts_in(&self.genes[g], self.owners[e], &self.sources[e])
    }

    /// Bounds of experiment `e`'s parameter vector: fixed values, free ones at
    /// their bounds.
    pub fn bounds(&self, e: usize) -> (Vec<f64>, Vec<f64>) {
        build::corners(&self.base[e], &self.genes, self.owners[e], &self.sources[e])
    }
}

/// FNV-1a, 64 bit: stable across Rust versions, unlike `DefaultHasher`.
pub(crate) fn fnv1a(hash: u64, bytes: &[u8]) -> u64 {
    bytes.iter().fold(hash, |h, &b| {
        (h ^ u64::from(b)).wrapping_mul(0x0000_0100_0000_01b3)
    })
}

/// FNV-1a offset basis.
pub(crate) const FNV_BASIS: u64 = 0xcbf2_9ce4_8422_2325;
