//! A GPU that fails in the middle of a job: the job says so and finishes on the
//! CPU from the same generation, or, when the GPU is required, stops with its last
//! checkpoint kept.

use std::path::Path;
use std::sync::Arc;
use std::sync::atomic::AtomicBool;

use rigfit::campaign::Campaign;
use rigfit::eval::{
    Batch, CpuEvaluator, EvalError, Evaluator, EvaluatorInfo, History, Precision, Problem, Scores,
};
use rigfit::job::{self, JobError, JobOptions};

/// Scores like the CPU reference, but its `fail_at`-th call reports a lost device.
struct FlakyGpu {
    inner: CpuEvaluator,
    calls: usize,
    fail_at: usize,
}

impl Evaluator for FlakyGpu {
    fn info(&self) -> EvaluatorInfo {
        EvaluatorInfo {
            backend: "gpu".into(),
            device: "flaky test device".into(),
            precision: Precision::F64,
        }
    }

    fn fitness(&mut self, batch: &Batch) -> Result<Scores, EvalError> {
        self.calls += 1;
        if self.calls == self.fail_at {
            return Err(EvalError::Device("device lost (test)".into()));
        }
        self.inner.fitness(batch)
    }

    fn problem(&self) -> &Problem {
        self.inner.problem()
    }

    fn checked_histories(
        &mut self,
        batch: &Batch,
        which: &[usize],
    ) -> Result<Vec<Vec<History>>, EvalError> {
        self.inner.histories(batch, which)
    }
}

fn campaign() -> Campaign {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("campaigns/aa2024_t3_synthetic.json");
    let mut c = Campaign::load(&path).unwrap();
    c.search.population = 16;
    c.search.generations = 6;
    c.search.checkpoint_every = 1;
    c.search.stall_generations = None;
    c
}

fn options(out: &Path, require_gpu: bool) -> JobOptions {
    JobOptions {
        out: out.to_path_buf(),
        resume: false,
        quiet: true,
        interrupt: Arc::new(AtomicBool::new(false)),
        require_gpu,
        threads: 1,
    }
}

fn flaky(c: &Campaign) -> Box<dyn Evaluator> {
    Box::new(FlakyGpu {
        inner: CpuEvaluator::new(c.problem.clone(), 1),
        calls: 0,
        fail_at: 4,
    })
}

#[test]
fn lost_device_continues_on_the_cpu_with_the_same_result() {
    let c = campaign();
    let dir = tempfile::tempdir().unwrap();
    let summary = job::run(&c, flaky(&c), &options(dir.path(), false)).unwrap();
    assert_eq!(summary.generations, 6);
    assert_eq!(
        summary.backend, "cpu",
        "the result names the evaluator that finished"
    );
    assert!(
        summary
            .warnings
            .iter()
            .any(|w| w.contains("continuing on the CPU")),
        "{:?}",
        summary.warnings
    );

    // The CPU and the (here CPU-backed) device agree, so the search path is the
    // same as a job that never left the CPU.
    let straight_dir = tempfile::tempdir().unwrap();
    let cpu = Box::new(CpuEvaluator::new(c.problem.clone(), 1));
    let straight = job::run(&c, cpu, &options(straight_dir.path(), false)).unwrap();
    assert_eq!(summary.params, straight.params);
}

#[test]
fn required_gpu_stops_and_keeps_the_checkpoint() {
    let c = campaign();
    let dir = tempfile::tempdir().unwrap();
    let err = job::run(&c, flaky(&c), &options(dir.path(), true)).unwrap_err();
    assert!(matches!(err, JobError::Search(_)), "{err}");
    let chain = format!("{:?}", anyhow::Error::from(err));
    assert!(chain.contains("device lost"), "{chain}");
    assert!(dir.path().join(job::CHECKPOINT_FILE).is_file());
    assert!(!dir.path().join("result.json").exists());
}
