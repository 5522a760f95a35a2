//! A sweep on the GPU gives the CPU's rows within the precision's tolerance:
//! the shipped tensile campaign's adapter sweep (slack-adapter damping × load
//! cell mass, a shared step) runs on the f64 CPU lanes and on the GPU's
//! history kernel (f32, and f64 where the adapter has it); every metric of
//! every row agrees with the CPU's to the documented tolerance
//! (docs/guide/design.md): 1e-12 of the metric's scale over the sweep in
//! f64, 1e-4 in f32 (a ringing is a difference of two nearly equal forces, so
//! its f32 error is relative to the force, not to itself), frequencies to
//! one bin of their spectrum. Lavapipe measured 7.9e-16 and 7.9e-7.
//! Without an adapter the test fails when `RIGFIT_REQUIRE_GPU=1` (CI).

mod gpu_common;
mod oracle;
mod tensile_common;

use std::path::Path;

use rigfit::design::{Engine, GpuRuns, RunOptions, Sweep, Table, run_sweep};
use rigfit::eval::PrecisionChoice;

fn sweep_file(dir: &Path) -> std::path::PathBuf {
    let campaign = Path::new(env!("CARGO_MANIFEST_DIR")).join("campaigns/aa2024_t3_synthetic.json");
    let path = dir.join("gpu.sweep.json");
    let text = format!(
        r#"{{"campaign": {:?},
            "variables": {{"c4": {{"log": [2e3, 5e4, 3]}}, "m1": {{"values": [6.0, 7.9]}}}},
            "metrics": [
              {{"name": "ring", "metric": "ringing", "output": "load_cell_force", "against": "specimen_force"}},
              {{"name": "ring_hz", "metric": "ringing_hz", "output": "load_cell_force", "against": "specimen_force"}},
              {{"name": "peak", "metric": "peak", "output": "load_cell_force"}},
              {{"name": "rms", "metric": "rms", "output": "specimen_force"}}
            ],
            "substeps": "shared"}}"#,
        campaign.display().to_string()
    );
    std::fs::write(&path, text).unwrap();
    path
}

fn compare(cpu: &Table, gpu: &Table, what: &str, rel: f64, dt: f64, samples: f64) {
    assert_eq!(cpu.rows.len(), gpu.rows.len());
    let mut worst = 0.0_f64;
    for (m, name) in cpu.metrics.iter().enumerate() {
        let scale = cpu
            .rows
            .iter()
            .filter_map(|r| r.metrics[m])
            .fold(0.0_f64, |a, v| a.max(v.abs()));
        for (a, b) in cpu.rows.iter().zip(&gpu.rows) {
            assert_eq!(a.substeps, b.substeps);
            let (x, y) = (a.metrics[m].unwrap(), b.metrics[m].unwrap());
            // A frequency agrees to one bin of the run's spectrum.
            let tol = if name.ends_with("_hz") {
                1.0 / (dt * samples) + rel * x.abs()
            } else {
                rel * scale
            };
            if !name.ends_with("_hz") {
                worst = worst.max((x - y).abs() / scale);
            }
            assert!(
                (x - y).abs() <= tol,
                "{what}: point {} {name}: CPU {x}, GPU {y} (difference {:e}, tolerance {tol:e})",
                a.point,
                (x - y).abs()
            );
        }
    }
    eprintln!("{what}: largest difference from the CPU {worst:.3e} of a metric's scale");
}

#[test]
fn gpu_sweep_rows_agree_with_the_cpu() {
    let Some(_ctx) = gpu_common::gpu() else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let sweep = Sweep::load(&sweep_file(dir.path())).unwrap();
    let exp = &sweep.campaign.problem.experiments[sweep.experiment];
    let (dt, samples) = (exp.dt, exp.window.len() as f64);
    let cpu = run_sweep(&sweep, &RunOptions::default(), Engine::Cpu, &|_, _| {}).unwrap();
    let mut f32 = GpuRuns::open(None, PrecisionChoice::F32).unwrap();
    let g32 = run_sweep(
        &sweep,
        &RunOptions::default(),
        Engine::Gpu(&mut f32),
        &|_, _| {},
    )
    .unwrap();
    compare(&cpu, &g32, "f32", 1e-4, dt, samples);
    let mut f64 = GpuRuns::open(None, PrecisionChoice::Auto).unwrap();
    if f64.precision().unwrap() == rigfit::eval::Precision::F64 {
        let g64 = run_sweep(
            &sweep,
            &RunOptions::default(),
            Engine::Gpu(&mut f64),
            &|_, _| {},
        )
        .unwrap();
        compare(&cpu, &g64, "f64", 1e-12, dt, samples);
    } else {
        eprintln!("the adapter has no f64: the f32 comparison alone ran");
    }
}
