//! Pre-calibration tools: quick, closed-form or small local fits that give a
//! campaign good fixed values (or tight bounds) before the big ensemble search.
//!
//! - [`specimen`]: the specimen law `S(e)` (elastic line up to `e_yield`, then a
//!   polynomial) from quasi-static force–elongation data (`rigfit fit-specimen`);
//! - [`ringdown`]: a free decay (a hammer impact, a release, the load cell after
//!   a brittle fracture) gives its natural frequency and three damping estimates
//!   with their agreement, and `c1_post` (and `k1` when `m1` is known)
//!   (`rigfit ringdown`);
//! - [`psd`]: the Welch power spectral density used by the ring-down analysis;
//! - [`csv_input`]: the two-column CSV reader both commands use, the
//!   identification tools' one reader ([`columns`]) held to two columns;
//! - the other modules: classical identification from the papers rigfit is
//!   built from (restoring force surface, direct parameter estimation,
//!   frequency response and modal fit, impedance, inverse-model least squares,
//!   reverse-path MISO, transmissibility; `rigfit identify <method>`): *A New
//!   Fatigue Testing Rig Based on Inertial Forces*, *Data interrogation for
//!   vehicle suspensions*, *Experimental Investigations of Lubricated Bearing
//!   Stiffness* and *Non-linear signal analysis applied to surface wear
//!   condition monitoring in reciprocating sliding testing machines*.
//!
//! Both reports turn into a campaign fragment, `{"params": {...}}`, whose values
//! are plain numbers, i.e. fixed parameters. A user who prefers to let the search
//! refine them can replace a number by bounds around it in the campaign.

pub mod columns;
pub mod csv_input;
mod decay_fit;
mod decrement;
pub mod dpe;
pub mod envelope;
pub mod frf;
pub mod idim;
pub mod impedance;
pub mod lsq;
pub mod modal;
pub mod nimiso;
pub mod plot;
pub mod psd;
pub mod rfs;
pub mod ringdown;
pub mod signal;
pub mod specimen;
pub mod transmissibility;

pub use decay_fit::DecayFit;

use std::path::PathBuf;

/// Everything that can go wrong in an identification tool.
#[derive(Debug, thiserror::Error)]
pub enum IdentifyError {
    /// The input file could not be read.
    #[error("cannot read {path}")]
    Io {
        /// The file.
        path: PathBuf,
        /// The underlying error.
        #[source]
        source: std::io::Error,
    },
    /// A data line does not hold exactly two fields.
    #[error("line {line}: expected {expected} columns, found {found}")]
    ColumnCount {
        /// 1-based line number in the file.
        line: usize,
        /// Columns expected (2).
        expected: usize,
        /// Columns found.
        found: usize,
    },
    /// A field is not a number.
    #[error("line {line}, column {column}: {found:?} is not a number")]
    NotNumeric {
        /// 1-based line number in the file.
        line: usize,
        /// 1-based column number.
        column: usize,
        /// The offending text.
        found: String,
    },
    /// A field is NaN or infinite.
    #[error("line {line}, column {column}: {found:?} is not a finite number")]
    NotFinite {
        /// 1-based line number in the file.
        line: usize,
        /// 1-based column number.
        column: usize,
        /// The offending text.
        found: String,
    },
    /// The two input slices differ in length.
    #[error("{what}: {x_len} abscissae but {y_len} forces")]
    LengthMismatch {
        /// Which input.
        what: &'static str,
        /// Length of the abscissa (elongation or time).
        x_len: usize,
        /// Length of the force.
        y_len: usize,
    },
    /// A value that must be finite is not (library callers bypassing the reader).
    #[error("{what}: sample {index} is not finite")]
    NonFiniteSample {
        /// Which input.
        what: &'static str,
        /// 0-based sample index.
        index: usize,
    },
    /// The polynomial degree is outside `1..=max`.
    #[error("polynomial degree {degree} is not supported (1..={max})")]
    DegreeOutOfRange {
        /// The degree asked for.
        degree: usize,
        /// The highest supported degree.
        max: usize,
    },
    /// Too few data points for what was asked.
    #[error("{what}: needs at least {needed} points, found {found}")]
    TooFewPoints {
        /// Which part of the data.
        what: &'static str,
        /// Points needed.
        needed: usize,
        /// Points available.
        found: usize,
    },
    /// The data are explained by the elastic line alone: there is nothing to fit a
    /// plastic polynomial to.
    #[error(
        "no plastic range: the elastic line alone explains the data (F = {f_statistic:.3} < {threshold}); \
         the polynomial branch would fit noise"
    )]
    NoPlasticRange {
        /// F statistic of the two-branch fit against the elastic line alone.
        f_statistic: f64,
        /// The smallest F statistic accepted.
        threshold: f64,
    },
    /// A fixed `e_yield` leaves too few points on one side.
    #[error("e_yield = {e_yield:e} m leaves {elastic} elastic and {plastic} plastic points")]
    BadYield {
        /// The e_yield asked for (m).
        e_yield: f64,
        /// Points with `e ≤ e_yield`.
        elastic: usize,
        /// Points with `e > e_yield`.
        plastic: usize,
    },
    /// Time stamps are not strictly increasing or not evenly spaced.
    #[error(
        "time stamps are not uniform at sample {index}: step {step:e} s, expected {expected:e} s"
    )]
    NonUniformTime {
        /// 0-based sample index.
        index: usize,
        /// The step found (s).
        step: f64,
        /// The median step (s).
        expected: f64,
    },
    /// No start of free ringing (a drop comparable to the signal's range,
    /// such as a fracture, a release or an impact's first swing) was found.
    #[error(
        "no start of free ringing found: the largest drop is {drop:.4e}, less than half the signal's range {range:.4e}; give the start time"
    )]
    NoRingStart {
        /// Largest drop found (N).
        drop: f64,
        /// Peak-to-peak force range (N).
        range: f64,
    },
    /// The post-fracture part is too short to analyse.
    #[error("ring-down too short: {what} is {found}, needs at least {needed}")]
    TooShortRingdown {
        /// What is short (samples, peaks, …).
        what: &'static str,
        /// What is needed.
        needed: usize,
        /// What was found.
        found: usize,
    },
    /// An option is invalid.
    #[error("invalid option {name}: {reason}")]
    InvalidOption {
        /// The option.
        name: &'static str,
        /// Why.
        reason: String,
    },
    /// A numerical step failed (singular system, non-convergence).
    #[error("numerical failure in {stage}: {reason}")]
    Numerical {
        /// Which stage.
        stage: &'static str,
        /// Why.
        reason: String,
    },
}

/// [`IdentifyError::TooFewPoints`] when `found` is less than `needed`: the one
/// check every method makes before it fits.
pub(crate) fn require_points(
    what: &'static str,
    needed: usize,
    found: usize,
) -> Result<(), IdentifyError> {
    if found < needed {
        return Err(IdentifyError::TooFewPoints {
            what,
            needed,
            found,
        });
    }
    Ok(())
}

/// Coefficient of determination `1 − SSE/SST`; 1 when the data are constant and
/// fitted exactly.
pub(crate) fn r_squared(sse: f64, values: &[f64]) -> f64 {
    if values.is_empty() {
        return f64::NAN;
    }
    let mean = values.iter().sum::<f64>() / values.len() as f64;
    let sst: f64 = values.iter().map(|v| (v - mean).powi(2)).sum();
    if sst == 0.0 {
        if sse == 0.0 { 1.0 } else { f64::NEG_INFINITY }
    } else {
        1.0 - sse / sst
    }
}

/// Checks that both slices have the same length and finite values.
pub(crate) fn check_inputs(what: &'static str, x: &[f64], y: &[f64]) -> Result<(), IdentifyError> {
    if x.len() != y.len() {
        return Err(IdentifyError::LengthMismatch {
            what,
            x_len: x.len(),
            y_len: y.len(),
        });
    }
    if let Some(index) = x
        .iter()
        .zip(y)
        .position(|(a, b)| !a.is_finite() || !b.is_finite())
    {
        return Err(IdentifyError::NonFiniteSample { what, index });
    }
    Ok(())
}
