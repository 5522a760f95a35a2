//! Bad rig files are refused with one line naming the file, the JSON path and
//! what was expected: a table of cases, each a small edit of a shipped rig.

use rigfit::model::compiled::CompiledRig;
use rigfit::rig::{RigSource, parse};
use serde_json::{Value, json};

fn base() -> Value {
    serde_json::from_str(
        rigfit::rig::SHIPPED
            .iter()
            .find(|(i, _)| *i == "tensile4")
            .unwrap()
            .1,
    )
    .unwrap()
}

fn compile(v: &Value) -> Result<(), String> {
    let src = RigSource::File("bad_rig.json".into());
    let desc = parse(&v.to_string(), &src).map_err(|e| e.to_string())?;
    CompiledRig::new(desc, &src.label())
        .map(|_| ())
        .map_err(|e| e.to_string())
}

type Edit = fn(&mut Value);

#[test]
fn every_bad_rig_is_refused_with_its_file_and_json_path() {
    let cases: Vec<(&str, Edit, &str)> = vec![
        (
            "element to a node that does not exist",
            |v| v["elements"][2]["between"][1] = json!("barr"),
            "elements[2].between[1]",
        ),
        (
            "a node no element touches",
            |v| {
                v["nodes"]
                    .as_array_mut()
                    .unwrap()
                    .push(json!({"name": "loose", "mass": "m1"}))
            },
            "nodes[4]",
        ),
        (
            "unknown spring law",
            |v| v["elements"][0]["spring"]["law"] = json!("hyperelastic"),
            "elements[0].spring",
        ),
        (
            "missing parameter",
            |v| v["elements"][2]["spring"]["k"] = json!("k33"),
            "elements[2].spring.k",
        ),
        (
            "negative mass",
            |v| v["nodes"][0]["mass"] = json!(-7.9),
            "nodes[0].mass",
        ),
        (
            "gap on a damper",
            |v| {
                v["elements"][2]["spring"] = Value::Null;
                v["elements"][2]["gap"] = json!({"kind": "tension", "size": "gap"});
            },
            "elements[2].gap",
        ),
        (
            "duplicate node",
            |v| v["nodes"][1]["name"] = json!("load_cell"),
            "nodes[1].name",
        ),
        (
            "duplicate parameter",
            |v| v["params"][1]["name"] = json!("m1"),
            "params[1].name",
        ),
        (
            "duplicate element",
            |v| v["elements"][1]["name"] = json!("load_cell"),
            "elements[1].name",
        ),
        (
            "unknown key",
            |v| v["elements"][0]["stiffness"] = json!(1.0),
            "elements[0]",
        ),
        (
            "polynomial of degree 6",
            |v| {
                v["elements"][1]["spring"]["coeffs"]
                    .as_array_mut()
                    .unwrap()
                    .push(json!(0.0))
            },
            "elements[1].spring.coeffs",
        ),
        (
            "a switch on an element that never breaks",
            |v| v["elements"][0]["damper"]["c"]["broken"] = json!("bar"),
            "elements[0].damper.c.broken",
        ),
        (
            "a switch on an unknown element",
            |v| v["elements"][0]["damper"]["c"]["broken"] = json!("specimenn"),
            "elements[0].damper.c.broken",
        ),
        (
            "unknown drive mode",
            |v| v["drives"][1]["mode"] = json!("torque"),
            "drives[1].mode",
        ),
        (
            "drive on an unknown node",
            |v| v["drives"][0]["node"] = json!("piston"),
            "drives[0].node",
        ),
        (
            "output term with two quantities",
            |v| v["outputs"][0]["sum"][0]["displacement"] = json!("bar"),
            "outputs[0].sum[0]",
        ),
        (
            "output of an unknown element",
            |v| v["outputs"][1]["sum"][0]["force"] = json!("specimen2"),
            "outputs[1].sum[0].force",
        ),
        ("no outputs", |v| v["outputs"] = json!([]), "outputs"),
        (
            "element joining a node to itself",
            |v| v["elements"][2]["between"] = json!(["bar", "bar"]),
            "elements[2].between",
        ),
        (
            "rig id that is not an identifier",
            |v| v["id"] = json!("tensile 4"),
            "id",
        ),
        (
            "table times not increasing",
            |v| {
                v["drives"][1]["law"] =
                    json!({"type": "force_table", "t": [0.0, 1.0, 0.5], "value": [0.0, 1.0, 2.0]})
            },
            "drives[1].law.t",
        ),
        (
            "base acceleration on one node",
            |v| v["drives"][0] = json!({"node": "bar", "law": {"type": "base_acceleration_table", "t": [0.0, 1.0], "value": [0.0, 1.0]}}),
            "drives[0].node",
        ),
        (
            "velocity-mode force drive without a table",
            |v| v["drives"][0] = json!({"node": "actuator", "law": {"type": "force_table"}}),
            "drives[0].law",
        ),
        (
            "negative gap",
            |v| v["elements"][3]["gap"]["size"] = json!(-1e-5),
            "elements[3].gap.size",
        ),
        (
            "element with no law",
            |v| {
                v["elements"][2]["spring"] = Value::Null;
                v["elements"][2]["damper"] = Value::Null;
            },
            "elements[2]",
        ),
        (
            "non-numeric coefficient",
            |v| v["elements"][2]["spring"]["k"] = json!([1, 2]),
            "elements[2].spring: expected a valid rig description, found invalid type: sequence, expected a parameter name",
        ),
        ("no nodes", |v| v["nodes"] = json!([]), "nodes"),
        (
            "sine drive with an unknown quantity",
            |v| v["drives"][0] = json!({"node": "actuator", "law": {"type": "sine", "quantity": "torque", "amplitude": 1.0, "frequency": 10.0}}),
            "drives[0].law: expected a valid rig description, found unknown variant `torque`",
        ),
        (
            "sine drive with an unknown parameter",
            |v| v["drives"][0] = json!({"node": "actuator", "law": {"type": "sine", "quantity": "force", "amplitude": "f0", "frequency": 10.0}}),
            "drives[0].law.amplitude",
        ),
        (
            "chirp drive without a rate",
            |v| v["drives"][0] = json!({"node": "actuator", "law": {"type": "chirp", "quantity": "force", "amplitude": 1.0, "f_start": 1.0}}),
            "drives[0].law",
        ),
        (
            "base-acceleration sine on one node",
            |v| v["drives"][0] = json!({"node": "bar", "law": {"type": "sine", "quantity": "base_acceleration", "amplitude": 1.0, "frequency": 10.0}}),
            "drives[0].node",
        ),
        (
            "force sine on no node",
            |v| v["drives"][0] = json!({"law": {"type": "sine", "quantity": "force", "amplitude": 1.0, "frequency": 10.0}}),
            "drives[0].node",
        ),
        (
            "half-sine pulse of zero length",
            |v| v["drives"][0] = json!({"node": "actuator", "law": {"type": "half_sine", "quantity": "force", "amplitude": 1.0, "duration": 0.0}}),
            "drives[0].law.duration",
        ),
        (
            "a second prescribed displacement of one node",
            |v| {
                v["drives"]
                    .as_array_mut()
                    .unwrap()
                    .push(json!({"node": "actuator", "law": {"type": "sine", "quantity": "displacement", "amplitude": 1e-3, "frequency": 5.0}}))
            },
            "drives[2].node",
        ),
        (
            "expression with an unknown name",
            |v| v["elements"][2]["spring"] = json!({"law": "expression", "force": "k3*x + k4*x^3"}),
            "elements[2].spring.force",
        ),
        (
            "expression with bad syntax",
            |v| v["elements"][2]["spring"] = json!({"law": "expression", "force": "k3*x + *x"}),
            "elements[2].spring.force",
        ),
        (
            "expression calling a function with the wrong arity",
            |v| v["elements"][2]["spring"] = json!({"law": "expression", "force": "k3*max(x)"}),
            "elements[2].spring.force",
        ),
        (
            "damper expression reading the elongation",
            |v| v["elements"][2]["damper"] = json!({"law": "expression", "force": "c3*x"}),
            "elements[2].damper.force",
        ),
        (
            "backlash behind a gap",
            |v| v["elements"][3]["backlash"] = json!({"half_width": 1e-3}),
            "elements[3].backlash",
        ),
        (
            "backlash with friction",
            |v| {
                v["elements"][2]["friction"] =
                    json!({"law": "stick_slip", "f_c": 10.0, "k_t": "k3"});
                v["elements"][2]["backlash"] = json!({"half_width": 1e-3});
            },
            "elements[2].backlash",
        ),
        (
            "backlash without a damper",
            |v| {
                v["elements"][2]["damper"] = Value::Null;
                v["elements"][2]["backlash"] = json!({"half_width": 1e-3});
            },
            "elements[2].backlash",
        ),
        (
            "backlash without a spring",
            |v| {
                v["elements"][2]["spring"] = Value::Null;
                v["elements"][2]["backlash"] = json!({"half_width": 1e-3});
            },
            "elements[2].backlash",
        ),
        (
            "backlash with a damper that is not viscous",
            |v| {
                v["elements"][2]["damper"] = json!({"law": "power_law", "c": "c3", "alpha": 2.0});
                v["elements"][2]["backlash"] = json!({"half_width": 1e-3});
            },
            "elements[2].damper",
        ),
        (
            "backlash with zero damping",
            |v| {
                v["elements"][2]["damper"]["c"] = json!(0.0);
                v["elements"][2]["backlash"] = json!({"half_width": 1e-3});
            },
            "elements[2].damper.c",
        ),
        (
            "backlash with a negative half-width",
            |v| v["elements"][2]["backlash"] = json!({"half_width": -1e-3}),
            "elements[2].backlash.half_width",
        ),
        (
            "backlash with an unknown key",
            |v| v["elements"][2]["backlash"] = json!({"half_width": 1e-3, "size": 1e-3}),
            "elements[2].backlash",
        ),
    ];
    assert!(cases.len() >= 20);
    assert!(compile(&base()).is_ok(), "the base rig compiles");
    for (what, edit, path) in cases {
        let mut v = base();
        edit(&mut v);
        let err = compile(&v).expect_err(what);
        println!("{what}: {err}");
        assert!(err.starts_with("bad_rig.json: "), "{what}: {err}");
        assert!(err.contains(path), "{what}: expected path {path} in: {err}");
        assert!(!err.contains('\n'), "{what}: more than one line: {err}");
        if what.starts_with("expression") || what.starts_with("damper expression") {
            assert!(err.contains("column "), "{what}: no column in: {err}");
        }
    }
}

#[test]
fn expression_errors_name_the_column_and_what_is_wrong() {
    let mut v = base();
    v["elements"][2]["spring"] = json!({"law": "expression", "force": "k3*x + k4*x^3"});
    let err = compile(&v).unwrap_err();
    assert!(err.contains("column 8"), "{err}");
    assert!(err.contains("unknown name 'k4'"), "{err}");
    assert!(err.contains("did you mean"), "{err}");
    v["elements"][2]["spring"] = json!({"law": "expression", "force": "k3*max(x)"});
    let err = compile(&v).unwrap_err();
    assert!(
        err.contains("column 4") && err.contains("takes 2 arguments, found 1"),
        "{err}"
    );
}

#[test]
fn output_names_and_units_that_would_break_a_csv_are_refused() {
    let cases: Vec<(&str, Edit, &str)> = vec![
        (
            "an output name with a comma",
            |v| v["outputs"][0]["name"] = json!("load,cell"),
            "outputs[0].name",
        ),
        (
            "an output name with a quote",
            |v| v["outputs"][0]["name"] = json!("load\"cell"),
            "outputs[0].name",
        ),
        (
            "an output name with a line break",
            |v| v["outputs"][1]["name"] = json!("x\nfitness: 0"),
            "outputs[1].name",
        ),
        (
            "an output name that is a spreadsheet formula",
            |v| v["outputs"][0]["name"] = json!("=HYPERLINK(\"http://x\")"),
            "outputs[0].name",
        ),
        (
            "two outputs named alike",
            |v| v["outputs"][1]["name"] = v["outputs"][0]["name"].clone(),
            "outputs[1].name: expected a unique output name",
        ),
        (
            "an output unit with a comma",
            |v| v["outputs"][0]["unit"] = json!("N,m"),
            "outputs[0].unit",
        ),
        (
            "an output unit with a line break",
            |v| v["outputs"][0]["unit"] = json!("N\nfitness"),
            "outputs[0].unit",
        ),
        (
            "an output unit that is a spreadsheet formula",
            |v| v["outputs"][0]["unit"] = json!("=1+1"),
            "outputs[0].unit",
        ),
        (
            "a parameter unit with a quote",
            |v| v["params"][0]["unit"] = json!("kg\""),
            "params[0].unit",
        ),
    ];
    for (what, edit, path) in cases {
        let mut v = base();
        edit(&mut v);
        let err = compile(&v).expect_err(what);
        println!("{what}: {err}");
        assert!(err.starts_with("bad_rig.json: "), "{what}: {err}");
        assert!(err.contains(path), "{what}: expected {path} in: {err}");
        assert!(!err.contains('\n'), "{what}: more than one line: {err}");
    }
    // Units as the shipped rigs write them are accepted.
    for unit in ["N", "m/s²", "N·s/m", "N·(s/m)^α", "1", "N/m^β", "", "%"] {
        let mut v = base();
        v["outputs"][0]["unit"] = json!(unit);
        compile(&v).unwrap_or_else(|e| panic!("{unit:?}: {e}"));
    }
}

#[test]
fn trailing_text_and_a_reach_that_is_not_positive_are_refused() {
    let src = RigSource::File("bad_rig.json".into());
    let text = base().to_string();
    for tail in ["}", " {\"id\": \"x\"}", "\nx"] {
        let err = parse(&format!("{text}{tail}"), &src)
            .unwrap_err()
            .to_string();
        println!("{tail:?}: {err}");
        assert!(
            err.starts_with("bad_rig.json: (top level): expected the end of the file"),
            "{err}"
        );
        assert!(err.contains("more text at line"), "{err}");
    }
    assert!(parse(&format!("\u{feff}{text}\n\n"), &src).is_ok());
    for (reach, path) in [
        (
            json!({"elongation": -0.01, "rate": 10.0}),
            "reach.elongation",
        ),
        (json!({"elongation": 0.0, "rate": 10.0}), "reach.elongation"),
        (json!({"elongation": 0.01, "rate": -10.0}), "reach.rate"),
    ] {
        let mut v = base();
        v["reach"] = reach;
        let err = compile(&v).unwrap_err();
        println!("{err}");
        assert!(err.contains(path) && err.contains("> 0"), "{err}");
    }
}
