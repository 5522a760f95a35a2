//! Design points: each variable's grid of values, and the full product of
//! all of them.
//!
//! A grid is a list `{"values": [...]}`, a linear range `{"linear": [from,
//! to, n]}` (`n` values evenly spaced, both ends included) or a log range
//! `{"log": [from, to, n]}` (`n` values evenly spaced in `ln`, both ends
//! included, `from` and `to` > 0). The design points are every combination,
//! numbered from 0 in row-major order: the first variable (in the sweep
//! file's order) varies slowest, the last fastest.

use serde::Deserialize;

/// One variable's grid as the sweep file writes it.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields, rename_all = "snake_case")]
pub enum RawGrid {
    /// The values as listed.
    Values(Vec<f64>),
    /// `[from, to, n]`: `n` values evenly spaced from `from` to `to`.
    Linear((f64, f64, f64)),
    /// `[from, to, n]`: `n` values evenly spaced in log from `from` to `to`.
    Log((f64, f64, f64)),
}

/// Most values one variable's range may have.
pub const MAX_GRID_VALUES: usize = 1_000_000;

impl RawGrid {
    /// The grid's values, or what was expected and what was found (for the
    /// message).
    pub fn values(&self) -> Result<Vec<f64>, (String, String)> {
        let count = |n: f64| -> Result<usize, (String, String)> {
            if n.fract() == 0.0 && (1.0..=MAX_GRID_VALUES as f64).contains(&n) {
                Ok(n as usize)
            } else {
                Err((
                    format!("a count n of values, a whole number from 1 to {MAX_GRID_VALUES}"),
                    format!("n = {n}"),
                ))
            }
        };
        let finite = |v: f64| -> Result<f64, (String, String)> {
            if v.is_finite() {
                Ok(v)
            } else {
                Err(("finite values".into(), v.to_string()))
            }
        };
        match *self {
            Self::Values(ref v) => {
                if v.is_empty() {
                    return Err(("at least one value".into(), "[]".into()));
                }
                v.iter().map(|&x| finite(x)).collect()
            }
            Self::Linear((a, b, n)) => {
                let (a, b, n) = (finite(a)?, finite(b)?, count(n)?);
                Ok(spaced(a, b, n, |x| x, |x| x))
            }
            Self::Log((a, b, n)) => {
                let (a, b, n) = (finite(a)?, finite(b)?, count(n)?);
                if !(a > 0.0 && b > 0.0) {
                    return Err((
                        "a log range between values > 0".into(),
                        format!("[{a}, {b}, {n}]"),
                    ));
                }
                Ok(spaced(a, b, n, f64::ln, f64::exp))
            }
        }
    }
}

/// `n` values evenly spaced in `to(·)` from `a` to `b`, both ends exact.
fn spaced(a: f64, b: f64, n: usize, to: fn(f64) -> f64, from: fn(f64) -> f64) -> Vec<f64> {
    if n == 1 {
        return vec![a];
    }
    let (ta, tb) = (to(a), to(b));
    (0..n)
        .map(|i| match i {
            0 => a,
            _ if i == n - 1 => b,
            _ => from(ta + (tb - ta) * i as f64 / (n - 1) as f64),
        })
        .collect()
}

/// The full product of the variables' values.
#[derive(Debug, Clone, PartialEq)]
pub struct DesignGrid {
    /// Each variable's values, in the sweep file's order.
    pub axes: Vec<Vec<f64>>,
}

impl DesignGrid {
    /// The number of design points (the product of the axes' lengths), `None`
    /// when it overflows.
    pub fn points(&self) -> Option<usize> {
        self.axes
            .iter()
            .try_fold(1_usize, |n, a| n.checked_mul(a.len()))
    }

    /// The values of design point `i` (row-major: the last axis fastest).
    pub fn point(&self, i: usize) -> Vec<f64> {
        let mut rest = i;
        let mut out = vec![0.0; self.axes.len()];
        for (slot, axis) in out.iter_mut().zip(&self.axes).rev() {
            *slot = axis[rest % axis.len()];
            rest /= axis.len();
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ranges_include_both_ends() {
        let lin = RawGrid::Linear((1.0, 2.0, 5.0)).values().expect("valid");
        assert_eq!(lin, vec![1.0, 1.25, 1.5, 1.75, 2.0]);
        let log = RawGrid::Log((1e3, 1e5, 3.0)).values().expect("valid");
        assert_eq!(log[0], 1e3);
        assert!((log[1] / 1e4 - 1.0).abs() < 1e-14);
        assert_eq!(log[2], 1e5);
    }

    #[test]
    fn bad_ranges_are_refused() {
        assert!(RawGrid::Linear((1.0, 2.0, 2.5)).values().is_err());
        assert!(RawGrid::Log((0.0, 2.0, 3.0)).values().is_err());
        assert!(RawGrid::Values(vec![]).values().is_err());
    }

    #[test]
    fn the_last_axis_varies_fastest() {
        let g = DesignGrid {
            axes: vec![vec![1.0, 2.0], vec![10.0, 20.0, 30.0]],
        };
        assert_eq!(g.points(), Some(6));
        assert_eq!(g.point(0), vec![1.0, 10.0]);
        assert_eq!(g.point(1), vec![1.0, 20.0]);
        assert_eq!(g.point(3), vec![2.0, 10.0]);
        assert_eq!(g.point(5), vec![2.0, 30.0]);
    }
}
