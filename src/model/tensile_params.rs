//! The tensile4 parameter table: names, units, scopes, defaults and search
//! scales, in the order of every parameter vector, with the reference values.

use super::{ParamInfo, ParamScope, Scale};

const fn p(
    name: &'static str,
    unit: &'static str,
    doc: &'static str,
    scope: ParamScope,
    default: Option<f64>,
    scale: Scale,
) -> ParamInfo {
    ParamInfo {
        name,
        unit,
        doc,
        scope,
        default,
        scale,
    }
}

use ParamScope::{Experiment as E, Rig as R};
use Scale::{Linear as Lin, Log};

/// Parameter order of every tensile parameter vector (and of the GPU block).
pub static PARAMS: [ParamInfo; 27] = [
    p("m1", "kg", "load-cell mass", R, None, Log),
    p("m2", "kg", "specimen-side (grip) mass", R, None, Log),
    p("m3", "kg", "sliding-bar mass", R, None, Log),
    p(
        "m4",
        "kg",
        "actuator mass (force drive only)",
        R,
        Some(37.4),
        Log,
    ),
    p("k1", "N/m", "load-cell stiffness", R, None, Log),
    p(
        "c1",
        "N·s/m",
        "load-cell damping before fracture",
        R,
        None,
        Log,
    ),
    p(
        "c1_post",
        "N·s/m",
        "load-cell damping after fracture",
        R,
        None,
        Log,
    ),
    p("k_lin", "N/m", "specimen elastic stiffness", E, None, Log),
    p(
        "e_yield",
        "m",
        "elongation where the polynomial branch starts",
        E,
        None,
        Lin,
    ),
    p(
        "a0",
        "N",
        "specimen polynomial coefficient of e^0",
        E,
        Some(0.0),
        Lin,
    ),
    p(
        "a1",
        "N/m",
        "specimen polynomial coefficient of e^1",
        E,
        Some(0.0),
        Lin,
    ),
    p(
        "a2",
        "N/m^2",
        "specimen polynomial coefficient of e^2",
        E,
        Some(0.0),
        Lin,
    ),
    p(
        "a3",
        "N/m^3",
        "specimen polynomial coefficient of e^3",
        E,
        Some(0.0),
        Lin,
    ),
    p(
        "a4",
        "N/m^4",
        "specimen polynomial coefficient of e^4",
        E,
        Some(0.0),
        Lin,
    ),
    p(
        "a5",
        "N/m^5",
        "specimen polynomial coefficient of e^5",
        E,
        Some(0.0),
        Lin,
    ),
    p(
        "e_fracture",
        "m",
        "elongation at which the specimen breaks; omitted or null: it never breaks",
        E,
        Some(f64::INFINITY),
        Lin,
    ),
    p("c2", "N·s/m", "specimen damping", E, Some(0.0), Lin),
    p("k3", "N/m", "sliding-bar (fixture) stiffness", R, None, Log),
    p("c3", "N·s/m", "sliding-bar damping", R, Some(0.0), Lin),
    p(
        "slack_a",
        "N/m",
        "slack-adapter exponential law: a",
        R,
        None,
        Log,
    ),
    p(
        "slack_b",
        "1/m",
        "slack-adapter exponential law: b",
        R,
        None,
        Log,
    ),
    p(
        "slack_c",
        "N/m",
        "slack-adapter exponential law: c (linear part)",
        R,
        None,
        Lin,
    ),
    p(
        "k4_lin",
        "N/m",
        "slack-adapter stiffness once fully engaged",
        R,
        None,
        Log,
    ),
    p(
        "c4",
        "N·s/m",
        "slack-adapter damping while engaged",
        R,
        None,
        Lin,
    ),
    p(
        "gap",
        "m",
        "slack-adapter free play before engagement",
        R,
        None,
        Lin,
    ),
    p(
        "velocity",
        "m/s",
        "actuator target velocity (velocity drive)",
        E,
        None,
        Lin,
    ),
    p(
        "ramp",
        "m",
        "actuator ramp length r (0: step to full velocity)",
        E,
        Some(0.0),
        Lin,
    ),
];

/// Index of each parameter in [`PARAMS`].
pub mod ix {
    #![allow(missing_docs)]
    pub const M1: usize = 0;
    pub const M2: usize = 1;
    pub const M3: usize = 2;
    pub const M4: usize = 3;
    pub const K1: usize = 4;
    pub const C1: usize = 5;
    pub const C1_POST: usize = 6;
    pub const K_LIN: usize = 7;
    pub const E_YIELD: usize = 8;
    pub const A0: usize = 9;
    pub const E_FRACTURE: usize = 15;
    pub const C2: usize = 16;
    pub const K3: usize = 17;
    pub const C3: usize = 18;
    pub const SLACK_A: usize = 19;
    pub const SLACK_B: usize = 20;
    pub const SLACK_C: usize = 21;
    pub const K4_LIN: usize = 22;
    pub const C4: usize = 23;
    pub const GAP: usize = 24;
    pub const VELOCITY: usize = 25;
    pub const RAMP: usize = 26;
}

/// The reference values of the published AA2024-T3 calibration (velocity 2 m/s).
pub const REFERENCE: [f64; 27] = [
    7.9, 0.14, 0.48, 37.4, 8.4e9, 5.51e5, 9.22e3, 8.63e7, 5.4e-5, 4.56e3, 1.97e6, -9.26e8, 1.36e11,
    0.0, 0.0, 1e-3, 0.0, 4.4e8, 0.0, 4.43e3, 4.87e5, 1.94e7, 1.19e8, 1.57e4, 1.87e-5, 2.0, 1.76e-6,
];
