//! Command-line arguments, converted into validated settings before any work.

use std::path::PathBuf;

use clap::{Args, Parser, Subcommand, ValueEnum};

/// Calibrates lumped mass-spring-damper models of mechanical test rigs to
/// measured force histories.
///
/// A campaign JSON file names the model, its fixed and free parameters, the
/// measured experiments and the search settings. `rigfit run` searches the free
/// parameters with a genetic algorithm whose populations are integrated on the
/// GPU (wgpu) or on all CPU cores (f64 reference), and writes the fitted
/// parameters, the cleaned specimen force and plots.
#[derive(Debug, Parser)]
#[command(
    name = "rigfit",
    version,
    propagate_version = true,
    max_term_width = 100
)]
#[command(after_help = "Examples:\n  \
    rigfit run campaigns/aa2024_t3_synthetic.json\n  \
    rigfit simulate campaigns/aa2024_t3_synthetic.json --out sim.csv\n  \
    rigfit modes campaigns/aa2024_t3_synthetic.json\n  \
    rigfit devices\n\n\
    Exit codes: 0 success, 1 failed job, 2 bad input or usage, 130 stopped by\n\
    Ctrl-C or SIGTERM (checkpoint kept; continue with --resume).\n\
    Diagnostics: RUST_LOG=debug rigfit …")]
pub struct Cli {
    /// Print nothing but errors (no progress bar, no summary).
    #[arg(long, short, global = true)]
    pub quiet: bool,
    /// Print a machine-readable JSON summary on stdout.
    #[arg(long, global = true)]
    pub json: bool,
    #[command(subcommand)]
    pub command: Command,
}

/// The subcommands.
#[derive(Debug, Subcommand)]
pub enum Command {
    /// Calibrate a campaign's free parameters (genetic algorithm).
    #[command(after_help = "Examples:\n  \
        rigfit run campaigns/aa2024_t3_synthetic.json\n  \
        rigfit run campaigns/aa2024_t3_synthetic.json --backend cpu --out results/cpu\n  \
        rigfit run campaigns/aa2024_t3_synthetic.json --resume\n\n\
        The output folder receives result.json, one CSV per experiment (measured,\n\
        every model output, residual), history.csv, fit_<experiment>.svg and\n\
        fitness.svg. A checkpoint is kept there while the job runs; Ctrl-C writes\n\
        one and stops cleanly, and --resume continues bit-identically.")]
    Run(RunArgs),
    /// Simulate a campaign with fixed values (or a result file) and write a CSV.
    #[command(after_help = "Examples:\n  \
        rigfit simulate campaigns/aa2024_t3_synthetic.json --out sim.csv\n  \
        rigfit simulate campaigns/aa2024_t3_synthetic.json --params results/aa2024/result.json --out fit.csv\n  \
        rigfit simulate campaigns/aa2024_t3_synthetic.json --noise 20 --seed 7 --out synthetic.csv\n\n\
        Columns: t_s (model time), load_cell_force_N, specimen_force_N, then every\n\
        state (y1..y4 in m, v1..v4 in m/s). With --noise the file is a synthetic\n\
        measurement instead: t_s (record time) and force_N with Gaussian noise.")]
    Simulate(SimulateArgs),
    /// Natural frequencies and mode shapes of the linearised rig.
    #[command(after_help = "Example:\n  rigfit modes campaigns/aa2024_t3_synthetic.json")]
    Modes(ModesArgs),
    /// List GPU adapters and whether they support f64 shaders.
    #[command(after_help = "Example:\n  rigfit devices\n\n\
        Set RIGFIT_REQUIRE_GPU=1 to make a missing adapter an error everywhere;\n\
        pick an adapter with `rigfit run --adapter I` (index, PCI bus id or a piece\n\
        of the name) or RIGFIT_ADAPTER.")]
    Devices,
    /// Fit the specimen law (linear, then polynomial) to quasi-static data.
    #[command(name = "fit-specimen")]
    #[command(after_help = "Example:\n  \
        rigfit fit-specimen campaigns/specimen_quasistatic_synthetic.csv --degree 3 --out specimen.json\n\n\
        Input: CSV of elongation (m) and force (N); '#' lines are comments.")]
    FitSpecimen(FitSpecimenArgs),
    /// Frequency and damping of a free ringdown (a hammer impact, a release, the load cell after a fracture).
    #[command(after_help = "Example:\n  \
        rigfit ringdown campaigns/ringdown_synthetic.csv --m1 7.9 --k1 8.4e9 --out loadcell.json\n\n\
        Input: CSV of time (s) and force (N); '#' lines are comments.")]
    Ringdown(RingdownArgs),
    /// Classical identification from the seed documents (restoring force, FRF, inverse model).
    Identify(super::identify::IdentifyArgs),
    /// Validate a campaign and its data without running anything.
    #[command(after_help = "Example:\n  rigfit check campaigns/aa2024_t3_synthetic.json")]
    Check(CheckArgs),
}

/// Evaluator backend on the command line.
#[derive(Debug, Clone, Copy, ValueEnum)]
pub enum BackendArg {
    /// GPU when an adapter exists, else CPU.
    Auto,
    /// GPU only.
    Gpu,
    /// f64 CPU reference.
    Cpu,
}

/// Arithmetic precision on the command line.
#[derive(Debug, Clone, Copy, ValueEnum)]
pub enum PrecisionArg {
    /// GPU: f64 when the adapter supports it, else f32. CPU: f64.
    Auto,
    /// Single precision (on the CPU: a compiled rig's native f32 lanes).
    F32,
    /// Double precision.
    F64,
}

/// `rigfit run`.
#[derive(Debug, Args)]
pub struct RunArgs {
    /// Campaign JSON file.
    pub campaign: PathBuf,
    /// Output folder (default: the campaign's "output").
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Evaluator backend (default: the campaign's solver.backend).
    #[arg(long, value_enum)]
    pub backend: Option<BackendArg>,
    /// Precision (default: the campaign's solver.precision); on the CPU only
    /// f32 differs from the f64 reference.
    #[arg(long, value_enum)]
    pub precision: Option<PrecisionArg>,
    /// Continue from the checkpoint in the output folder.
    #[arg(long)]
    pub resume: bool,
    /// Replace an output folder that holds an earlier job's files.
    #[arg(long)]
    pub overwrite: bool,
    /// Override the campaign's search.population.
    #[arg(long)]
    pub population: Option<usize>,
    /// Override the campaign's search.generations.
    #[arg(long)]
    pub generations: Option<usize>,
    /// Override the campaign's search.seed.
    #[arg(long)]
    pub seed: Option<u64>,
    /// Override the campaign's search.target_fitness (stop once 1 − R² ≤ this).
    #[arg(long)]
    pub target_fitness: Option<f64>,
    /// CPU threads for the CPU evaluator (0: all cores).
    #[arg(long, default_value_t = 0)]
    pub threads: usize,
    /// Refuse a job whose candidate takes more RK4 steps than this (all
    /// experiments together).
    #[arg(long, default_value_t = rigfit::campaign::DEFAULT_MAX_STEPS, value_parser = positive)]
    pub max_steps: f64,
    /// Refuse a job whose estimated memory exceeds this (bytes, or with K, M,
    /// G, T in powers of 1024: 512M, 2G); default: the memory available now
    /// (MemAvailable in /proc/meminfo).
    #[arg(long, value_parser = memory_size)]
    pub max_memory: Option<f64>,
    /// GPU adapter: its index, PCI bus id or a piece of its name, as `rigfit
    /// devices` lists them (default: RIGFIT_ADAPTER, else the first
    /// high-performance adapter). Recorded in result.json.
    #[arg(long)]
    pub adapter: Option<String>,
}

/// `rigfit simulate`.
#[derive(Debug, Args)]
pub struct SimulateArgs {
    /// Campaign JSON file.
    pub campaign: PathBuf,
    /// Parameter file (e.g. a result.json) whose "params" replace the campaign's values.
    #[arg(long)]
    pub params: Option<PathBuf>,
    /// CSV file to write.
    #[arg(long)]
    pub out: PathBuf,
    /// Replace the --out file when it exists (never the campaign's own input files).
    #[arg(long)]
    pub overwrite: bool,
    /// Experiment to simulate, by name (default: the first).
    #[arg(long)]
    pub experiment: Option<String>,
    /// Write a synthetic measurement with Gaussian noise of this standard deviation
    /// (in the unit of the rig's output 0, the fitted one: N for the tensile rig).
    #[arg(long)]
    pub noise: Option<f64>,
    /// Seed of the noise.
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
    /// Samples to simulate at the experiment's sample interval (default: the
    /// experiment's run length).
    #[arg(long)]
    pub samples: Option<usize>,
    /// Refuse a job whose candidate takes more RK4 steps than this (all
    /// experiments together).
    #[arg(long, default_value_t = rigfit::campaign::DEFAULT_MAX_STEPS, value_parser = positive)]
    pub max_steps: f64,
}

/// `rigfit modes`.
#[derive(Debug, Args)]
pub struct ModesArgs {
    /// Campaign JSON file.
    pub campaign: PathBuf,
    /// Parameter file (e.g. a result.json) whose "params" replace the campaign's values.
    #[arg(long)]
    pub params: Option<PathBuf>,
}

/// `rigfit check`.
#[derive(Debug, Args)]
pub struct CheckArgs {
    /// Campaign JSON file.
    pub campaign: PathBuf,
    /// Refuse a job whose candidate takes more RK4 steps than this (all
    /// experiments together).
    #[arg(long, default_value_t = rigfit::campaign::DEFAULT_MAX_STEPS, value_parser = positive)]
    pub max_steps: f64,
}

/// `rigfit fit-specimen`.
#[derive(Debug, Args)]
pub struct FitSpecimenArgs {
    /// CSV of elongation (m) and force (N).
    pub data: PathBuf,
    /// Degree of the plastic polynomial (3 for aluminium, 5 for carbon/epoxy; at most 5).
    #[arg(long, default_value_t = 3)]
    pub degree: usize,
    /// Write the campaign fragment (JSON) here.
    #[arg(long)]
    pub out: Option<PathBuf>,
}

/// `rigfit ringdown`.
#[derive(Debug, Args)]
pub struct RingdownArgs {
    /// CSV of time (s) and force (N).
    pub data: PathBuf,
    /// Load-cell mass m1 (kg): with it, k1 follows from the frequency.
    #[arg(long)]
    pub m1: Option<f64>,
    /// Load-cell stiffness k1 (N/m), held fixed in the damping fit.
    #[arg(long)]
    pub k1: Option<f64>,
    /// Start of the free ringing (s; default: the start of the largest drop, e.g. a fracture).
    #[arg(long)]
    pub start: Option<f64>,
    /// Write the campaign fragment (JSON) here.
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Write the figure (SVG) here: the ringing with its fitted decay and envelope,
    /// and the peaks' decay against each estimator's.
    #[arg(long)]
    pub svg: Option<PathBuf>,
}

/// A memory size: `2G`, `512M`, `1048576`.
fn memory_size(s: &str) -> Result<f64, String> {
    rigfit::job::memory::parse_bytes(s).ok_or_else(|| {
        format!(
            "expected a size > 0 in bytes or with K, M, G or T (512M, 2G), found {}",
            rigfit::base::text::echo(s)
        )
    })
}

/// A finite number > 0.
fn positive(s: &str) -> Result<f64, String> {
    match s.parse::<f64>() {
        Ok(v) if v > 0.0 && v.is_finite() => Ok(v),
        _ => Err(format!(
            "expected a number > 0, found {}",
            rigfit::base::text::echo(s)
        )),
    }
}
