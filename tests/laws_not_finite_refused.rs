//! A law that is not a finite number over the rig's reach is refused: a part
//! that reads no parameter (`0/0`, `exp(1000)`, `ln(0)`, a division by 0)
//! when the rig is loaded, by any command; a part that depends on a
//! parameter by `rigfit check`, at the campaign's bounds; and `rigfit modes`
//! says when the linearisation is not finite instead of printing a mode.

use std::path::Path;
use std::process::Command;

use rigfit::model::compiled::CompiledRig;
use rigfit::rig::{RigSource, parse};
use serde_json::{Value, json};

fn rig(force: &str) -> Value {
    json!({
        "id": "one_mass",
        "params": [
            {"name": "m", "unit": "kg"},
            {"name": "k", "unit": "N/m"},
            {"name": "c", "unit": "N·s/m"}
        ],
        "nodes": [{"name": "mass", "mass": "m"}],
        "elements": [{
            "name": "spring", "between": ["ground", "mass"],
            "spring": {"law": "expression", "force": force},
            "damper": {"law": "viscous", "c": 1.0}
        }],
        "drives": [{"node": "mass", "law": {"type": "sine", "quantity": "force", "amplitude": 1.0, "frequency": 2.0}}],
        "outputs": [{"name": "x_mass", "unit": "m", "sum": [{"displacement": "mass"}]}]
    })
}

fn compile(force: &str) -> Result<CompiledRig, String> {
    let src = RigSource::File("law_rig.json".into());
    let desc = parse(&rig(force).to_string(), &src).map_err(|e| e.to_string())?;
    CompiledRig::new(desc, &src.label()).map_err(|e| e.to_string())
}

#[test]
fn a_part_without_parameters_that_is_not_finite_is_refused_on_loading() {
    for (force, part) in [
        ("k*x + 0/0", "(0 / 0)"),
        ("k*x + exp(1000)", "exp(1000)"),
        ("k*x + ln(0)", "ln(0)"),
        ("k*x/0", "((k * x) / 0)"),
        ("k*x + 1/x", "(1 / x)"),
        ("k*ln(x)", "ln(x)"),
    ] {
        let Err(e) = compile(force) else {
            panic!("{force}: accepted");
        };
        println!("{force}: {e}");
        assert!(
            e.starts_with(
                "law_rig.json: elements[0].spring.force: expected a law finite for every x"
            ),
            "{e}"
        );
        assert!(e.contains(part), "{force}: names {part}: {e}");
    }
    for force in [
        "k*x",
        "k*x + c*x^3",
        "k*spow(x, 0.5)",
        "k*x*exp(-x^2)",
        "k*tanh(x/0.01)",
    ] {
        compile(force).unwrap_or_else(|e| panic!("{force}: {e}"));
    }
}

fn rigfit() -> Command {
    Command::new(env!("CARGO_BIN_EXE_rigfit"))
}

fn setup(dir: &Path, force: &str, params: Value) {
    std::fs::write(dir.join("law_rig.json"), rig(force).to_string()).unwrap();
    let mut csv = String::from("t_s,x_m\n");
    for i in 0..200 {
        csv += &format!("{},{}\n", f64::from(i) * 0.01, 1e-3 * f64::from(i % 7));
    }
    std::fs::write(dir.join("d.csv"), csv).unwrap();
    let c = json!({
        "name": "laws", "rig": "law_rig.json", "params": params,
        "experiments": [{"name": "e", "data": {"file": "d.csv", "time_column": "t_s", "force_column": "x_m"}, "drive": "velocity"}]
    });
    std::fs::write(dir.join("c.json"), c.to_string()).unwrap();
}

#[test]
fn check_refuses_a_law_not_finite_at_the_bounds_of_its_parameters() {
    let tmp = tempfile::tempdir().unwrap();
    setup(
        tmp.path(),
        "k*x/c",
        json!({"m": 1.0, "k": 1e3, "c": {"min": 0.0, "max": 2.0}}),
    );
    let out = rigfit()
        .args(["check", "c.json"])
        .current_dir(tmp.path())
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    println!("{err}");
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert!(err.contains("elements[0].spring.force"), "{err}");
    assert!(err.contains("c = 0"), "names the parameter's value: {err}");
    // Inside bounds that keep it finite, the same law checks.
    setup(
        tmp.path(),
        "k*x/c",
        json!({"m": 1.0, "k": 1e3, "c": {"min": 0.5, "max": 2.0}}),
    );
    let out = rigfit()
        .args(["check", "c.json"])
        .current_dir(tmp.path())
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
}

#[test]
fn modes_says_when_the_linearisation_is_not_finite() {
    let tmp = tempfile::tempdir().unwrap();
    setup(
        tmp.path(),
        "k*x*ln(c)",
        json!({"m": 1.0, "k": 1e3, "c": 0.0}),
    );
    let out = rigfit()
        .args(["modes", "c.json"])
        .current_dir(tmp.path())
        .output()
        .unwrap();
    let (so, err) = (
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr),
    );
    println!("{so}\n{err}");
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert!(err.contains("linearisation is not finite"), "{err}");
    assert!(!so.contains("Hz"), "no mode printed: {so}");
}
