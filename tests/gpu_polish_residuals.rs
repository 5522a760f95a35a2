//! The polish's residuals and Jacobian through the GPU evaluator agree with the
//! f64 CPU reference: residuals within [`F64_HISTORY_TOLERANCE`] of the largest
//! measured force (f64 kernels) or [`F32_HISTORY_TOLERANCE`] (f32), and the
//! standard errors built from the stencil's Jacobian within 1e-6 (f64).
mod oracle;
mod tensile_common;

mod gpu_common;
use gpu_common as common;

use std::path::Path;

use rigfit::campaign::Campaign;
use rigfit::eval::{CpuEvaluator, Evaluator, Precision};
use rigfit::gpu::{F32_HISTORY_TOLERANCE, F64_HISTORY_TOLERANCE};
use rigfit::job::{CampaignCost, gene_specs};
use rigfit::search::{Polish, PolishOutcome, PolishSettings, ResidualCost};

fn campaign() -> Campaign {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("campaigns");
    Campaign::load(&dir.join("aa2024_t3_synthetic.json")).unwrap()
}

/// The true values of the shipped record, and the same ×1.05 in every gene.
fn genomes(c: &Campaign) -> Vec<Vec<f64>> {
    let truth: Vec<f64> = c
        .genes
        .iter()
        .map(|g| match g.name.as_str() {
            "k1" => 8.4e9,
            "c1" => 5.51e5,
            "c1_post" => 9.22e3,
            "v2.k_lin" => 8.63e7,
            "v2.e_fracture" => 1e-3,
            "c4" => 1.57e4,
            "gap" => 1.87e-5,
            other => panic!("unexpected gene {other}"),
        })
        .collect();
    let off = truth.iter().map(|v| v * 1.05).collect();
    vec![truth, off]
}

/// Residuals, and the uncertainty from one stencil (no iteration) at the truth.
fn through(c: &Campaign, ev: Box<dyn Evaluator>) -> (Vec<Vec<f64>>, PolishOutcome) {
    let mut cost = CampaignCost::new(c, ev, true, 0);
    let g = genomes(c);
    let r = cost
        .residuals(&g)
        .unwrap()
        .into_iter()
        .map(Option::unwrap)
        .collect();
    let settings = PolishSettings {
        max_iterations: 0,
        ..PolishSettings::default()
    };
    let p = Polish::new(settings, gene_specs(c))
        .run(&mut cost, &g[..1])
        .unwrap();
    (r, p)
}

#[test]
fn polish_residuals_and_jacobian_match_the_cpu_reference() {
    let Some(ctx) = common::gpu() else { return };
    let c = campaign();
    let (r_cpu, p_cpu) = through(&c, Box::new(CpuEvaluator::new(c.problem.clone(), 0)));
    let exp = &c.problem.experiments[0];
    let f_max = exp.measured.iter().fold(0.0_f64, |m, f| m.max(f.abs()));
    // The residuals are scaled by √(w / (W · SS_tot)); a force error of ε·F_max
    // is a residual error of ε·F_max times that scale.
    let scale = (1.0 / exp.ss_tot()).sqrt();
    let mut precisions = vec![(Precision::F32, F32_HISTORY_TOLERANCE)];
    if ctx.has_f64() {
        precisions.push((Precision::F64, F64_HISTORY_TOLERANCE));
    }
    for (precision, tol) in precisions {
        let (r_gpu, p_gpu) = through(&c, Box::new(common::evaluator(&ctx, &c.problem, precision)));
        for (a, b) in r_cpu.iter().zip(&r_gpu) {
            assert_eq!(a.len(), b.len());
            let worst = a
                .iter()
                .zip(b)
                .fold(0.0_f64, |m, (x, y)| m.max((x - y).abs()));
            assert!(
                worst <= tol * f_max * scale,
                "{precision:?}: residuals differ by {:e} of F_max",
                worst / (f_max * scale)
            );
        }
        if precision == Precision::F64 {
            let (u_cpu, u_gpu) = (p_cpu.uncertainty.as_ref(), p_gpu.uncertainty.as_ref());
            for (a, b) in u_cpu.unwrap().genes.iter().zip(&u_gpu.unwrap().genes) {
                let (x, y) = (a.std_error.unwrap(), b.std_error.unwrap());
                assert!((x / y - 1.0).abs() < 1e-6, "{}: {x:e} vs {y:e}", a.name);
            }
        }
    }
}
