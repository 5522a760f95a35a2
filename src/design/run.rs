//! The batch: every design point simulated on the CPU (the f64 lanes,
//! [`crate::eval::simulate_histories`], parallel over groups of runs with
//! rayon) or on the GPU ([`super::device`]), in chunks whose histories fit in
//! memory; each run's metrics are computed as its chunk finishes and its
//! history dropped.
//!
//! A point is prepared as `rigfit simulate --params` prepares its run: its
//! values applied to the campaign ([`crate::campaign::Campaign::apply_values`],
//! which chooses the step again), then the step a simulation without noise
//! takes ([`crate::campaign::Campaign::simulation_step`]). Those runs of the
//! step rule (the f64 tape, several runs per point) cost far more than the
//! point's own run; a shared step ([`Step::Shared`]) is chosen once, the
//! finest the rule takes at the design's corners, and held at each point to
//! the stability rule's count; a fixed one ([`Step::Fixed`]) runs as `rigfit
//! simulate --substeps` runs. With the calibration's uncertainty, each point
//! also runs at every draw of the fitted parameters, at the point's step.
//! Runs that share a step and a clock offset advance together; the lanes
//! give the bits of one run alone.

use std::collections::BTreeMap;

use rayon::prelude::*;

use super::DesignError;
use super::device::GpuRuns;
use super::file::{Step, Sweep, point_values};
use super::uncertainty::band;
use crate::eval::{History, simulate_histories};

/// How a sweep runs.
#[derive(Debug, Clone)]
pub struct RunOptions {
    /// The most memory (bytes) the histories held at once may take, and where
    /// the limit comes from (for the message); `None`: no limit.
    pub max_memory: Option<(f64, String)>,
    /// The most RK4 steps one run may take (the campaign's run length check).
    pub max_steps: f64,
    /// The most runs simulated per chunk.
    pub chunk: usize,
}

impl Default for RunOptions {
    fn default() -> Self {
        Self {
            max_memory: None,
            max_steps: crate::campaign::DEFAULT_MAX_STEPS,
            chunk: DEFAULT_CHUNK,
        }
    }
}

/// Runs per chunk by default: enough to keep every core and lane busy, and a
/// GPU's dispatch full.
pub const DEFAULT_CHUNK: usize = 16_384;

/// The histories of a chunk are held to this many bytes by default (the
/// chunk is made smaller); the memory limit refuses what even one run per
/// thread cannot fit.
pub const CHUNK_BYTES: f64 = 512.0 * 1024.0 * 1024.0;

/// Runs advanced together by one call of the lanes.
pub const LANE_GROUP: usize = 64;

/// A metric's band over the draws of the calibration's uncertainty.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Band {
    /// The median over the draws.
    pub median: f64,
    /// The band's lower end.
    pub lo: f64,
    /// Its upper end.
    pub hi: f64,
}

/// One design point's row.
#[derive(Debug, Clone, PartialEq)]
pub struct Row {
    /// The point's number (row-major over a grid's variables, see
    /// [`super::grid::DesignGrid::point`], or the draw's order).
    pub point: usize,
    /// Each variable's value.
    pub values: Vec<f64>,
    /// Each metric's value at the point's values (the calibrated ones
    /// elsewhere), `None` where it is not defined.
    pub metrics: Vec<Option<f64>>,
    /// Each metric's band over the draws, where the sweep carries the
    /// calibration's uncertainty (`None` in it where fewer than two draws
    /// define the metric); empty otherwise.
    pub bands: Vec<Option<Band>>,
    /// RK4 steps per sample the point ran with.
    pub substeps: usize,
}

/// The sweep's table: one row per design point, in point order.
#[derive(Debug, Clone, PartialEq)]
pub struct Table {
    /// The variables' names.
    pub variables: Vec<String>,
    /// The metrics' names.
    pub metrics: Vec<String>,
    /// Whether the rows carry bands.
    pub banded: bool,
    /// The rows.
    pub rows: Vec<Row>,
}

impl Table {
    /// The columns' names: `point`, each variable, each metric and, with
    /// bands, each metric's `.median`, `.lo` and `.hi`.
    pub fn header(&self) -> Vec<String> {
        let mut h = vec!["point".to_string()];
        h.extend(self.variables.iter().cloned());
        h.extend(self.metrics.iter().cloned());
        if self.banded {
            for m in &self.metrics {
                for end in ["median", "lo", "hi"] {
                    h.push(format!("{m}.{end}"));
                }
            }
        }
        h
    }

    /// Row `r`'s cells in [`Self::header`]'s order, `None` where empty.
    pub fn cells(&self, r: &Row) -> Vec<Option<f64>> {
        let mut c = vec![Some(r.point as f64)];
        c.extend(r.values.iter().map(|&v| Some(v)));
        c.extend(r.metrics.iter().copied());
        if self.banded {
            for b in &r.bands {
                match b {
                    Some(b) => c.extend([Some(b.median), Some(b.lo), Some(b.hi)]),
                    None => c.extend([None, None, None]),
                }
            }
        }
        c
    }

    /// The table as CSV ([`Self::header`]); values in Rust's shortest
    /// round-trip form, empty where a metric is not defined.
    pub fn csv(&self) -> String {
        let mut s = self.header().join(",");
        s.push('\n');
        for r in &self.rows {
            let cells = self.cells(r);
            s.push_str(&r.point.to_string());
            for c in &cells[1..] {
                s.push(',');
                if let Some(v) = c {
                    s.push_str(&v.to_string());
                }
            }
            s.push('\n');
        }
        s
    }
}

/// A design point ready to run: the experiment's parameters and clock offset
/// of each of its runs (the point's own first, then one per draw), and the
/// step they share.
#[derive(Debug, Clone, PartialEq)]
pub struct PreparedPoint {
    /// The point's values, one per variable.
    pub values: Vec<f64>,
    /// Per run: the full parameter vector of the experiment and its clock
    /// offset (s).
    pub runs: Vec<(Vec<f64>, f64)>,
    /// RK4 steps per sample.
    pub substeps: usize,
}

/// The step [`Step::Shared`] starts from: the finest the step rule chooses
/// at the design's corners (the calibrated values elsewhere).
pub fn shared_substeps(sweep: &Sweep, max_steps: f64) -> Result<usize, DesignError> {
    let corners = sweep.points.corners();
    let steps: Vec<usize> = corners
        .par_iter()
        .map(|values| {
            let mut c = sweep.campaign.clone();
            let at = point_values(&sweep.variables, values);
            c.apply_values(&at, &sweep.file, "variables.")?;
            let channels: Vec<(usize, f64)> = sweep.runs.iter().map(|&i| (i, 0.0)).collect();
            Ok(c.simulation_step(&channels, None, max_steps).substeps)
        })
        .collect::<Result<_, DesignError>>()?;
    Ok(steps.into_iter().max().unwrap_or(1))
}

/// Design point `point` prepared as `rigfit simulate --params` prepares a
/// run of the same values (with [`Step::Each`]), or with the step `shared`
/// gives; with the calibration's uncertainty, one run per draw too.
pub fn prepare_point(
    sweep: &Sweep,
    point: usize,
    shared: Option<usize>,
    max_steps: f64,
) -> Result<PreparedPoint, DesignError> {
    let values = sweep.points.point(point);
    let mut c = sweep.campaign.clone();
    let listed = || {
        sweep
            .variables
            .iter()
            .zip(&values)
            .map(|(n, v)| format!("{n} = {v}"))
            .collect::<Vec<_>>()
            .join(", ")
    };
    let refused = |source| DesignError::Point {
        point,
        values: listed(),
        source: Box::new(source),
    };
    let at = point_values(&sweep.variables, &values);
    let stable = |c: &crate::campaign::Campaign| {
        sweep
            .runs
            .iter()
            .map(|&i| c.stable_substeps(i))
            .max()
            .unwrap_or(1)
    };
    let substeps = match sweep.step {
        // As `rigfit simulate --substeps n`: the values set, the step given.
        Step::Fixed(n) => {
            c.set_values(&at, &sweep.file, "variables.")
                .map_err(refused)?;
            let stable = stable(&c);
            if n < stable {
                return Err(DesignError::Invalid {
                    file: sweep.file.clone(),
                    path: "substeps".into(),
                    expected: format!(
                        "at least {stable} RK4 steps per sample, the count the stability rule \
                         takes at design point {point} ({}); a coarser step can diverge",
                        listed()
                    ),
                    found: n.to_string(),
                });
            }
            n
        }
        Step::Shared => {
            c.set_values(&at, &sweep.file, "variables.")
                .map_err(refused)?;
            shared.unwrap_or(1).max(stable(&c))
        }
        Step::Each => {
            c.apply_values(&at, &sweep.file, "variables.")
                .map_err(refused)?;
            let channels: Vec<(usize, f64)> = sweep.runs.iter().map(|&i| (i, 0.0)).collect();
            c.simulation_step(&channels, None, max_steps).substeps
        }
    };
    c.problem.substeps = substeps;
    c.check_run_length(max_steps).map_err(refused)?;
    let e = sweep.experiment;
    let mut runs = vec![(c.base[e].clone(), c.base_offsets[e])];
    if let Some(u) = &sweep.uncertainty {
        for draw in &u.draws {
            let drawn = point_values(&u.names, draw);
            c.set_values(&drawn, &sweep.file, "uncertainty.")
                .map_err(refused)?;
            runs.push((c.base[e].clone(), c.base_offsets[e]));
        }
    }
    Ok(PreparedPoint {
        values,
        runs,
        substeps,
    })
}

/// The metrics of one run's history over the experiment's fit window, the
/// formulas last (in the file's order, each reading the metrics before it
/// and the point's `values`).
pub fn metrics_of(sweep: &Sweep, h: &History, values: &[f64]) -> Vec<Option<f64>> {
    let exp = &sweep.campaign.problem.experiments[sweep.experiment];
    let end = exp.window.end.min(h.t.len());
    let start = exp.window.start.min(end);
    let t = &h.t[start..end];
    let outputs: Vec<&[f64]> = h.outputs.iter().map(|o| &o[start..end]).collect();
    let mut out: Vec<Option<f64>> = Vec::with_capacity(sweep.metrics.len());
    for m in &sweep.metrics {
        let v = match &m.formula {
            Some(f) => f.value(&out, values),
            None => m.evaluate_gated(t, &outputs, exp.dt),
        };
        out.push(v);
    }
    out
}

/// Bytes of one run's history: its time, outputs and states per sample.
pub fn history_bytes(sweep: &Sweep) -> f64 {
    let c = &sweep.campaign;
    let samples = c.problem.experiments[sweep.experiment].window.end as f64;
    let columns = 1 + c.model.output_names().len() + c.model.state_names().len();
    samples * columns as f64 * 8.0
}

/// Where the runs are simulated.
pub enum Engine<'a> {
    /// The f64 CPU lanes on the current rayon pool.
    Cpu,
    /// A GPU's history kernel.
    Gpu(&'a mut GpuRuns),
}

/// Runs every design point of `sweep`, chunk by chunk, calling `progress(done,
/// total)` after each chunk (and once the step is chosen). Runs on the
/// current rayon pool.
pub fn run_sweep(
    sweep: &Sweep,
    options: &RunOptions,
    engine: Engine<'_>,
    progress: &(dyn Fn(usize, usize) + Sync),
) -> Result<Table, DesignError> {
    let mut engine = engine;
    let total = sweep.points();
    let per_point = history_bytes(sweep) * sweep.runs_per_point() as f64;
    let chunk = ((CHUNK_BYTES / per_point).floor() as usize)
        .clamp(1, (options.chunk / sweep.runs_per_point()).max(1));
    let chunk = chunk.min(total.max(1));
    if let Some((limit, from)) = &options.max_memory {
        // The chunk's histories, and a campaign copy per thread preparing.
        let at_once = chunk.max(rayon::current_num_threads().min(total));
        let needed = at_once as f64 * per_point * 1.1;
        if needed > *limit {
            return Err(DesignError::Memory {
                points: at_once,
                per_run_kib: per_point / 1024.0,
                needed_mib: needed / 1048576.0,
                limit_mib: limit / 1048576.0,
                limit_from: from.clone(),
            });
        }
    }
    let shared = match sweep.step {
        Step::Shared => Some(shared_substeps(sweep, options.max_steps)?),
        _ => None,
    };
    progress(0, total);
    let mut rows = Vec::with_capacity(total);
    let mut done = 0;
    while done < total {
        let end = (done + chunk).min(total);
        let prepared: Vec<PreparedPoint> = (done..end)
            .into_par_iter()
            .map(|i| prepare_point(sweep, i, shared, options.max_steps))
            .collect::<Result<_, _>>()?;
        let metrics = match &mut engine {
            Engine::Cpu => cpu_metrics(sweep, &prepared),
            Engine::Gpu(g) => g.metrics(sweep, &prepared)?,
        };
        for (k, (p, m)) in prepared.into_iter().zip(metrics).enumerate() {
            rows.push(row(sweep, done + k, p, m));
        }
        done = end;
        progress(done, total);
    }
    Ok(Table {
        variables: sweep.variables.clone(),
        metrics: sweep.metrics.iter().map(|m| m.name.clone()).collect(),
        banded: sweep.uncertainty.is_some(),
        rows,
    })
}

/// Point `point`'s row from the metrics of its runs (its own, then the
/// draws').
fn row(sweep: &Sweep, point: usize, p: PreparedPoint, runs: Vec<Vec<Option<f64>>>) -> Row {
    let bands = match &sweep.uncertainty {
        None => Vec::new(),
        Some(u) => (0..sweep.metrics.len())
            .map(|m| {
                let v: Vec<f64> = runs[1..].iter().map(|r| r[m].unwrap_or(f64::NAN)).collect();
                band(&v, u.level).map(|(median, lo, hi)| Band { median, lo, hi })
            })
            .collect(),
    };
    Row {
        point,
        values: p.values,
        metrics: runs.into_iter().next().unwrap_or_default(),
        bands,
        substeps: p.substeps,
    }
}

/// A run of a chunk: its point's index in the chunk and its own among the
/// point's runs.
type RunKey = (usize, usize);

/// The metrics of every run of the prepared points, `[point][run][metric]`,
/// on the CPU lanes: runs sharing a step and an offset in groups of
/// [`LANE_GROUP`], the groups in parallel.
fn cpu_metrics(sweep: &Sweep, prepared: &[PreparedPoint]) -> Vec<Vec<Vec<Option<f64>>>> {
    let mut by_step: BTreeMap<(usize, u64), Vec<RunKey>> = BTreeMap::new();
    for (k, p) in prepared.iter().enumerate() {
        for (r, run) in p.runs.iter().enumerate() {
            by_step
                .entry((p.substeps, run.1.to_bits()))
                .or_default()
                .push((k, r));
        }
    }
    let groups: Vec<(usize, f64, &[RunKey])> = by_step
        .iter()
        .flat_map(|(&(n, off), ks)| {
            ks.chunks(LANE_GROUP)
                .map(move |g| (n, f64::from_bits(off), g))
        })
        .collect();
    let base = &sweep.campaign.problem;
    let computed: Vec<(RunKey, Vec<Option<f64>>)> = groups
        .par_iter()
        .flat_map_iter(|&(substeps, offset, ks)| {
            let mut problem = base.clone();
            problem.substeps = substeps;
            let params: Vec<&[f64]> = ks
                .iter()
                .map(|&(k, r)| prepared[k].runs[r].0.as_slice())
                .collect();
            let hs = simulate_histories(&problem, sweep.experiment, &params, offset);
            ks.iter()
                .zip(hs)
                .map(|(&kr, h)| (kr, metrics_of(sweep, &h, &prepared[kr.0].values)))
                .collect::<Vec<_>>()
        })
        .collect();
    let mut out: Vec<Vec<Vec<Option<f64>>>> = prepared
        .iter()
        .map(|p| vec![Vec::new(); p.runs.len()])
        .collect();
    for ((k, r), m) in computed {
        out[k][r] = m;
    }
    out
}
