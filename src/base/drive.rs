//! How an experiment drives the rig.

use serde::{Deserialize, Serialize};

/// A piecewise-linear function of time, held constant beyond its ends.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PiecewiseLinear {
    /// Breakpoint times (s), strictly increasing.
    pub t: Vec<f64>,
    /// Values at the breakpoints.
    pub value: Vec<f64>,
}

impl PiecewiseLinear {
    /// Value at time `t`: linear between breakpoints, the end values beyond them.
    pub fn at(&self, t: f64) -> f64 {
        let n = self.t.len();
        if n == 0 {
            return 0.0;
        }
        if t <= self.t[0] {
            return self.value[0];
        }
        if t >= self.t[n - 1] {
            return self.value[n - 1];
        }
        let i = self.t.partition_point(|&x| x <= t) - 1;
        let w = (t - self.t[i]) / (self.t[i + 1] - self.t[i]);
        self.value[i] + w * (self.value[i + 1] - self.value[i])
    }
}

/// The actuator's drive mode for one experiment.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Drive {
    /// Prescribed displacement from the model's velocity and ramp parameters.
    #[default]
    Velocity,
    /// Actuator mass driven by a force table (t in s, force in N); zero for t < 0.
    Force(PiecewiseLinear),
}

impl Drive {
    /// The force table of a [`Drive::Force`].
    pub fn force_table(&self) -> Option<&PiecewiseLinear> {
        match self {
            Self::Force(t) => Some(t),
            Self::Velocity => None,
        }
    }
}
