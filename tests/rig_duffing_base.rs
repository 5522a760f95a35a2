//! `rigs/duffing_base.json` — a rig that exists as a file only — against the
//! closed form of its linear case, and its cubic case's convergence order.

use std::ops::ControlFlow;

use rigfit::integrate::SampleGrid;
use rigfit::model::compiled::CompiledRig;
use rigfit::model::{Drive, RigModel};
use rigfit::rig::desc::DriveLaw;

fn rig(accel: Option<(Vec<f64>, Vec<f64>)>) -> CompiledRig {
    let mut desc = rigfit::rig::shipped("duffing_base").unwrap();
    if let Some((t, a)) = accel {
        desc.drives[0].law = DriveLaw::BaseAccelerationTable { t, value: a };
    }
    CompiledRig::new(desc, "rigs/duffing_base.json").unwrap()
}

fn history(rig: &CompiledRig, p: &[f64], dt: f64, samples: usize, substeps: usize) -> Vec<f64> {
    let grid = SampleGrid {
        t0: 0.0,
        dt,
        samples,
        substeps,
    };
    let mut h = vec![];
    rig.simulate(p, &Drive::Velocity, &grid, &mut |s| {
        h.push(s.outputs[0]);
        ControlFlow::Continue(())
    });
    h
}

#[test]
fn linear_case_under_a_constant_base_acceleration_matches_the_closed_form() {
    let (m, k, c, a0) = (1.0, 4e4, 20.0, 9.81);
    let r = rig(Some((vec![0.0, 1.0], vec![a0, a0])));
    let dt = 1e-4;
    let x = history(&r, &[m, k, 0.0, c], dt, 2000, 2);
    let w = (k / m).sqrt();
    let z = c / (2.0 * m * w);
    let wd = w * (1.0 - z * z).sqrt();
    let mut worst: f64 = 0.0;
    for (i, xi) in x.iter().enumerate() {
        let t = i as f64 * dt;
        let exact = -(a0 / (w * w))
            * (1.0
                - (-z * w * t).exp()
                    * ((wd * t).cos() + z / (1.0 - z * z).sqrt() * (wd * t).sin()));
        worst = worst.max((xi - exact).abs());
    }
    let scale = a0 / (w * w);
    println!(
        "largest error {:.3e} of a static deflection {scale:.3e} m",
        worst
    );
    assert!(worst < 1e-8 * scale, "{worst}");
}

#[test]
fn cubic_case_converges_at_fourth_order() {
    let r = rig(None);
    let p = [1.0, 4e4, 1e9, 20.0];
    let dt = 2e-4;
    let fine = history(&r, &p, dt, 2500, 64);
    let errs: Vec<f64> = [1, 2, 4, 8]
        .iter()
        .map(|&s| {
            let h = history(&r, &p, dt, 2500, s);
            let num: f64 = h.iter().zip(&fine).map(|(a, b)| (a - b).powi(2)).sum();
            let den: f64 = fine.iter().map(|b| b * b).sum();
            (num / den).sqrt()
        })
        .collect();
    let orders: Vec<f64> = errs.windows(2).map(|w| (w[0] / w[1]).log2()).collect();
    println!("errors {errs:?}, orders {orders:.2?}");
    for o in orders {
        assert!(o >= 3.5, "order {o}");
    }
    // The cubic term matters at this amplitude: the response differs from the
    // linear rig's by more than the integration error by far.
    let lin = history(&r, &[1.0, 4e4, 0.0, 20.0], dt, 2500, 8);
    let num: f64 = lin.iter().zip(&fine).map(|(a, b)| (a - b).powi(2)).sum();
    let den: f64 = fine.iter().map(|b| b * b).sum();
    assert!((num / den).sqrt() > 1e-3);
}
