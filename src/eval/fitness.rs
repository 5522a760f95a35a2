//! `1 − R²` of one run, accumulated sample by sample as the GPU kernel does.

use std::ops::ControlFlow;

use super::{DIVERGED, ExperimentData, History, Precision, Problem};
use crate::base::Report;

/// Running residual sum over the fit window, with the blow-up guard.
#[derive(Debug, Clone, Copy)]
pub struct FitnessAccumulator {
    ss_res: f64,
    ss_tot: f64,
    limit: f64,
    diverged: bool,
}

impl FitnessAccumulator {
    /// For one experiment.
    pub fn new(exp: &ExperimentData) -> Self {
        Self {
            ss_res: 0.0,
            ss_tot: exp.ss_tot(),
            limit: exp.blowup_limit(),
            diverged: false,
        }
    }

    /// Adds sample `k` with model output `model`; breaks once the run diverged.
    pub fn add(&mut self, exp: &ExperimentData, k: usize, model: f64) -> ControlFlow<()> {
        self.add_measured(model, Self::measured(exp, k))
    }

    /// The measured value sample `k` is scored against: `None` outside the
    /// fit window (the same for every run of a sample, so a group looks it
    /// up once).
    pub fn measured(exp: &ExperimentData, k: usize) -> Option<f64> {
        exp.window.contains(&k).then(|| exp.measured[k])
    }

    /// [`Self::add`] with the sample's [`Self::measured`] value.
    #[inline]
    pub fn add_measured(&mut self, model: f64, measured: Option<f64>) -> ControlFlow<()> {
        if model.is_nan() || model.abs() > self.limit {
            self.diverged = true;
            return ControlFlow::Break(());
        }
        if let Some(m) = measured {
            let r = model - m;
            self.ss_res += r * r;
        }
        ControlFlow::Continue(())
    }

    /// [`Self::add_measured`] for a group's runs at one sample: run `j` of
    /// `accs` gets `values[j]` while its bit in `live` is set, and a run that
    /// diverges clears its bit. With every run live and none diverging (the
    /// usual case), one pass without a branch per run; the same sums.
    pub fn add_group(accs: &mut [Self], values: &[f64], measured: Option<f64>, live: &mut u64) {
        let all = crate::base::lane_bits(values.len());
        if *live == all {
            let ok = accs
                .iter()
                .zip(values)
                .fold(true, |ok, (a, &v)| ok & (v.abs() <= a.limit));
            if ok {
                if let Some(m) = measured {
                    for (a, &v) in accs.iter_mut().zip(values) {
                        let r = v - m;
                        a.ss_res += r * r;
                    }
                }
                return;
            }
        }
        let mut left = *live;
        while left != 0 {
            let j = left.trailing_zeros() as usize;
            left &= left - 1;
            if accs[j].add_measured(values[j], measured).is_break() {
                *live &= !(1 << j);
            }
        }
    }

    /// Whether the run blew up.
    pub fn diverged(&self) -> bool {
        self.diverged
    }

    /// `1 − R²`, or [`DIVERGED`].
    pub fn value(&self) -> f64 {
        let v = self.ss_res / self.ss_tot;
        if self.diverged || !v.is_finite() {
            DIVERGED
        } else {
            v
        }
    }
}

/// `1 − R²` of one candidate in one experiment with the f64 reference, and
/// whether it diverged.
pub fn score_one(problem: &Problem, e: usize, params: &[f64], offset: f64) -> (f64, bool) {
    let exp = &problem.experiments[e];
    let grid = exp.grid(offset, problem.substeps);
    let mut acc = FitnessAccumulator::new(exp);
    problem
        .scoring_model(e)
        .simulate(params, &exp.drive, &grid, &mut |s| {
            acc.add(exp, s.index, s.outputs[0])
        });
    let v = acc.value();
    (v, acc.diverged() || v >= DIVERGED)
}

/// [`score_one`] for several candidates of experiment `e` with one offset, run
/// together where the model has lanes (the same values as one by one), in
/// `precision` ([`Precision::F32`] where the model has an f32 path, see
/// [`crate::model::CompiledRig::simulate_measured`]; f64 otherwise).
pub fn score_many(
    problem: &Problem,
    e: usize,
    params: &[&[f64]],
    offset: f64,
    precision: Precision,
) -> Vec<(f64, bool)> {
    let exp = &problem.experiments[e];
    let grid = exp.grid(offset, problem.substeps);
    // The record's spread and blow-up limit, once for every run.
    let mut accs = vec![FitnessAccumulator::new(exp); params.len()];
    problem.scoring_model(e).simulate_measured(
        params,
        &exp.drive,
        &grid,
        precision == Precision::F32,
        &mut |s, live| {
            let measured = FitnessAccumulator::measured(exp, s.index);
            let accs = &mut accs[s.first..s.first + s.values.len()];
            FitnessAccumulator::add_group(accs, s.values, measured, live);
        },
    );
    accs.iter()
        .map(|acc| {
            let v = acc.value();
            (v, acc.diverged() || v >= DIVERGED)
        })
        .collect()
}

/// [`simulate_history`] of several runs of experiment `e` at one clock
/// offset, advanced together by the rig's lane ensemble
/// ([`crate::model::CompiledRig::simulate_many`]): the same histories, bit
/// for bit, at the lanes' rate.
pub fn simulate_histories(
    problem: &Problem,
    e: usize,
    params: &[&[f64]],
    offset: f64,
) -> Vec<History> {
    let exp = &problem.experiments[e];
    let grid = exp.grid(offset, problem.substeps);
    let mut hs: Vec<History> = params
        .iter()
        .map(|_| History::for_grid(problem, &grid))
        .collect();
    let model = &problem.model;
    model.simulate_many(params, &exp.drive, &grid, Report::Full, &mut |i, s| {
        hs[i].push(s);
        ControlFlow::Continue(())
    });
    hs
}

/// The scored output ([`super::ExperimentData::output`]) of several runs of
/// experiment `e` at one clock offset, over samples `0..window.end`: the
/// scoring rig's output 0 alone ([`Report::Measured`]), advanced by the
/// lane ensemble as [`simulate_histories`] advances them, with the bits of
/// those histories' scored output (the lanes' f64 code fuses nothing).
pub fn simulate_scored(
    problem: &Problem,
    e: usize,
    params: &[&[f64]],
    offset: f64,
) -> Vec<Vec<f64>> {
    let exp = &problem.experiments[e];
    let grid = exp.grid(offset, problem.substeps);
    let mut out = vec![Vec::with_capacity(grid.samples); params.len()];
    let model = problem.scoring_model(e);
    model.simulate_many(params, &exp.drive, &grid, Report::Measured, &mut |i, s| {
        out[i].push(s.outputs[0]);
        ControlFlow::Continue(())
    });
    out
}

/// Full f64 reference history of one candidate in one experiment.
pub fn simulate_history(problem: &Problem, e: usize, params: &[f64], offset: f64) -> History {
    let exp = &problem.experiments[e];
    let grid = exp.grid(offset, problem.substeps);
    let mut h = History::for_grid(problem, &grid);
    problem.model.simulate(params, &exp.drive, &grid, &mut |s| {
        h.push(s);
        ControlFlow::Continue(())
    });
    h
}

impl History {
    /// An empty history with room for `grid`'s samples of `problem`'s rig.
    fn for_grid(problem: &Problem, grid: &crate::base::SampleGrid) -> Self {
        let model = &problem.model;
        Self {
            t: Vec::with_capacity(grid.samples),
            outputs: vec![Vec::with_capacity(grid.samples); model.output_names().len()],
            states: vec![Vec::with_capacity(grid.samples); model.state_names().len()],
        }
    }

    /// Appends sample `s` (its time, every output, the full state).
    fn push(&mut self, s: &crate::base::Sample<'_>) {
        self.t.push(s.t);
        for (o, v) in self.outputs.iter_mut().zip(s.outputs) {
            o.push(*v);
        }
        for (o, v) in self.states.iter_mut().zip(s.state) {
            o.push(*v);
        }
    }
}
