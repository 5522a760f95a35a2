//! The ensemble as a function: `rigfit.simulate` (histories of many
//! parameter sets at once) and the campaign's objective (their costs), on the
//! CPU lanes or the GPU, the GIL released while they run.

use std::sync::{Arc, Mutex};

use numpy::ndarray::{Array4, ArrayView2, Axis};
use numpy::{IntoPyArray, PyArray1, PyArray4, PyReadonlyArray2, PyUntypedArrayMethods};
use pyo3::prelude::*;

use crate::campaign::PyCampaign;
use crate::errors::{self, Kind};
use rigfit::campaign::Campaign;
use rigfit::eval::{Batch, Evaluator, ExperimentData, Problem};

/// Candidates simulated per call of the evaluator: bounds the histories held
/// at once beside the output array.
pub(crate) const CHUNK: usize = 1024;

/// Rows of `theta` as genomes, checked against the genes.
pub(crate) fn genomes(c: &Campaign, theta: ArrayView2<'_, f64>) -> PyResult<Vec<Vec<f64>>> {
    let p = c.genes.len();
    if theta.ncols() != p {
        let names: Vec<&str> = c.genes.iter().map(|g| g.name.as_str()).collect();
        return Err(errors::raise(
            Kind::Campaign,
            format!(
                "theta: expected {p} column(s), one per free parameter ({}), found {}",
                names.join(", "),
                theta.ncols()
            ),
        ));
    }
    Ok(theta.axis_iter(Axis(0)).map(|r| r.to_vec()).collect())
}

/// Histories of the parameter sets `theta` (S, P) in every experiment, as
/// (S, experiments, samples, outputs); an experiment with fewer samples than
/// the longest is padded with NaN. Also returns the notes to warn with. A
/// simulation that does not fit in `max_memory` (or the memory available
/// now) is refused before any work ([`crate::sim_memory::check`]).
#[pyfunction]
#[pyo3(signature = (campaign, theta, *, backend = None, precision = None, adapter = None, threads = 0, max_memory = None))]
#[expect(clippy::too_many_arguments, reason = "the Python function's keywords")]
pub fn simulate<'py>(
    py: Python<'py>,
    campaign: &PyCampaign,
    theta: PyReadonlyArray2<'py, f64>,
    backend: Option<&str>,
    precision: Option<&str>,
    adapter: Option<String>,
    threads: usize,
    max_memory: Option<crate::memory::MaxMemory>,
) -> PyResult<(Bound<'py, PyArray4<f64>>, Vec<String>)> {
    errors::guard(|| {
        let c = &*campaign.inner;
        let n_max = c
            .problem
            .experiments
            .iter()
            .map(|x| x.window.end)
            .max()
            .unwrap_or(0);
        // Before a single parameter set is copied or a sample allocated.
        crate::sim_memory::check(
            c,
            theta.shape()[0],
            c.problem.experiments.len(),
            n_max,
            max_memory.as_ref(),
        )?;
        let sets = genomes(c, theta.as_array())?;
        let b = crate::evaluator::backend(c, backend)?;
        let pr = crate::evaluator::precision(c, precision)?;
        let out = py.allow_threads(|| -> PyResult<_> {
            let mut opened = crate::evaluator::open(c, b, pr, adapter.as_deref(), threads, false)?;
            let n_exp = c.problem.experiments.len();
            let n = n_max;
            let n_out = c.model.output_names().len();
            let mut out = Array4::<f64>::from_elem((sets.len(), n_exp, n, n_out), f64::NAN);
            if b == rigfit::eval::Backend::Cpu {
                drop(opened.evaluator);
                simulate_lanes(c, &sets, threads, &mut out);
                return Ok((out, opened.notes));
            }
            for (k, chunk) in sets.chunks(CHUNK).enumerate() {
                let batch = c.batch(chunk);
                let which: Vec<usize> = (0..chunk.len()).collect();
                let h = opened
                    .evaluator
                    .histories(&batch, &which)
                    .map_err(|e| errors::eval(&e))?;
                for (i, runs) in h.iter().enumerate() {
                    for (e, run) in runs.iter().enumerate() {
                        for (o, values) in run.outputs.iter().enumerate() {
                            for (s, v) in values.iter().enumerate() {
                                out[[k * CHUNK + i, e, s, o]] = *v;
                            }
                        }
                    }
                }
            }
            Ok((out, opened.notes))
        })?;
        Ok((out.0.into_pyarray(py), out.1))
    })
}

/// The CPU path of [`simulate`]: every experiment of the campaign, each
/// with its own parameters in `sets`' batch ([`lanes`]).
fn simulate_lanes(c: &Campaign, sets: &[Vec<f64>], threads: usize, out: &mut Array4<f64>) {
    let batch = c.batch(sets);
    let runs: Vec<(&ExperimentData, usize)> = c
        .problem
        .experiments
        .iter()
        .enumerate()
        .map(|(e, x)| (x, e))
        .collect();
    let (_, _, n, n_out) = out.dim();
    let Some(flat) = out.as_slice_mut() else {
        unreachable!("an array just allocated has the standard layout")
    };
    lanes(
        &c.problem,
        &runs,
        &batch,
        c.problem.substeps,
        threads,
        flat,
        (n, n_out),
    );
}

/// Histories of the batch's candidates in `runs` (an experiment's grid and
/// drive, and the batch experiment its parameters and clock offset come
/// from), written into `flat` as (candidates, runs, `n` samples, `n_out`
/// outputs): the candidates split over `threads` threads (0: every core),
/// each share advanced together in the rig's vector lanes (native code where
/// the C compiler built it), which give the f64 reference's bits (`rigfit
/// simulate`'s) many times faster than one run after the other. Runs with
/// different clock offsets need different grids, so each offset's runs go
/// together.
pub(crate) fn lanes(
    problem: &Problem,
    runs: &[(&ExperimentData, usize)],
    batch: &Batch,
    substeps: usize,
    threads: usize,
    flat: &mut [f64],
    (n, n_out): (usize, usize),
) {
    use std::ops::ControlFlow;
    let threads = match threads {
        0 => rigfit::eval::all_cores(),
        n => n,
    };
    let n_exp = runs.len();
    let share = batch.candidates.div_ceil(threads).max(1);
    // Standard layout: a share of candidates is one contiguous block, and a
    // value's place in it is computed, not looked up through a 4-D view.
    std::thread::scope(|s| {
        for (k, part) in flat.chunks_mut(share * n_exp * n * n_out).enumerate() {
            s.spawn(move || {
                let first = k * share;
                let count = part.len() / (n_exp * n * n_out).max(1);
                for (e, &(exp, from)) in runs.iter().enumerate() {
                    let mut groups: Vec<(u64, Vec<usize>)> = Vec::new();
                    for i in 0..count {
                        let bits = batch.offsets[from][first + i].to_bits();
                        match groups.iter_mut().find(|g| g.0 == bits) {
                            Some(g) => g.1.push(i),
                            None => groups.push((bits, vec![i])),
                        }
                    }
                    for (bits, members) in groups {
                        let grid = exp.grid(f64::from_bits(bits), substeps);
                        let params: Vec<&[f64]> = members
                            .iter()
                            .map(|&i| batch.params_of(from, first + i))
                            .collect();
                        let report = rigfit::base::Report::Full;
                        problem.model.simulate_many(
                            &params,
                            &exp.drive,
                            &grid,
                            report,
                            &mut |run, sample| {
                                let at = ((members[run] * n_exp + e) * n + sample.index) * n_out;
                                part[at..at + n_out].copy_from_slice(sample.outputs);
                                ControlFlow::Continue(())
                            },
                        );
                    }
                }
            });
        }
    });
}

/// The campaign's cost of parameter sets: the weighted mean of 1 − R² over
/// its experiments, what the GA minimises (1e30 for a run that diverged).
#[pyclass(module = "rigfit._rigfit", frozen)]
pub struct Objective {
    campaign: Arc<Campaign>,
    evaluator: Mutex<Box<dyn Evaluator>>,
    #[pyo3(get)]
    notes: Vec<String>,
}

#[pymethods]
impl Objective {
    #[new]
    #[pyo3(signature = (campaign, *, backend = None, precision = None, adapter = None, threads = 0))]
    fn new(
        py: Python<'_>,
        campaign: &PyCampaign,
        backend: Option<&str>,
        precision: Option<&str>,
        adapter: Option<String>,
        threads: usize,
    ) -> PyResult<Self> {
        errors::guard(|| {
            let c = campaign.inner.clone();
            let opened = crate::evaluator::open_named(
                py,
                &c,
                backend,
                precision,
                adapter.as_deref(),
                threads,
            )?;
            Ok(Self {
                campaign: c,
                evaluator: Mutex::new(opened.evaluator),
                notes: opened.notes,
            })
        })
    }

    /// Costs of the rows of `theta` (S, P), one per row.
    fn costs<'py>(
        &self,
        py: Python<'py>,
        theta: PyReadonlyArray2<'py, f64>,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        errors::guard(|| {
            let c = &*self.campaign;
            if theta.shape()[0] == 0 {
                return Ok(Vec::<f64>::new().into_pyarray(py));
            }
            let sets = genomes(c, theta.as_array())?;
            let costs = py.allow_threads(|| -> PyResult<Vec<f64>> {
                let batch = c.batch(&sets);
                let mut ev = self
                    .evaluator
                    .lock()
                    .map_err(|_| errors::raise(Kind::Error, "the evaluator failed earlier"))?;
                let scores = ev.fitness(&batch).map_err(|e| errors::eval(&e))?;
                Ok(c.combine(&scores))
            })?;
            Ok(costs.into_pyarray(py))
        })
    }
}
