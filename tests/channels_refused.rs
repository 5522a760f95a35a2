//! Bad `channels` are refused before any work, naming the campaign file, the
//! JSON path, what was expected and what was found.

use std::path::Path;

use rigfit::campaign::Campaign;
use serde_json::{Value, json};

fn load(channels: Value, column: Option<&str>) -> String {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("campaigns");
    let mut data = json!({"file": "quarter_car_channels_synthetic.csv", "time_column": "t_s"});
    if let Some(c) = column {
        data["column"] = json!(c);
    }
    let c = json!({
        "name": "bad-channels",
        "rig": "quarter_car",
        "params": {"m1": 40.0, "m2": 350.0, "k1": 1.751e5, "c1": 1751.0,
                   "k2": {"min": 5e3, "max": 1e5}, "c2": 2500.0},
        "experiments": [{
            "name": "sweep",
            "data": data,
            "channels": channels,
            "params": {"amplitude": 0.0005, "f_start": 1.0, "rate": 2.8}
        }]
    });
    Campaign::from_str(&c.to_string(), &dir, "bad.json")
        .map(|_| "accepted".to_string())
        .unwrap_or_else(|e| e.to_string())
}

fn accel() -> Value {
    json!({"output": "sprung_acceleration", "column": "sprung_acceleration_m/s²"})
}

#[test]
fn an_unknown_output_is_named_with_the_rig_outputs() {
    let e = load(json!([{"output": "sprung_accel", "column": 1}]), None);
    assert!(
        e.starts_with("bad.json: experiments[0].channels[0].output"),
        "{e}"
    );
    assert!(
        e.contains("strut_force") && e.contains("\"sprung_accel\""),
        "{e}"
    );
}

#[test]
fn an_output_in_two_channels_is_refused() {
    let e = load(json!([accel(), accel()]), None);
    assert!(
        e.starts_with("bad.json: experiments[0].channels[1].output"),
        "{e}"
    );
    assert!(e.contains("already channels[0]"), "{e}");
}

#[test]
fn a_data_column_beside_channels_is_refused() {
    let e = load(json!([accel()]), Some("strut_force_N"));
    assert!(e.starts_with("bad.json: experiments[0].data"), "{e}");
}

#[test]
fn no_channels_zero_scales_and_weights_are_refused() {
    let e = load(json!([]), None);
    assert!(
        e.contains("experiments[0].channels: expected at least one channel"),
        "{e}"
    );
    let mut zero = accel();
    zero["scale"] = json!(0.0);
    let e = load(json!([zero]), None);
    assert!(e.contains("experiments[0].channels[0].scale"), "{e}");
    let mut neg = accel();
    neg["weight"] = json!(-1.0);
    let e = load(json!([neg]), None);
    assert!(e.contains("experiments[0].channels[0].weight"), "{e}");
}

#[test]
fn a_missing_column_names_the_data_file() {
    let e = load(
        json!([{"output": "strut_force", "column": "no_such"}]),
        None,
    );
    assert!(e.contains("quarter_car_channels_synthetic.csv"), "{e}");
    assert!(e.contains("no_such"), "{e}");
    assert_eq!(load(json!([accel()]), None), "accepted");
}
