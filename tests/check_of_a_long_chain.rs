//! `rigfit check` on a chain of 1 000 masses finishes: the interval
//! stability bound costs what the rig's Jacobian holds (a chain's is banded),
//! not the square of its size. The work is asserted (the enclosure's nonzero
//! entries grow linearly with the chain), and the binary checks the 1 000-mass
//! chain end to end.

mod chain;

use std::path::Path;
use std::process::Command;

use rigfit::compile::analysis::interval::{InputBox, Interval, all_regimes, deriv_jacobian_box};
use serde_json::{Value, json};

use chain::chain;

/// Nonzero entries of the chain's Jacobian enclosure.
fn nonzero_entries(n: usize) -> usize {
    let desc = serde_json::from_value(chain(n)).unwrap();
    let lowered = rigfit::compile::lower(&desc, "chain").unwrap();
    let prog = &lowered.programs[0];
    let states = prog.deriv.len();
    let bx = InputBox {
        slots: vec![
            Interval::point(1.0),
            Interval::new(1e3, 1e4),
            Interval::point(1.0),
        ],
        t: Interval::new(0.0, 1.0),
        y: vec![Interval::new(-1.0, 1.0); states],
        regimes: all_regimes(prog),
        force: None,
    };
    deriv_jacobian_box(prog, &bx)
        .iter()
        .filter(|e| e.mag() != 0.0)
        .count()
}

#[test]
fn the_jacobian_enclosure_of_a_chain_is_banded() {
    for n in [10, 100, 400] {
        let nz = nonzero_entries(n);
        println!("{n} masses: {nz} nonzero entries of {}", 4 * n * n);
        // Each velocity row reads its own and its neighbours' x and v; each
        // displacement row its own v.
        assert!(nz <= 8 * n, "{n} masses: {nz} nonzero entries");
    }
}

#[test]
fn check_of_a_1000_mass_chain_finishes() {
    let tmp = tempfile::tempdir().unwrap();
    let dir: &Path = tmp.path();
    std::fs::write(dir.join("chain.json"), chain(1000).to_string()).unwrap();
    let mut csv = String::from("t_s,x_m\n");
    for i in 0..200 {
        csv += &format!("{},{}\n", f64::from(i) * 0.01, 1e-3 * f64::from(i % 7));
    }
    std::fs::write(dir.join("d.csv"), csv).unwrap();
    let c = json!({
        "name": "chain", "rig": "chain.json",
        "params": {"m": 1.0, "k": {"min": 1e3, "max": 1e4}, "c": 1.0},
        "experiments": [{"name": "e", "data": {"file": "d.csv", "time_column": "t_s", "force_column": "x_m"}, "drive": "velocity"}]
    });
    std::fs::write(dir.join("c.json"), c.to_string()).unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_rigfit"))
        .args(["check", "c.json"])
        .current_dir(dir)
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{err}");
    assert!(String::from_utf8_lossy(&out.stdout).contains("valid"));
}

/// The chain with a stick-slip contact between its driven end and ground.
fn switched_chain(n: usize) -> Value {
    let mut rig = chain(n);
    rig["params"].as_array_mut().unwrap().extend([
        json!({"name": "f_c", "unit": "N"}),
        json!({"name": "k_t", "unit": "N/m"}),
    ]);
    rig["elements"].as_array_mut().unwrap().push(json!({
        "name": "contact", "between": [format!("n{}", n - 1), "ground"],
        "friction": {"law": "stick_slip", "f_c": "f_c", "k_t": "k_t"}
    }));
    rig
}

#[test]
fn check_of_a_1000_mass_chain_with_a_switch_bounds_the_step_estimate_by_its_work() {
    // With a switch, the step-doubling estimate asked for ever more substeps,
    // each trial a run of the whole chain on the reference: its steps were
    // bounded (1e6) but not their cost, 100 times a small rig's per step, and
    // `check` took minutes. The bound is now on work: steps × states.
    let tmp = tempfile::tempdir().unwrap();
    let dir: &Path = tmp.path();
    std::fs::write(dir.join("chain.json"), switched_chain(1000).to_string()).unwrap();
    let mut csv = String::from("t_s,x_m\n");
    for i in 0..200 {
        let t = f64::from(i) * 0.01;
        csv += &format!("{t},{}\n", 1e-3 * (t * 7.0).sin() + 1e-5 * f64::from(i % 3));
    }
    std::fs::write(dir.join("d.csv"), csv).unwrap();
    let c = json!({
        "name": "chain", "rig": "chain.json",
        "params": {"m": 1.0, "k": {"min": 1e3, "max": 1e4}, "c": 1.0, "f_c": 1e-3, "k_t": 1e6},
        "experiments": [{"name": "e", "data": {"file": "d.csv", "time_column": "t_s", "force_column": "x_m"}, "drive": "velocity"}]
    });
    std::fs::write(dir.join("c.json"), c.to_string()).unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_rigfit"))
        .args(["check", "c.json", "--no-measure"])
        .current_dir(dir)
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    let said = format!("{}{err}", String::from_utf8_lossy(&out.stdout));
    assert!(out.status.success(), "{said}");
    let limit = rigfit::campaign::estimate_max_steps(2001);
    assert!(limit <= 1e4, "{limit}");
    assert!(
        said.contains("for a rig of 2001 states"),
        "the estimate was not bounded by the rig's size: {said}"
    );
}
