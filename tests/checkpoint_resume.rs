//! Proves checkpoints are safe and exact: a search interrupted (or killed) and
//! resumed ends bit-identical to one never interrupted; writes are atomic; a
//! checkpoint of a different campaign is refused, naming what changed.

use std::path::Path;
use std::sync::Arc;
use std::sync::atomic::AtomicBool;

use rigfit::base::Scale;
use rigfit::base::fsutil::temp_path_for;
use rigfit::search::{
    BatchCost, Checkpoint, CostBatch, Executor, Fingerprint, FnCost, GeneSpec, GeneticAlgorithm,
    ObserverMode, SearchError, SearchOutcome, SearchSettings, TerminationReason,
};

mod common;
use common::{InterruptAt, assert_same_result, rosenbrock, settings};

fn genes() -> Vec<GeneSpec> {
    vec![
        GeneSpec::new("k", 1e-2, 1e2, Scale::Log),
        GeneSpec::new("x", -2.0, 2.0, Scale::Linear),
    ]
}

fn base_settings(every: usize) -> SearchSettings {
    let mut s = settings(16, 40, 99);
    s.checkpoint_every = every;
    s
}

fn fingerprint(data: &str) -> Fingerprint {
    Fingerprint::new()
        .with("rig", "tensile4")
        .with("data", data)
}

/// The analytic cost every run here uses.
type Rosenbrock = FnCost<fn(&[f64]) -> f64>;

fn executor(s: SearchSettings) -> Executor<Rosenbrock> {
    let ga = GeneticAlgorithm::new(s, genes()).unwrap();
    Executor::new(ga, FnCost(rosenbrock as fn(&[f64]) -> f64)).fingerprint(fingerprint("abc"))
}

fn straight() -> SearchOutcome {
    executor(base_settings(0)).run().unwrap()
}

fn interrupted_at(path: &Path, at: usize, every: usize) -> SearchOutcome {
    let flag = Arc::new(AtomicBool::new(false));
    executor(base_settings(every))
        .checkpoint_to(path)
        .interrupt(flag.clone())
        .observe(InterruptAt { at, flag }, ObserverMode::Always)
        .run()
        .unwrap()
}

fn resumed(path: &Path) -> SearchOutcome {
    executor(base_settings(0))
        .checkpoint_to(path)
        .resume_from(path)
        .unwrap()
        .run()
        .unwrap()
}

#[test]
fn interrupted_then_resumed_equals_straight_run_bit_for_bit() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("checkpoint.json");
    let reference = straight();
    for at in [0, 1, 13, 38] {
        let stopped = interrupted_at(&path, at, 0);
        assert_eq!(stopped.termination, TerminationReason::Interrupted);
        assert_eq!(stopped.generations, at + 1);
        let out = resumed(&path);
        assert_same_result(&reference, &out);
        assert_eq!(out.termination, TerminationReason::MaxGenerations);
    }
}

/// Fails on its `fail_on`-th call, like a process killed mid-generation.
struct DiesAt {
    calls: usize,
    fail_on: usize,
}

impl BatchCost for DiesAt {
    fn cost(&mut self, genomes: &[Vec<f64>]) -> Result<CostBatch, SearchError> {
        self.calls += 1;
        if self.calls == self.fail_on {
            return Err(SearchError::Cost("killed".into()));
        }
        FnCost(rosenbrock).cost(genomes)
    }
}

#[test]
fn killed_run_resumes_from_last_periodic_checkpoint() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("checkpoint.json");
    let ga = GeneticAlgorithm::new(base_settings(5), genes()).unwrap();
    let err = Executor::new(
        ga,
        DiesAt {
            calls: 0,
            fail_on: 23,
        },
    )
    .fingerprint(fingerprint("abc"))
    .checkpoint_to(&path)
    .run()
    .unwrap_err();
    assert!(matches!(err, SearchError::Cost(_)));
    // Generations 0..=21 were evaluated; the last periodic save was after 19.
    assert_eq!(Checkpoint::load(&path).unwrap().state.generation, 19);
    assert_same_result(&straight(), &resumed(&path));
}

#[test]
fn resuming_a_finished_search_returns_the_same_outcome() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("checkpoint.json");
    let done = executor(base_settings(0))
        .checkpoint_to(&path)
        .run()
        .unwrap();
    let again = resumed(&path);
    assert_same_result(&done, &again);
    assert!(again.wall_time_s >= done.wall_time_s);
}

#[test]
fn checkpoint_write_never_uses_the_final_name_for_the_temp_file() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("checkpoint.json");
    assert_ne!(temp_path_for(&path).unwrap(), path);
    interrupted_at(&path, 3, 1);
    let names: Vec<String> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name().into_string().unwrap())
        .collect();
    assert_eq!(names, ["checkpoint.json"]);
}

#[test]
fn failing_write_leaves_the_previous_checkpoint() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("checkpoint.json");
    interrupted_at(&path, 4, 0);
    let before = std::fs::read(&path).unwrap();
    let old = Checkpoint::load(&path).unwrap();
    // A directory where the temporary file should go makes the write fail.
    std::fs::create_dir(temp_path_for(&path).unwrap()).unwrap();
    let mut newer = old.clone();
    newer.state.generation += 1;
    let err = newer.save(&path).unwrap_err();
    assert!(matches!(err, SearchError::Io { .. }), "{err}");
    assert_eq!(std::fs::read(&path).unwrap(), before);
    assert_eq!(Checkpoint::load(&path).unwrap(), old);
}

#[test]
fn changed_fingerprint_is_refused_naming_the_changed_key() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("checkpoint.json");
    interrupted_at(&path, 2, 0);
    let err = executor(base_settings(0))
        .fingerprint(fingerprint("abd"))
        .resume_from(&path)
        .unwrap()
        .run()
        .unwrap_err();
    match &err {
        SearchError::FingerprintMismatch { changed_keys, .. } => {
            assert_eq!(changed_keys, &["data"])
        }
        other => panic!("unexpected {other}"),
    }
    assert!(err.to_string().contains("data: abc → abd"), "{err}");

    let mut s = base_settings(0);
    s.population = 20;
    let err = executor(s).resume_from(&path).unwrap().run().unwrap_err();
    assert!(
        err.to_string().contains("search.population: 16 → 20"),
        "{err}"
    );
}

#[test]
fn corrupt_checkpoint_is_a_format_error() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("checkpoint.json");
    std::fs::write(&path, b"{\"format\": \"something else\"").unwrap();
    let err = executor(base_settings(0)).resume_from(&path).err().unwrap();
    assert!(matches!(err, SearchError::CheckpointFormat { .. }), "{err}");
}

/// Raises the interrupt flag during its `cancel_on`-th call and returns
/// [`EvalError::Cancelled`], like an evaluator stopped mid-generation.
struct CancelledAt {
    calls: usize,
    cancel_on: usize,
    flag: Arc<AtomicBool>,
}

impl BatchCost for CancelledAt {
    fn cost(&mut self, genomes: &[Vec<f64>]) -> Result<CostBatch, SearchError> {
        self.calls += 1;
        if self.calls == self.cancel_on {
            self.flag.store(true, std::sync::atomic::Ordering::SeqCst);
            return Err(SearchError::Eval(rigfit::eval::EvalError::Cancelled));
        }
        FnCost(rosenbrock).cost(genomes)
    }
}

#[test]
fn a_generation_cancelled_in_flight_is_dropped_and_resume_repeats_it_exactly() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("checkpoint.json");
    let flag = Arc::new(AtomicBool::new(false));
    let ga = GeneticAlgorithm::new(base_settings(0), genes()).unwrap();
    let cost = CancelledAt {
        calls: 0,
        cancel_on: 8,
        flag: flag.clone(),
    };
    let stopped = Executor::new(ga, cost)
        .fingerprint(fingerprint("abc"))
        .checkpoint_to(&path)
        .interrupt(flag)
        .run()
        .unwrap();
    assert_eq!(stopped.termination, TerminationReason::Interrupted);
    // Calls 1..=7 finished generations 0..=6; the eighth was dropped.
    assert_eq!(stopped.generations, 7);
    assert_eq!(Checkpoint::load(&path).unwrap().state.generation, 6);
    assert_same_result(&straight(), &resumed(&path));
}
