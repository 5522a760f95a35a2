//! A rig file's controllers that cannot run are refused before any work, with
//! the file, the JSON path, what was expected and what was found.

use rigfit::model::compiled::CompiledRig;
use rigfit::rig::desc::RigDesc;
use serde_json::{Value, json};

fn held_pd() -> Value {
    let path = format!("{}/tests/rigs/held_pd.json", env!("CARGO_MANIFEST_DIR"));
    serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}

/// The message `CompiledRig::new` gives for `v`.
fn refusal(v: Value) -> String {
    let desc: RigDesc = serde_json::from_value(v).unwrap();
    CompiledRig::new(desc, "bad_rig.json")
        .expect_err("refused")
        .to_string()
}

/// A case: what is wrong, the edit that makes it so, what the message holds.
type Case = (
    &'static str,
    Box<dyn Fn(&mut Value)>,
    &'static [&'static str],
);

#[test]
fn bad_controllers_are_refused_with_their_json_path() {
    let cases: Vec<Case> = vec![
        (
            "a period of zero",
            Box::new(|v| v["controllers"][0]["period"] = json!(0.0)),
            &[
                "bad_rig.json: controllers[0].period: expected a sample period in seconds, finite and > 0, found 0",
            ],
        ),
        (
            "a negative phase",
            Box::new(|v| v["controllers"][0]["phase"] = json!(-1e-3)),
            &[
                "controllers[0].phase: expected the first sample instant",
                "found -0.001",
            ],
        ),
        (
            "an unknown name in a law",
            Box::new(|v| v["controllers"][0]["states"][1]["update"] = json!("-kp*positon")),
            &[
                "controllers[0].states[1].update: expected a formula of the controller's states",
                "column 5: unknown name 'positon'",
                "did you mean 'position'?",
            ],
        ),
        (
            "reference outside a force-mode controller",
            Box::new(|v| {
                v["controllers"][0]["states"][1]["update"] = json!("kp*(reference - position)")
            }),
            &[
                "controllers[0].states[1].update",
                "'reference' is the experiment's table, which only a \"force\"-mode controller has",
            ],
        ),
        (
            "a command that is not a state",
            Box::new(|v| v["controllers"][0]["command"] = json!("force")),
            &[
                "controllers[0].command: expected one of the controller's states (x_prev, u), found \"force\"",
            ],
        ),
        (
            "a node that does not exist",
            Box::new(|v| v["controllers"][0]["acts_on"]["node"] = json!("cart")),
            &["controllers[0].acts_on.node: expected a node name, found \"cart\""],
        ),
        (
            "a state named like a parameter",
            Box::new(|v| v["controllers"][0]["states"][0]["name"] = json!("kp")),
            &[
                "controllers[0].states[0].name",
                "found \"kp\", the name of a parameter",
            ],
        ),
        (
            "another controller's state",
            Box::new(|v| {
                let mut other = v["controllers"][0].clone();
                other["name"] = json!("other");
                other["states"] = json!([{"name": "w", "update": "u"}]);
                other["command"] = json!("w");
                v["controllers"].as_array_mut().unwrap().push(other);
            }),
            &[
                "controllers[1].states[0].update",
                "unknown name 'u'",
                "'u' is a state of controller 'pd': a law reads only its own controller's states",
            ],
        ),
        (
            "two rates in one drive kind",
            Box::new(|v| {
                let mut other = v["controllers"][0].clone();
                other["name"] = json!("other");
                other["period"] = json!(2e-3);
                v["controllers"].as_array_mut().unwrap().push(other);
            }),
            &[
                "controllers[1].period: expected the period and phase of controllers[0] (0.001 s, 0 s)",
            ],
        ),
        (
            "an output naming no controller",
            Box::new(|v| v["outputs"][1]["sum"][0]["controller"] = json!("servo")),
            &["outputs[1].sum[0].controller: expected a controller name, found \"servo\""],
        ),
    ];
    for (what, edit, want) in cases {
        let mut v = held_pd();
        edit(&mut v);
        let msg = refusal(v);
        for w in want {
            assert!(msg.contains(w), "{what}: {msg}");
        }
    }
}
