//! The command line: the top-level options and the list of commands. Each
//! command's own arguments live beside its code.

use clap::{CommandFactory, FromArgMatches, Parser, Subcommand};

use super::check::CheckArgs;
use super::fit_specimen::FitSpecimenArgs;
use super::identify::IdentifyArgs;
use super::inspect::InspectArgs;
use super::modes::ModesArgs;
use super::profile::ProfileArgs;
use super::report::ReportArgs;
use super::ringdown::RingdownArgs;
use super::run::RunArgs;
use super::series::SeriesArgs;
use super::simulate::SimulateArgs;
use super::sweep::SweepArgs;
use super::validate::ValidateArgs;

/// Calibrates lumped mass-spring-damper models of mechanical test rigs to
/// measured force histories.
///
/// A campaign JSON file names the rig, its fixed and free parameters, the
/// measured experiments and the search settings. `rigfit run` searches the free
/// parameters with a genetic algorithm whose populations are integrated on the
/// GPU (wgpu) or on all CPU cores (f64 reference), and writes the fitted
/// parameters, the cleaned specimen force and plots. The method is that of Yoo,
/// Kim, Toso, Voggenreiter, "Application of Model-based Design Approach on
/// Dynamic Tensile Testing of Carbon/Epoxy Composites at Intermediate Strain
/// Rates".
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
        every rig output, residual), history.csv, fit_<experiment>.svg and\n\
        fitness.svg. A checkpoint is kept there while the job runs; Ctrl-C writes\n\
        one and stops cleanly, and --resume continues bit-identically.")]
    Run(RunArgs),
    /// Simulate a campaign with fixed values (or a result file) and write a CSV.
    #[command(after_help = "Examples:\n  \
        rigfit simulate campaigns/aa2024_t3_synthetic.json --out sim.csv\n  \
        rigfit simulate campaigns/aa2024_t3_synthetic.json --params results/aa2024/result.json --out fit.csv\n  \
        rigfit simulate campaigns/aa2024_t3_synthetic.json --noise 20 --seed 7 --out synthetic.csv\n  \
        rigfit simulate my_campaign.json --params truth.json --duration 2 --dt 1e-3 --noise 5e-6 --out e1.csv\n\n\
        Columns: t_s (simulated time), then each of the rig's outputs as <name>_<unit>,\n\
        then each of its states, all by the rig's own names, then a drive column the\n\
        campaign reads from its record. With --noise the file is a synthetic record\n\
        instead, in the columns the campaign reads: time, the measured output (output\n\
        0) with Gaussian noise in that output's unit, and the drive column if any.\n\
        With --dt (and --samples or --duration) no record is read: the run starts at\n\
        t = 0, and a drive column comes from --drive FILE.")]
    Simulate(SimulateArgs),
    /// Run the rig over a grid of design changes and write each run's metrics (ringing, peak, overshoot, …).
    #[command(after_help = "Examples:\n  \
        rigfit sweep adapter_damping.sweep.json --out table.csv\n  \
        rigfit sweep adapter_damping.sweep.json --out table.csv --overwrite --threads 4 --json\n\n\
        The sweep file names a campaign (paths relative to the sweep file), optionally\n\
        \"params\": a parameter file of calibrated values as simulate --params takes it,\n\
        \"experiment\" (default: the first), \"variables\": {name: grid} with a grid\n\
        {\"values\": [...]}, {\"linear\": [from, to, n]} or {\"log\": [from, to, n]}, and\n\
        \"metrics\": [{\"name\", \"metric\", \"output\", ...}] of peak, max, min, mean, rms,\n\
        overshoot, rise_time, settling_time, first_crossing (\"threshold\"), energy,\n\
        ringing and ringing_hz (\"against\": another output, or \"window_s\": a moving\n\
        average), over the experiment's fit window. Every point of the full grid is\n\
        simulated as `rigfit simulate --params` would run it (its step included, or\n\
        \"substeps\": N for all, as simulate --substeps N), on all CPU cores, in chunks\n\
        of bounded memory. The CSV: point, each variable, each\n\
        metric (empty where not defined). See docs/guide/design.md.")]
    Sweep(SweepArgs),
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
    #[command(
        after_help = "A pre-calibration step, taken before the rig is searched: the specimen law of\n\
        the tensile rig, as in Yoo, Kim, Toso, Voggenreiter, \"Application of Model-based\n\
        Design Approach on Dynamic Tensile Testing of Carbon/Epoxy Composites at\n\
        Intermediate Strain Rates\".\n\n\
        Example:\n  \
        rigfit fit-specimen campaigns/specimen_quasistatic_synthetic.csv --degree 3 --out specimen.json\n\n\
        Input: CSV of elongation (m) and force (N); '#' lines are comments."
    )]
    FitSpecimen(FitSpecimenArgs),
    /// Frequency and damping of a free ringdown (a hammer impact, a release, the load cell after a fracture).
    #[command(
        after_help = "A pre-calibration step, taken before the rig is searched: the load cell's\n\
        ringing after a fracture, as in Yoo, Kim, Toso, Voggenreiter, \"Application of\n\
        Model-based Design Approach on Dynamic Tensile Testing of Carbon/Epoxy Composites\n\
        at Intermediate Strain Rates\", and the free decay and logarithmic decrement of\n\
        \"Experimental Investigations of Lubricated Bearing Stiffness\".\n\n\
        Example:\n  \
        rigfit ringdown campaigns/ringdown_synthetic.csv --m1 7.9 --k1 8.4e9 --out loadcell.json\n  \
        rigfit ringdown hammer.csv --time t_s --signal x_m --mass 3 --names k_x,c_x --out bearing.json\n\n\
        Input: CSV of time (s) and the ringing signal (force in N, or a motion), two columns\n\
        or those --time and --signal name; '#' lines are comments."
    )]
    Ringdown(RingdownArgs),
    /// Classical identification from the papers the shipped rigs come from (restoring force, FRF, inverse model).
    Identify(IdentifyArgs),
    /// List what a record file holds (channels, units, lengths, rates): CSV, TDMS, HDF5, MAT, UFF 58.
    #[command(after_help = "Examples:\n  \
        rigfit inspect campaigns/formats/aa2024_t3_v2.tdms\n  \
        rigfit inspect run7.h5 --json\n  \
        rigfit inspect export.dat --format uff\n\n\
        Each channel is listed with its index (0-based), its full name (TDMS\n\
        group/channel, HDF5 /group/dataset, MAT variable or struct.field, UFF 58 the\n\
        dataset's first ID line), the unit the file records, its sample count, its\n\
        own timing where the file states one, and its range; then the \"data\" object a\n\
        campaign reads it with. Campaign column keys take the full name, the index, or\n\
        the name's last part where no other channel ends alike. See\n\
        docs/guide/records.md.")]
    Inspect(InspectArgs),
    /// Validate a campaign and its data without running the job, and estimate its memory and time.
    #[command(
        after_help = "The time is estimated from rates measured for this job on this machine: \
        `run --backend auto`'s, the rate its last search here ran at, or, where there are none, \
        check's own race of the two paths as `run --backend auto` races them (a fraction of a \
        second to a second or two; the choice is cached, and the run that follows takes it \
        without a trial), or the CPU lanes timed alone where there is no GPU. --no-measure: \
        assumed rates.\n\n\
        Example:\n  rigfit check campaigns/aa2024_t3_synthetic.json"
    )]
    Check(CheckArgs),
    /// Rebuild a result folder's report.html (one self-contained page) from its files.
    #[command(after_help = "Examples:\n  \
        rigfit report results/aa2024\n  \
        rigfit report results/aa2024 --out aa2024.html\n\n\
        The page is built from the folder's files alone (result.json, the experiments'\n\
        CSVs, history.csv): the same bytes the job wrote. It opens offline in any\n\
        browser: the verdict and warnings, the run's summary with the data files'\n\
        SHA-256, each experiment's fit, residual and residual spectrum (wheel to zoom,\n\
        drag to pan), the parameter table, correlations, convergence, profiles and\n\
        validation. A file that exists and is not a report rigfit wrote is never\n\
        replaced.")]
    Report(ReportArgs),
    /// Simulate records a finished job did not fit at its fitted values, and score them.
    #[command(after_help = "Examples:\n  \
        rigfit validate results/my-rig my_campaign.json\n  \
        rigfit validate results/my-rig more_records.json\n\n\
        CAMPAIGN names the same rig as the job; its \"validation\" records are read, or,\n\
        in a file without \"validation\", its \"experiments\". Each record is simulated\n\
        (f64 CPU reference) at the values in RESULT_DIR/result.json, never fitted: a\n\
        record may take the top-level params and fixed values of its own, not a free\n\
        range. Written into RESULT_DIR: validation_<record>.csv (the fit CSVs' columns)\n\
        and result.json's \"validation\" (R², residual RMS, noise estimate, cost over\n\
        the noise floor), its warnings and verdict flags, then report.html again. A\n\
        record fitted more than 2× worse over its noise floor than the worst estimation\n\
        record is flagged: over-fitting, or a rig that does not generalise.")]
    Validate(ValidateArgs),
    /// Profile likelihoods of a finished job's fitted parameters, added to its result.json.
    #[command(after_help = "Examples:\n  \
        rigfit profile results/aa2024\n  \
        rigfit profile results/aa2024 --backend cpu --points 16 --span 4\n\n\
        Each free parameter is held at a grid of values across its 95 % interval and\n\
        beyond, and the others are re-optimised there (Levenberg–Marquardt, every grid\n\
        point of every parameter in one batch per iteration). The profile's interval is\n\
        where Δχ² ≤ 1.96²; flat, one-sided or far-from-quadratic profiles are flagged.\n\
        The result goes into result.json's `profiles`, its warnings and verdict, and\n\
        report.html is rebuilt. Ctrl-C stops between iterations; the same command goes\n\
        on from where it stopped.")]
    Profile(ProfileArgs),
    /// Run a lab's test series: one campaign and a table of tests (or a list of campaigns), here or as a Slurm array.
    #[command(after_help = "Examples:\n  \
        rigfit series rates.series.json\n  \
        rigfit series rates.series.json --slurm /scratch/rates --throttle 8\n  \
        rigfit series /scratch/rates --task 3\n  \
        rigfit series /scratch/rates --summary\n\n\
        The series file names a campaign and a CSV table with one row per test: its\n\
        name (\"test\"), its record (\"record\" or \"record.<experiment>\"), its seed, fixed\n\
        values (\"value.<param>\") and bounds (\"min.<param>\", \"max.<param>\"), and any\n\
        other column as a covariate (rate, temperature, specimen). Or it lists campaign\n\
        files (\"campaigns\", with * and ? in file names). Each test's campaign is written\n\
        to <folder>/campaigns/<test>.json and its job to <folder>/tests/<test>/, exactly\n\
        as `rigfit run` on that file writes it. Tests run side by side (--jobs) on one\n\
        device; a test already done is skipped, an interrupted one resumes. The summary\n\
        (summary.csv, summary.html) lists every test, failed and missing ones with\n\
        their error. See docs/guide/series.md.")]
    Series(SeriesArgs),
    /// Read an HDF5 file from stdin for a parent rigfit (not for people: the
    /// answer on stdout is binary).
    #[command(name = rigfit::record::hdf5_child::SUBCOMMAND, hide = true)]
    ReadHdf5,
}

impl Cli {
    /// Parses the process's arguments as [`Parser::try_parse`] does, except
    /// that every option taking a value accepts a negative number (`--mass
    /// -2`, `--start=-1`): the value then reaches the command, which refuses
    /// it with what it expected, instead of clap reading it as an unknown flag.
    pub fn try_parse_args() -> Result<Self, clap::Error> {
        let cmd = negative_numbers(Self::command());
        let mut matches = cmd.try_get_matches()?;
        Self::from_arg_matches_mut(&mut matches)
    }
}

/// `cmd` and its subcommands with negative numbers allowed as the values of
/// every option that takes one.
fn negative_numbers(cmd: clap::Command) -> clap::Command {
    cmd.mut_args(|a| {
        let takes_value = a.get_action().takes_values();
        if takes_value && !a.is_positional() {
            a.allow_negative_numbers(true)
        } else {
            a
        }
    })
    .mut_subcommands(negative_numbers)
}
