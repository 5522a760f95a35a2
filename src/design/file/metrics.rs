//! The sweep file's metrics: each `{"name", "metric", "output", …}` read and
//! validated against the rig (names, outputs, each kind's keys, a gate, a
//! formula's names).

use serde::Deserialize;

use super::super::DesignError;
use super::super::metrics::{Formula, Metric, MetricKind};
use crate::campaign::Campaign;

/// One metric as written.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawMetric {
    /// Its column in the table.
    pub name: String,
    /// What it computes.
    pub metric: MetricKind,
    /// The rig output it reads (not for an expression).
    #[serde(default)]
    pub output: Option<String>,
    /// The formula of an `"expression"` metric.
    #[serde(default)]
    pub expression: Option<String>,
    /// The reference output of `ringing`, `ringing_hz`.
    #[serde(default)]
    pub against: Option<String>,
    /// The moving average's width (s) that is the reference of `ringing`,
    /// `ringing_hz` without `against`.
    #[serde(default)]
    pub window_s: Option<f64>,
    /// The level of `first_crossing` (output's unit).
    #[serde(default)]
    pub threshold: Option<f64>,
    /// Read only the span where another output is near its largest (the
    /// plateau).
    #[serde(default)]
    pub gate: Option<RawGate>,
}

/// `"gate": {"output": name, "above": fraction}`: the span from the first to
/// the last sample where the output's magnitude is at least `above` times
/// its largest.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RawGate {
    /// The output that opens the gate.
    pub output: String,
    /// The fraction of its largest magnitude, in (0, 1].
    pub above: f64,
}

/// The metrics of the file, validated against the campaign's rig: names
/// unique and safe for a column, outputs the rig's, each kind's keys.
pub(super) fn read_metrics(
    raw: &[RawMetric],
    c: &Campaign,
    variables: &[String],
    dt: f64,
    invalid: &dyn Fn(String, String, String) -> DesignError,
) -> Result<Vec<Metric>, DesignError> {
    let outputs: Vec<String> = c.model.output_names().iter().map(|o| o.0.clone()).collect();
    let mut metrics = Vec::new();
    let mut columns: Vec<&str> = vec!["point"];
    columns.extend(variables.iter().map(String::as_str));
    for (i, m) in raw.iter().enumerate() {
        let at = |key: &str| format!("metrics[{i}].{key}");
        if m.name.is_empty()
            || !m
                .name
                .chars()
                .all(|ch| ch.is_ascii_alphanumeric() || "_.-".contains(ch))
        {
            return Err(invalid(
                at("name"),
                "a column name of letters, digits, '_', '.' or '-'".into(),
                crate::base::text::echo(&m.name),
            ));
        }
        if columns.contains(&m.name.as_str()) {
            return Err(invalid(
                at("name"),
                "a name not yet taken by `point`, a variable or another metric".into(),
                format!("'{}'", m.name),
            ));
        }
        columns.push(&m.name);
        let output_of = |key: &str, name: &str| {
            outputs.iter().position(|o| o == name).ok_or_else(|| {
                invalid(
                    at(key),
                    format!("an output of rig {} ({})", c.model.id(), outputs.join(", ")),
                    format!("'{name}'"),
                )
            })
        };
        if m.metric == MetricKind::Expression {
            metrics.push(formula_metric(m, i, &metrics, variables, invalid)?);
            continue;
        }
        if m.expression.is_some() {
            return Err(invalid(
                at("expression"),
                "an expression only with \"metric\": \"expression\"".into(),
                "an expression".into(),
            ));
        }
        let Some(output_name) = &m.output else {
            return Err(invalid(
                at("output"),
                format!(
                    "the output it reads, of rig {} ({})",
                    c.model.id(),
                    outputs.join(", ")
                ),
                "none".into(),
            ));
        };
        let output = output_of("output", output_name)?;
        let against = m
            .against
            .as_deref()
            .map(|a| output_of("against", a))
            .transpose()?;
        let reference = m.metric.uses_reference();
        if !reference && (m.against.is_some() || m.window_s.is_some()) {
            let key = if m.against.is_some() {
                "against"
            } else {
                "window_s"
            };
            return Err(invalid(
                at(key),
                "no reference: only ringing and ringing_hz compare with one".into(),
                "a reference".into(),
            ));
        }
        let window_samples = match (reference, against, m.window_s) {
            (true, Some(_), Some(_)) => {
                return Err(invalid(
                    at("window_s"),
                    "either \"against\" or \"window_s\", not both".into(),
                    "both".into(),
                ));
            }
            (true, None, None) => {
                return Err(invalid(
                    at("against"),
                    "a reference: \"against\": another output, or \"window_s\": a moving \
                     average's width (s)"
                        .into(),
                    "neither".into(),
                ));
            }
            (true, None, Some(w)) => {
                let n = (w / dt).round();
                if !(n >= 3.0 && n.is_finite()) {
                    return Err(invalid(
                        at("window_s"),
                        format!(
                            "a width (s) of at least 3 samples (≥ {:e} s at dt = {dt:e} s)",
                            3.0 * dt
                        ),
                        w.to_string(),
                    ));
                }
                Some((n as usize) | 1)
            }
            _ => None,
        };
        let threshold = match (m.metric, m.threshold) {
            (MetricKind::FirstCrossing, Some(t)) if t.is_finite() => Some(t),
            (MetricKind::FirstCrossing, t) => {
                return Err(invalid(
                    at("threshold"),
                    "a finite level (output's unit) that first_crossing looks for".into(),
                    t.map_or_else(|| "none".into(), |t| t.to_string()),
                ));
            }
            (_, Some(_)) => {
                return Err(invalid(
                    at("threshold"),
                    "no threshold: only first_crossing takes one".into(),
                    "a threshold".into(),
                ));
            }
            (_, None) => None,
        };
        let gate = match &m.gate {
            None => None,
            Some(g) => {
                if !(g.above > 0.0 && g.above <= 1.0) {
                    return Err(invalid(
                        at("gate.above"),
                        "a fraction in (0, 1] of the gate output's largest magnitude".into(),
                        g.above.to_string(),
                    ));
                }
                Some((output_of("gate.output", &g.output)?, g.above))
            }
        };
        metrics.push(Metric {
            name: m.name.clone(),
            kind: m.metric,
            output,
            against,
            window_samples,
            threshold,
            gate,
            formula: None,
        });
    }
    if metrics.is_empty() {
        return Err(invalid(
            "metrics".into(),
            "at least one metric".into(),
            "[]".into(),
        ));
    }
    Ok(metrics)
}

/// An `"expression"` metric (`metrics[i]`): its formula parsed, every name
/// it reads one of the metrics before it or a design variable.
fn formula_metric(
    m: &RawMetric,
    i: usize,
    before: &[Metric],
    variables: &[String],
    invalid: &dyn Fn(String, String, String) -> DesignError,
) -> Result<Metric, DesignError> {
    let at = |key: &str| format!("metrics[{i}].{key}");
    for (key, given) in [
        ("output", m.output.is_some()),
        ("against", m.against.is_some()),
        ("window_s", m.window_s.is_some()),
        ("threshold", m.threshold.is_some()),
        ("gate", m.gate.is_some()),
    ] {
        if given {
            return Err(invalid(
                at(key),
                format!("no \"{key}\": an expression reads the metrics before it"),
                format!("\"{key}\""),
            ));
        }
    }
    let Some(text) = &m.expression else {
        return Err(invalid(
            at("expression"),
            "a formula of the metrics before it (\"100 * ring / peak\")".into(),
            "none".into(),
        ));
    };
    let expr = crate::compile::front::expr::parse(text).map_err(|e| {
        invalid(
            at("expression"),
            format!("a formula ({} at character {})", e.message, e.column),
            crate::base::text::echo(text),
        )
    })?;
    let mut used = Vec::new();
    expr.names(&mut used);
    let mut names = Vec::new();
    for (n, column) in used {
        let found = match before.iter().position(|x| x.name == n) {
            Some(k) => Ok(k),
            None => match variables.iter().position(|v| *v == n) {
                Some(j) => Err(j),
                None => {
                    let mut known: Vec<&str> = before.iter().map(|x| x.name.as_str()).collect();
                    known.extend(variables.iter().map(String::as_str));
                    return Err(invalid(
                        at("expression"),
                        format!(
                            "names of the metrics before it or of design variables ({})",
                            known.join(", ")
                        ),
                        format!("'{n}' at character {column}"),
                    ));
                }
            },
        };
        names.push((n, found));
    }
    Ok(Metric {
        name: m.name.clone(),
        kind: MetricKind::Expression,
        output: 0,
        against: None,
        window_samples: None,
        threshold: None,
        gate: None,
        formula: Some(Formula { expr, names }),
    })
}
