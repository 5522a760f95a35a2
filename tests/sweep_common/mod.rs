//! Helpers shared by the sweep tests: a one-mass rig whose responses have
//! closed forms.
#![allow(dead_code, reason = "each test file uses a different subset")]

/// One mass on a spring and a viscous damper to ground, a unit force step
/// from t = 0, its displacement the output `x`.
pub const SDOF_STEP_RIG: &str = r#"{
  "id": "sdof_step",
  "doc": "One mass on a spring and a viscous damper, a unit force step from t = 0.",
  "params": [
    {"name": "m", "unit": "kg", "doc": "mass"},
    {"name": "k", "unit": "N/m", "doc": "stiffness"},
    {"name": "c", "unit": "N·s/m", "doc": "damping"}
  ],
  "nodes": [{"name": "mass", "mass": "m"}],
  "elements": [{"name": "support", "between": ["ground", "mass"],
    "spring": {"law": "linear", "k": "k"}, "damper": {"law": "viscous", "c": "c"}}],
  "drives": [{"node": "mass", "law": {"type": "force_table", "t": [0.0, 10.0], "value": [1.0, 1.0]}}],
  "outputs": [{"name": "x", "unit": "m", "sum": [{"displacement": "mass"}]}],
  "reach": {"elongation": 0.01, "rate": 1.0}
}"#;
