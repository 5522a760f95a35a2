//! A rig of any size for the tests that grow one: a chain of masses.

use serde_json::{Value, json};

/// A chain of `n` masses from ground, springs and dampers between, driven
/// at its far end.
pub fn chain(n: usize) -> Value {
    let nodes: Vec<Value> = (0..n)
        .map(|i| json!({"name": format!("n{i}"), "mass": "m"}))
        .collect();
    let elements: Vec<Value> = (0..n)
        .map(|i| {
            let a = if i == 0 {
                "ground".to_string()
            } else {
                format!("n{}", i - 1)
            };
            json!({"name": format!("e{i}"), "between": [a, format!("n{i}")],
                   "spring": {"law": "linear", "k": "k"}, "damper": {"law": "viscous", "c": "c"}})
        })
        .collect();
    json!({
        "id": "chain",
        "params": [{"name": "m", "unit": "kg"}, {"name": "k", "unit": "N/m"}, {"name": "c", "unit": "N·s/m"}],
        "nodes": nodes, "elements": elements,
        "drives": [{"node": format!("n{}", n - 1), "law": {"type": "sine", "quantity": "force", "amplitude": 1.0, "frequency": 1.0}}],
        "outputs": [{"name": "x_end", "unit": "m", "sum": [{"displacement": format!("n{}", n - 1)}]}]
    })
}
