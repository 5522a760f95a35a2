//! The batch: every design point simulated on the CPU (the f64 lanes,
//! [`crate::eval::simulate_histories`], parallel over groups of points with
//! rayon), in chunks whose histories fit in memory; each run's metrics are
//! computed as its chunk finishes and its history dropped.
//!
//! A point is prepared as `rigfit simulate --params` prepares its run: its
//! values applied to the campaign ([`crate::campaign::Campaign::apply_values`],
//! which chooses the step again), then the step a simulation without noise
//! takes ([`crate::campaign::Campaign::simulation_step`]). Those runs of the
//! step rule (the f64 tape, several runs per point) cost far more than the
//! point's own run; a sweep file's `"substeps"` sets one step for every point
//! instead, as `rigfit simulate --substeps` runs (held to the stability
//! rule's count at each point). Points that share
//! a step and a clock offset run together; the lanes give the bits of one run
//! alone.

use std::collections::BTreeMap;

use rayon::prelude::*;

use super::DesignError;
use super::file::{Sweep, point_values};
use crate::eval::{History, simulate_histories};

/// How a sweep runs.
#[derive(Debug, Clone)]
pub struct RunOptions {
    /// The most memory (bytes) the histories held at once may take, and where
    /// the limit comes from (for the message); `None`: no limit.
    pub max_memory: Option<(f64, String)>,
    /// The most RK4 steps one run may take (the campaign's run length check).
    pub max_steps: f64,
    /// The most points simulated per chunk.
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

/// Points per chunk by default: enough to keep every core and lane busy.
pub const DEFAULT_CHUNK: usize = 4096;

/// The histories of a chunk are held to this many bytes by default (the
/// chunk is made smaller); the memory limit refuses what even one run per
/// thread cannot fit.
pub const CHUNK_BYTES: f64 = 512.0 * 1024.0 * 1024.0;

/// Runs advanced together by one call of the lanes.
pub const LANE_GROUP: usize = 64;

/// One design point's row.
#[derive(Debug, Clone, PartialEq)]
pub struct Row {
    /// The point's number (row-major over the variables, see
    /// [`super::grid::DesignGrid::point`]).
    pub point: usize,
    /// Each variable's value.
    pub values: Vec<f64>,
    /// Each metric's value, `None` where it is not defined.
    pub metrics: Vec<Option<f64>>,
}

/// The sweep's table: one row per design point, in point order.
#[derive(Debug, Clone, PartialEq)]
pub struct Table {
    /// The variables' names.
    pub variables: Vec<String>,
    /// The metrics' names.
    pub metrics: Vec<String>,
    /// The rows.
    pub rows: Vec<Row>,
}

impl Table {
    /// The table as CSV: `point`, each variable, each metric; values in
    /// Rust's shortest round-trip form, empty where a metric is not defined.
    pub fn csv(&self) -> String {
        let mut s = String::from("point");
        for name in self.variables.iter().chain(&self.metrics) {
            s.push(',');
            s.push_str(name);
        }
        s.push('\n');
        for r in &self.rows {
            s.push_str(&r.point.to_string());
            for v in &r.values {
                s.push(',');
                s.push_str(&v.to_string());
            }
            for m in &r.metrics {
                s.push(',');
                if let Some(v) = m {
                    s.push_str(&v.to_string());
                }
            }
            s.push('\n');
        }
        s
    }
}

/// A design point ready to run: the experiment's parameters, clock offset
/// and step.
#[derive(Debug, Clone, PartialEq)]
pub struct PreparedPoint {
    /// The full parameter vector of the experiment.
    pub params: Vec<f64>,
    /// Its clock offset (s).
    pub offset: f64,
    /// RK4 steps per sample.
    pub substeps: usize,
}

/// Design point `point` prepared as `rigfit simulate --params` prepares a
/// run of the same values.
pub fn prepare_point(
    sweep: &Sweep,
    point: usize,
    max_steps: f64,
) -> Result<PreparedPoint, DesignError> {
    let values = sweep.grid.point(point);
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
    let substeps = match sweep.substeps {
        // As `rigfit simulate --substeps n`: the values set, the step given.
        Some(n) => {
            c.set_values(&at, &sweep.file, "variables.")
                .map_err(refused)?;
            let stable = sweep
                .runs
                .iter()
                .map(|&i| c.stable_substeps(i))
                .max()
                .unwrap_or(1);
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
        None => {
            c.apply_values(&at, &sweep.file, "variables.")
                .map_err(refused)?;
            let channels: Vec<(usize, f64)> = sweep.runs.iter().map(|&i| (i, 0.0)).collect();
            c.simulation_step(&channels, None, max_steps).substeps
        }
    };
    c.problem.substeps = substeps;
    c.check_run_length(max_steps).map_err(refused)?;
    let e = sweep.experiment;
    Ok(PreparedPoint {
        params: c.base[e].clone(),
        offset: c.base_offsets[e],
        substeps,
    })
}

/// The metrics of one run's history over the experiment's fit window.
pub fn metrics_of(sweep: &Sweep, h: &History) -> Vec<Option<f64>> {
    let exp = &sweep.campaign.problem.experiments[sweep.experiment];
    let end = exp.window.end.min(h.t.len());
    let start = exp.window.start.min(end);
    let t = &h.t[start..end];
    let outputs: Vec<&[f64]> = h.outputs.iter().map(|o| &o[start..end]).collect();
    sweep
        .metrics
        .iter()
        .map(|m| m.evaluate(t, &outputs, exp.dt))
        .collect()
}

/// Bytes of one run's history: its time, outputs and states per sample.
pub fn history_bytes(sweep: &Sweep) -> f64 {
    let c = &sweep.campaign;
    let samples = c.problem.experiments[sweep.experiment].window.end as f64;
    let columns = 1 + c.model.output_names().len() + c.model.state_names().len();
    samples * columns as f64 * 8.0
}

/// Runs every design point of `sweep`, chunk by chunk, calling `progress(done,
/// total)` after each chunk. Runs on the current rayon pool.
pub fn run_sweep(
    sweep: &Sweep,
    options: &RunOptions,
    progress: &(dyn Fn(usize, usize) + Sync),
) -> Result<Table, DesignError> {
    let total = sweep.points();
    let per_run = history_bytes(sweep);
    let chunk = ((CHUNK_BYTES / per_run).floor() as usize).clamp(1, options.chunk.max(1));
    let chunk = chunk.min(total.max(1));
    if let Some((limit, from)) = &options.max_memory {
        // The chunk's histories, and a campaign copy per thread preparing.
        let at_once = chunk.max(rayon::current_num_threads().min(total));
        let needed = at_once as f64 * per_run * 1.1;
        if needed > *limit {
            return Err(DesignError::Memory {
                points: at_once,
                per_run_kib: per_run / 1024.0,
                needed_mib: needed / 1048576.0,
                limit_mib: limit / 1048576.0,
                limit_from: from.clone(),
            });
        }
    }
    let mut rows = Vec::with_capacity(total);
    let mut done = 0;
    while done < total {
        let end = (done + chunk).min(total);
        let prepared: Vec<PreparedPoint> = (done..end)
            .into_par_iter()
            .map(|i| prepare_point(sweep, i, options.max_steps))
            .collect::<Result<_, _>>()?;
        // Points sharing a step and an offset, in groups the lanes advance
        // together.
        let mut by_step: BTreeMap<(usize, u64), Vec<usize>> = BTreeMap::new();
        for (k, p) in prepared.iter().enumerate() {
            by_step
                .entry((p.substeps, p.offset.to_bits()))
                .or_default()
                .push(k);
        }
        let groups: Vec<(usize, f64, &[usize])> = by_step
            .iter()
            .flat_map(|(&(n, off), ks)| {
                ks.chunks(LANE_GROUP)
                    .map(move |g| (n, f64::from_bits(off), g))
            })
            .collect();
        let base = &sweep.campaign.problem;
        let mut chunk_rows: Vec<Row> = groups
            .par_iter()
            .flat_map_iter(|&(substeps, offset, ks)| {
                let mut problem = base.clone();
                problem.substeps = substeps;
                let params: Vec<&[f64]> =
                    ks.iter().map(|&k| prepared[k].params.as_slice()).collect();
                let hs = simulate_histories(&problem, sweep.experiment, &params, offset);
                ks.iter()
                    .zip(hs)
                    .map(|(&k, h)| Row {
                        point: done + k,
                        values: sweep.grid.point(done + k),
                        metrics: metrics_of(sweep, &h),
                    })
                    .collect::<Vec<_>>()
            })
            .collect();
        chunk_rows.sort_by_key(|r| r.point);
        rows.extend(chunk_rows);
        done = end;
        progress(done, total);
    }
    Ok(Table {
        variables: sweep.variables.clone(),
        metrics: sweep.metrics.iter().map(|m| m.name.clone()).collect(),
        rows,
    })
}
