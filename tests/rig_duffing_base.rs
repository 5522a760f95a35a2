//! `rigs/duffing_base.json` — a rig that exists as a file only — against the
//! closed form of its linear case, and its cubic case's convergence order.

use std::ops::ControlFlow;

use rigfit::base::Drive;
use rigfit::base::SampleGrid;
use rigfit::model::compiled::CompiledRig;
use rigfit::rig::desc::{DriveLaw, TableDesc};

fn rig(accel: Option<(Vec<f64>, Vec<f64>)>) -> CompiledRig {
    let mut desc = rigfit::rig::shipped("duffing_base").unwrap();
    if let Some((t, a)) = accel {
        desc.drives[0].law = DriveLaw::BaseAccelerationTable(TableDesc {
            t: Some(t),
            value: Some(a),
            gain: None,
        });
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

/// The base acceleration read from the experiment's table (a measured column,
/// `"drive": {"force": {"column": …}}` in a campaign), with a gain, gives the
/// same run as the rig's own table in m/s² (to rounding: the gain multiplies
/// after the interpolation instead of before).
#[test]
fn base_acceleration_from_the_experiments_table_matches_the_inline_table() {
    use rigfit::base::PiecewiseLinear;
    use rigfit::rig::desc::Coef;
    let t: Vec<f64> = (0..400).map(|i| i as f64 * 2.5e-4).collect();
    let volts: Vec<f64> = t
        .iter()
        .map(|&ti| (40.0 * ti).sin() + 0.3 * (170.0 * ti).cos())
        .collect();
    let gain = 4.0; // m/s² per volt: an accelerometer's sensitivity
    let accel: Vec<f64> = volts.iter().map(|v| gain * v).collect();
    let inline = rig(Some((t.clone(), accel)));
    let mut desc = rigfit::rig::shipped("duffing_base").unwrap();
    desc.drives[0].mode = "force".into();
    desc.drives[0].law = DriveLaw::BaseAccelerationTable(TableDesc {
        t: None,
        value: None,
        gain: Some(Coef::Number(gain)),
    });
    let measured = CompiledRig::new(desc, "rigs/duffing_base.json").unwrap();
    let grid = SampleGrid {
        t0: 0.0,
        dt: 2.5e-4,
        samples: 400,
        substeps: 2,
    };
    let p = [1.0, 4e4, 3e9, 20.0];
    let want = history(&inline, &p, 2.5e-4, 400, 2);
    let drive = Drive::Force(PiecewiseLinear { t, value: volts });
    let mut got = vec![];
    measured.simulate(&p, &drive, &grid, &mut |s| {
        got.push(s.outputs[0]);
        ControlFlow::Continue(())
    });
    let scale = want.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
    assert!(scale > 1e-5, "the base moves the mass: {scale}");
    assert_eq!(got.len(), want.len());
    for (k, (a, b)) in got.iter().zip(&want).enumerate() {
        assert!((a - b).abs() <= 1e-12 * scale, "sample {k}: {a} vs {b}");
    }
}
