//! Genes: the free parameters the search moves, each in its own scale.
//!
//! The GA works in *scale space*: the value itself for [`Scale::Linear`], its
//! natural logarithm for [`Scale::Log`]. Operators see only scale space and its
//! bounds; genomes handed to a cost function are always values, clamped into
//! `[lower, upper]` so that `exp(ln x)` rounding can never step outside.

use serde::{Deserialize, Serialize};

use super::SearchError;
use crate::base::Scale;

/// One free parameter of the search.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct GeneSpec {
    /// Name used in reports and checkpoints.
    pub name: String,
    /// Smallest allowed value (in the parameter's own unit).
    pub lower: f64,
    /// Largest allowed value (in the parameter's own unit).
    pub upper: f64,
    /// Scale the search moves in.
    pub scale: Scale,
    /// Starting guess, if any; see [`crate::search::GeneticAlgorithm::init`].
    pub init: Option<f64>,
}

impl GeneSpec {
    /// A gene without starting guess.
    pub fn new(name: impl Into<String>, lower: f64, upper: f64, scale: Scale) -> Self {
        Self {
            name: name.into(),
            lower,
            upper,
            scale,
            init: None,
        }
    }

    /// The same gene with a starting guess.
    pub fn with_init(mut self, init: f64) -> Self {
        self.init = Some(init);
        self
    }

    /// Checks bounds, scale and starting guess.
    pub fn validate(&self) -> Result<(), SearchError> {
        let bad = |reason: String| SearchError::InvalidGene {
            name: self.name.clone(),
            reason,
        };
        if !self.lower.is_finite() || !self.upper.is_finite() {
            return Err(bad(format!(
                "bounds must be finite, found [{}, {}]",
                self.lower, self.upper
            )));
        }
        if self.lower > self.upper {
            return Err(bad(format!(
                "lower bound {} is above upper bound {}",
                self.lower, self.upper
            )));
        }
        if self.scale == Scale::Log && self.lower <= 0.0 {
            return Err(bad(format!(
                "log scale needs a positive range, found lower bound {}",
                self.lower
            )));
        }
        if let Some(init) = self.init
            && !(self.lower..=self.upper).contains(&init)
        {
            return Err(bad(format!(
                "initial value {init} is outside [{}, {}]",
                self.lower, self.upper
            )));
        }
        Ok(())
    }

    /// Bounds in scale space.
    pub fn scaled_bounds(&self) -> (f64, f64) {
        (self.to_scaled(self.lower), self.to_scaled(self.upper))
    }

    /// A value mapped into scale space.
    pub fn to_scaled(&self, value: f64) -> f64 {
        match self.scale {
            Scale::Linear => value,
            Scale::Log => value.ln(),
        }
    }

    /// The value at fraction `u` (0 at the lower bound, 1 at the upper) of the
    /// range in scale space: uniform `u` gives values uniform on a linear scale
    /// and log-uniform on a log scale.
    pub fn at_fraction(&self, u: f64) -> f64 {
        let (lo, hi) = self.scaled_bounds();
        self.to_value(lo + u * (hi - lo))
    }

    /// A scale-space coordinate mapped back to a value inside the bounds.
    pub fn to_value(&self, scaled: f64) -> f64 {
        let v = match self.scale {
            Scale::Linear => scaled,
            Scale::Log => scaled.exp(),
        };
        clamp_into(v, self.lower, self.upper)
    }
}

/// `x` clamped into `[lo, hi]`; NaN maps to the midpoint so that no operator
/// result can leave the bounds, whatever it computed.
pub fn clamp_into(x: f64, lo: f64, hi: f64) -> f64 {
    if x.is_nan() {
        0.5 * (lo + hi)
    } else {
        x.max(lo).min(hi)
    }
}

/// Maps a scale-space genome to values.
pub fn genome_values(genes: &[GeneSpec], scaled: &[f64]) -> Vec<f64> {
    genes
        .iter()
        .zip(scaled)
        .map(|(g, &x)| g.to_value(x))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn log_round_trip_stays_in_bounds() {
        let g = GeneSpec::new("k", 1e-3, 7.3e5, Scale::Log);
        let (lo, hi) = g.scaled_bounds();
        assert!(g.to_value(lo) >= g.lower && g.to_value(hi) <= g.upper);
        assert!((g.to_value(g.to_scaled(2.5)) - 2.5).abs() < 1e-12);
    }

    #[test]
    fn fractions_span_the_range_in_scale_space() {
        let g = GeneSpec::new("k", 1e2, 1e6, Scale::Log);
        let near = |a: f64, b: f64| (a / b - 1.0).abs() < 1e-12;
        assert!(near(g.at_fraction(0.0), 1e2));
        assert!(near(g.at_fraction(0.5), 1e4));
        assert!(near(g.at_fraction(1.0), 1e6) && g.at_fraction(1.0) <= 1e6);
        let l = GeneSpec::new("x", -1.0, 3.0, Scale::Linear);
        assert_eq!(l.at_fraction(0.25), 0.0);
    }

    #[test]
    fn validation_names_the_problem() {
        let e = GeneSpec::new("c", 0.0, 1.0, Scale::Log)
            .validate()
            .unwrap_err();
        assert!(e.to_string().contains("`c`") && e.to_string().contains("positive"));
        assert!(
            GeneSpec::new("m", 2.0, 1.0, Scale::Linear)
                .validate()
                .is_err()
        );
        let g = GeneSpec::new("m", 0.0, 1.0, Scale::Linear).with_init(3.0);
        assert!(g.validate().is_err());
    }

    #[test]
    fn clamp_handles_nan() {
        assert_eq!(clamp_into(f64::NAN, 0.0, 2.0), 1.0);
        assert_eq!(clamp_into(5.0, 0.0, 2.0), 2.0);
    }
}
