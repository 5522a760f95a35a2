//! An evaluator that answers one batch it has already scored from memory.
//!
//! `auto`'s trial ([`crate::job::backend::race`]) scores the search's first
//! generation on each path to time it; the path it keeps has then already
//! scored that generation, and the job asks for it again at once. Wrapped in
//! [`Remembered`], the evaluator answers that one request from memory (the
//! same scores: the same evaluator on the same batch, bit for bit) and every
//! other request as it would.

use super::{Batch, EvalError, Evaluator, EvaluatorInfo, History, Problem, Scores, Timed};

/// `inner`, with the scores of one batch kept for the first request of it.
pub struct Remembered {
    inner: Box<dyn Timed>,
    kept: Option<(Batch, Scores)>,
}

impl Remembered {
    /// `inner`, which scored `batch` as `scores`.
    pub fn new(inner: Box<dyn Timed>, batch: Batch, scores: Scores) -> Self {
        Self {
            inner,
            kept: Some((batch, scores)),
        }
    }
}

/// Whether `a` and `b` are the same batch, bit for bit.
fn same_batch(a: &Batch, b: &Batch) -> bool {
    let bits = |x: &Vec<Vec<f64>>, y: &Vec<Vec<f64>>| {
        x.len() == y.len()
            && x.iter().zip(y).all(|(u, v)| {
                u.len() == v.len() && u.iter().zip(v).all(|(p, q)| p.to_bits() == q.to_bits())
            })
    };
    a.candidates == b.candidates && bits(&a.params, &b.params) && bits(&a.offsets, &b.offsets)
}

impl Evaluator for Remembered {
    fn info(&self) -> EvaluatorInfo {
        self.inner.info()
    }

    fn problem(&self) -> &Problem {
        self.inner.problem()
    }

    /// The kept scores for the kept batch, the first time it is asked for
    /// first; the inner evaluator's for anything else (and from then on).
    fn fitness(&mut self, batch: &Batch) -> Result<Scores, EvalError> {
        match self.kept.take() {
            Some((kept, scores)) if same_batch(&kept, batch) => {
                log::info!(
                    "{} candidates answered from memory: the backend trial scored them on this path",
                    batch.candidates
                );
                Ok(scores)
            }
            _ => self.inner.fitness(batch),
        }
    }

    fn checked_histories(
        &mut self,
        batch: &Batch,
        which: &[usize],
    ) -> Result<Vec<Vec<History>>, EvalError> {
        self.inner.checked_histories(batch, which)
    }

    fn checked_scored_outputs(
        &mut self,
        batch: &Batch,
        which: &[usize],
    ) -> Result<Vec<Vec<Vec<f64>>>, EvalError> {
        self.inner.checked_scored_outputs(batch, which)
    }

    fn set_cancel(&mut self, flag: std::sync::Arc<std::sync::atomic::AtomicBool>) {
        self.inner.set_cancel(flag);
    }
}

impl Timed for Remembered {
    fn warm_up(&mut self, batch: &Batch) -> Result<(), EvalError> {
        self.inner.warm_up(batch)
    }

    fn fitness_part(&mut self, batch: &Batch, steps: usize) -> Result<Option<usize>, EvalError> {
        self.inner.fitness_part(batch, steps)
    }

    fn prepare(&mut self) {
        self.inner.prepare();
    }

    fn prepare_soon(&mut self) {
        self.inner.prepare_soon();
    }

    fn kernel_variants(&self) -> &'static [&'static str] {
        self.inner.kernel_variants()
    }

    fn use_kernel_variant(&mut self, variant: &str) {
        self.inner.use_kernel_variant(variant);
    }
}

#[cfg(test)]
mod tests {
    use std::sync::Arc;
    use std::sync::atomic::{AtomicUsize, Ordering};

    use super::*;

    /// Scores each candidate by its first parameter, counting the batches
    /// it is asked to score.
    struct Counting {
        problem: Problem,
        calls: Arc<AtomicUsize>,
    }

    impl Evaluator for Counting {
        fn info(&self) -> EvaluatorInfo {
            EvaluatorInfo {
                backend: "cpu".into(),
                device: "test".into(),
                precision: super::super::Precision::F64,
            }
        }
        fn problem(&self) -> &Problem {
            &self.problem
        }
        fn fitness(&mut self, batch: &Batch) -> Result<Scores, EvalError> {
            self.calls.fetch_add(1, Ordering::Relaxed);
            Ok(Scores {
                experiments: 1,
                values: (0..batch.candidates)
                    .map(|i| batch.params_of(0, i)[0])
                    .collect(),
                diverged: 0,
            })
        }
        fn checked_histories(
            &mut self,
            _batch: &Batch,
            _which: &[usize],
        ) -> Result<Vec<Vec<History>>, EvalError> {
            Ok(vec![])
        }
    }

    impl Timed for Counting {}

    fn batch(first: f64) -> Batch {
        Batch {
            candidates: 2,
            params: vec![vec![first, 1.0, 2.0, 3.0]],
            offsets: vec![vec![0.0, 0.0]],
        }
    }

    #[test]
    fn the_kept_batch_is_answered_once_and_anything_else_is_scored() {
        let path = std::path::Path::new("campaigns/quarter_car_synthetic.json");
        let problem = crate::campaign::Campaign::load(path)
            .expect("a shipped campaign")
            .problem;
        let calls = Arc::new(AtomicUsize::new(0));
        let counting = || Counting {
            problem: problem.clone(),
            calls: calls.clone(),
        };
        let kept = counting().fitness(&batch(0.5)).unwrap();
        let mut r = Remembered::new(Box::new(counting()), batch(0.5), kept.clone());
        let before = calls.load(Ordering::Relaxed);
        // The kept batch, from memory: nothing scored.
        assert_eq!(r.fitness(&batch(0.5)).unwrap(), kept);
        assert_eq!(calls.load(Ordering::Relaxed), before);
        // Asked again, it is scored: memory answers once.
        assert_eq!(r.fitness(&batch(0.5)).unwrap(), kept);
        assert_eq!(calls.load(Ordering::Relaxed), before + 1);
        // A batch one bit away is scored, and the memory is gone.
        let mut r = Remembered::new(Box::new(counting()), batch(0.5), kept);
        let nudged = f64::from_bits(0.5f64.to_bits() + 1);
        assert_eq!(r.fitness(&batch(nudged)).unwrap().values[0], nudged);
        assert_eq!(calls.load(Ordering::Relaxed), before + 2);
        r.fitness(&batch(0.5)).unwrap();
        assert_eq!(calls.load(Ordering::Relaxed), before + 3);
    }
}
