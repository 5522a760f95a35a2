//! Expression laws (`{"law": "expression", "force": "…"}`) compute what the
//! built-in laws compute: the Duffing rig with its polynomial spring and viscous
//! damper written as formulas gives the same history to rounding, and a
//! formula with functions (a quadratic damper, a tanh friction) integrates to
//! fourth order in dt.

use std::ops::ControlFlow;

use rigfit::base::Drive;
use rigfit::base::SampleGrid;
use rigfit::model::compiled::CompiledRig;
use serde_json::{Value, json};

fn duffing(edit: impl Fn(&mut Value)) -> CompiledRig {
    let text = rigfit::rig::SHIPPED
        .iter()
        .find(|(i, _)| *i == "duffing_base")
        .unwrap()
        .1;
    let mut v: Value = serde_json::from_str(text).unwrap();
    edit(&mut v);
    CompiledRig::new(serde_json::from_value(v).unwrap(), "duffing (test)").unwrap()
}

fn history(rig: &CompiledRig, p: &[f64], samples: usize, substeps: usize) -> Vec<f64> {
    let grid = SampleGrid {
        t0: 0.0,
        dt: 2e-4,
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

const P: [f64; 4] = [1.0, 4e4, 4e10, 20.0];

#[test]
fn formulas_of_the_built_in_laws_give_the_same_history() {
    let built_in = duffing(|_| {});
    let formula = duffing(|v| {
        v["elements"][0]["spring"] = json!({"law": "expression", "force": "k*x + k3*x^3"});
        v["elements"][0]["damper"] = json!({"law": "expression", "force": "c*v"});
    });
    let (a, b) = (
        history(&built_in, &P, 500, 2),
        history(&formula, &P, 500, 2),
    );
    let scale = a.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
    let worst = a
        .iter()
        .zip(&b)
        .fold(0.0_f64, |m, (x, y)| m.max((x - y).abs()));
    println!("largest difference {:.2e} of {scale:.3e}", worst);
    assert!(scale > 1e-6, "the rig moves");
    assert!(worst <= 1e-12 * scale, "{worst} of {scale}");
}

#[test]
fn a_formula_with_functions_integrates_at_fourth_order() {
    let rig = duffing(|v| {
        v["elements"][0]["damper"] = json!({
            "law": "expression",
            "force": "c*v + 0.5*c*v*abs(v) + 0.1*c*tanh(v/0.01)"
        });
    });
    let reference = history(&rig, &P, 400, 64);
    let err = |sub: usize| {
        let h = history(&rig, &P, 400, sub);
        let num: f64 = h.iter().zip(&reference).map(|(a, b)| (a - b).powi(2)).sum();
        let den: f64 = reference.iter().map(|b| b * b).sum();
        (num / den).sqrt()
    };
    let (e1, e2, e4) = (err(1), err(2), err(4));
    let (o1, o2) = ((e1 / e2).log2(), (e2 / e4).log2());
    println!("errors {e1:.2e} {e2:.2e} {e4:.2e}, orders {o1:.2} {o2:.2}");
    assert!(o1 > 3.5 && o2 > 3.5, "orders {o1} {o2}");
}
