//! The one-line verdict at the top of a job's summary, and the warnings of
//! a polish that did not give the intervals what they assume: one that
//! stopped short of convergence, and starts that ended apart beyond the
//! intervals at the same cost.

use serde::Serialize;

use super::outputs::{ExperimentFit, ParamSummary, SYSTEMATIC_MISFIT};
use crate::search::{AtBound, PolishOutcome, PolishStop, Uncertainty, Z95};

/// The fit's cost over the noise floor up to which it is at the floor (the
/// record's noise estimate is good to a few per cent).
pub const AT_FLOOR: f64 = 1.1;

/// The verdict in `result.json`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Verdict {
    /// The line the summary starts with: `"at the noise floor (1.01×); 5 of 6
    /// parameters determined; flagged: …"`.
    pub line: String,
    /// The joint fitness over the noise floor the records' noise implies
    /// (about 1 at the floor); `null` where a record's noise is unknown.
    pub cost_over_noise_floor: Option<f64>,
    /// Whether that is at most `AT_FLOOR` (1.1×).
    pub at_noise_floor: Option<bool>,
    /// Free parameters the data determine (after the polish; 0 without one).
    pub determined: usize,
    /// Free parameters.
    pub free: usize,
    /// What the job flags, briefly (the warnings say why and what to do).
    pub flags: Vec<String>,
}

impl Verdict {
    /// The verdict of a job whose joint fitness is `ratio` times the noise
    /// floor, with `parameters`, the polish (where one ran) and `flags`.
    pub fn new(
        ratio: Option<f64>,
        parameters: &[ParamSummary],
        polished: bool,
        flags: Vec<String>,
    ) -> Self {
        let free = parameters.iter().filter(|p| p.free).count();
        let determined = parameters
            .iter()
            .filter(|p| p.free && p.determined == Some(true))
            .count();
        let floor = match ratio {
            Some(k) if k <= AT_FLOOR => format!("at the noise floor ({k:.2}×)"),
            Some(k) if k <= SYSTEMATIC_MISFIT => format!("above the noise floor ({k:.2}×)"),
            Some(k) => {
                format!("far above the noise floor ({k:.3}×): the misfit is more than noise")
            }
            None => "noise floor unknown (a record too short to estimate its noise)".into(),
        };
        let counted = if polished {
            format!("{determined} of {free} parameters determined")
        } else {
            format!("{free} parameters fitted, none checked (no polish, no intervals)")
        };
        let flagged = flagged_text(&flags);
        Self {
            line: format!("{floor}; {counted}; {flagged}"),
            cost_over_noise_floor: ratio,
            at_noise_floor: ratio.map(|k| k <= AT_FLOOR),
            determined,
            free,
            flags,
        }
    }
}

/// The verdict line's last part: `"nothing flagged"` or `"flagged: a; b"`.
fn flagged_text(flags: &[String]) -> String {
    if flags.is_empty() {
        "nothing flagged".to_string()
    } else {
        format!("flagged: {}", flags.join("; "))
    }
}

/// A written verdict (`result.json`'s `verdict`) with its flags that start
/// with `prefix` replaced by `flags`, and its line to match (what
/// `rigfit validate` does to a finished job's verdict).
pub fn replace_flags(verdict: &mut serde_json::Value, prefix: &str, flags: &[String]) {
    let mut all = strings(&verdict["flags"]);
    all.retain(|f| !f.starts_with(prefix));
    all.extend(flags.iter().cloned());
    if let Some(line) = verdict["line"].as_str() {
        let head = ["; nothing flagged", "; flagged: "]
            .iter()
            .filter_map(|m| line.find(m))
            .min()
            .map_or(line, |k| &line[..k]);
        verdict["line"] = format!("{head}; {}", flagged_text(&all)).into();
    }
    verdict["flags"] = all.into();
}

/// The strings of a JSON array (none for anything else).
fn strings(v: &serde_json::Value) -> Vec<String> {
    v.as_array()
        .map(|a| {
            a.iter()
                .filter_map(|f| f.as_str().map(String::from))
                .collect()
        })
        .unwrap_or_default()
}

/// The verdict flags of the profiles start with this (`"profile of c1:
/// one-sided"`); a new profile replaces them.
pub const PROFILE_FLAG_PREFIX: &str = "profile of ";

impl Verdict {
    /// The verdict with its flags that start with `prefix` replaced by
    /// `flags`, and its line to match ([`replace_flags`]).
    pub fn replace_flags(&mut self, prefix: &str, flags: &[String]) {
        let mut json = serde_json::json!({"line": self.line, "flags": self.flags});
        replace_flags(&mut json, prefix, flags);
        if let Some(line) = json["line"].as_str() {
            self.line = line.to_string();
        }
        self.flags = strings(&json["flags"]);
    }
}

/// `warnings` with the profiles' earlier warnings (`"<name>: profile …"`
/// of one of their parameters) replaced by theirs.
pub fn replace_profile_warnings(
    warnings: &[String],
    profiles: &crate::search::ProfileOutcome,
) -> Vec<String> {
    let ours = |w: &String| {
        profiles
            .parameters
            .iter()
            .any(|p| w.starts_with(&format!("{}: profile ", p.name)))
    };
    let mut all: Vec<String> = warnings.iter().filter(|w| !ours(w)).cloned().collect();
    all.extend(profiles.warnings());
    all
}

/// A written `result.json` (parsed) with `profiles` set, and the profiles'
/// warnings and verdict flags in place of any earlier ones.
pub fn attach_profiles(result: &mut serde_json::Value, profiles: &crate::search::ProfileOutcome) {
    let warnings = strings(&result["warnings"]);
    result["warnings"] = replace_profile_warnings(&warnings, profiles).into();
    replace_flags(
        &mut result["verdict"],
        PROFILE_FLAG_PREFIX,
        &profiles.flags(),
    );
    result["profiles"] = serde_json::to_value(profiles).expect("the profiles serialise");
}

/// The short flags of a job: the polish's stop, parameters at a bound,
/// experiments whose residual is not noise, and `more` (the checks'
/// own, already short).
pub fn flags(
    polish: Option<&PolishOutcome>,
    parameters: &[ParamSummary],
    experiments: &[ExperimentFit],
    more: impl IntoIterator<Item = String>,
) -> Vec<String> {
    let mut out = Vec::new();
    if let Some(p) = polish.filter(|p| p.stop.short()) {
        out.push(format!("polish {}", p.stop));
    }
    out.extend(more);
    for p in parameters.iter().filter(|p| p.free) {
        if let Some(b) = p.at_bound {
            let side = match b {
                AtBound::Lower => "lower",
                AtBound::Upper => "upper",
            };
            out.push(format!("{} at its {side} bound", p.name));
        }
    }
    for e in experiments {
        if e.residual_autocorrelation
            .is_some_and(|r| r > super::outputs::NOT_WHITE)
        {
            out.push(format!("{}: residual not white", e.name));
        }
        if e.integration_error.above_allowed() {
            out.push(format!("{}: integration error", e.name));
        }
    }
    out
}

/// The warning of a polish that stopped short of convergence, with what to
/// do; `max_iterations` is the campaign's `search.polish.max_iterations`.
pub fn polish_stop_warning(
    p: &PolishOutcome,
    max_iterations: usize,
    method: crate::search::Method,
) -> Option<String> {
    let searched = method.label();
    let assumes = "the intervals assume the optimum was reached, and they can be far too narrow \
                   or off-centre where it was not";
    Some(match p.stop {
        PolishStop::Converged => return None,
        PolishStop::MaxIterations if max_iterations == 0 => format!(
            "the polish ran no iteration (\"search\": {{\"polish\": {{\"max_iterations\": 0}}}}): \
             the result is the {searched}'s best, and {assumes}; allow the polish iterations (default 30) \
             and run again"
        ),
        PolishStop::MaxIterations => {
            let best = if p.best_converged {
                "the best start had converged, but a start still moving may have ended lower"
            } else {
                "the start that gave the result had not converged"
            };
            format!(
                "the polish stopped at its iteration limit ({max_iterations}) with {} of {} \
                 starts still moving ({best}): {assumes}; raise \"search\": {{\"polish\": \
                 {{\"max_iterations\": {}}}}} and run again",
                p.unconverged_starts,
                p.starts.len(),
                (2 * max_iterations).max(60)
            )
        }
        PolishStop::Interrupted => format!(
            "the polish was interrupted after {} iterations: the result is where it stopped, and \
             {assumes}; run the job again (or --resume) to let it finish",
            p.iterations
        ),
        PolishStop::NoStart => format!(
            "every start of the polish blew up: the result is the {searched}'s best and has no \
             intervals"
        ),
    })
}

/// The warning where a polished start other than the best ended outside the
/// best's 95 % interval in some parameter at a cost within what a point on
/// that interval's edge costs (`Z95² s²` above the best): the cost is not
/// the one quadratic bowl the intervals assume (several minima as good as
/// each other, or a flat valley), so they are too narrow.
pub fn starts_beyond_intervals(p: &PolishOutcome, u: &Uncertainty) -> Option<String> {
    let edge = Z95 * Z95 * u.residual_variance;
    let mut outside: Vec<String> = Vec::new();
    for (i, s) in p.starts.iter().enumerate() {
        if i == p.best_start
            || s.genome.len() != u.genes.len()
            || !(s.polished.is_finite() && s.polished - p.best_cost <= edge)
        {
            continue;
        }
        for (g, &v) in u.genes.iter().zip(&s.genome) {
            if let Some([lo, hi]) = g.interval_95
                && (v < lo || v > hi)
            {
                outside.push(format!(
                    "start {i} ended at {} = {v:.6e}, outside [{lo:.6e}, {hi:.6e}]",
                    g.name
                ));
                break;
            }
        }
    }
    if outside.is_empty() {
        return None;
    }
    Some(format!(
        "the polish's starts disagree beyond their intervals at the same cost ({}): the cost has \
         several equally good minima or a flat valley, and the 95 % intervals, which assume one \
         quadratic bowl, are too narrow",
        outside.join("; ")
    ))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::search::{GeneSpec, Method, StartReport};
    use nalgebra::DMatrix;

    fn outcome(stop: PolishStop, starts: Vec<StartReport>) -> PolishOutcome {
        PolishOutcome {
            best_genome: vec![1.0, 2.0],
            best_cost: 1.0,
            best_start: 0,
            starts,
            iterations: 5,
            evaluations: 50,
            wall_time_s: 0.1,
            stop,
            unconverged_starts: 1,
            best_converged: false,
            history: Vec::new(),
            uncertainty: None,
        }
    }

    fn start(polished: f64, genome: [f64; 2]) -> StartReport {
        StartReport {
            initial: 2.0,
            polished,
            genome: genome.to_vec(),
        }
    }

    #[test]
    fn every_stop_short_of_convergence_is_said_with_what_to_do() {
        let starts = vec![start(1.0, [1.0, 2.0])];
        let p = outcome(PolishStop::Converged, starts.clone());
        assert_eq!(polish_stop_warning(&p, 30, Method::Ga), None);
        let p = outcome(PolishStop::MaxIterations, starts.clone());
        let w = polish_stop_warning(&p, 30, Method::Ga).unwrap();
        assert!(w.starts_with("the polish stopped at its iteration limit (30) with 1 of 1"));
        assert!(w.contains("\"max_iterations\": 60"), "{w}");
        let w = polish_stop_warning(&p, 0, Method::Ga).unwrap();
        assert!(w.contains("ran no iteration"), "{w}");
        for stop in [PolishStop::Interrupted, PolishStop::NoStart] {
            assert!(stop.short());
            assert!(polish_stop_warning(&outcome(stop, starts.clone()), 30, Method::Ga).is_some());
        }
    }

    #[test]
    fn starts_apart_beyond_the_intervals_at_the_same_cost_are_said() {
        let genes = [
            GeneSpec::new("a", -10.0, 10.0, crate::base::Scale::Linear),
            GeneSpec::new("b", -10.0, 10.0, crate::base::Scale::Linear),
        ];
        // Standard errors 0.01 (s² = 1e-4 over 1001 residuals, JᵀJ = I).
        let u = Uncertainty::at(
            &genes,
            &[1.0, 2.0],
            &DMatrix::identity(2, 2),
            1e-4 * 999.0,
            1001,
        );
        let edge = Z95 * Z95 * u.residual_variance;
        // Inside the intervals, or outside at a higher cost: nothing.
        let near = outcome(
            PolishStop::Converged,
            vec![start(1.0, [1.0, 2.0]), start(1.0, [1.01, 2.0])],
        );
        assert_eq!(starts_beyond_intervals(&near, &u), None);
        let worse = outcome(
            PolishStop::Converged,
            vec![start(1.0, [1.0, 2.0]), start(1.0 + 2.0 * edge, [1.5, 2.0])],
        );
        assert_eq!(starts_beyond_intervals(&worse, &u), None);
        // Outside at the same cost: said, naming the start and the gene.
        let apart = outcome(
            PolishStop::Converged,
            vec![start(1.0, [1.0, 2.0]), start(1.0 + 0.5 * edge, [1.0, 2.5])],
        );
        let w = starts_beyond_intervals(&apart, &u).unwrap();
        assert!(w.contains("start 1 ended at b = 2.5"), "{w}");
    }

    #[test]
    fn replaced_flags_keep_the_others_and_the_line_follows() {
        let v = Verdict::new(Some(1.02), &[], true, vec!["k at its lower bound".into()]);
        let mut json = serde_json::to_value(&v).unwrap();
        let new = ["validation w: 3.0× the fit's misfit".to_string()];
        replace_flags(&mut json, "validation ", &new);
        replace_flags(&mut json, "validation ", &new);
        assert_eq!(json["flags"].as_array().unwrap().len(), 2);
        let line = json["line"].as_str().unwrap();
        assert!(
            line.ends_with("flagged: k at its lower bound; validation w: 3.0× the fit's misfit"),
            "{line}"
        );
        let clean = Verdict::new(Some(1.02), &[], true, Vec::new());
        let mut json = serde_json::to_value(&clean).unwrap();
        replace_flags(&mut json, "validation ", &[]);
        assert_eq!(json["line"], clean.line.as_str());
    }
}
