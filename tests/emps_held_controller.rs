//! The EMPS drive's digital controller as a held controller in `rigs/emps.json`,
//! against the real record (`campaigns/emps/closed_loop.csv`, Janot, Gautier,
//! Brunot 2019): simulated at the benchmark's inverse-model values (M =
//! 95.09 kg, Fv = 203.1 N·s/m, Fc = 20.44 N, OFF = −3.19 N) and driven by the
//! recorded reference position, the rig's command must reproduce the
//! recorded controller voltage and its position the recorded position.

use std::ops::ControlFlow;

use rigfit::base::{Drive, PiecewiseLinear, SampleGrid};
use rigfit::model::compiled::CompiledRig;

/// The record's columns: time, position, reference, voltage.
fn record() -> [Vec<f64>; 4] {
    let path = format!(
        "{}/campaigns/emps/closed_loop.csv",
        env!("CARGO_MANIFEST_DIR")
    );
    let text = std::fs::read_to_string(path).unwrap();
    let mut cols: [Vec<f64>; 4] = Default::default();
    for line in text.lines().filter(|l| !l.starts_with('#')).skip(1) {
        for (c, v) in cols.iter_mut().zip(line.split(',')) {
            c.push(v.parse().unwrap());
        }
    }
    cols
}

fn r_squared(got: &[f64], want: &[f64]) -> f64 {
    let mean = want.iter().sum::<f64>() / want.len() as f64;
    let ss_res: f64 = got.iter().zip(want).map(|(g, w)| (g - w).powi(2)).sum();
    let ss_tot: f64 = want.iter().map(|w| (w - mean).powi(2)).sum();
    1.0 - ss_res / ss_tot
}

#[test]
fn the_held_controller_at_the_inverse_models_values_reproduces_the_record() {
    let [t, q, qg, vir] = record();
    assert_eq!(t.len(), 24_841);
    let r = CompiledRig::new(rigfit::rig::shipped("emps").unwrap(), "emps").unwrap();
    let names: Vec<&str> = r.params().iter().map(|p| p.name.as_str()).collect();
    let p: Vec<f64> = r
        .params()
        .iter()
        .map(|p| match p.name.as_str() {
            "m" => 95.09,
            "f_v" => 203.1,
            "f_c" => 20.44,
            "f_offset" => -3.19,
            _ => p.default.unwrap(),
        })
        .collect();
    let out = |name: &str| {
        r.output_names()
            .iter()
            .position(|(n, _)| n == name)
            .unwrap_or_else(|| panic!("{name} in {names:?}"))
    };
    let (pos, volt) = (out("position"), out("voltage"));
    let drive = Drive::Force(PiecewiseLinear {
        t: t.clone(),
        value: qg,
    });
    let grid = SampleGrid {
        t0: 0.0,
        dt: 1e-3,
        samples: t.len(),
        substeps: 5,
    };
    let (mut sim_q, mut sim_v) = (vec![], vec![]);
    r.simulate(&p, &drive, &grid, &mut |s| {
        sim_q.push(s.outputs[pos]);
        sim_v.push(s.outputs[volt]);
        ControlFlow::Continue(())
    });
    let (rq, rv) = (r_squared(&sim_q, &q), r_squared(&sim_v, &vir));
    eprintln!("position R² = 1 − {:.3e}, voltage R² = {rv:.5}", 1.0 - rq);
    // Measured: position 1 − 4.3e-10, voltage 0.99738.
    assert!(1.0 - rq < 1e-9, "position R² = 1 − {:.3e}", 1.0 - rq);
    assert!(rv > 0.995, "voltage R² = {rv}");
}
