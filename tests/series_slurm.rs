//! A series run as a Slurm job array on a real single-node cluster gives the
//! same fitted parameters, bit for bit, as the same series run here; a task
//! warned with SIGUSR1 checkpoints, is requeued and resumes to the same bits;
//! the array keeps to its throttle; the summary job runs after the array; a
//! test with a broken record is listed as failed with its error.
//!
//! A second test holds the plan's scripts alone to their promises, with a
//! stand-in for rigfit: arrays split below `MaxArraySize` run every task
//! once with its offset, a task warned with SIGUSR1 passes the signal on
//! and is requeued, and the summary job runs last.
//!
//! Both need a running cluster (`bash scripts/slurm-ci.sh start`: Debian's
//! slurm-wlm and munge on 127.0.0.1, root only) and runs only when
//! `RIGFIT_SLURM_TEST=1`; otherwise it says so and passes. `scripts/test.sh`
//! (what CI runs) starts the cluster, sets the variable and stops the cluster
//! afterwards, so in CI it always runs. Slurm's commands find the cluster
//! through `SLURM_CONF` (default: the file `scripts/slurm-ci.sh` writes).

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::time::{Duration, Instant};

use serde_json::Value;

const RIGFIT: &str = env!("CARGO_BIN_EXE_rigfit");
/// The series' tests that have a good record (one more has a broken one).
const GOOD_TESTS: usize = 12;
/// How many tasks may run at once.
const THROTTLE: usize = 2;
/// summary.csv's columns that say where, how and how long a test ran (and
/// its error, which names the folder): the rest is the same on Slurm and here.
const MAY_DIFFER: &[&str] = &[
    "error",
    "wall_time_s",
    "backend",
    "device",
    "adapter",
    "host",
    "restarts",
];
/// The whole array and its summary must be done within this.
const DEADLINE: Duration = Duration::from_secs(240);

fn slurm_conf() -> String {
    std::env::var("SLURM_CONF").unwrap_or_else(|_| {
        let dir = std::env::var("SLURM_CI_DIR").unwrap_or_else(|_| "/tmp/rigfit-slurm-ci".into());
        format!("{dir}/slurm.conf")
    })
}

/// A Slurm command (or any) with the cluster's configuration.
fn slurm(program: &str, args: &[&str]) -> Output {
    Command::new(program)
        .args(args)
        .env("SLURM_CONF", slurm_conf())
        .output()
        .unwrap_or_else(|e| {
            panic!("{program}: {e} (is Slurm installed? bash scripts/slurm-ci.sh start)")
        })
}

fn text(o: &Output) -> String {
    format!(
        "{}{}",
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    )
}

/// Cancels the jobs it holds when dropped, so a failing test leaves no job
/// running on the cluster.
struct Jobs(Vec<String>);

impl Drop for Jobs {
    fn drop(&mut self) {
        for id in &self.0 {
            let _ = slurm("scancel", &[id]);
        }
    }
}

/// The series: the shipped tensile campaign on its record, 12 tests with
/// covariates and seeds of their own, and one on a record of garbage.
fn write_series(dir: &Path) -> PathBuf {
    let shipped = Path::new(env!("CARGO_MANIFEST_DIR")).join("campaigns");
    let record = shipped.join("aa2024_t3_v2_synthetic.csv");
    std::fs::write(dir.join("broken.csv"), "this is not,a record\n1,2,3\nx\n").unwrap();
    let mut table = String::from("test,record,seed,specimen,rate_mps\n");
    for i in 0..GOOD_TESTS {
        let rate = [0.5, 1.0, 2.0][i % 3];
        table += &format!(
            "s{i:02},{},{},A{},{rate}\n",
            record.display(),
            11 + 7 * i,
            i / 3
        );
    }
    table += "broken,broken.csv,5,B0,2.0\n";
    std::fs::write(dir.join("tests.csv"), table).unwrap();
    let series = serde_json::json!({
        "name": "slurm-ci",
        "campaign": shipped.join("aa2024_t3_synthetic.json"),
        "tests": "tests.csv",
        // Small searches: about a second each on one core. A checkpoint
        // every 4 generations tells the test that a search is under way.
        "search": {
            "population": 128,
            "generations": 40,
            "profiles": false,
            "stall_generations": 1000,
            "checkpoint_every": 4
        },
        "output": "results/slurm-ci"
    });
    let path = dir.join("series.json");
    std::fs::write(&path, serde_json::to_string_pretty(&series).unwrap()).unwrap();
    path
}

/// Each test's fitted parameters (`result.json`'s "params") as bits.
fn fitted(root: &Path) -> BTreeMap<String, BTreeMap<String, u64>> {
    let manifest: Value =
        serde_json::from_str(&std::fs::read_to_string(root.join("series.json")).unwrap()).unwrap();
    let mut all = BTreeMap::new();
    for t in manifest["tests"].as_array().unwrap() {
        let id = t["id"].as_str().unwrap().to_string();
        let out = root.join(t["out"].as_str().unwrap());
        let Ok(text) = std::fs::read_to_string(out.join("result.json")) else {
            continue;
        };
        let result: Value = serde_json::from_str(&text).unwrap();
        let params = result["params"]
            .as_object()
            .unwrap()
            .iter()
            .map(|(k, v)| (k.clone(), v.as_f64().unwrap().to_bits()))
            .collect();
        all.insert(id, params);
    }
    all
}

fn status(root: &Path, id: &str) -> Value {
    let path = root.join("status").join(format!("{id}.json"));
    let text = std::fs::read_to_string(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    serde_json::from_str(&text).unwrap()
}

/// The summary's rows by test, as header → cell.
fn summary_rows(root: &Path) -> Option<BTreeMap<String, BTreeMap<String, String>>> {
    let text = std::fs::read_to_string(root.join("summary.csv")).ok()?;
    let mut reader = csv::ReaderBuilder::new()
        .comment(Some(b'#'))
        .flexible(true)
        .from_reader(text.as_bytes());
    let header: Vec<String> = reader.headers().ok()?.iter().map(String::from).collect();
    let test = header.iter().position(|h| h == "test" || h == "id")?;
    let mut rows = BTreeMap::new();
    for rec in reader.records() {
        let rec = rec.ok()?;
        let row: BTreeMap<String, String> = header
            .iter()
            .cloned()
            .zip(rec.iter().map(String::from))
            .collect();
        rows.insert(rec.get(test)?.to_string(), row);
    }
    Some(rows)
}

/// The array's tasks by state, from `squeue` (`12345_3 RUNNING`).
fn array_states(array: &str) -> Vec<(String, String)> {
    let o = slurm("squeue", &["-h", "-r", "-j", array, "-o", "%i %T"]);
    String::from_utf8_lossy(&o.stdout)
        .lines()
        .filter_map(|l| {
            l.split_once(' ')
                .map(|(a, b)| (a.to_string(), b.trim().to_string()))
        })
        .collect()
}

/// The job id of task `index` of an array while it runs: its own
/// (`12346`), not the array's notation (`12345_1`).
fn task_job_id(array: &str, index: usize) -> Option<String> {
    let o = slurm("squeue", &["-h", "-r", "-j", array, "-o", "%K %A %T"]);
    String::from_utf8_lossy(&o.stdout).lines().find_map(|l| {
        let f: Vec<&str> = l.split_whitespace().collect();
        (f.len() == 3 && f[0] == index.to_string() && f[2] == "RUNNING").then(|| f[1].to_string())
    })
}

/// Sends USR1 to task `index`'s batch shell, as Slurm does before the time
/// limit; whether it was sent. Slurm 22.05 delivers the signal at once but
/// may answer an array task's signal with "Job can not be altered now",
/// and scancel then retries every 5 s or so, which would warn the task again
/// after its requeue: scancel is stopped after 2 s.
fn warn_task(array: &str, index: usize) -> bool {
    let Some(id) = task_job_id(array, index) else {
        return false;
    };
    let mut child = Command::new("scancel")
        .args(["--batch", "--signal=USR1", &id])
        .env("SLURM_CONF", slurm_conf())
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null())
        .spawn()
        .expect("scancel");
    let start = Instant::now();
    loop {
        if let Some(status) = child.try_wait().unwrap() {
            return status.success();
        }
        if start.elapsed() > Duration::from_secs(2) {
            let _ = child.kill();
            let _ = child.wait();
            return true;
        }
        std::thread::sleep(Duration::from_millis(20));
    }
}

/// `key`'s value in `scontrol show job`, one per job (an array's tasks each
/// have a line).
fn job_fields(job: &str, key: &str) -> Vec<String> {
    let o = slurm("scontrol", &["show", "job", "-o", job]);
    let t = text(&o);
    let values: Vec<String> = t
        .lines()
        .filter_map(|l| {
            l.split_whitespace()
                .find_map(|w| w.strip_prefix(&format!("{key}=")))
        })
        .map(String::from)
        .collect();
    assert!(
        !values.is_empty(),
        "scontrol show job {job}: no {key} in {t}"
    );
    values
}

fn job_field(job: &str, key: &str) -> String {
    job_fields(job, key).swap_remove(0)
}

#[test]
fn a_series_on_slurm_matches_the_local_run_bit_for_bit() {
    if std::env::var("RIGFIT_SLURM_TEST").as_deref() != Ok("1") {
        eprintln!(
            "series_slurm: not asked (RIGFIT_SLURM_TEST is not 1); scripts/test.sh starts a cluster and sets it"
        );
        return;
    }
    let started = Instant::now();
    let dir = tempfile::tempdir().unwrap();
    let series = write_series(dir.path());
    let on_slurm = dir.path().join("on-slurm");
    let here = dir.path().join("here");

    // The plan.
    let o = Command::new(RIGFIT)
        .arg("series")
        .arg(&series)
        .arg("--slurm")
        .arg(&on_slurm)
        .args([
            "--throttle",
            &THROTTLE.to_string(),
            "--backend",
            "cpu",
            "--threads",
            "1",
            "--time",
            "10",
        ])
        .output()
        .unwrap();
    assert!(o.status.success(), "rigfit series --slurm: {}", text(&o));
    for f in [
        "series.json",
        "slurm/array-0.sbatch",
        "slurm/summary.sbatch",
        "slurm/submit.sh",
    ] {
        assert!(
            on_slurm.join(f).is_file(),
            "the plan has no {f}: {}",
            text(&o)
        );
    }
    let manifest: Value =
        serde_json::from_str(&std::fs::read_to_string(on_slurm.join("series.json")).unwrap())
            .unwrap();
    assert_eq!(manifest["tests"].as_array().unwrap().len(), GOOD_TESTS + 1);
    let tasks: Vec<Vec<usize>> = serde_json::from_value(manifest["tasks"].clone()).unwrap();

    // Submitted as a person would.
    let submit = on_slurm.join("slurm/submit.sh");
    let o = slurm("bash", &[submit.to_str().unwrap()]);
    assert!(o.status.success(), "submit.sh: {}", text(&o));
    let out = String::from_utf8_lossy(&o.stdout).to_string();
    let job = |what: &str| {
        out.lines()
            .find_map(|l| l.strip_prefix(what))
            .unwrap_or_else(|| panic!("submit.sh printed no `{what}…`: {out}"))
            .trim()
            .to_string()
    };
    let array = job("array 0 ");
    let summary = job("summary ");
    let mut jobs = Jobs(vec![array.clone(), summary.clone()]);

    // The summary job waits for the array.
    let state = job_field(&summary, "JobState");
    assert_eq!(
        state, "PENDING",
        "the summary job did not wait for the array"
    );

    // Warn a task with USR1, as Slurm does before the time limit, once its
    // search is under way (its checkpoint written: rigfit runs, with its
    // handlers installed); watch that no more than THROTTLE tasks run at
    // once. The checkpoints are looked for often, squeue less often.
    let mut most_running = 0;
    let mut signalled: Option<usize> = None;
    for round in 0.. {
        assert!(
            started.elapsed() < DEADLINE,
            "the array did not end in {DEADLINE:?}: {:?}",
            array_states(&array)
        );
        if signalled.is_none() {
            for (index, task) in tasks.iter().enumerate() {
                let first = &manifest["tests"][task[0]];
                let out = on_slurm.join(first["out"].as_str().unwrap());
                if first["id"] != "broken" && out.join("checkpoint.json").is_file() {
                    // Not sent where the task has just ended: try another.
                    if warn_task(&array, index) {
                        signalled = Some(index);
                        break;
                    }
                }
            }
        }
        if round % 10 == 0 {
            let states = array_states(&array);
            let running = states.iter().filter(|s| s.1 == "RUNNING").count();
            most_running = most_running.max(running);
            if states.is_empty() {
                break;
            }
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    let signalled = signalled.expect("no task was seen running a search, to be signalled");
    assert!(
        most_running <= THROTTLE,
        "{most_running} tasks ran at once; the throttle is {THROTTLE}"
    );
    while !array_states(&summary).is_empty() {
        assert!(
            started.elapsed() < DEADLINE,
            "the summary job did not end in {DEADLINE:?}"
        );
        std::thread::sleep(Duration::from_millis(100));
    }
    assert_eq!(
        job_field(&summary, "JobState"),
        "COMPLETED",
        "the summary job failed"
    );
    // It started once the last task had ended (Slurm's times: ISO 8601, to
    // the second, in one zone: their order is the text's).
    let last_end = job_fields(&array, "EndTime").into_iter().max().unwrap();
    let summary_start = job_field(&summary, "StartTime");
    assert!(
        summary_start >= last_end,
        "the summary started at {summary_start}, before the array ended at {last_end}"
    );
    jobs.0.clear();
    let slurm_time = started.elapsed();

    // The warned task was requeued, resumed and finished.
    let log = std::fs::read_to_string(on_slurm.join(format!("slurm/logs/{array}_{signalled}.out")))
        .unwrap();
    assert!(
        log.contains("requeued"),
        "task {signalled} was not requeued:\n{log}"
    );
    for &t in &tasks[signalled] {
        let id = manifest["tests"][t]["id"].as_str().unwrap();
        let s = status(&on_slurm, id);
        assert_eq!(s["state"], "done", "test {id} of the requeued task: {s}");
        assert!(
            s["restarts"].as_u64().unwrap() >= 1,
            "test {id}: Slurm's restart count not kept: {s}"
        );
    }

    // The same series here.
    let local_start = Instant::now();
    let o = Command::new(RIGFIT)
        .arg("series")
        .arg(&series)
        .arg("--out")
        .arg(&here)
        .args([
            "--backend",
            "cpu",
            "--jobs",
            &THROTTLE.to_string(),
            "--threads",
            "1",
        ])
        .output()
        .unwrap();
    assert_eq!(
        o.status.code(),
        Some(1),
        "rigfit series (a test fails): {}",
        text(&o)
    );
    let local_time = local_start.elapsed();

    // Bit for bit, every parameter of every test.
    let (a, b) = (fitted(&on_slurm), fitted(&here));
    assert_eq!(
        a.len(),
        GOOD_TESTS,
        "tests with results on Slurm: {:?}",
        a.keys()
    );
    assert_eq!(a, b, "the fitted parameters differ between Slurm and here");

    // The broken test failed, with its error, in both.
    for root in [&on_slurm, &here] {
        let s = status(root, "broken");
        assert_eq!(s["state"], "failed", "{}: {s}", root.display());
        let error = s["error"].as_str().unwrap_or_default();
        assert!(
            error.contains("broken.csv"),
            "the error does not name the record: {error}"
        );
    }

    // The summaries agree cell for cell (every parameter, its interval, the
    // fit), apart from where and how long each test ran, and list the failure.
    let sa = summary_rows(&on_slurm).expect("the summary job wrote no summary.csv");
    let sb = summary_rows(&here).expect("the local run wrote no summary.csv");
    assert_eq!(
        sa.len(),
        GOOD_TESTS + 1,
        "summary.csv's rows: {:?}",
        sa.keys()
    );
    let params: Vec<&String> = a.values().next().unwrap().keys().collect();
    let mut compared_params = 0;
    for (id, row) in &sa {
        for (col, cell) in row {
            if MAY_DIFFER.contains(&col.as_str()) {
                continue;
            }
            assert_eq!(
                Some(cell),
                sb[id].get(col),
                "summary.csv: test {id}, column {col}"
            );
            compared_params += usize::from(params.contains(&col));
        }
    }
    assert!(
        compared_params > 0,
        "summary.csv has no parameter columns: {:?}",
        sa["s00"].keys()
    );
    assert_eq!(
        sa["broken"]["status"], "failed",
        "the summary's row: {:?}",
        sa["broken"]
    );
    assert!(
        sa["broken"]["error"].contains("broken.csv"),
        "the summary's row: {:?}",
        sa["broken"]
    );
    eprintln!(
        "series_slurm: {} tests on Slurm in {slurm_time:.1?} (task {signalled} requeued), here in {local_time:.1?}",
        GOOD_TESTS + 1
    );
}

/// A stand-in for rigfit: logs each call to `ROOT/calls`; task 0, on its
/// first run, waits to be signalled and then exits 130 as rigfit does when
/// it has checkpointed.
const FAKE_RIGFIT: &str = r#"#!/bin/bash
root="$2"
if [ "$3" = --summary ]; then
    echo "summary after $(wc -l <"$root/calls") calls" >>"$root/calls"
    exit 0
fi
task="$4"
trap 'echo "interrupted $task" >>"$root/calls"; exit 130' USR1 TERM
echo "start $task restart=${SLURM_RESTART_COUNT:-0} args=${*:5}" >>"$root/calls"
if [ "$task" = 0 ] && [ "${SLURM_RESTART_COUNT:-0}" = 0 ]; then
    sleep 60 &
    wait $!
fi
echo "done $task" >>"$root/calls"
"#;

#[test]
fn the_plans_scripts_split_requeue_and_summarise() {
    use rigfit::series::slurm::{PlanOptions, write_plan};
    use rigfit::series::{Manifest, TestEntry};
    if std::env::var("RIGFIT_SLURM_TEST").as_deref() != Ok("1") {
        eprintln!(
            "series_slurm: not asked (RIGFIT_SLURM_TEST is not 1); scripts/test.sh starts a cluster and sets it"
        );
        return;
    }
    let started = Instant::now();
    let dir = tempfile::tempdir().unwrap();
    let root = dir.path().join("plan");
    std::fs::create_dir_all(&root).unwrap();
    let fake = dir.path().join("fake-rigfit");
    std::fs::write(&fake, FAKE_RIGFIT).unwrap();
    std::fs::set_permissions(&fake, std::os::unix::fs::PermissionsExt::from_mode(0o755)).unwrap();
    let tests: Vec<TestEntry> = (0..3)
        .map(|i| TestEntry {
            id: format!("t{i}"),
            campaign: PathBuf::from(format!("campaigns/t{i}.json")),
            out: PathBuf::from(format!("tests/t{i}")),
            seed: i,
            covariates: Vec::new(),
            source: String::new(),
            error: None,
            work: 0.0,
        })
        .collect();
    let mut manifest = Manifest {
        generator: "rigfit series".into(),
        name: "fake".into(),
        series_file: dir.path().join("series.json"),
        covariates: Vec::new(),
        tasks: Vec::new(),
        tests,
    };
    // Arrays of at most 2 tasks: tasks 0 and 1, then task 2 alone.
    let opts = PlanOptions {
        throttle: Some(THROTTLE),
        max_array_size: 3,
        time_limit: "5".into(),
        rigfit: fake.clone(),
        task_args: vec!["--backend".into(), "cpu".into()],
        ..PlanOptions::default()
    };
    let plan = write_plan(&root, &mut manifest, &opts).unwrap();
    assert_eq!(plan.arrays.len(), 2);

    let o = slurm("bash", &[plan.submit.to_str().unwrap()]);
    assert!(o.status.success(), "submit.sh: {}", text(&o));
    let out = String::from_utf8_lossy(&o.stdout).to_string();
    let ids: Vec<String> = out
        .lines()
        .filter_map(|l| l.split_whitespace().last().map(String::from))
        .collect();
    assert_eq!(ids.len(), 3, "submit.sh printed: {out}");
    let mut jobs = Jobs(ids.clone());
    let calls = root.join("calls");
    let read = || std::fs::read_to_string(&calls).unwrap_or_default();

    // Warn task 0 once it runs.
    while !read().contains("start 0 restart=0") {
        assert!(
            started.elapsed() < DEADLINE,
            "task 0 never started: {:?}",
            array_states(&ids[0])
        );
        std::thread::sleep(Duration::from_millis(50));
    }
    assert!(
        warn_task(&ids[0], 0),
        "task 0 of {} could not be signalled",
        ids[0]
    );
    while !ids.iter().all(|id| array_states(id).is_empty()) {
        assert!(
            started.elapsed() < DEADLINE,
            "the jobs did not end: {}",
            read()
        );
        std::thread::sleep(Duration::from_millis(100));
    }
    jobs.0.clear();
    let log = read();
    let lines: Vec<&str> = log.lines().collect();
    let at = |l: &str| {
        lines
            .iter()
            .position(|x| *x == l)
            .unwrap_or_else(|| panic!("no `{l}` in\n{log}"))
    };
    assert!(at("start 0 restart=0 args=--backend cpu") < at("interrupted 0"));
    assert!(at("interrupted 0") < at("start 0 restart=1 args=--backend cpu"));
    for task in 0..3 {
        assert_eq!(
            lines
                .iter()
                .filter(|l| **l == format!("done {task}"))
                .count(),
            1,
            "task {task}:\n{log}"
        );
    }
    assert!(
        lines.last().unwrap().starts_with("summary after"),
        "the summary did not run last:\n{log}"
    );
    // The second array waited for the first: the throttle holds over both.
    let first_done = at("done 0").max(at("done 1"));
    assert!(
        at("start 2 restart=0 args=--backend cpu") > first_done,
        "{log}"
    );
    let task_log =
        std::fs::read_to_string(root.join(format!("slurm/logs/{}_0.out", ids[0]))).unwrap();
    assert!(task_log.contains("requeued"), "{task_log}");
    assert_eq!(job_field(&ids[2], "JobState"), "COMPLETED");
    eprintln!(
        "series_slurm: the plan's scripts with a stand-in rigfit in {:.1?}",
        started.elapsed()
    );
}
