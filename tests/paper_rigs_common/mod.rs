//! Shared by the papers rigfit is built from' rig tests: a shipped campaign run on the CPU
//! backend with a small GA and the polish, judged against the noise floor (the
//! joint `1 − R²` of the values that made the synthetic record, on that record)
//! and against those values.

#![allow(dead_code, reason = "each test binary uses part of it")]

use std::ops::ControlFlow;
use std::path::{Path, PathBuf};

use rigfit::base::Drive;
use rigfit::base::SampleGrid;
use rigfit::campaign::Campaign;
use rigfit::eval::{CpuEvaluator, Evaluator};
use rigfit::job::{self, JobOptions, JobSummary};
use rigfit::model::compiled::CompiledRig;
use serde_json::Value;

/// `campaigns/NAME`.
pub fn shipped(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("campaigns")
        .join(name)
}

/// The values that made a shipped record (`campaigns/*_reference_params.json`).
pub fn truth(file: &str) -> serde_json::Map<String, Value> {
    let v: Value = serde_json::from_str(&std::fs::read_to_string(shipped(file)).unwrap()).unwrap();
    v["params"].as_object().unwrap().clone()
}

/// A shipped rig, compiled.
pub fn rig(id: &str) -> CompiledRig {
    CompiledRig::new(
        rigfit::rig::shipped(id).unwrap(),
        &format!("rigs/{id}.json"),
    )
    .unwrap()
}

/// The full parameter vector of `rig` from `values` (names of the rig's
/// parameters; an `exp.name` key counts for `name`), defaults elsewhere.
pub fn params(rig: &CompiledRig, values: &serde_json::Map<String, Value>) -> Vec<f64> {
    rig.params()
        .iter()
        .map(|p| {
            values
                .iter()
                .find(|(k, _)| k.rsplit('.').next() == Some(p.name.as_str()))
                .and_then(|(_, v)| v.as_f64())
                .or(p.default)
                .unwrap_or_else(|| panic!("no value for {}", p.name))
        })
        .collect()
}

/// Every output of `rig` at `p` on a grid of `samples` samples `dt` apart.
pub fn outputs(
    rig: &CompiledRig,
    p: &[f64],
    dt: f64,
    samples: usize,
    substeps: usize,
) -> Vec<Vec<f64>> {
    let grid = SampleGrid {
        t0: 0.0,
        dt,
        samples,
        substeps,
    };
    let mut h = vec![vec![]; rig.output_names().len()];
    rig.simulate(p, &Drive::Velocity, &grid, &mut |s| {
        for (o, v) in h.iter_mut().zip(s.outputs) {
            o.push(*v);
        }
        ControlFlow::Continue(())
    });
    h
}

/// What a recovery run measured.
pub struct Recovery {
    pub campaign: Campaign,
    pub summary: JobSummary,
    /// Joint `1 − R²` of the true values on the record.
    pub floor: f64,
    /// Per gene: (name, fitted, true).
    pub genes: Vec<(String, f64, f64)>,
}

/// Runs the shipped campaign `file` on the CPU with `population` × `generations`
/// and the polish from `starts` starts, and measures it against the values in
/// `truth_file`.
pub fn recover(
    file: &str,
    truth_file: &str,
    population: usize,
    generations: usize,
    starts: usize,
) -> Recovery {
    let mut c = Campaign::load(&shipped(file)).unwrap();
    c.search.population = population;
    c.search.generations = generations;
    c.search.stall_generations = None;
    c.search.polish.starts = starts;
    let t = truth(truth_file);
    let true_genes: Vec<f64> = c
        .genes
        .iter()
        .map(|g| {
            t.get(&g.name)
                .and_then(Value::as_f64)
                .unwrap_or_else(|| panic!("{truth_file} has no {}", g.name))
        })
        .collect();
    let mut cpu = CpuEvaluator::new(c.problem.clone(), 0);
    let floor = c.combine(
        &cpu.fitness(&c.batch(std::slice::from_ref(&true_genes)))
            .unwrap(),
    )[0];
    let out = tempfile::tempdir().unwrap();
    let opts = JobOptions::quiet(out.path());
    let ev = Box::new(CpuEvaluator::new(c.problem.clone(), 0));
    let summary = job::run(&c, ev, &opts).unwrap();
    let genes: Vec<(String, f64, f64)> = c
        .genes
        .iter()
        .zip(&true_genes)
        .map(|(g, &tv)| {
            let p = summary
                .parameters
                .iter()
                .find(|p| p.name == g.name)
                .unwrap();
            (g.name.clone(), p.value, tv)
        })
        .collect();
    let ga = summary.polish.as_ref().map(|p| p.ga_fitness);
    eprintln!(
        "{file}: floor {floor:.6e}; GA {ga:?}; polished {:.6e} ({:.4}× the floor); {} evaluations",
        summary.fitness,
        summary.fitness / floor,
        summary.evaluations
    );
    for p in summary.parameters.iter().filter(|p| p.free) {
        let tv = genes.iter().find(|g| g.0 == p.name).unwrap().2;
        eprintln!(
            "  {:<12} {:.6e} (true {tv:.6e}, {:+.3} %) 95 % {:?} determined {:?}",
            p.name,
            p.value,
            100.0 * (p.value / tv - 1.0),
            p.interval_95,
            p.determined
        );
    }
    Recovery {
        campaign: c,
        summary,
        floor,
        genes,
    }
}

impl Recovery {
    /// Asserts the fit reached the floor (within `slack`, e.g. 1.02) and that
    /// every determined parameter lies within three standard errors of its true
    /// value (a 95 % interval misses one time in twenty, and a record is fixed
    /// once made) with an interval narrower than ± `width` of the value.
    pub fn assert_recovered(&self, slack: f64, width: f64) {
        assert!(
            self.summary.fitness <= slack * self.floor,
            "fit {:e} vs floor {:e}",
            self.summary.fitness,
            self.floor
        );
        for (name, value, tv) in &self.genes {
            let p = self
                .summary
                .parameters
                .iter()
                .find(|p| &p.name == name)
                .unwrap();
            if p.determined != Some(true) {
                continue;
            }
            let [lo, hi] = p.interval_95.unwrap();
            let three_se = 3.0 / 1.96 * 0.5 * (hi - lo);
            assert!(
                (value - tv).abs() <= three_se,
                "{name}: {value:e} is more than 3 standard errors ({:e}) from {tv:e}",
                three_se / 3.0
            );
            assert!(
                0.5 * (hi - lo) <= width * value.abs(),
                "{name}: interval [{lo:e}, {hi:e}] wider than ±{width} of {value:e}"
            );
        }
    }

    /// Whether the polish called `name` determined.
    pub fn determined(&self, name: &str) -> bool {
        self.summary
            .parameters
            .iter()
            .find(|p| p.name == name)
            .and_then(|p| p.determined)
            == Some(true)
    }
}
