//! Shared builders for the campaign tests: a campaign shaped like the shipped
//! example and uniformly sampled CSV text.

#![allow(dead_code, reason = "each test file uses a different subset")]

use std::path::{Path, PathBuf};

use serde_json::{Value, json};

/// CSV text with two comment lines, a `t_s,force_N` header and `n` samples of
/// `dt` starting at `t0`.
pub fn csv(n: usize, dt: f64, t0: f64) -> String {
    let mut s =
        String::from("# synthetic test record\n# columns: time (s), force (N)\nt_s,force_N\n");
    for k in 0..n {
        let t = t0 + k as f64 * dt;
        s.push_str(&format!("{t:e},{}\n", 1000.0 * (k as f64 * 0.01).sin()));
    }
    s
}

/// A campaign shaped like `campaigns/aa2024_t3_synthetic.json`: one experiment
/// `v2` reading `v2.csv`, shared free `k1` and `c1`, its own free `k_lin`.
pub fn example() -> Value {
    json!({
        "name": "aa2024-t3-synthetic",
        "description": "test campaign",
        "rig": "tensile4",
        "params": {
            "m1": 7.9, "m2": 0.14, "m3": 0.48,
            "k1": {"min": 2e9, "max": 3e10, "scale": "log", "init": 8e9},
            "c1": {"min": 1e4, "max": 3e6},
            "c1_post": 9.22e3,
            "k3": 4.4e8,
            "slack_a": 4.43e3, "slack_b": 4.87e5, "slack_c": 1.94e7,
            "k4_lin": 1.19e8, "c4": 1.57e4, "gap": 1.87e-5,
            "k_lin": 8.63e7, "e_yield": 5.4e-5, "e_fracture": 1e-3,
            "a0": 4.56e3, "a1": 1.97e6, "a2": -9.26e8, "a3": 1.36e11
        },
        "experiments": [{
            "name": "v2",
            "data": {"file": "v2.csv", "time_column": "t_s", "force_column": "force_N"},
            "drive": "velocity",
            "fit_window": {"start": 0.0, "end": 2.5e-4},
            "offset": 0.0,
            "weight": 1.0,
            "params": {"velocity": 2.0, "k_lin": {"min": 3e7, "max": 3e8}}
        }],
        "solver": {"substeps": "auto", "backend": "auto", "precision": "auto"},
        "search": {"population": 64, "generations": 5, "seed": 1},
        "output": "results/aa2024"
    })
}

/// Writes `campaign.json` and the named data files into `dir`; returns the
/// campaign path.
pub fn write(dir: &Path, campaign: &str, data: &[(&str, &str)]) -> PathBuf {
    for (name, text) in data {
        std::fs::write(dir.join(name), text).unwrap();
    }
    let path = dir.join("campaign.json");
    std::fs::write(&path, campaign).unwrap();
    path
}

/// Sets the value at a JSON pointer (creating object keys as needed).
pub fn set(v: &mut Value, pointer: &str, value: Value) {
    let (parent, key) = pointer.rsplit_once('/').unwrap();
    let target = v
        .pointer_mut(parent)
        .unwrap_or_else(|| panic!("no {parent}"));
    match target {
        Value::Object(m) => {
            m.insert(key.to_string(), value);
        }
        Value::Array(a) => a[key.parse::<usize>().unwrap()] = value,
        _ => panic!("{parent} is not a container"),
    }
}

/// Removes the key at a JSON pointer.
pub fn remove(v: &mut Value, pointer: &str) {
    let (parent, key) = pointer.rsplit_once('/').unwrap();
    v.pointer_mut(parent)
        .unwrap()
        .as_object_mut()
        .unwrap()
        .remove(key);
}
