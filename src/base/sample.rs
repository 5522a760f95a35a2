//! What a run reports at each measurement sample: every output and the state,
//! or output 0 alone of a group of runs (the fitness path).

/// What a model reports at each measurement sample.
#[derive(Debug, Clone, Copy)]
pub struct Sample<'a> {
    /// Sample index on the grid.
    pub index: usize,
    /// Model time (s).
    pub t: f64,
    /// Full state vector (see [`crate::model::CompiledRig::state_names`]).
    pub state: &'a [f64],
    /// Observed outputs (see [`crate::model::CompiledRig::output_names`]); output 0 is the quantity
    /// fitted against the measured history.
    pub outputs: &'a [f64],
}

/// Output 0 of a group of runs at one sample ([`crate::model::CompiledRig::simulate_measured`]).
#[derive(Debug, Clone, Copy)]
pub struct MeasuredSample<'a> {
    /// The run `values[0]` belongs to; `values[j]` is run `first + j`'s.
    pub first: usize,
    /// Sample index on the grid.
    pub index: usize,
    /// Sample time (s).
    pub t: f64,
    /// Output 0 of each run of the group (NaN for a run that chattered).
    pub values: &'a [f64],
}

/// Runs `0..n` of a group as `live` bits ([`crate::model::CompiledRig::simulate_measured`];
/// `n ≤ 64`).
pub fn lane_bits(n: usize) -> u64 {
    assert!(n <= 64, "at most 64 runs to a group");
    if n == 64 { u64::MAX } else { (1 << n) - 1 }
}

/// What [`crate::model::CompiledRig::simulate_many`] reports at each sample.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Report {
    /// Every output and the full state.
    Full,
    /// Output 0 alone, the quantity fitted to the measurement: the sample's
    /// `outputs` holds only it and its `state` is empty, which spares a
    /// lane-batched model the rest of the report (the fitness needs no more).
    Measured,
}

impl Report {
    /// `s` cut down to what this report holds.
    pub fn of<'a>(self, s: &Sample<'a>) -> Sample<'a> {
        match self {
            Self::Full => *s,
            Self::Measured => Sample {
                state: &[],
                outputs: &s.outputs[..s.outputs.len().min(1)],
                ..*s
            },
        }
    }
}
