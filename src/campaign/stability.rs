//! Choosing (or refusing) the number of RK4 steps per sample interval.
//!
//! Classic RK4 is stable for real eigenvalues while `h·|λ| < 2.785` and for
//! imaginary ones while `h·|λ| < 2.828` (issue 6). The model bounds `|λ|` over the
//! free parameters' ranges with [`crate::model::CompiledRig::omega_bound`]; we require
//! `h·ω_bound ≤` [`STABILITY_LIMIT`] = 2.0, a margin of about 30 % for the
//! looseness of nonlinear springs beyond their linearisation.
//!
//! A stable step is not yet an accurate one: `"auto"` then estimates the
//! integration error of output 0 by step doubling with the f64 reference at
//! the initial parameters ([`crate::model::step_error`]) and takes the
//! fewest substeps whose error is at most [`NOISE_FRACTION`] of the record's
//! noise (estimated from the record, [`crate::base::noise::noise_sigma`]) or the campaign's
//! `solver.tolerance`, up to [`ACCURACY_CAP_FACTOR`] times the stable count.

mod blame;

use super::raw::RawSubsteps;
use crate::base::text::echo_bare;
use crate::eval::{Backend, ExperimentData, PrecisionChoice};
use crate::model::CompiledRig;
use crate::model::step_error::{StepDoubling, StepStop};

/// Largest `h·ω_bound` accepted (RK4's own limit is about 2.8).
pub const STABILITY_LIMIT: f64 = 2.0;

/// Most substeps `"auto"` will choose (or a campaign may ask for) before the
/// campaign is refused.
pub const MAX_AUTO_SUBSTEPS: usize = 10_000;

/// The integration error `"auto"` allows, as a fraction of the record's noise
/// (without a `solver.tolerance`), and the fraction of the fit's residual RMS
/// above which a finished job warns of it.
pub const NOISE_FRACTION: f64 = 0.01;

/// `"auto"` aims at this fraction of the integration error it allows, so that
/// the error stays within it where the step-doubling estimate, the record's
/// noise estimate or the fitted parameters (away from the initial ones the
/// step is chosen at) differ from the truth by up to this factor.
pub const ACCURACY_MARGIN: f64 = 0.5;

/// The smallest integration error `"auto"` asks for without a tolerance, as
/// a fraction of the record's standard deviation over the fit window: far
/// below any measured record's noise (a 24-bit converter resolves 6e-8 of its
/// range), it bounds the steps a record without noise asks for.
pub const SPREAD_FLOOR: f64 = 1e-6;

/// `"auto"` takes at most this many times the substeps stability needs for
/// accuracy (and warns when that is not enough): the search's cost grows with
/// the substeps, and 8 times the step cuts a fourth-order error 4096-fold.
pub const ACCURACY_CAP_FACTOR: usize = 8;

/// Longest reference run (RK4 steps) the step-doubling estimate takes; a
/// longer run keeps the stable step and says so. The f64 reference it runs
/// takes 5e5 to 7e5 steps/s on one core for the shipped rigs (a 2-core Xeon,
/// 2026-11-29), so a try's three runs (7/4 of this) take about 3 s at most;
/// at 2e7 a record starting at t = 1000 s (a 3.9e6-step prologue) held
/// `set_data` for 54 s. The shipped campaigns' longest run is 2e5.
pub const ESTIMATE_MAX_RUN_STEPS: f64 = 1e6;

/// The rig size [`ESTIMATE_MAX_RUN_STEPS`] is reckoned for, in states: the
/// reference's cost per step grows with the rig (a chain of 1 000 masses,
/// 2 001 states, took about 200 µs a step against 1.5–2 µs for the shipped
/// rigs' few), so a larger rig's estimate may take proportionally fewer
/// steps ([`estimate_max_steps`]): its work, not its steps, is bounded.
pub const ESTIMATE_REFERENCE_STATES: usize = 16;

/// The longest reference run the step-doubling estimate takes for a rig of
/// `states` states: [`ESTIMATE_MAX_RUN_STEPS`], scaled down for a rig larger
/// than [`ESTIMATE_REFERENCE_STATES`].
pub fn estimate_max_steps(states: usize) -> f64 {
    let size = states.max(ESTIMATE_REFERENCE_STATES) as f64;
    ESTIMATE_MAX_RUN_STEPS * ESTIMATE_REFERENCE_STATES as f64 / size
}

/// The campaign's `"solver"` object after validation.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct SolverSettings {
    /// RK4 steps per sample interval.
    pub substeps: usize,
    /// Evaluator choice.
    pub backend: Backend,
    /// GPU precision choice.
    pub precision: PrecisionChoice,
    /// Whether `substeps` was chosen automatically.
    pub auto: bool,
    /// How the step was chosen or checked: worst `h·ω`, experiment and limiting
    /// parameter, the integration error it leaves, for the log.
    pub note: String,
    /// `solver.tolerance`: the integration error of output 0 `"auto"` allows
    /// (output 0's unit); without it, [`NOISE_FRACTION`] of the record's noise.
    pub tolerance: Option<f64>,
    /// Per experiment, the integration error of output 0 (RMS over the fit
    /// window, output 0's unit) estimated by step doubling at the chosen
    /// substeps and the initial parameters; `None` where not estimated (an
    /// explicit count, a record without a noise level, a run too long).
    pub estimated_error: Vec<Option<f64>>,
}

/// A step chosen by [`choose`].
#[derive(Debug, Clone)]
pub(crate) struct Chosen {
    pub substeps: usize,
    pub auto: bool,
    pub note: String,
    /// Said once to the user: the cap held the error above its target.
    pub warning: Option<String>,
    pub estimated_error: Vec<Option<f64>>,
    pub tolerance: Option<f64>,
}

impl Chosen {
    /// The validated `"solver"` object.
    pub fn settings(&self, backend: Backend, precision: PrecisionChoice) -> SolverSettings {
        SolverSettings {
            substeps: self.substeps,
            backend,
            precision,
            auto: self.auto,
            note: self.note.clone(),
            tolerance: self.tolerance,
            estimated_error: self.estimated_error.clone(),
        }
    }
}

/// The tightest experiment: its index, ω bound (rad/s) and limiting parameter.
struct Worst {
    exp: usize,
    omega: f64,
    name: String,
    need: usize,
    /// `need` before it is held to a count, for a refusal.
    need_f: f64,
    /// The lightest node and its mass over the bounds, for a refusal.
    lightest: String,
}

/// The run's last model time with clock offset `offset` (s): what the drive
/// can reach bounds what the model must stay stable for.
fn run_end(x: &ExperimentData, offset: f64) -> f64 {
    x.t_first + x.window.end.saturating_sub(1) as f64 * x.dt + offset
}

/// The stability rule for one run of `x` over the parameters `lo..hi` with
/// clock offset `offset` (s): the run's frequency bound ω (rad/s), the law
/// that limits it, and the RK4 steps per sample `h·ω ≤` [`STABILITY_LIMIT`]
/// needs, rounded up but not yet held to a count (infinite or huge where
/// nothing can step it).
pub(crate) fn stability_need(
    model: &CompiledRig,
    x: &ExperimentData,
    lo: &[f64],
    hi: &[f64],
    offset: f64,
) -> (f64, String, f64) {
    let (omega, name) = model.omega_bound_in_run(lo, hi, &x.drive, run_end(x, offset));
    (omega, name, (omega * x.dt / STABILITY_LIMIT).ceil())
}

/// Substeps for `requested`, or the one-line reason it cannot work.
/// `bounds(e)` gives experiment `e`'s lower and upper parameter vectors,
/// `offset(e)` its latest clock offset (s), `initial(e)` the parameters and
/// offset the accuracy of `"auto"` is judged at (the initial values, free
/// ones mid-range); `genes` name a free mass's range in a refusal.
#[expect(
    clippy::too_many_arguments,
    reason = "the campaign's pieces the step depends on, each read by closure"
)]
pub(crate) fn choose(
    model: &CompiledRig,
    exps: &[ExperimentData],
    genes: &[super::Gene],
    bounds: impl Fn(usize) -> (Vec<f64>, Vec<f64>),
    offset: impl Fn(usize) -> f64,
    initial: impl Fn(usize) -> (Vec<f64>, f64),
    requested: RawSubsteps,
    tolerance: Option<f64>,
) -> Result<Chosen, String> {
    let mut worst: Option<Worst> = None;
    for (e, x) in exps.iter().enumerate() {
        let (lo, hi) = bounds(e);
        let off = offset(e);
        let (omega, name, need_f) = stability_need(model, x, &lo, &hi, off);
        let t_end = run_end(x, off);
        if !omega.is_finite() || need_f > MAX_AUTO_SUBSTEPS as f64 {
            // A mass at or below zero, or one so light that nothing can step
            // it, is the cause whatever stiffness the bound names.
            if let Some(cause) = mass_cause(model, genes, e, &lo, &hi, |lo| {
                let (w, _) = model.omega_bound_in_run(lo, &hi, &x.drive, t_end);
                w.is_finite() && (w * x.dt / STABILITY_LIMIT).ceil() <= MAX_AUTO_SUBSTEPS as f64
            }) {
                return Err(format!(
                    "experiment '{}': {cause}; the frequency bound is {}",
                    echo_bare(&x.name),
                    if omega.is_finite() {
                        format!(
                            "ω ≤ {omega:.3e} rad/s, too high to step at dt = {:e} s",
                            x.dt
                        )
                    } else {
                        "not finite".into()
                    }
                ));
            }
        }
        if !omega.is_finite() {
            return Err(format!(
                "experiment '{}': the frequency bound is not finite (limited by '{name}'{}); \
                 expected finite masses, stiffnesses and dampings",
                x.name,
                lightest(model, &lo)
            ));
        }
        let need = need_f.min(usize::MAX as f64).max(1.0) as usize;
        if worst.as_ref().is_none_or(|w| need > w.need) {
            worst = Some(Worst {
                exp: e,
                omega,
                name,
                need,
                need_f,
                lightest: lightest(model, &lo),
            });
        }
    }
    let w = worst.expect("at least one experiment");
    let x = &exps[w.exp];
    match requested {
        RawSubsteps::Auto => {
            if w.need > MAX_AUTO_SUBSTEPS {
                let need = if w.need_f < 1e9 {
                    format!("{}", w.need)
                } else {
                    format!("{:.1e}", w.need_f)
                };
                let (lo, hi) = bounds(w.exp);
                let t_end = run_end(x, offset(w.exp));
                let fix =
                    blame::remedy(model, genes, w.exp, x, (&lo, &hi, t_end), w.omega, &w.name);
                return Err(format!(
                    "\"auto\" would need {need} substeps (more than {MAX_AUTO_SUBSTEPS}) for \
                     experiment '{}': ω ≤ {:.3e} rad/s limited by '{}'{} at dt = {:e} s; {}",
                    x.name,
                    w.omega,
                    w.name,
                    w.lightest,
                    x.dt,
                    fix.unwrap_or_else(|| format!(
                        "use a sample interval ≤ {:.3e} s",
                        STABILITY_LIMIT * MAX_AUTO_SUBSTEPS as f64 / w.omega
                    ))
                ));
            }
            let hw = w.omega * x.dt / w.need as f64;
            let stable = format!(
                "h·ω ≤ {hw:.2} (limit {STABILITY_LIMIT}, RK4 diverges near 2.8), tightest in \
                 experiment '{}' where ω ≤ {:.3e} rad/s is limited by '{}' at dt = {:e} s",
                x.name, w.omega, w.name, x.dt
            );
            let acc = accurate(model, exps, &initial, w.need, tolerance);
            let n = acc.substeps;
            let note = if n == w.need {
                format!(
                    "substeps = {n} chosen automatically: {stable}; {}",
                    acc.words
                )
            } else {
                format!(
                    "substeps = {n} chosen automatically for accuracy: {}; stability alone \
                     needs {}: {stable}",
                    acc.words, w.need
                )
            };
            Ok(Chosen {
                substeps: n,
                auto: true,
                note,
                warning: acc.warning,
                estimated_error: acc.errors,
                tolerance,
            })
        }
        RawSubsteps::Count(n) if n > MAX_AUTO_SUBSTEPS as u64 => Err(format!(
            "expected at most {MAX_AUTO_SUBSTEPS} substeps, found {n}"
        )),
        RawSubsteps::Count(n) => {
            let n = n as usize;
            let hw = w.omega * x.dt / n as f64;
            if hw > STABILITY_LIMIT {
                let dt_ok = STABILITY_LIMIT * n as f64 / w.omega;
                let (lo, hi) = bounds(w.exp);
                let t_end = run_end(x, offset(w.exp));
                let fix =
                    blame::remedy(model, genes, w.exp, x, (&lo, &hi, t_end), w.omega, &w.name)
                        .map_or_else(String::new, |f| format!(", or {f}"));
                return Err(format!(
                    "expected a stable RK4 step (h·ω ≤ {STABILITY_LIMIT}), found substeps = {n} \
                     giving h·ω = {hw:.2} in experiment '{}': ω ≤ {:.3e} rad/s is limited by \
                     '{}'; use substeps ≥ {} (or \"auto\") or a sample interval ≤ {dt_ok:.3e} s{fix}",
                    x.name, w.omega, w.name, w.need
                ));
            }
            let note = format!(
                "substeps = {n} as requested: h·ω ≤ {hw:.2} (limit {STABILITY_LIMIT}), \
                 tightest in experiment '{}' limited by '{}'",
                x.name, w.name
            );
            Ok(Chosen {
                substeps: n,
                auto: false,
                note,
                warning: None,
                estimated_error: vec![None; exps.len()],
                tolerance,
            })
        }
    }
}

/// The integration error `"auto"` allows in experiment `x` (output 0's
/// unit) and how to say it: the tolerance, else [`NOISE_FRACTION`] of the
/// record's noise over the fit window, but never below [`SPREAD_FLOOR`] of the
/// record's spread (a record without noise, whose noise estimate is the
/// signal's own smoothness, would otherwise ask for any number of steps).
/// `None` for a constant record (a simulation's placeholder) or one too short
/// for a noise estimate.
pub(crate) fn target(
    x: &ExperimentData,
    tolerance: Option<f64>,
    unit: &str,
) -> Option<(f64, String)> {
    if let Some(t) = tolerance {
        return Some((t, format!("solver.tolerance = {t:.3e} {unit}")));
    }
    let sigma = x.noise_estimate()?;
    let spread = (x.ss_tot() / x.window.len() as f64).sqrt();
    let floor = SPREAD_FLOOR * spread;
    let noise = NOISE_FRACTION * sigma;
    if noise >= floor && noise > 0.0 {
        Some((
            noise,
            format!(
                "{:.0} % of the record's noise, ≈ {sigma:.3e} {unit} estimated from the record",
                100.0 * NOISE_FRACTION
            ),
        ))
    } else if floor > 0.0 {
        Some((
            floor,
            format!(
                "{SPREAD_FLOOR:e} of the record's standard deviation {spread:.3e} {unit}, above \
                 {:.0} % of its noise estimate {sigma:.3e} {unit}",
                100.0 * NOISE_FRACTION
            ),
        ))
    } else {
        None
    }
}

/// What the accuracy part of `"auto"` chose.
struct Accurate {
    substeps: usize,
    words: String,
    warning: Option<String>,
    errors: Vec<Option<f64>>,
}

/// The fewest substeps from `stable` (up to [`ACCURACY_CAP_FACTOR`]`·stable`)
/// whose estimated integration error is at most every experiment's
/// [`target`], each experiment judged at `initial(e)`.
fn accurate(
    model: &CompiledRig,
    exps: &[ExperimentData],
    initial: &impl Fn(usize) -> (Vec<f64>, f64),
    stable: usize,
    tolerance: Option<f64>,
) -> Accurate {
    let names = model.output_names();
    let unit = |x: &ExperimentData| names.get(x.output).map_or("", |o| o.1.as_str());
    let cap = stable
        .saturating_mul(ACCURACY_CAP_FACTOR)
        .min(MAX_AUTO_SUBSTEPS)
        .max(stable);
    let at: Vec<(Vec<f64>, f64)> = (0..exps.len()).map(initial).collect();
    // A channel is judged on its own output: the rig compiled to score it.
    let scoring: Vec<Option<std::sync::Arc<CompiledRig>>> = exps
        .iter()
        .map(|x| {
            (x.output != 0).then(|| {
                model
                    .scoring(x.output)
                    .expect("a scoring rig compiled when the channel was read")
            })
        })
        .collect();
    let mut runs: Vec<StepDoubling<'_>> = exps
        .iter()
        .zip(&at)
        .zip(&scoring)
        .map(|((x, (p, off)), s)| {
            let model = s.as_deref().unwrap_or(model);
            StepDoubling::new(model, p, &x.drive, x.grid(*off, stable), x.window.clone())
        })
        .collect();
    let states = model.state_names().len();
    let max_steps = estimate_max_steps(states);
    let mut n = stable;
    // (experiment, error, target, target in words) of the experiment that set n.
    let mut setter: Option<(usize, f64, f64, String)> = None;
    let mut unjudged = Vec::new();
    let mut capped = None;
    for (e, (x, run)) in exps.iter().zip(&mut runs).enumerate() {
        let Some((t, words)) = target(x, tolerance, unit(x)) else {
            unjudged.push(format!(
                "'{}': no noise level in the record",
                echo_bare(&x.name)
            ));
            continue;
        };
        let c = run.choose(stable, cap, ACCURACY_MARGIN * t, max_steps);
        match c.stop {
            StepStop::TooLong => unjudged.push(format!(
                "'{}': a reference run at {} substeps would take {:.2e} RK4 steps (more than \
                 {max_steps:.2e} for a rig of {states} states)",
                echo_bare(&x.name),
                4 * c.substeps,
                run.steps_of(4 * c.substeps)
            )),
            StepStop::NotFinite => unjudged.push(format!(
                "'{}': the reference run at the initial parameters is not finite",
                echo_bare(&x.name)
            )),
            StepStop::Cap | StepStop::Tries if c.error.is_none_or(|err| err > t) => {
                let err = c.error.unwrap_or(f64::NAN);
                capped.get_or_insert((e, c.substeps, err, t, words.clone()));
            }
            StepStop::Cap | StepStop::Tries => {}
            StepStop::Met => {}
        }
        if (c.substeps > n || setter.is_none())
            && let Some(err) = c.error
        {
            setter = Some((e, err, t, words));
        }
        n = n.max(c.substeps);
    }
    // Every experiment's error at the substeps all of them take.
    let errors: Vec<Option<f64>> = exps
        .iter()
        .zip(&mut runs)
        .map(|(x, run)| {
            let judged = target(x, tolerance, unit(x)).is_some();
            (judged && run.steps_of(4 * n) <= max_steps)
                .then(|| run.error(n))
                .flatten()
        })
        .collect();
    let mut words = match &setter {
        Some((e, _, t, tw)) => format!(
            "integration error ≈ {:.2e} {unit} by step doubling at the initial parameters in \
             experiment '{}' (allowed {t:.2e} {unit}: {tw}; aimed at {:.0} % of it)",
            errors[*e].unwrap_or(f64::NAN),
            echo_bare(&exps[*e].name),
            100.0 * ACCURACY_MARGIN,
            unit = unit(&exps[*e]),
        ),
        None => "integration error not estimated".to_string(),
    };
    if !unjudged.is_empty() {
        words += &format!(
            " (not estimated for {}: the stable step is kept there)",
            unjudged.join("; ")
        );
    }
    let warning = capped.map(|(e, m, err, t, tw)| {
        let unit = unit(&exps[e]);
        format!(
            "experiment '{}': the RK4 step is not as fine as accuracy asks: at {} the integration \
             error is still ≈ {err:.2e} {unit}, against {t:.2e} {unit} allowed ({tw}); \"auto\" takes at most \
             {ACCURACY_CAP_FACTOR}× the {} substeps stability needs, so the fit may feel the \
             step: give solver.substeps a larger count, or a solver.tolerance you accept",
            echo_bare(&exps[e].name),
            crate::base::text::steps_per_sample(m),
            stable
        )
    });
    Accurate {
        substeps: n,
        words,
        warning,
        errors,
    }
}

/// A node mass that makes the frequency bound unusable, in words with where it
/// is set: one at or below zero (a rig file's number, in any stage of a mass
/// that switches when an element breaks, or a parameter's range), or a free
/// mass whose lower bound alone does it (`fixes(lo)` says whether `lo` with
/// that bound raised to the upper one gives a usable bound).
fn mass_cause(
    model: &CompiledRig,
    genes: &[super::Gene],
    e: usize,
    lo: &[f64],
    hi: &[f64],
    fixes: impl Fn(&[f64]) -> bool,
) -> Option<String> {
    use crate::rig::desc::Coef;
    // Each stage of a mass: its coefficient, its JSON path in the rig and when.
    fn stages<'c>(
        c: &'c Coef,
        path: String,
        when: String,
        out: &mut Vec<(&'c Coef, String, String)>,
    ) {
        match c {
            Coef::Switch(s) => {
                stages(
                    &s.before,
                    format!("{path}.before"),
                    format!(" before '{}' breaks", s.broken),
                    out,
                );
                stages(
                    &s.after,
                    format!("{path}.after"),
                    format!(" after '{}' breaks", s.broken),
                    out,
                );
            }
            _ => out.push((c, path, when)),
        }
    }
    let where_set = |name: &str| {
        let i = model.params().iter().position(|p| p.name == name)?;
        let g = genes
            .iter()
            .filter(|g| g.target == super::GeneTarget::Param(i))
            .find(|g| g.experiment == Some(e))
            .or_else(|| {
                genes
                    .iter()
                    .find(|g| g.target == super::GeneTarget::Param(i) && g.experiment.is_none())
            })?;
        Some(match g.experiment {
            Some(x) => format!("experiments[{x}].params.{name}"),
            None => format!("params.{name}"),
        })
    };
    for (k, node) in model.desc.nodes.iter().enumerate() {
        let mut all = Vec::new();
        stages(
            &node.mass,
            format!("nodes[{k}].mass"),
            String::new(),
            &mut all,
        );
        let node_name = echo_bare(&node.name);
        for (c, path, when) in all {
            match c {
                Coef::Number(v) if !(*v > 0.0 && v.is_finite()) => {
                    return Some(format!(
                        "node '{node_name}' has a mass of {v} kg{when} (rig '{}', {path}); \
                         expected a mass > 0 in every stage",
                        model.id()
                    ));
                }
                Coef::Param(name) => {
                    let i = model.params().iter().position(|p| p.name == *name)?;
                    let (a, b) = (lo[i], hi[i]);
                    let at = where_set(name);
                    if !(a > 0.0 && b.is_finite()) {
                        let at = at.map_or_else(
                            || format!("rig '{}', {path}", model.id()),
                            |p| format!("{p}.min"),
                        );
                        return Some(format!(
                            "node '{node_name}' has a mass '{name}'{when} that reaches {a:e} kg \
                             ({at}); expected a mass > 0"
                        ));
                    }
                    if a < b {
                        let mut raised = lo.to_vec();
                        raised[i] = b;
                        if fixes(&raised) {
                            let at = at.map_or_else(String::new, |p| format!(" ({p}.min)"));
                            return Some(format!(
                                "node '{node_name}' has a mass '{name}'{when} whose lower bound \
                                 {a:e} kg{at} is too light for any RK4 step; raise that bound \
                                 (the mass at {b:e} kg steps)"
                            ));
                        }
                    }
                }
                _ => {}
            }
        }
    }
    None
}

/// `, with the lightest node 'plate' at 1e-300 kg`: what a frequency bound is
/// inversely proportional to, for a refusal whose named parameter is a
/// stiffness or a damping. Empty for a rig without free nodes.
fn lightest(model: &CompiledRig, lo: &[f64]) -> String {
    use crate::rig::desc::Coef;
    fn least(model: &CompiledRig, c: &Coef, lo: &[f64]) -> f64 {
        match c {
            Coef::Number(v) => *v,
            Coef::Param(n) => model
                .params()
                .iter()
                .position(|p| p.name == *n)
                .map_or(f64::NAN, |i| lo[i]),
            Coef::Switch(s) => least(model, &s.before, lo).min(least(model, &s.after, lo)),
        }
    }
    model
        .desc
        .nodes
        .iter()
        .map(|n| (n, least(model, &n.mass, lo)))
        .min_by(|a, b| a.1.total_cmp(&b.1))
        .map_or_else(String::new, |(n, m)| {
            format!(
                ", with the lightest node '{}' at {m:e} kg",
                echo_bare(&n.name)
            )
        })
}
