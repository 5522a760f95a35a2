//! A rig driven by a measured column of its own record (the EMPS drive's
//! reference position) on the GPU: the table lies on the record's uniform
//! grid, so the kernels are built with `TABLE_EXACT` and look values up at
//! the fractional index, without a search (src/gpu/shaders.rs,
//! `ProblemShape::exact_tables`). They agree with the f64 CPU reference to
//! the GPU parity tolerances (1e-9 relative in f64, 2e-3 in f32); so do the
//! kernels that keep the search paths, for the same table with its
//! breakpoints jittered (the spacing guess and its corrections) and with two
//! breakpoints moved off the grid (the binary search).
mod oracle;
mod tensile_common;

mod gpu_common;
use gpu_common as common;

use std::path::Path;

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rigfit::base::Drive;
use rigfit::campaign::Campaign;
use rigfit::eval::{CpuEvaluator, Evaluator, Precision};
use rigfit::gpu::{GpuEvaluator, GpuOptions};
use rigfit::job::gene_specs;

/// The shipped EMPS closed-loop campaign on its position channel, its fit
/// shortened to 1500 samples (the drive table keeps the whole record).
fn campaign() -> Campaign {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("campaigns");
    let text = std::fs::read_to_string(dir.join("emps_closed_loop.json")).unwrap();
    let mut v: serde_json::Value = serde_json::from_str(&text).unwrap();
    v["experiments"][0]["channels"] =
        serde_json::json!([{"output": "position", "column": "position_m"}]);
    let mut c = Campaign::from_str(&v.to_string(), &dir, "emps_closed_loop.json").unwrap();
    for e in &mut c.problem.experiments {
        let n = e.measured.len().min(1500);
        e.measured.truncate(n);
        e.window = e.window.start.min(n)..n;
    }
    c
}

/// Moves the drive table's breakpoints: `f(i, dt)` added to breakpoint `i`.
fn move_breakpoints(c: &mut Campaign, f: impl Fn(usize, f64) -> f64) {
    for e in &mut c.problem.experiments {
        let Drive::Force(table) = &mut e.drive else {
            panic!("a force-driven experiment")
        };
        let dt = table.t[1] - table.t[0];
        for (i, t) in table.t.iter_mut().enumerate() {
            *t += f(i, dt);
        }
    }
}

fn agrees_with_the_cpu(c: &Campaign, exact: bool) {
    let Some(ctx) = common::gpu() else { return };
    let mut rng = ChaCha8Rng::seed_from_u64(11);
    let genes = gene_specs(c);
    let genomes: Vec<Vec<f64>> = (0..12)
        .map(|_| genes.iter().map(|g| g.at_fraction(rng.random())).collect())
        .collect();
    let batch = c.batch(&genomes);
    let cpu = CpuEvaluator::new(c.problem.clone(), 1)
        .fitness(&batch)
        .unwrap();
    let mut precisions = vec![(Precision::F32, 2e-3)];
    if ctx.has_f64() {
        precisions.push((Precision::F64, 1e-9));
    }
    for (precision, tol) in precisions {
        let mut gpu = GpuEvaluator::new(
            ctx.clone(),
            c.problem.clone(),
            precision,
            GpuOptions::default(),
        )
        .unwrap();
        assert_eq!(gpu.tables_exact(), exact, "{precision:?}");
        let g = gpu.fitness(&batch).unwrap();
        for (a, b) in g.values.iter().zip(&cpu.values) {
            assert!(
                (a - b).abs() <= tol * b.abs().max(1e-3),
                "{precision:?}, exact tables {exact}: GPU {a} vs CPU {b}"
            );
        }
    }
}

#[test]
fn a_measured_column_on_the_records_grid_is_looked_up_without_a_search() {
    let c = campaign();
    let Drive::Force(table) = &c.problem.experiments[0].drive else {
        panic!("the EMPS closed loop is force-driven")
    };
    assert!(
        table.kernel_header() > 0.0,
        "the record's own grid is exact"
    );
    agrees_with_the_cpu(&c, true);
}

#[test]
fn jittered_and_uneven_tables_keep_the_search_paths() {
    let header = |c: &Campaign| match &c.problem.experiments[0].drive {
        Drive::Force(t) => t.kernel_header(),
        Drive::Velocity => panic!("a force-driven experiment"),
    };
    let mut rough = campaign();
    move_breakpoints(&mut rough, |i, dt| {
        1e-4 * dt * ((i * 7919 % 13) as f64 / 12.0 - 0.5)
    });
    assert!(
        header(&rough) < 0.0,
        "the spacing guess and its corrections"
    );
    agrees_with_the_cpu(&rough, false);
    let mut uneven = campaign();
    move_breakpoints(&mut uneven, |i, dt| match i {
        100 => 0.4 * dt,
        700 => -0.45 * dt,
        _ => 0.0,
    });
    assert_eq!(header(&uneven), 0.0, "the binary search");
    agrees_with_the_cpu(&uneven, false);
}
