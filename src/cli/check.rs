//! `rigfit check`: a campaign and its data validated without running the
//! job, with the run length, the memory and the search time it would take.
//! Where nothing has measured the job on this machine, `check` races the two
//! paths as `run --backend auto` would and caches the choice (or, with no GPU,
//! times the CPU lanes alone on a few of its candidates): a fraction of a
//! second to a second or two, unless `--no-measure` asks for assumed rates.

use std::fmt::Write as _;
use std::path::PathBuf;

use anyhow::Result;
use clap::Args;

use super::campaign_file::load_for_check;
use super::options::RunLengthArgs;
use super::output::Output;
use rigfit::campaign::Campaign;
use rigfit::job::memory::{self, GPU_STEPS_PER_S_ASSUMED, MemoryEstimate, human_bytes};

/// `rigfit check`.
#[derive(Debug, Args)]
pub struct CheckArgs {
    /// Campaign JSON file.
    pub campaign: PathBuf,
    #[command(flatten)]
    pub run_length: RunLengthArgs,
    /// Estimate the job's time at assumed rates instead of measuring them
    /// where nothing has measured this job here (a race of the two paths as
    /// `run --backend auto` races them, or the CPU lanes alone without a GPU:
    /// a fraction of a second to a second or two).
    #[arg(long)]
    pub no_measure: bool,
}

/// The job's wall time, estimated from its steps: the GA's candidates on
/// every core and at [`GPU_STEPS_PER_S_ASSUMED`] on the GPU, then the polish's
/// ([`memory::TimeEstimate`]).
/// Where `run --backend auto` has measured this job on this machine before
/// (src/job/backend/), its measured rates take the assumed ones' place;
/// where a run of it searched on every CPU core here, the rate that search
/// ran at takes the CPU's, and the GPU's start-up the trial timed takes
/// [`memory::STARTUP_SECONDS`]'s place. Where `auto` has measured nothing and `measure`
/// asks, `check` races the two paths as `auto` would
/// ([`rigfit::job::backend::AutoPick::Race`], whatever the job's length;
/// `trial` in the JSON) and caches what it measured for the next run; with
/// no GPU to race (`gpu_trial_skipped`, with why), the CPU lanes alone are
/// timed on a few of the job's candidates where no run has measured them
/// ([`rigfit::job::backend::cpu_trial`]: `cpu_trial`, or `cpu_trial_skipped`
/// with why).
fn search_estimate(c: &Campaign, steps_per_candidate: f64, measure: bool) -> serde_json::Value {
    use rigfit::eval::{Backend, PrecisionChoice};
    use rigfit::job::backend::{self, AutoPick};
    let cores = rigfit::eval::all_cores();
    let precision = format!("{:?}", c.solver.precision).to_lowercase();
    let mut measured = backend::cached(&backend::auto_key(c, &precision));
    let mut raced = None;
    let mut gpu_skipped = None;
    if !measure || measured.is_some() {
        // Nothing to race.
    } else if c.solver.backend == Backend::Cpu {
        gpu_skipped = Some("the campaign's solver.backend is \"cpu\"".to_string());
    } else if let Some((_, named_by)) = rigfit::gpu::requested_adapter(None) {
        gpu_skipped = Some(format!(
            "{named_by} names the adapter `run` takes, unmeasured"
        ));
    } else {
        let opened = backend::open_job_evaluator(
            c,
            Backend::Auto,
            c.solver.precision,
            None,
            0,
            AutoPick::Race,
        );
        match opened {
            Ok(je) => match je.trial {
                // Too long a job for even a shortened race: nothing measured.
                Some(t) if t.skipped => gpu_skipped = Some(t.line()),
                Some(t) => {
                    raced = (!t.cached).then(|| t.clone());
                    measured = Some(t);
                }
                None => {
                    let notes: Vec<String> = je.notes.iter().map(|n| n.to_string()).collect();
                    gpu_skipped = Some(if notes.is_empty() {
                        "no GPU to race".to_string()
                    } else {
                        notes.join("; ")
                    });
                }
            },
            Err(e) => gpu_skipped = Some(format!("{e:#}")),
        }
    }
    let cpu_precision = match c.solver.precision {
        PrecisionChoice::F32 => "f32",
        PrecisionChoice::Auto | PrecisionChoice::F64 => "f64",
    };
    let observed = backend::observed_cpu_rate(c, cpu_precision);
    let mut e = memory::TimeEstimate::of(c, steps_per_candidate, cores, GPU_STEPS_PER_S_ASSUMED);
    if let Some(t) = &measured {
        e = e.with_cpu_rate(t.cpu_rate).with_gpu_rate(t.gpu_rate);
        if let Some(s) = t.gpu_startup_s {
            e = e.with_gpu_startup(s);
        }
    }
    if let Some(rate) = observed {
        e = e.with_cpu_rate(rate);
        e.cpu_rate_observed = true;
    }
    let mut trial = None;
    let mut skipped = None;
    if measure && measured.is_none() && observed.is_none() {
        match backend::cpu_trial(c, cpu_precision == "f32") {
            Ok(t) => {
                e = e.with_cpu_rate(t.rate);
                trial = Some(t);
            }
            Err(why) => skipped = Some(why.to_string()),
        }
    }
    let mut v = serde_json::to_value(e).unwrap_or_default();
    v["measured"] = serde_json::Value::Bool(measured.is_some());
    if let Some(t) = raced {
        v["trial"] = serde_json::to_value(t).unwrap_or_default();
    }
    if let Some(why) = gpu_skipped {
        v["gpu_trial_skipped"] = serde_json::Value::String(why);
    }
    if let Some(t) = trial {
        v["cpu_trial"] = serde_json::to_value(t).unwrap_or_default();
    }
    if let Some(why) = skipped {
        v["cpu_trial_skipped"] = serde_json::Value::String(why);
    }
    v
}

/// Validates a campaign and its data.
pub fn check(args: &CheckArgs, out: &Output) -> Result<()> {
    let c = load_for_check(&args.campaign)?;
    // Every expression law over the rig's reach, with the parameters at the
    // campaign's bounds: one not finite there is refused before any work.
    for e in 0..c.problem.experiments.len() {
        let (lo, hi) = c.bounds(e);
        let file = format!("{} (rig {})", args.campaign.display(), c.model.id());
        rigfit::compile::front::finite::check_laws(&c.model.desc, &file, &[&lo, &hi])
            .map_err(|e| super::exit::BadInput(e.to_string()))?;
    }
    let length = c.check_run_length(args.run_length.max_steps)?;
    // The memory `run` will check, on the CPU and (where the rig has kernels)
    // on the GPU in f64, for the campaign's population.
    let cpu_memory = MemoryEstimate::of(&c, None);
    let gpu_memory = rigfit::gpu::kernel_groups(&c.problem)
        .is_ok()
        .then(|| MemoryEstimate::of(&c, Some(8)));
    let available = memory::available_memory();
    // A job `run` would refuse for its memory is not timed either.
    let fits = available.is_none_or(|a| cpu_memory.total <= a);
    let search = c
        .search_given
        .then(|| search_estimate(&c, length.steps_per_candidate, !args.no_measure && fits));
    out.json(&serde_json::json!({
        "campaign": c.name, "rig": c.model.id(), "experiments": c.problem.experiments.len(),
        "genes": c.genes.iter().map(|g| &g.name).collect::<Vec<_>>(),
        "substeps": c.solver.substeps, "warnings": c.warnings, "run_length": length,
        "memory": {"cpu": cpu_memory, "gpu": gpu_memory, "available_bytes": available},
        "search_estimate": search,
    }))?;
    let experiments = c.experiment_names().len();
    let runs = c.problem.experiments.len();
    let channels = if runs > experiments {
        format!(" ({runs} measured channels)")
    } else {
        String::new()
    };
    out.say(|| {
        let mut s = format!(
            "{}: valid — rig {}, {experiments} experiment(s){channels}, {} free parameter(s), {} ({})",
            args.campaign.display(),
            c.model.id(),
            c.genes.len(),
            rigfit::base::text::steps_per_sample(c.solver.substeps),
            c.solver.note
        );
        for e in &c.problem.experiments {
            let _ = write!(
                s,
                "\n  {}: {} samples at {:.3e} s, fit window samples {}..{}",
                e.name,
                e.measured.len(),
                e.dt,
                e.window.start,
                e.window.end
            );
        }
        for k in &c.model.desc.controllers {
            let states: Vec<&str> = k.states.iter().map(|x| x.name.as_str()).collect();
            let _ = write!(
                s,
                "\n  controller {} (\"{}\" experiments): sampled every {:e} s from {:e} s, held \
                 states {}, command {} pushing {}",
                k.name,
                k.mode,
                k.period,
                k.phase,
                states.join(", "),
                k.command,
                k.acts_on.node
            );
        }
        let _ = write!(
            s,
            "\n  one candidate: {:.3e} RK4 steps, about {} on one CPU core",
            length.steps_per_candidate,
            rigfit::campaign::human_duration(length.cpu_core_seconds_per_candidate)
        );
        for g in &c.genes {
            let _ = write!(
                s,
                "\n  free {} in [{:e}, {:e}] {} ({:?})",
                g.name, g.lower, g.upper, g.unit, g.scale
            );
        }
        if let Some(e) = &search {
            let f = |k: &str| e[k].as_f64().unwrap_or(0.0);
            let observed = e["cpu_rate_observed"].as_bool() == Some(true);
            // What `check`'s own race measured, where it raced.
            let raced = e.get("trial").map(|t| {
                format!(
                    "measured just now for this job, as `run --backend auto` measures them ({} \
                     of its candidates, {:.2} s; kept, so that its next run here takes no trial)",
                    t["candidates"],
                    t["trial_s"].as_f64().unwrap_or(0.0)
                )
            });
            let rates = if e["measured"].as_bool() == Some(true) {
                format!(
                    "about {} on the CPU (at {:.2e} candidate-steps/s), about {} on the GPU \
                     (at {:.2e}), the rates {}",
                    rigfit::campaign::human_duration(f("cpu_seconds")),
                    f("cpu_steps_per_s_assumed"),
                    rigfit::campaign::human_duration(f("gpu_seconds")),
                    f("gpu_steps_per_s_assumed"),
                    match (observed, raced) {
                        (true, None) => "its last search on the CPU ran at and `run --backend \
                                         auto` measured on the GPU for this job here"
                            .to_string(),
                        (true, Some(how)) => {
                            format!("its last search on the CPU ran at, and on the GPU {how}")
                        }
                        (false, Some(how)) => how,
                        (false, None) => {
                            "`run --backend auto` measured for this job here".to_string()
                        }
                    },
                )
            } else if let Some(t) = e.get("cpu_trial") {
                format!(
                    "about {} on the CPU (at {:.2e} candidate-steps/s, measured here in {:.2} s \
                     on {} of its candidates in {}), about {} on the GPU (at an assumed {:.0e} \
                     candidate-steps/s, lavapipe's f32 rate; a discrete GPU runs 10 to 100 times \
                     more); `run --backend auto` measures both (a job under {} s on its faster \
                     path runs on the CPU unmeasured)",
                    rigfit::campaign::human_duration(f("cpu_seconds")),
                    f("cpu_steps_per_s_assumed"),
                    t["trial_s"].as_f64().unwrap_or(0.0),
                    t["candidates"],
                    t["precision"].as_str().unwrap_or("f64"),
                    rigfit::campaign::human_duration(f("gpu_seconds")),
                    GPU_STEPS_PER_S_ASSUMED,
                    rigfit::job::backend::SHORT_JOB_SECONDS,
                )
            } else if observed {
                format!(
                    "about {} on the CPU (at {:.2e} candidate-steps/s, the rate its last search \
                     on every core here ran at), about {} on the GPU (at an assumed {:.0e} \
                     candidate-steps/s, lavapipe's f32 rate; a discrete GPU runs 10 to 100 times \
                     more)",
                    rigfit::campaign::human_duration(f("cpu_seconds")),
                    f("cpu_steps_per_s_assumed"),
                    rigfit::campaign::human_duration(f("gpu_seconds")),
                    GPU_STEPS_PER_S_ASSUMED,
                )
            } else {
                format!(
                    "about {} on the CPU ({} cores at an assumed {:.0e} steps/s each), about \
                     {} on the GPU (at an assumed {:.0e} candidate-steps/s, lavapipe's f32 rate; \
                     a discrete GPU runs 10 to 100 times more); `run --backend auto` measures \
                     both (a job under {} s on its faster path runs on the CPU unmeasured), and \
                     `check` uses its figures once it has",
                    rigfit::campaign::human_duration(f("cpu_seconds")),
                    f("cpu_cores"),
                    rigfit::campaign::CPU_STEPS_PER_S_PER_CORE,
                    rigfit::campaign::human_duration(f("gpu_seconds")),
                    GPU_STEPS_PER_S_ASSUMED,
                    rigfit::job::backend::SHORT_JOB_SECONDS,
                ) + &e["cpu_trial_skipped"]
                    .as_str()
                    .map(|why| format!(" (the CPU was not timed here: {why})"))
                    .unwrap_or_default()
            };
            let gpu_skipped = e["gpu_trial_skipped"]
                .as_str()
                .map(|why| format!("; the GPU was not timed here: {why}"))
                .unwrap_or_default();
            let _ = write!(
                s,
                "\n  the search: at most {:.3e} candidates ({} × {} generations), {:.3e} RK4 \
                 steps: {rates}{gpu_skipped}",
                f("candidates"),
                c.search.population,
                c.search.generations,
                f("steps"),
            );
            let _ = write!(s, "{}", memory::polish_estimate_text(e));
        }
        if c.search_given {
            let _ = write!(
                s,
                "\n  memory at population {}: about {} on the CPU",
                cpu_memory.population,
                human_bytes(cpu_memory.total)
            );
            if let Some(g) = &gpu_memory {
                let _ = write!(s, ", {} on the GPU (f64)", human_bytes(g.total));
            }
            if let Some(a) = available {
                let largest = gpu_memory.as_ref().unwrap_or(&cpu_memory).total;
                let _ = write!(s, "; {} available now", human_bytes(a));
                if largest > a {
                    s += " (run will refuse it: lower the population or pass --max-memory)";
                }
            }
        }
        s
    });
    Ok(())
}
