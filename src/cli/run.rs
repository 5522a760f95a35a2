//! `rigfit run`: the calibration job.

use std::fmt::Write as _;
use std::path::{Component, Path, PathBuf};
use std::process::ExitCode;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};

use anyhow::{Context, Result};

use super::args::{BackendArg, PrecisionArg, RunArgs};
use super::{EXIT_INTERRUPTED, Output};
use rigfit::campaign::Campaign;
use rigfit::eval::{Backend, CpuEvaluator, EvalError, PrecisionChoice};
use rigfit::job::memory::{self, MemoryEstimate, human_bytes};
use rigfit::job::{self, FolderMode, JobError, JobOptions, JobSummary, OutputFolder};
use rigfit::search::SearchError;

/// How to get the GPU path when `auto` fell back to the CPU.
const GPU_HINT: &str = "for the GPU path install a Vulkan driver (Debian: \
    `apt-get install mesa-vulkan-drivers` for the software adapter lavapipe, or your GPU vendor's driver)";

/// Loads, validates, runs and reports one calibration job.
pub fn run(a: &RunArgs, out: &Output) -> Result<ExitCode> {
    let mut c = Campaign::load(&a.campaign)?;
    c.require_search()?;
    if let Some(n) = a.population {
        c.search.population = n;
    }
    if let Some(n) = a.generations {
        c.search.generations = n;
    }
    if let Some(s) = a.seed {
        c.search.seed = s;
    }
    if let Some(t) = a.target_fitness {
        c.search.target_fitness = Some(t);
    }
    c.search.validate().map_err(|e| {
        // Blame the flag that set the value, not the campaign file.
        let flag = match e.field {
            "population" => a.population.map(|n| format!("--population {n}")),
            "generations" => a.generations.map(|n| format!("--generations {n}")),
            "target_fitness" => a.target_fitness.map(|t| format!("--target-fitness {t}")),
            "tournament" | "elitism" => a.population.map(|n| {
                format!(
                    "--population {n}: the campaign's search.{} = {} needs a larger population",
                    e.field, e.found
                )
            }),
            _ => None,
        };
        match flag {
            Some(flag) => super::BadInput(format!(
                "{flag}: expected {}, found {}",
                e.expected, e.found
            )),
            None => super::BadInput(format!("{}: search.{e}", a.campaign.display())),
        }
    })?;
    c.require_genes()?;
    let length = c.check_run_length(a.max_steps)?;
    let backend = match a.backend {
        Some(BackendArg::Auto) => Backend::Auto,
        Some(BackendArg::Gpu) => Backend::Gpu,
        Some(BackendArg::Cpu) => Backend::Cpu,
        None => c.solver.backend,
    };
    let precision = match a.precision {
        Some(PrecisionArg::Auto) => PrecisionChoice::Auto,
        Some(PrecisionArg::F32) => PrecisionChoice::F32,
        Some(PrecisionArg::F64) => PrecisionChoice::F64,
        None => c.solver.precision,
    };
    let memory = check_memory(&c, a, backend, precision)?;
    for w in &c.warnings {
        out.note(&format!("warning: {w}"));
    }
    let cores = std::thread::available_parallelism().map_or(1, usize::from);
    if a.threads > 2 * cores {
        out.note(&format!(
            "warning: --threads {} is far above the {cores} cores here; threads beyond the \
             cores only slow the job down",
            a.threads
        ));
    }
    // Start the threads now, so a system that refuses them is told before any work
    // (a GPU job needs them if it falls back to the CPU).
    let cpu = CpuEvaluator::try_new(c.problem.clone(), a.threads)
        .map_err(|e| super::BadInput(format!("--threads {}: {e}", a.threads)))?;
    // f32 on the CPU is a compiled rig's native f32 lanes, built now, before
    // any work; a model without them is scored in f64 (as before they
    // existed), with a warning.
    let mut cpu = cpu;
    if backend == Backend::Cpu
        && precision == PrecisionChoice::F32
        && let Err(e) = cpu.use_f32()
    {
        let asked = match a.precision {
            Some(_) => "--precision f32".to_string(),
            None => format!("{}: solver.precision \"f32\"", a.campaign.display()),
        };
        out.note(&format!("warning: {asked} on the CPU: {e}; scoring in f64"));
    }
    if backend != Backend::Cpu
        && let Some((selector, selected_by)) = rigfit::gpu::requested_adapter(a.adapter.as_deref())
    {
        // Before any work: a selector that names no adapter is bad input.
        let adapters = rigfit::gpu::list_adapters();
        if let Err(why) = rigfit::gpu::choose_adapter(&selector, &adapters) {
            return Err(super::BadInput(format!(
                "{selected_by}: {why}; the adapters are: {}",
                rigfit::gpu::adapter_list(&adapters)
            ))
            .into());
        }
    }
    if a.out.is_none() {
        check_output_inside(&c, &a.campaign)?;
    }
    let dir = a.out.clone().unwrap_or_else(|| c.output.clone());
    let mode = match (a.resume, a.overwrite) {
        (true, _) => FolderMode::Resume,
        (false, true) => FolderMode::Overwrite,
        (false, false) => FolderMode::New,
    };
    // Held to the end of the job: the lock keeps other jobs out of the folder.
    let _folder = OutputFolder::open(&dir, &job::output_files(&c), &c.inputs, mode).map_err(
        |e| -> anyhow::Error {
            match (&e, &a.out) {
                (JobError::OutputPath { .. }, None) => {
                    super::BadInput(format!("{}: output: {e}", a.campaign.display())).into()
                }
                (JobError::OutputPath { .. }, Some(_)) => {
                    super::BadInput(format!("--out: {e}")).into()
                }
                _ => e.into(),
            }
        },
    )?;

    let mut evaluator: Box<dyn rigfit::eval::Evaluator> = if backend == Backend::Cpu {
        Box::new(cpu)
    } else {
        drop(cpu);
        let opened = rigfit::gpu::open_evaluator_on(
            c.problem.clone(),
            backend,
            precision,
            a.adapter.as_deref(),
        )
        .context("opening the GPU evaluator")?;
        if let Some(note) = &opened.note {
            // A driver helps only where the model has kernels to run.
            if rigfit::gpu::kernel_groups(&c.problem).is_ok() {
                out.note(&format!("note: {note}; {GPU_HINT}"));
            } else {
                out.note(&format!("note: {note}"));
            }
        }
        opened.evaluator
    };
    let info = evaluator.info();
    out.note(&format!(
        "{} on {} ({}, {}), {} RK4 steps per sample ({}), {:.3e} steps per candidate, \
         memory {} of {}",
        rigfit::base::text::echo_bare(&c.name),
        info.backend,
        info.device,
        format!("{:?}", info.precision).to_lowercase(),
        c.solver.substeps,
        c.solver.note,
        length.steps_per_candidate,
        human_bytes(memory.0.total),
        memory.1
    ));

    let interrupt = Arc::new(AtomicBool::new(false));
    {
        let flag = interrupt.clone();
        // A second signal while the job is winding down ends the process.
        let _ = ctrlc::set_handler(move || {
            if flag.swap(true, Ordering::SeqCst) {
                std::process::exit(i32::from(EXIT_INTERRUPTED));
            }
            eprintln!(
                "\nrigfit: interrupted; stopping the evaluation and keeping the last checkpoint"
            );
        });
    }
    evaluator.set_cancel(interrupt.clone());
    let opts = JobOptions {
        out: dir.clone(),
        resume: a.resume,
        quiet: out.quiet || out.json,
        interrupt: interrupt.clone(),
        require_gpu: backend == Backend::Gpu || rigfit::gpu::gpu_required(),
        threads: a.threads,
    };
    let summary = match job::run(&c, evaluator, &opts) {
        Err(JobError::Search(SearchError::Eval(EvalError::Cancelled))) => {
            out.note(&format!(
                "interrupted before the first generation was complete: nothing to keep; \
                 start it again with: rigfit run {}",
                a.campaign.display()
            ));
            return Ok(ExitCode::from(EXIT_INTERRUPTED));
        }
        other => other?,
    };
    out.json(&summary)?;
    out.say(|| summary_text(&summary, &dir, job::steps_per_candidate(&c)));
    if interrupt.load(Ordering::SeqCst) {
        out.note(&format!(
            "checkpoint kept in {}; continue with: rigfit run {} --resume",
            dir.display(),
            a.campaign.display()
        ));
        return Ok(ExitCode::from(EXIT_INTERRUPTED));
    }
    Ok(ExitCode::SUCCESS)
}

/// Estimates the job's memory and refuses it, with the estimate and the
/// limit, when it exceeds `--max-memory` or the memory available now. Returns
/// the estimate and the limit's description.
fn check_memory(
    c: &Campaign,
    a: &RunArgs,
    backend: Backend,
    precision: PrecisionChoice,
) -> Result<(MemoryEstimate, String), super::BadInput> {
    let gpu_real = match (backend, precision) {
        (Backend::Cpu, _) => None,
        _ if rigfit::gpu::kernel_groups(&c.problem).is_err() => None,
        (_, PrecisionChoice::F32) => Some(4),
        _ => Some(8),
    };
    let estimate = MemoryEstimate::of(c, gpu_real);
    let (limit, what) = match (a.max_memory, memory::available_memory()) {
        (Some(m), _) => (m, format!("--max-memory {}", human_bytes(m))),
        (None, Some(m)) => (m, format!("{} available", human_bytes(m))),
        (None, None) => return Ok((estimate, "an unknown amount available".into())),
    };
    if estimate.total <= limit {
        return Ok((estimate, what));
    }
    let whom = match a.population {
        Some(n) => format!("--population {n}"),
        None => format!("{}: search.population", a.campaign.display()),
    };
    let hint = if a.max_memory.is_some() {
        "lower the population or raise --max-memory"
    } else {
        "lower the population, free memory, or set --max-memory to the memory the job may use"
    };
    Err(super::BadInput(format!(
        "{whom}: expected a job that fits in {limit_text} ({source}), found {estimate}; {hint}",
        limit_text = human_bytes(limit),
        source = match a.max_memory {
            Some(_) => "--max-memory",
            None => "the memory available now, MemAvailable in /proc/meminfo",
        },
    )))
}

/// A campaign's own `output` must stay inside the campaign's folder or the
/// current folder: a campaign from someone else must not send files to `/etc`.
/// `--out` is the user's own choice and goes anywhere.
fn check_output_inside(c: &Campaign, file: &Path) -> Result<(), super::BadInput> {
    let Ok(cwd) = std::env::current_dir() else {
        return Ok(());
    };
    let absolute = |p: &Path| -> PathBuf {
        let mut out = PathBuf::new();
        for part in cwd.join(p).components() {
            match part {
                Component::ParentDir => {
                    out.pop();
                }
                Component::CurDir => {}
                other => out.push(other),
            }
        }
        out
    };
    let output = absolute(&c.output);
    let home = absolute(c.path.parent().unwrap_or(Path::new(".")));
    if output.starts_with(&home) || output.starts_with(absolute(Path::new("."))) {
        return Ok(());
    }
    Err(super::BadInput(format!(
        "{}: output: expected a folder inside the campaign's folder `{}` or the current \
         folder, found `{}`; pass --out DIR to write elsewhere",
        file.display(),
        home.display(),
        output.display()
    )))
}

/// The one-screen summary at the end of a job.
pub fn summary_text(s: &JobSummary, dir: &std::path::Path, steps: f64) -> String {
    let mut t = String::new();
    let rate = s.evaluations as f64 * steps / s.wall_time_s.max(1e-9);
    let _ = writeln!(t, "\n{} — {}", s.campaign, s.stop_reason);
    let _ = writeln!(
        t,
        "  {} generations, {} evaluations in {:.1} s on {} ({}, {}): {:.3e} candidate-steps/s",
        s.generations, s.evaluations, s.wall_time_s, s.backend, s.device, s.precision, rate
    );
    for e in &s.experiments {
        let _ = writeln!(
            t,
            "  {}: R² = {:.6} (1 − R² = {:.3e}; f64 CPU reference R² = {:.6})",
            e.name, e.r2, e.one_minus_r2, e.r2_cpu_reference
        );
    }
    if let Some(p) = &s.polish {
        let _ = writeln!(
            t,
            "  polish: 1 − R² {:.4e} (GA) → {:.4e} in {} iterations, {} evaluations, {:.1} s",
            p.ga_fitness, s.fitness, p.iterations, p.evaluations, p.wall_time_s
        );
    }
    let _ = writeln!(
        t,
        "  fitted parameters (95 % interval from the covariance at the optimum, relative \
         to the value; elite width: spread of the GA's best 10 % relative to the value):"
    );
    let _ = writeln!(
        t,
        "    {:<18} {:>14} {:<7} {:>25} {:>25} {:>12}",
        "name", "value", "unit", "bounds", "95 % interval", "elite width"
    );
    for p in s.parameters.iter().filter(|p| p.free) {
        let bounds = p
            .bounds
            .map(|[lo, hi]| format!("[{lo:.3e}, {hi:.3e}]"))
            .unwrap_or_default();
        let interval = p
            .interval_95
            .map(|[lo, hi]| {
                // Relative to the value: a log-scale interval is asymmetric.
                let rel = |x: f64| 100.0 * (x / p.value - 1.0);
                format!("{:+.3} % / {:+.3} %", rel(lo), rel(hi))
            })
            .unwrap_or_else(|| {
                if p.determined.is_some() {
                    "—".into()
                } else {
                    String::new()
                }
            });
        let width = p
            .elite_relative_width
            .map(|w| format!("{:.2} %", 100.0 * w))
            .unwrap_or_default();
        let mut flags = String::new();
        if p.determined == Some(false) {
            flags += "  not determined by the data";
        }
        if !p.correlated_with.is_empty() {
            let _ = write!(
                flags,
                "  |corr| > 0.99 with {}",
                p.correlated_with.join(", ")
            );
        }
        let _ = writeln!(
            t,
            "    {:<18} {:>14.6e} {:<7} {:>25} {:>25} {:>12}{flags}",
            p.name, p.value, p.unit, bounds, interval, width
        );
    }
    for w in &s.warnings {
        let _ = writeln!(t, "  warning: {w}");
    }
    let mut files = vec!["result.json".to_string()];
    for e in &s.experiments {
        files.push(e.csv.clone());
        files.push(e.plot.clone());
    }
    files.push("history.csv".into());
    files.push("fitness.svg".into());
    let _ = write!(t, "  results in {}: {}", dir.display(), files.join(", "));
    t
}
