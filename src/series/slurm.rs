//! A series as a Slurm plan: its tests packed into tasks, the tasks into job
//! arrays, and a summary job after them, written into `slurm/` of the
//! series' folder for a person to submit (`bash slurm/submit.sh`).
//!
//! Each array task runs `rigfit series ROOT --task N`, with `N` the array
//! index plus the array's offset: a series of more tasks than Slurm's
//! `MaxArraySize` is split into several arrays. The array script forwards
//! Slurm's warning before the time limit (`--signal=B:USR1@T`, sent to the
//! batch shell) and SIGTERM to rigfit, which checkpoints and exits with
//! [`EXIT_INTERRUPTED`]; after a USR1 the script requeues its task, which
//! then resumes from the checkpoints to the same bits. GPU tasks ask for one
//! GPU each (`--gres=gpu:1`); the task finds which one it was given
//! ([`super::scheduler_gpu`]).

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use super::SeriesError;
use super::manifest::{Manifest, TestEntry};
use crate::base::fsutil::atomic_write;

/// The folder of the plan in a series' folder.
pub const SLURM_DIR: &str = "slurm";
/// The folder of the tasks' logs in [`SLURM_DIR`].
pub const LOGS_DIR: &str = "logs";
/// The exit status of an interrupted rigfit (checkpoint written).
pub const EXIT_INTERRUPTED: i32 = 130;
/// Slurm's default `MaxArraySize`: an array's indices stay below it.
pub const DEFAULT_MAX_ARRAY_SIZE: usize = 1001;

/// The second line of every file rigfit writes in `slurm/`: a file there
/// without it is not rigfit's, and is never replaced.
const MARK: &str = "# Written by `rigfit series --slurm`; rigfit replaces this file when it writes the plan again.";

/// The candidate-steps per second a packing estimate assumes for one task:
/// slow on purpose, so that a packed task rather ends early than runs into
/// its time limit. The CPU lanes score the shipped tensile example at about
/// 1.1e8 on 2 cores of the developers' machine (docs/guide/gpus-and-memory.md);
/// this is a fifth of that, about half of one such core; a GPU task is faster.
pub const PACK_STEPS_PER_SECOND: f64 = 2.0e7;
/// The seconds a packing estimate adds to each test for what its search's
/// steps leave out: reading the record, compiling the rig, the polish, the
/// outputs and the report.
pub const PACK_SECONDS_PER_TEST: f64 = 5.0;

/// How a plan is written.
#[derive(Debug, Clone, PartialEq)]
pub struct PlanOptions {
    /// One GPU per task (`--gres=gpu:1`); otherwise CPU tasks.
    pub gpus: bool,
    /// At most this many tasks at once (`%K`), over all the arrays: the
    /// arrays of a split series then run one after the other.
    pub throttle: Option<usize>,
    /// Short tests are packed into one task up to this many estimated
    /// seconds ([`estimated_seconds`]); 0 packs nothing (one test a task).
    pub pack_seconds: f64,
    /// Each task's time limit, as Slurm's `--time` takes it (`2:00:00`).
    pub time_limit: String,
    /// The partition (`--partition`), or the cluster's default.
    pub partition: Option<String>,
    /// The cluster's `MaxArraySize`: each array has fewer tasks.
    pub max_array_size: usize,
    /// How long before the time limit Slurm warns a task with USR1 (s).
    pub signal_seconds: u32,
    /// The rigfit binary the tasks run (absolute).
    pub rigfit: PathBuf,
    /// CPUs per task (`--cpus-per-task`).
    pub cpus_per_task: usize,
    /// Options every task's `rigfit series … --task N` gets (`--backend`,
    /// `--precision`, `--threads`), each one word.
    pub task_args: Vec<String>,
}

impl Default for PlanOptions {
    fn default() -> Self {
        PlanOptions {
            gpus: false,
            throttle: None,
            pack_seconds: 0.0,
            time_limit: "2:00:00".into(),
            partition: None,
            max_array_size: DEFAULT_MAX_ARRAY_SIZE,
            signal_seconds: 120,
            rigfit: PathBuf::from("rigfit"),
            cpus_per_task: 1,
            task_args: Vec::new(),
        }
    }
}

/// One job array of a plan.
#[derive(Debug, Clone, PartialEq)]
pub struct PlanArray {
    /// Its script (absolute).
    pub script: PathBuf,
    /// The first task it runs: task `offset + SLURM_ARRAY_TASK_ID`.
    pub offset: usize,
    /// How many tasks it runs.
    pub tasks: usize,
}

/// A plan as written.
#[derive(Debug, Clone, PartialEq)]
pub struct Plan {
    /// The arrays, in order.
    pub arrays: Vec<PlanArray>,
    /// The summary job's script.
    pub summary: PathBuf,
    /// The script that submits it all.
    pub submit: PathBuf,
}

/// A test's estimated seconds, for packing: [`PACK_SECONDS_PER_TEST`] plus
/// its search's candidate-steps at [`PACK_STEPS_PER_SECOND`].
pub fn estimated_seconds(test: &TestEntry) -> f64 {
    PACK_SECONDS_PER_TEST + test.work.max(0.0) / PACK_STEPS_PER_SECOND
}

/// The tests packed into tasks, in their order: a task takes the next test
/// while its estimated seconds stay within `pack_seconds`; a test longer
/// than that has a task of its own.
pub fn pack(tests: &[TestEntry], pack_seconds: f64) -> Vec<Vec<usize>> {
    let mut tasks: Vec<Vec<usize>> = Vec::new();
    let mut load = 0.0;
    for (i, test) in tests.iter().enumerate() {
        let secs = estimated_seconds(test);
        match tasks.last_mut() {
            Some(task) if !task.is_empty() && load + secs <= pack_seconds => {
                task.push(i);
                load += secs;
            }
            _ => {
                tasks.push(vec![i]);
                load = secs;
            }
        }
    }
    tasks
}

/// The arrays `tasks` tasks are split into: `(offset, count)`, each count
/// below `max_array_size` (Slurm's indices run to `MaxArraySize − 1`).
pub fn split(tasks: usize, max_array_size: usize) -> Vec<(usize, usize)> {
    let most = max_array_size.saturating_sub(1).max(1);
    (0..tasks)
        .step_by(most)
        .map(|o| (o, most.min(tasks - o)))
        .collect()
}

/// Writes the plan of the series in `root`: packs `manifest`'s tests into
/// tasks (written back to its manifest), and writes `slurm/array-<k>.sbatch`,
/// `slurm/summary.sbatch` and `slurm/submit.sh`. Refuses to replace a file
/// in `slurm/` rigfit did not write.
pub fn write_plan(
    root: &Path,
    manifest: &mut Manifest,
    opts: &PlanOptions,
) -> Result<Plan, SeriesError> {
    check_options(opts)?;
    let root = std::path::absolute(root).map_err(|e| SeriesError::io(root, e))?;
    let dir = root.join(SLURM_DIR);
    let logs = dir.join(LOGS_DIR);
    if std::fs::symlink_metadata(&dir).is_ok_and(|m| !m.is_dir()) {
        return Err(SeriesError::Folder {
            path: dir,
            reason:
                "it is not a folder (a link or a file); rigfit writes the plan only into a folder"
                    .into(),
        });
    }
    std::fs::create_dir_all(&logs).map_err(|e| SeriesError::io(&logs, e))?;

    manifest.tasks = pack(&manifest.tests, opts.pack_seconds);
    let arrays = split(manifest.tasks.len(), opts.max_array_size);
    let mut files: Vec<(PathBuf, String)> = Vec::new();
    let mut plan_arrays = Vec::new();
    for (k, &(offset, count)) in arrays.iter().enumerate() {
        let script = dir.join(format!("array-{k}.sbatch"));
        files.push((
            script.clone(),
            array_script(&root, manifest, opts, k, arrays.len(), offset, count),
        ));
        plan_arrays.push(PlanArray {
            script,
            offset,
            tasks: count,
        });
    }
    let summary = dir.join("summary.sbatch");
    files.push((summary.clone(), summary_script(&root, manifest, opts)));
    let submit = dir.join("submit.sh");
    files.push((submit.clone(), submit_script(manifest, opts, &arrays)));

    // Every file is checked before any is written: a refusal leaves the
    // folder as it was.
    for (path, _) in &files {
        check_ours(path)?;
    }
    let stale = stale_arrays(&dir, arrays.len())?;
    manifest.write(&root)?;
    for (path, text) in &files {
        atomic_write(path, text.as_bytes()).map_err(|e| SeriesError::io(path, e))?;
    }
    for path in stale {
        std::fs::remove_file(&path).map_err(|e| SeriesError::io(&path, e))?;
    }
    Ok(Plan {
        arrays: plan_arrays,
        summary,
        submit,
    })
}

fn check_options(opts: &PlanOptions) -> Result<(), SeriesError> {
    let bad = |what: &str, reason: String| {
        Err(SeriesError::Task(format!(
            "the Slurm plan's {what}: {reason}"
        )))
    };
    if opts.throttle == Some(0) {
        return bad(
            "throttle",
            "0 would run no task; expected at least 1".into(),
        );
    }
    if opts.max_array_size < 2 {
        return bad(
            "largest array",
            format!(
                "{}: expected at least 2 (Slurm's default is 1001)",
                opts.max_array_size
            ),
        );
    }
    if !(opts.pack_seconds.is_finite() && opts.pack_seconds >= 0.0) {
        return bad(
            "packing time",
            format!("{}: expected seconds, 0 or more", opts.pack_seconds),
        );
    }
    if opts.time_limit.is_empty()
        || !opts
            .time_limit
            .chars()
            .all(|c| c.is_ascii_digit() || c == ':' || c == '-')
    {
        return bad(
            "time limit",
            format!(
                "\"{}\": expected Slurm's form, minutes or [days-]hours:minutes:seconds",
                opts.time_limit
            ),
        );
    }
    if let Some(p) = &opts.partition
        && (p.is_empty()
            || !p
                .chars()
                .all(|c| c.is_ascii_alphanumeric() || "_-.,".contains(c)))
    {
        return bad(
            "partition",
            format!("\"{p}\": expected letters, digits, `_`, `-`, `.` and `,`"),
        );
    }
    if opts.cpus_per_task == 0 {
        return bad("CPUs per task", "0: expected at least 1".into());
    }
    Ok(())
}

/// A word quoted for the shell.
fn quote(word: &str) -> String {
    if !word.is_empty()
        && word
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || "/._-:=+,@".contains(c))
    {
        word.to_string()
    } else {
        format!("'{}'", word.replace('\'', r"'\''"))
    }
}

fn quote_path(path: &Path) -> String {
    quote(&path.to_string_lossy())
}

/// The `#SBATCH` lines every job of the plan shares.
fn common_lines(text: &mut String, opts: &PlanOptions, job_name: &str) {
    let _ = writeln!(text, "#SBATCH --job-name={job_name}");
    let _ = writeln!(text, "#SBATCH --time={}", opts.time_limit);
    if let Some(p) = &opts.partition {
        let _ = writeln!(text, "#SBATCH --partition={p}");
    }
    let _ = writeln!(text, "#SBATCH --ntasks=1");
}

/// The script of array `k` of `of`: tasks `offset .. offset + count`.
fn array_script(
    root: &Path,
    manifest: &Manifest,
    opts: &PlanOptions,
    k: usize,
    of: usize,
    offset: usize,
    count: usize,
) -> String {
    let mut t = String::new();
    let _ = writeln!(t, "#!/bin/bash");
    let _ = writeln!(t, "{MARK}");
    let _ = writeln!(
        t,
        "# Series \"{}\": array {} of {of}, tasks {offset} to {} ({} tests in all). Submitted by submit.sh,\n\
         # from this folder: the log paths are relative to it.",
        manifest.name,
        k + 1,
        offset + count - 1,
        manifest.tests.len()
    );
    common_lines(&mut t, opts, &format!("rigfit-{}", manifest.name));
    let throttle = opts.throttle.map(|k| format!("%{k}")).unwrap_or_default();
    let _ = writeln!(t, "#SBATCH --array=0-{}{throttle}", count - 1);
    let _ = writeln!(t, "#SBATCH --requeue");
    let _ = writeln!(t, "#SBATCH --open-mode=append");
    let _ = writeln!(t, "#SBATCH --signal=B:USR1@{}", opts.signal_seconds);
    let _ = writeln!(t, "#SBATCH --output={LOGS_DIR}/%A_%a.out");
    if opts.gpus {
        let _ = writeln!(t, "#SBATCH --gres=gpu:1");
    }
    let _ = writeln!(t, "#SBATCH --cpus-per-task={}", opts.cpus_per_task);
    let mut command = vec![
        quote_path(&opts.rigfit),
        "series".into(),
        quote_path(root),
        "--task".into(),
        "\"$task\"".into(),
    ];
    command.extend(opts.task_args.iter().map(|a| quote(a)));
    let _ = write!(
        t,
        r#"
task=$((SLURM_ARRAY_TASK_ID + {offset}))
echo "rigfit series: task $task (job ${{SLURM_ARRAY_JOB_ID}}_${{SLURM_ARRAY_TASK_ID}}, restart ${{SLURM_RESTART_COUNT:-0}}) on $(hostname) at $(date -Is)"

# Slurm's warning before the time limit (USR1, to this shell alone) and
# SIGTERM go to rigfit, which checkpoints and exits {EXIT_INTERRUPTED}.
child=""
signalled=""
forward() {{
    signalled="$1"
    if [ -n "$child" ]; then kill -s "$1" "$child" 2>/dev/null || true; fi
}}
trap 'forward USR1' USR1
trap 'forward TERM' TERM

{command} &
child=$!
# A trapped signal ends `wait` early: wait again while rigfit runs; the
# last `wait` gives its exit status.
while kill -0 "$child" 2>/dev/null; do wait "$child"; done
wait "$child"
status=$?

if [ "$status" -eq {EXIT_INTERRUPTED} ] && [ "$signalled" = USR1 ]; then
    echo "rigfit series: task $task checkpointed before the time limit; requeued"
    scontrol requeue "$SLURM_JOB_ID"
    exit 0
fi
exit "$status"
"#,
        command = command.join(" ")
    );
    t
}

fn summary_script(root: &Path, manifest: &Manifest, opts: &PlanOptions) -> String {
    let mut t = String::new();
    let _ = writeln!(t, "#!/bin/bash");
    let _ = writeln!(t, "{MARK}");
    let _ = writeln!(
        t,
        "# Series \"{}\": its summary (summary.csv, summary.html), after every task has ended.",
        manifest.name
    );
    common_lines(&mut t, opts, &format!("rigfit-{}-summary", manifest.name));
    let _ = writeln!(t, "#SBATCH --cpus-per-task=1");
    let _ = writeln!(t, "#SBATCH --output={LOGS_DIR}/summary_%j.out");
    let _ = writeln!(
        t,
        "\nexec {} series {} --summary",
        quote_path(&opts.rigfit),
        quote_path(root)
    );
    t
}

fn submit_script(manifest: &Manifest, opts: &PlanOptions, arrays: &[(usize, usize)]) -> String {
    let mut t = String::new();
    let _ = writeln!(t, "#!/usr/bin/env bash");
    let _ = writeln!(t, "{MARK}");
    let _ = writeln!(
        t,
        "# Submits series \"{}\": {} tests in {} tasks, as {} job array(s){}, then its summary\n\
         # job once every task has ended (afterany). Prints `array K JOBID` and `summary JOBID`.",
        manifest.name,
        manifest.tests.len(),
        manifest.tasks.len(),
        arrays.len(),
        if opts.throttle.is_some() && arrays.len() > 1 {
            " one after the other (the throttle holds over all of them)"
        } else {
            ""
        }
    );
    let _ = writeln!(t, "set -euo pipefail");
    let _ = writeln!(t, "cd \"$(dirname \"$0\")\"");
    let _ = writeln!(t, "mkdir -p {LOGS_DIR}");
    let _ = writeln!(t, "ids=()");
    for k in 0..arrays.len() {
        let after = if k > 0 && opts.throttle.is_some() {
            " --dependency=afterany:\"${ids[-1]}\""
        } else {
            ""
        };
        let _ = writeln!(t, "id=$(sbatch --parsable{after} array-{k}.sbatch)");
        let _ = writeln!(t, "id=\"${{id%%;*}}\"");
        let _ = writeln!(t, "ids+=(\"$id\")");
        let _ = writeln!(t, "echo \"array {k} $id\"");
    }
    let _ = writeln!(t, "deps=$(IFS=:; echo \"${{ids[*]}}\")");
    let _ = writeln!(
        t,
        "id=$(sbatch --parsable --dependency=afterany:\"$deps\" summary.sbatch)"
    );
    let _ = writeln!(t, "echo \"summary ${{id%%;*}}\"");
    t
}

/// Whether `path` may be written: missing, or a file whose second line is
/// [`MARK`] (the first is its `#!` line).
fn check_ours(path: &Path) -> Result<(), SeriesError> {
    let Ok(meta) = std::fs::symlink_metadata(path) else {
        return Ok(());
    };
    let ours = meta.is_file()
        && std::fs::read_to_string(path).is_ok_and(|text| text.lines().nth(1) == Some(MARK));
    if ours {
        Ok(())
    } else {
        Err(SeriesError::Folder {
            path: path.to_path_buf(),
            reason: "this file was not written by rigfit series --slurm (its second line is not rigfit's mark); \
                     rigfit never replaces it: move it away"
                .into(),
        })
    }
}

/// rigfit's `array-<k>.sbatch` files from an earlier plan of more arrays.
fn stale_arrays(dir: &Path, arrays: usize) -> Result<Vec<PathBuf>, SeriesError> {
    let mut stale = Vec::new();
    for entry in std::fs::read_dir(dir)
        .map_err(|e| SeriesError::io(dir, e))?
        .flatten()
    {
        let name = entry.file_name().to_string_lossy().into_owned();
        let k = name
            .strip_prefix("array-")
            .and_then(|r| r.strip_suffix(".sbatch"))
            .and_then(|k| k.parse::<usize>().ok());
        if k.is_some_and(|k| k >= arrays) && check_ours(&entry.path()).is_ok() {
            stale.push(entry.path());
        }
    }
    Ok(stale)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::series::manifest::GENERATOR;

    fn test_entry(i: usize, work: f64) -> TestEntry {
        TestEntry {
            id: format!("t{i}"),
            campaign: PathBuf::from(format!("campaigns/t{i}.json")),
            out: PathBuf::from(format!("tests/t{i}")),
            seed: i as u64,
            covariates: Vec::new(),
            source: format!("tests.csv line {}", i + 2),
            error: None,
            work,
        }
    }

    fn manifest(works: &[f64]) -> Manifest {
        let tests: Vec<TestEntry> = works
            .iter()
            .enumerate()
            .map(|(i, &w)| test_entry(i, w))
            .collect();
        Manifest {
            generator: GENERATOR.into(),
            name: "rates".into(),
            series_file: PathBuf::from("/lab/rates.json"),
            covariates: Vec::new(),
            tasks: (0..tests.len()).map(|i| vec![i]).collect(),
            tests,
        }
    }

    #[test]
    fn packing_keeps_order_and_the_time_budget() {
        let secs = |w: f64| PACK_SECONDS_PER_TEST + w / PACK_STEPS_PER_SECOND;
        // Three 10 s tests, one of 100 s, two of 10 s, with a 25 s budget.
        let w10 = (10.0 - PACK_SECONDS_PER_TEST) * PACK_STEPS_PER_SECOND;
        let w100 = (100.0 - PACK_SECONDS_PER_TEST) * PACK_STEPS_PER_SECOND;
        let m = manifest(&[w10, w10, w10, w100, w10, w10]);
        assert!((secs(w10) - 10.0).abs() < 1e-9);
        assert_eq!(
            pack(&m.tests, 25.0),
            vec![vec![0, 1], vec![2], vec![3], vec![4, 5]]
        );
        // No budget: one test a task.
        assert_eq!(
            pack(&m.tests, 0.0),
            (0..6).map(|i| vec![i]).collect::<Vec<_>>()
        );
        // Every test lands in exactly one task, in order.
        let flat: Vec<usize> = pack(&m.tests, 1e9).concat();
        assert_eq!(flat, (0..6).collect::<Vec<_>>());
    }

    #[test]
    fn arrays_stay_below_max_array_size() {
        assert_eq!(
            split(2500, 1001),
            vec![(0, 1000), (1000, 1000), (2000, 500)]
        );
        assert_eq!(split(1000, 1001), vec![(0, 1000)]);
        assert_eq!(split(1001, 1001), vec![(0, 1000), (1000, 1)]);
        assert_eq!(split(0, 1001), vec![]);
        for (n, max) in [(7, 3), (1, 2), (12, 5)] {
            let arrays = split(n, max);
            assert!(arrays.iter().all(|&(_, c)| c >= 1 && c < max), "{arrays:?}");
            assert_eq!(arrays.iter().map(|a| a.1).sum::<usize>(), n);
        }
    }

    fn options() -> PlanOptions {
        PlanOptions {
            throttle: Some(4),
            rigfit: PathBuf::from("/opt/rig fit/bin/rigfit"),
            task_args: vec!["--backend".into(), "cpu".into()],
            ..PlanOptions::default()
        }
    }

    #[test]
    fn a_plan_of_2500_tests_is_three_arrays_and_a_summary() {
        let dir = tempfile::tempdir().unwrap();
        let mut m = manifest(&vec![1.0; 2500]);
        let opts = PlanOptions {
            gpus: true,
            partition: Some("gpu".into()),
            ..options()
        };
        let plan = write_plan(dir.path(), &mut m, &opts).unwrap();
        assert_eq!(plan.arrays.len(), 3);
        assert_eq!(Manifest::read(dir.path()).unwrap().tasks.len(), 2500);
        let a2 = std::fs::read_to_string(&plan.arrays[2].script).unwrap();
        for line in [
            "#SBATCH --array=0-499%4",
            "#SBATCH --requeue",
            "#SBATCH --open-mode=append",
            "#SBATCH --signal=B:USR1@120",
            "#SBATCH --output=logs/%A_%a.out",
            "#SBATCH --gres=gpu:1",
            "#SBATCH --partition=gpu",
            "task=$((SLURM_ARRAY_TASK_ID + 2000))",
            "trap 'forward USR1' USR1",
            "scontrol requeue \"$SLURM_JOB_ID\"",
        ] {
            assert!(
                a2.lines().any(|l| l.trim() == line),
                "missing {line:?} in\n{a2}"
            );
        }
        let root = std::path::absolute(dir.path()).unwrap();
        let run = format!(
            "'/opt/rig fit/bin/rigfit' series {} --task \"$task\" --backend cpu &",
            quote_path(&root)
        );
        assert!(a2.contains(&run), "missing {run:?} in\n{a2}");
        let submit = std::fs::read_to_string(&plan.submit).unwrap();
        assert!(
            submit.contains("sbatch --parsable array-0.sbatch"),
            "{submit}"
        );
        // The throttle holds over the arrays: each waits for the one before.
        assert!(
            submit
                .contains("sbatch --parsable --dependency=afterany:\"${ids[-1]}\" array-2.sbatch"),
            "{submit}"
        );
        assert!(
            submit.contains("--dependency=afterany:\"$deps\" summary.sbatch"),
            "{submit}"
        );
        let summary = std::fs::read_to_string(&plan.summary).unwrap();
        assert!(
            summary.contains(&format!(" series {} --summary", quote_path(&root))),
            "{summary}"
        );
        assert!(!summary.contains("--gres"), "{summary}");
    }

    #[test]
    fn the_scripts_are_valid_bash() {
        let dir = tempfile::tempdir().unwrap();
        let mut m = manifest(&[1.0; 3]);
        let plan = write_plan(dir.path(), &mut m, &options()).unwrap();
        for script in [&plan.arrays[0].script, &plan.summary, &plan.submit] {
            let out = std::process::Command::new("bash")
                .arg("-n")
                .arg(script)
                .output()
                .unwrap();
            assert!(
                out.status.success(),
                "{}: {}",
                script.display(),
                String::from_utf8_lossy(&out.stderr)
            );
        }
        let cpu = std::fs::read_to_string(&plan.arrays[0].script).unwrap();
        assert!(
            cpu.contains("#SBATCH --cpus-per-task=1") && !cpu.contains("--gres"),
            "{cpu}"
        );
    }

    #[test]
    fn files_rigfit_did_not_write_are_never_replaced() {
        let dir = tempfile::tempdir().unwrap();
        let mut m = manifest(&[1.0; 3]);
        let plan = write_plan(dir.path(), &mut m, &options()).unwrap();
        // Written again over its own files: fine, and a smaller plan
        // removes only its own stale arrays.
        let mut opts = options();
        opts.max_array_size = 2;
        let plan2 = write_plan(dir.path(), &mut m, &opts).unwrap();
        assert_eq!(plan2.arrays.len(), 3);
        let foreign = dir.path().join("slurm/array-5.sbatch");
        std::fs::write(&foreign, "#!/bin/bash\n# mine\n").unwrap();
        write_plan(dir.path(), &mut m, &options()).unwrap();
        assert!(!dir.path().join("slurm/array-1.sbatch").exists());
        assert!(foreign.exists(), "a file rigfit did not write was removed");
        // A file of someone else's where rigfit would write: refused,
        // naming it, and nothing is changed.
        std::fs::write(&plan.summary, "#!/bin/bash\necho hand-written\n").unwrap();
        let before = std::fs::read_to_string(&plan.arrays[0].script).unwrap();
        let e = write_plan(
            dir.path(),
            &mut m,
            &PlanOptions {
                throttle: Some(9),
                ..options()
            },
        )
        .unwrap_err();
        assert!(
            e.to_string().contains("summary.sbatch")
                && e.to_string().contains("not written by rigfit"),
            "{e}"
        );
        assert_eq!(
            std::fs::read_to_string(&plan.summary).unwrap(),
            "#!/bin/bash\necho hand-written\n"
        );
        assert_eq!(
            std::fs::read_to_string(&plan.arrays[0].script).unwrap(),
            before
        );
        #[cfg(unix)]
        {
            std::fs::remove_file(&plan.summary).unwrap();
            std::os::unix::fs::symlink("/etc/passwd", &plan.summary).unwrap();
            assert!(write_plan(dir.path(), &mut m, &options()).is_err());
        }
    }

    #[test]
    fn bad_options_are_refused() {
        let dir = tempfile::tempdir().unwrap();
        let mut m = manifest(&[1.0]);
        for opts in [
            PlanOptions {
                throttle: Some(0),
                ..options()
            },
            PlanOptions {
                time_limit: "1h; rm -rf /".into(),
                ..options()
            },
            PlanOptions {
                partition: Some("a b".into()),
                ..options()
            },
            PlanOptions {
                max_array_size: 1,
                ..options()
            },
            PlanOptions {
                pack_seconds: f64::NAN,
                ..options()
            },
        ] {
            assert!(write_plan(dir.path(), &mut m, &opts).is_err(), "{opts:?}");
        }
        assert!(!dir.path().join("slurm").exists());
    }
}
