//! A specimen that never breaks within the record: `e_fracture` omitted or
//! `null`. The stability bound scans the specimen's law only up to the
//! elongation the run can reach, and names the parameter that drives it; both
//! evaluators run such a specimen to the end of the record.

mod gpu_common;
use gpu_common as common;

use std::path::{Path, PathBuf};
use std::process::Command;

use serde_json::{Value, json};

use rigfit::campaign::Campaign;
use rigfit::eval::{CpuEvaluator, Evaluator, Precision};
use rigfit::model::tensile::{TENSILE4, ix};
use rigfit::model::{Drive, RigModel};

fn repo() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// The shipped campaign with its experiment's `e_fracture` set by `set`.
fn campaign(dir: &Path, set: impl FnOnce(&mut Value)) -> PathBuf {
    let text = std::fs::read_to_string(repo().join("campaigns/aa2024_t3_synthetic.json")).unwrap();
    let mut c: Value = serde_json::from_str(&text).unwrap();
    let record = repo().join("campaigns/aa2024_t3_v2_synthetic.csv");
    c["experiments"][0]["data"]["file"] = json!(record.to_str().unwrap());
    c["output"] = json!("out");
    set(&mut c["experiments"][0]["params"]);
    let path = dir.join("c.json");
    std::fs::write(&path, serde_json::to_string_pretty(&c).unwrap()).unwrap();
    path
}

#[test]
fn omitted_null_and_huge_e_fracture_validate_with_the_shipped_step() {
    let dir = tempfile::tempdir().unwrap();
    let shipped = Campaign::load(&campaign(dir.path(), |_| {})).unwrap();
    // None: the key is left out.
    let variants = [
        ("omitted", None),
        ("null", Some(json!(null))),
        ("1e9", Some(json!(1e9))),
    ];
    for (what, value) in variants {
        let set = |p: &mut Value| match value {
            Some(v) => p["e_fracture"] = v,
            None => {
                p.as_object_mut().unwrap().remove("e_fracture");
            }
        };
        let c = Campaign::load(&campaign(dir.path(), set))
            .unwrap_or_else(|e| panic!("e_fracture {what}: {e}"));
        assert_eq!(c.solver.substeps, shipped.solver.substeps, "{what}");
        let o = Command::new(env!("CARGO_BIN_EXE_rigfit"))
            .arg("check")
            .arg(dir.path().join("c.json"))
            .output()
            .unwrap();
        assert_eq!(
            o.status.code(),
            Some(0),
            "{what}: {}",
            String::from_utf8_lossy(&o.stderr)
        );
    }
}

#[test]
fn the_bound_names_e_fracture_or_the_coefficient_that_drives_it() {
    let mut lo = rigfit::model::tensile::REFERENCE;
    lo[ix::A0 + 3] = 1e15;
    let drive = Drive::Velocity;
    let t_end = 2.5e-3;
    // A fracture range inside the travel (2 · 2 m/s · 2.5 ms = 1 cm).
    let mut hi = lo;
    lo[ix::E_FRACTURE] = 1e-3;
    hi[ix::E_FRACTURE] = 5e-3;
    assert_eq!(
        TENSILE4.omega_bound_in_run(&lo, &hi, &drive, t_end).1,
        "e_fracture"
    );
    // Never breaking: the travel bounds the elongation; a3 drives the bound.
    lo[ix::E_FRACTURE] = f64::INFINITY;
    hi[ix::E_FRACTURE] = f64::INFINITY;
    let (never, name) = TENSILE4.omega_bound_in_run(&lo, &hi, &drive, t_end);
    assert_eq!(name, "a3");
    assert!(never.is_finite());
    // ... and is the bound of a specimen breaking at the farthest reach.
    lo[ix::E_FRACTURE] = 1e-2;
    hi[ix::E_FRACTURE] = 1e-2;
    assert_eq!(
        never.to_bits(),
        TENSILE4
            .omega_bound_in_run(&lo, &hi, &drive, t_end)
            .0
            .to_bits()
    );
    // Without a run length the old scan up to e_fracture remains.
    hi[ix::E_FRACTURE] = 1.0;
    assert!(TENSILE4.omega_bound(&lo, &hi, &drive).0 > 10.0 * never);
}

#[test]
fn a_specimen_that_never_breaks_runs_to_the_end_on_both_paths() {
    let dir = tempfile::tempdir().unwrap();
    let c = Campaign::load(&campaign(dir.path(), |p| p["e_fracture"] = json!(null))).unwrap();
    let mut params = rigfit::model::tensile::REFERENCE;
    params[ix::E_FRACTURE] = f64::INFINITY;
    let broken = {
        let mut p = params;
        p[ix::E_FRACTURE] = 1e-3;
        p
    };
    let batch = common::batch_of(&c.problem, [params, broken].concat());
    let mut cpu = CpuEvaluator::new(c.problem.clone(), 1);
    let h = cpu.histories(&batch, &[0, 1]).unwrap();
    let last = |i: usize| *h[i][0].outputs[1].last().unwrap();
    // The specimen still carries load at the record's end; the broken one not.
    assert!(last(0).abs() > 1e3, "{}", last(0));
    assert_eq!(last(1), 0.0);
    let cpu_fit = cpu.fitness(&batch).unwrap();
    assert!(cpu_fit.values.iter().all(|v| v.is_finite()), "{cpu_fit:?}");
    let Some(ctx) = common::gpu() else { return };
    for precision in [Precision::F32, Precision::F64] {
        if precision == Precision::F64 && !ctx.has_f64() {
            continue;
        }
        let mut gpu = common::evaluator(&ctx, &c.problem, precision);
        let g = gpu.histories(&batch, &[0, 1]).unwrap();
        let scale = h[0][0].outputs[0]
            .iter()
            .fold(0.0_f64, |m, v| m.max(v.abs()));
        let tol = match precision {
            Precision::F32 => rigfit::gpu::F32_HISTORY_TOLERANCE,
            Precision::F64 => rigfit::gpu::F64_HISTORY_TOLERANCE,
        };
        for i in 0..2 {
            for (a, b) in h[i][0].outputs[0].iter().zip(&g[i][0].outputs[0]) {
                assert!(
                    (a - b).abs() <= tol * scale,
                    "{precision:?} run {i}: {a} vs {b}"
                );
            }
        }
    }
}
