//! The Sobol indices of every metric of a sweep drawn as Saltelli's design
//! ([`super::sobol`]), as a table: one row per metric and variable.

use super::file::Sweep;
use super::points::Points;
use super::run::Table;
use super::sobol::{Indices, sobol_indices};

/// Bootstrap resamples of the indices' 95 % intervals.
pub const RESAMPLES: usize = 1000;

/// Every metric's indices.
#[derive(Debug, Clone, PartialEq)]
pub struct IndexTable {
    /// The variables' names.
    pub variables: Vec<String>,
    /// Per metric: its name and its variables' indices, or why they are
    /// not defined (a metric that does not vary, or is undefined at most
    /// points).
    pub metrics: Vec<(String, Result<Vec<Indices>, String>)>,
}

/// The indices of `table`'s metrics, for a sweep drawn as Saltelli's design
/// (at the points' own values, not the draws of the calibration's
/// uncertainty).
pub fn sobol_table(sweep: &Sweep, table: &Table) -> Result<IndexTable, String> {
    let Points::Drawn(d) = &sweep.points else {
        return Err("the points are a grid, not drawn".into());
    };
    if !d.indices {
        return Err("the points are not Saltelli's design (\"indices\": false)".into());
    }
    let k = sweep.variables.len();
    let metrics = table
        .metrics
        .iter()
        .enumerate()
        .map(|(m, name)| {
            let y: Vec<f64> = table
                .rows
                .iter()
                .map(|r| r.metrics[m].unwrap_or(f64::NAN))
                .collect();
            (
                name.clone(),
                sobol_indices(&y, d.base, k, RESAMPLES, d.seed),
            )
        })
        .collect();
    Ok(IndexTable {
        variables: sweep.variables.clone(),
        metrics,
    })
}

impl IndexTable {
    /// As CSV: `metric,variable,first,first_lo,first_hi,total,total_lo,total_hi`,
    /// empty where a metric's indices are not defined.
    pub fn csv(&self) -> String {
        let mut s =
            String::from("metric,variable,first,first_lo,first_hi,total,total_lo,total_hi\n");
        for (m, ix) in &self.metrics {
            for (i, v) in self.variables.iter().enumerate() {
                match ix {
                    Ok(ix) => {
                        let x = &ix[i];
                        s.push_str(&format!(
                            "{m},{v},{},{},{},{},{},{}\n",
                            x.first,
                            x.first_95[0],
                            x.first_95[1],
                            x.total,
                            x.total_95[0],
                            x.total_95[1]
                        ));
                    }
                    Err(_) => s.push_str(&format!("{m},{v},,,,,,\n")),
                }
            }
        }
        s
    }

    /// As JSON: `{metric: {variable: {first, first_95, total, total_95}} or
    /// {"error": why}}`.
    pub fn json(&self) -> serde_json::Value {
        let mut out = serde_json::Map::new();
        for (m, ix) in &self.metrics {
            let v = match ix {
                Ok(ix) => serde_json::Value::Object(
                    self.variables
                        .iter()
                        .zip(ix)
                        .map(|(v, x)| (v.clone(), serde_json::json!(x)))
                        .collect(),
                ),
                Err(why) => serde_json::json!({"error": why}),
            };
            out.insert(m.clone(), v);
        }
        serde_json::Value::Object(out)
    }

    /// A few lines for a person: each metric's first-order and total
    /// indices by variable.
    pub fn text(&self) -> String {
        let mut s = String::from("Sobol indices (first-order S1, total ST, 95 % intervals):");
        for (m, ix) in &self.metrics {
            s.push_str(&format!("\n  {m}:"));
            match ix {
                Ok(ix) => {
                    for (v, x) in self.variables.iter().zip(ix) {
                        s.push_str(&format!(
                            "\n    {v:<16} S1 {:>6.3} [{:.3}, {:.3}]   ST {:>6.3} [{:.3}, {:.3}]",
                            x.first,
                            x.first_95[0],
                            x.first_95[1],
                            x.total,
                            x.total_95[0],
                            x.total_95[1]
                        ));
                    }
                }
                Err(why) => s.push_str(&format!(" not defined: {why}")),
            }
        }
        s
    }
}
