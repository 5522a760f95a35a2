//! Commands that read a campaign without searching: `simulate`, `modes`, `check`.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use anyhow::{Context, Result};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

use super::args::{CheckArgs, ModesArgs, SimulateArgs};
use super::{BadInput, Output};
use rigfit::base::fsutil::atomic_write;
use rigfit::base::noise::gaussian;
use rigfit::campaign::Campaign;
use rigfit::eval::{Problem, simulate_history};
use rigfit::job::memory::{self, MemoryEstimate, human_bytes};
use rigfit::model::modes::ModeReport;

fn load(path: &std::path::Path, params: Option<&std::path::Path>) -> Result<Campaign> {
    let mut c = Campaign::load(path)?;
    if let Some(p) = params {
        c.apply_param_file(p)?;
    }
    for w in &c.warnings {
        eprintln!("rigfit: warning: {w}");
    }
    Ok(c)
}

/// Simulates one experiment with the campaign's values and writes a CSV.
pub fn simulate(args: &SimulateArgs, out: &Output) -> Result<()> {
    let c = load(&args.campaign, args.params.as_deref())?;
    c.check_run_length(args.max_steps)?;
    check_out_file(&args.out, &c, args.params.as_deref(), args.overwrite)?;
    let e = match &args.experiment {
        None => 0,
        Some(name) => c.experiment_index(name).map_err(|names| {
            BadInput(format!(
                "--experiment `{name}`: the campaign has experiments {names}"
            ))
        })?,
    };
    if let Some(sigma) = args.noise {
        if !(sigma >= 0.0 && sigma.is_finite()) {
            return Err(BadInput(format!(
                "--noise {sigma}: expected a standard deviation ≥ 0 (N)"
            ))
            .into());
        }
    }
    let mut problem: Problem = c.problem.clone();
    let exp = &mut problem.experiments[e];
    if let Some(n) = args.samples {
        if n < 2 {
            return Err(BadInput(format!("--samples {n}: expected at least 2")).into());
        }
        exp.force.resize(n, 0.0);
        exp.window = 0..n;
    }
    let (params, offset) = (c.base[e].clone(), c.base_offsets[e]);
    let h = simulate_history(&problem, e, &params, offset);
    let exp = &problem.experiments[e];
    let mut s = String::new();
    match args.noise {
        Some(sigma) => {
            let mut rng = ChaCha8Rng::seed_from_u64(args.seed);
            let _ = writeln!(
                s,
                "# SYNTHETIC measurement: made by `rigfit simulate` from campaign {} (experiment {}),\n\
                 # rig {}, Gaussian noise sigma = {sigma} {} on output {}, seed {}. Not a measured record.",
                c.name,
                exp.name,
                c.model.id(),
                c.model.output_names()[0].1,
                c.model.output_names()[0].0,
                args.seed
            );
            s += "t_s,force_N\n";
            for (k, f) in h.outputs[0].iter().enumerate() {
                let t = exp.t_first + k as f64 * exp.dt;
                let _ = writeln!(s, "{t:.9e},{:.6e}", f + sigma * gaussian(&mut rng));
            }
        }
        None => {
            s += "t_s";
            for (name, unit) in c.model.output_names() {
                let _ = write!(s, ",{name}_{unit}");
            }
            for name in c.model.state_names() {
                let _ = write!(s, ",{name}");
            }
            s.push('\n');
            for k in 0..h.t.len() {
                let _ = write!(s, "{:.9e}", h.t[k]);
                for o in h.outputs.iter().chain(&h.states) {
                    let _ = write!(s, ",{:.9e}", o[k]);
                }
                s.push('\n');
            }
        }
    }
    atomic_write(&args.out, s.as_bytes())
        .with_context(|| format!("writing `{}`", args.out.display()))?;
    // Output 0 is the fitted one, in the rig's own name and unit.
    let (name, unit) = c.model.output_names()[0];
    let peak = h.outputs[0].iter().fold(0.0_f64, |m, f| m.max(f.abs()));
    out.json(&serde_json::json!({
        "out": args.out, "experiment": exp.name, "samples": h.t.len(),
        "peak": {"output": name, "unit": unit, "abs_max": peak},
    }))?;
    out.say(|| {
        format!(
            "simulated {} ({} samples, {} RK4 steps per sample): largest |{name}| {peak:.4e} {unit} → {}",
            exp.name,
            h.t.len(),
            problem.substeps,
            args.out.display()
        )
    });
    Ok(())
}

/// Refuses an `--out` file that is one of the job's inputs, or that exists
/// without `--overwrite`.
fn check_out_file(
    out: &Path,
    c: &Campaign,
    params: Option<&Path>,
    overwrite: bool,
) -> Result<(), BadInput> {
    let Ok(meta) = std::fs::metadata(out) else {
        return Ok(());
    };
    let target = out.canonicalize().ok();
    let input = c
        .inputs
        .iter()
        .map(PathBuf::as_path)
        .chain(params)
        .find(|p| p.canonicalize().ok() == target);
    if let Some(input) = input {
        return Err(BadInput(format!(
            "--out `{}` is the input file `{}`; rigfit never writes over its inputs",
            out.display(),
            input.display()
        )));
    }
    if !meta.is_file() {
        return Err(BadInput(format!(
            "--out `{}`: expected a file name, found an existing folder or device",
            out.display()
        )));
    }
    if !overwrite {
        return Err(BadInput(format!(
            "--out `{}` exists; pass --overwrite to replace it",
            out.display()
        )));
    }
    Ok(())
}

/// Prints the natural frequencies and mode shapes of the linearised rig.
pub fn modes(args: &ModesArgs, out: &Output) -> Result<()> {
    let c = load(&args.campaign, args.params.as_deref())?;
    let mut reports = Vec::new();
    for (e, exp) in c.problem.experiments.iter().enumerate() {
        let lin = c.model.linearise(&c.base[e], &exp.drive);
        let report = ModeReport::new(&lin).context("modal analysis")?;
        reports.push((exp.name.clone(), report));
    }
    let about = c.model.linearisation_point();
    out.json(&serde_json::json!(
        reports
            .iter()
            .map(|(n, r)| serde_json::json!({"experiment": n, "linearised": about, "modes": r}))
            .collect::<Vec<_>>()
    ))?;
    out.say(|| {
        let mut s = String::new();
        for (name, r) in &reports {
            let _ = writeln!(s, "experiment {name}: {about}");
            let _ = writeln!(s, "{r}");
        }
        s.trim_end().to_string()
    });
    Ok(())
}

/// Candidate-steps per second `check` assumes for the GPU path: lavapipe's
/// f32 kernels on two cores measure about 1.2e8 (README, throughput); a
/// discrete GPU runs one to two orders of magnitude more, so on one the
/// estimate is an upper bound.
const GPU_STEPS_PER_S_ASSUMED: f64 = 1e8;

/// The search's wall time, estimated from its steps: population × generations
/// candidates (an upper bound: elites are not evaluated again) at
/// `CPU_STEPS_PER_S_PER_CORE` on every core, and at
/// [`GPU_STEPS_PER_S_ASSUMED`] on the GPU.
fn search_estimate(c: &rigfit::campaign::Campaign, steps_per_candidate: f64) -> serde_json::Value {
    let candidates = (c.search.population * c.search.generations) as f64;
    let steps = candidates * steps_per_candidate;
    let cores = std::thread::available_parallelism().map_or(1, usize::from);
    let cpu_rate = rigfit::campaign::CPU_STEPS_PER_S_PER_CORE * cores as f64;
    serde_json::json!({
        "candidates": candidates, "steps": steps,
        "cpu_cores": cores, "cpu_steps_per_s_assumed": cpu_rate, "cpu_seconds": steps / cpu_rate,
        "gpu_steps_per_s_assumed": GPU_STEPS_PER_S_ASSUMED,
        "gpu_seconds": steps / GPU_STEPS_PER_S_ASSUMED,
    })
}

/// Validates a campaign and its data.
pub fn check(args: &CheckArgs, out: &Output) -> Result<()> {
    let c = load(&args.campaign, None)?;
    let length = c.check_run_length(args.max_steps)?;
    let search = c
        .search_given
        .then(|| search_estimate(&c, length.steps_per_candidate));
    // The memory `run` will check, on the CPU and (where the rig has kernels)
    // on the GPU in f64, for the campaign's population.
    let cpu_memory = MemoryEstimate::of(&c, None);
    let gpu_memory = rigfit::gpu::kernel_groups(&c.problem)
        .is_ok()
        .then(|| MemoryEstimate::of(&c, Some(8)));
    let available = memory::available_memory();
    out.json(&serde_json::json!({
        "campaign": c.name, "rig": c.model.id(), "experiments": c.problem.experiments.len(),
        "genes": c.genes.iter().map(|g| &g.name).collect::<Vec<_>>(),
        "substeps": c.solver.substeps, "warnings": c.warnings, "run_length": length,
        "memory": {"cpu": cpu_memory, "gpu": gpu_memory, "available_bytes": available},
        "search_estimate": search,
    }))?;
    out.say(|| {
        let mut s = format!(
            "{}: valid — rig {}, {} experiment(s), {} free parameter(s), {} RK4 steps per sample ({})",
            args.campaign.display(),
            c.model.id(),
            c.problem.experiments.len(),
            c.genes.len(),
            c.solver.substeps,
            c.solver.note
        );
        for e in &c.problem.experiments {
            let _ = write!(
                s,
                "\n  {}: {} samples at {:.3e} s, fit window samples {}..{}",
                e.name,
                e.force.len(),
                e.dt,
                e.window.start,
                e.window.end
            );
        }
        let _ = write!(
            s,
            "\n  one candidate: {:.3e} RK4 steps, about {} on one CPU core",
            length.steps_per_candidate,
            rigfit::campaign::human_duration(length.cpu_core_seconds_per_candidate)
        );
        for g in &c.genes {
            let _ = write!(s, "\n  free {} in [{:e}, {:e}] {} ({:?})", g.name, g.lower, g.upper, g.unit, g.scale);
        }
        if let Some(e) = &search {
            let f = |k: &str| e[k].as_f64().unwrap_or(0.0);
            let _ = write!(
                s,
                "\n  the search: at most {:.3e} candidates ({} × {} generations), {:.3e} RK4 \
                 steps: about {} on the CPU ({} cores at an assumed {:.0e} steps/s each), about \
                 {} on the GPU (at an assumed {:.0e} candidate-steps/s, lavapipe's f32 rate; a \
                 discrete GPU runs 10 to 100 times more)",
                f("candidates"),
                c.search.population,
                c.search.generations,
                f("steps"),
                rigfit::campaign::human_duration(f("cpu_seconds")),
                f("cpu_cores"),
                rigfit::campaign::CPU_STEPS_PER_S_PER_CORE,
                rigfit::campaign::human_duration(f("gpu_seconds")),
                GPU_STEPS_PER_S_ASSUMED
            );
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
