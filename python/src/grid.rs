//! `rigfit.simulate` on a time grid of the caller's own: one experiment of a
//! campaign run on a record that holds its times and its drive column alone
//! (a campaign whose records do not exist yet included), as `rigfit simulate`
//! makes a synthetic record, each parameter set's values taken from the
//! campaign as the array path takes them.

use std::path::PathBuf;

use numpy::ndarray::Array3;
use numpy::{IntoPyArray, PyArray3, PyReadonlyArray2, PyUntypedArrayMethods};
use pyo3::prelude::*;

use crate::campaign::PyCampaign;
use crate::errors::{self, Kind};
use crate::memory::MaxMemory;
use crate::record::PyRecord;
use rigfit::campaign::{Campaign, DEFAULT_MAX_STEPS, MAX_AUTO_SUBSTEPS, SimulationGrid};

/// Histories (S, samples, outputs) of the parameter sets `theta` (S, P, the
/// campaign's genes) in campaign experiment `experiment` on the grid of
/// `record` (path, its columns: the campaign's `json` reduced to that
/// experiment names it as its data file): the grid's record is read as
/// `rigfit simulate` reads one (not scored), the values of each set are the
/// campaign's ([`Campaign::batch`]), the step is `substeps` (held to the
/// stability rule) or the one `rigfit simulate` takes for a record with
/// noise `sigmas` (one per channel, at the first set's values); `samples`
/// the grid's times, the memory refused before any work. Also returns
/// the RK4 steps per sample taken and the notes to warn with.
#[pyfunction]
#[pyo3(signature = (campaign, json, base_dir, origin, record, experiment, theta, *, samples, sigmas, substeps = None, threads = 0, max_memory = None))]
#[expect(clippy::too_many_arguments, reason = "the Python function's keywords")]
pub fn simulate_grid<'py>(
    py: Python<'py>,
    campaign: &PyCampaign,
    json: &str,
    base_dir: PathBuf,
    origin: &str,
    record: (PathBuf, Bound<'py, PyRecord>),
    experiment: usize,
    theta: PyReadonlyArray2<'py, f64>,
    samples: usize,
    sigmas: Vec<f64>,
    substeps: Option<usize>,
    threads: usize,
    max_memory: Option<MaxMemory>,
) -> PyResult<(Bound<'py, PyArray3<f64>>, usize, Vec<String>)> {
    errors::guard(|| {
        let c = &*campaign.inner;
        let runs: Vec<usize> = (0..c.owners.len())
            .filter(|&r| c.owners[r] == experiment)
            .collect();
        let Some(&first) = runs.first() else {
            return Err(errors::raise(
                Kind::Campaign,
                format!("experiment {experiment}: the campaign has no such experiment"),
            ));
        };
        // Before the grid's record is read or a sample allocated.
        let sets_count = theta.shape()[0];
        crate::sim_memory::check(c, sets_count, 1, samples, max_memory.as_ref())?;
        let mut lent = rigfit::record::lent::Lent::none();
        let loan = rigfit::record::lent::Loan::Record(record.1.get().inner.clone());
        lent.lend(record.0.clone(), loan);
        let grid = py
            .allow_threads(|| {
                let grid = Some(&SimulationGrid::Record);
                Campaign::from_str_lent(json, &base_dir, origin, &lent, grid)
            })
            .map_err(|e| errors::campaign(&e))?;
        drop(lent);
        if grid.problem.experiments.len() != runs.len() || sigmas.len() != runs.len() {
            return Err(errors::raise(
                Kind::Error,
                "the grid's campaign does not hold the experiment's channels (a bug)",
            ));
        }
        let n = grid.problem.experiments[0].window.end;
        if n != samples {
            return Err(errors::raise(
                Kind::Error,
                format!("the grid of {samples} times was read as {n} samples (a bug)"),
            ));
        }
        let sets = crate::ensemble::genomes(c, theta.as_array())?;
        if sets.is_empty() {
            return Err(errors::raise(
                Kind::Campaign,
                "params: expected at least one parameter set, found none",
            ));
        }
        let n_out = c.model.output_names().len();
        let out = py.allow_threads(|| -> PyResult<_> {
            let batch = c.batch(&sets);
            let mut grid = grid;
            // The step is chosen at the first set's values, as `rigfit
            // simulate` chooses it at the campaign's.
            for r in 0..runs.len() {
                grid.base[r] = batch.params_of(first, 0).to_vec();
                grid.base_offsets[r] = batch.offsets[first][0];
            }
            let step = step(&grid, &sigmas, substeps)?;
            grid.problem.substeps = step.substeps;
            grid.check_run_length(DEFAULT_MAX_STEPS)
                .map_err(|e| errors::campaign(&e))?;
            let mut out = Array3::<f64>::from_elem((sets.len(), n, n_out), f64::NAN);
            let Some(flat) = out.as_slice_mut() else {
                unreachable!("an array just allocated has the standard layout")
            };
            let exp = &grid.problem.experiments[0];
            crate::ensemble::lanes(
                &c.problem,
                &[(exp, first)],
                &batch,
                step.substeps,
                threads,
                flat,
                (n, n_out),
            );
            Ok((
                out,
                step.substeps,
                step.warning.into_iter().collect::<Vec<_>>(),
            ))
        })?;
        Ok((out.0.into_pyarray(py), out.1, out.2))
    })
}

/// The step `rigfit simulate` takes: `substeps` where given (at least the
/// stability rule's count, at most [`MAX_AUTO_SUBSTEPS`]), else at least a
/// fit's and, with noise, finer until the integration error is well below it.
fn step(
    grid: &Campaign,
    sigmas: &[f64],
    substeps: Option<usize>,
) -> PyResult<rigfit::campaign::SimulationStep> {
    let channels: Vec<(usize, f64)> = sigmas.iter().copied().enumerate().collect();
    if let Some(n) = substeps {
        let stable = (0..channels.len())
            .map(|r| grid.stable_substeps(r))
            .max()
            .unwrap_or(1);
        if n < stable || n > MAX_AUTO_SUBSTEPS {
            return Err(errors::raise(
                Kind::Campaign,
                format!(
                    "substeps={n}: expected from {stable} (the count the stability rule takes on \
                     this grid over the free parameters' ranges; a coarser step can diverge) to \
                     {MAX_AUTO_SUBSTEPS} RK4 steps per sample"
                ),
            ));
        }
    }
    Ok(grid.simulation_step(&channels, substeps, DEFAULT_MAX_STEPS))
}
