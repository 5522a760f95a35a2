//! The sweep file's design variables: each a grid or a distribution, in the
//! file's order, and the design points they make (the grids' product, or
//! points drawn as `"sampling"` says).

use std::fmt;

use serde::Deserialize;
use serde::de::{MapAccess, Visitor};

use super::super::DesignError;
use super::super::grid::{DesignGrid, RawGrid};
use super::super::points::{Drawn, Points};
use super::super::sample::{Distribution, Method, unit_points};
use super::super::sobol::saltelli_design;
use super::{MAX_POINTS, RawSweep};

/// `{"name": grid, …}` in the file's order; a name given twice is refused.
#[derive(Debug)]
pub struct Variables(pub Vec<(String, RawVariable)>);

impl<'de> Deserialize<'de> for Variables {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        struct Ordered;
        impl<'de> Visitor<'de> for Ordered {
            type Value = Variables;
            fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                f.write_str("an object of parameter names and their grids")
            }
            fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<Variables, A::Error> {
                let mut out: Vec<(String, RawVariable)> = Vec::new();
                while let Some(key) = map.next_key::<String>()? {
                    if out.iter().any(|(k, _)| *k == key) {
                        return Err(serde::de::Error::custom(format!(
                            "variable '{key}' given twice"
                        )));
                    }
                    let grid = map.next_value::<RawVariable>()?;
                    out.push((key, grid));
                }
                Ok(Variables(out))
            }
        }
        d.deserialize_map(Ordered)
    }
}

/// `"sampling"`: how points are drawn from the variables' distributions.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawSampling {
    /// `"random"`, `"latin"` or `"sobol"`.
    pub method: Method,
    /// How many points (the base count `n` of Saltelli's design).
    pub points: u64,
    /// The draw's seed (default 1).
    #[serde(default = "super::one")]
    pub seed: u64,
    /// Sobol sensitivity indices of every metric: the points become
    /// Saltelli's design, `n (k + 2)` runs for `k` variables.
    #[serde(default)]
    pub indices: bool,
}

/// One variable as written: a grid or a distribution.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields, rename_all = "snake_case")]
pub enum RawVariable {
    /// `{"values": [...]}`.
    Values(Vec<f64>),
    /// `{"linear": [from, to, n]}`.
    Linear((f64, f64, f64)),
    /// `{"log": [from, to, n]}`.
    Log((f64, f64, f64)),
    /// `{"uniform": [lo, hi]}`.
    Uniform([f64; 2]),
    /// `{"loguniform": [lo, hi]}`.
    Loguniform([f64; 2]),
    /// `{"normal": [mean, sd]}`.
    Normal([f64; 2]),
    /// `{"lognormal": [median, sigma of ln]}`.
    Lognormal([f64; 2]),
    /// `{"triangular": [lo, mode, hi]}`.
    Triangular([f64; 3]),
}

impl RawVariable {
    /// The grid or the distribution.
    pub fn split(&self) -> Result<RawGrid, Distribution> {
        match self.clone() {
            Self::Values(v) => Ok(RawGrid::Values(v)),
            Self::Linear(r) => Ok(RawGrid::Linear(r)),
            Self::Log(r) => Ok(RawGrid::Log(r)),
            Self::Uniform(r) => Err(Distribution::Uniform(r)),
            Self::Loguniform(r) => Err(Distribution::Loguniform(r)),
            Self::Normal(r) => Err(Distribution::Normal(r)),
            Self::Lognormal(r) => Err(Distribution::Lognormal(r)),
            Self::Triangular(r) => Err(Distribution::Triangular(r)),
        }
    }
}

/// The design points the file asks for: the product of grids, or points
/// drawn from distributions as `"sampling"` says.
pub(super) fn design_points(
    raw: &RawSweep,
    invalid: &dyn Fn(String, String, String) -> DesignError,
) -> Result<Points, DesignError> {
    if raw.variables.0.is_empty() {
        return Err(invalid(
            "variables".into(),
            "at least one design variable {\"name\": grid or distribution}".into(),
            "{}".into(),
        ));
    }
    let split: Vec<(&String, Result<RawGrid, Distribution>)> = raw
        .variables
        .0
        .iter()
        .map(|(n, v)| (n, v.split()))
        .collect();
    let drawn = split.iter().filter(|(_, v)| v.is_err()).count();
    if drawn > 0 && drawn < split.len() {
        let (name, _) = split.iter().find(|(_, v)| v.is_ok()).expect("a grid");
        return Err(invalid(
            format!("variables.{name}"),
            "every variable a distribution (the others are) or every one a grid".into(),
            "a grid".into(),
        ));
    }
    if drawn == 0 {
        if raw.sampling.is_some() {
            return Err(invalid(
                "sampling".into(),
                "no \"sampling\" for a grid: it draws from distributions \
                 ({\"uniform\": [lo, hi]}, …)"
                    .into(),
                "\"sampling\"".into(),
            ));
        }
        let mut axes = Vec::new();
        for (name, g) in &split {
            let g = g.as_ref().expect("a grid");
            let values = g
                .values()
                .map_err(|(e, f)| invalid(format!("variables.{name}"), e, f))?;
            axes.push(values);
        }
        let grid = DesignGrid { axes };
        grid.points().filter(|&n| n <= MAX_POINTS).ok_or_else(|| {
            invalid(
                "variables".into(),
                format!("at most {MAX_POINTS} design points"),
                "more".into(),
            )
        })?;
        return Ok(Points::Grid(grid));
    }
    let Some(sampling) = &raw.sampling else {
        return Err(invalid(
            "sampling".into(),
            "{\"method\": \"random\", \"latin\" or \"sobol\", \"points\": n}: how to draw \
             the variables' distributions"
                .into(),
            "none".into(),
        ));
    };
    let mut distributions = Vec::new();
    for (name, d) in &split {
        let d = *d.as_ref().expect_err("a distribution");
        d.check()
            .map_err(|(e, f)| invalid(format!("variables.{name}"), e, f))?;
        distributions.push(d);
    }
    let k = distributions.len();
    let n = sampling.points;
    let rows = if sampling.indices {
        n.checked_mul(k as u64 + 2)
    } else {
        Some(n)
    };
    if n < 2 || rows.is_none_or(|r| r > MAX_POINTS as u64) {
        return Err(invalid(
            "sampling.points".into(),
            format!(
                "from 2 to {} points{}",
                if sampling.indices {
                    MAX_POINTS / (k + 2)
                } else {
                    MAX_POINTS
                },
                if sampling.indices {
                    " (Saltelli's design runs n (k + 2))"
                } else {
                    ""
                }
            ),
            n.to_string(),
        ));
    }
    let n = n as usize;
    let unit = if sampling.indices {
        saltelli_design(sampling.method, n, k, sampling.seed)
    } else {
        unit_points(sampling.method, n, k, sampling.seed)
    }
    .map_err(|why| invalid("sampling".into(), why, format!("{k} variables")))?;
    let values = unit
        .iter()
        .map(|u| {
            u.iter()
                .zip(&distributions)
                .map(|(&u, d)| d.quantile(u))
                .collect()
        })
        .collect();
    Ok(Points::Drawn(Drawn {
        method: sampling.method,
        base: n,
        seed: sampling.seed,
        distributions,
        values,
        indices: sampling.indices,
    }))
}
