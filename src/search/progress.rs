//! A terminal progress bar as an [`Observer`].

use std::io::IsTerminal;

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};

use super::SearchError;
use super::observers::Observer;
use super::polish::PolishIteration;
use super::report::{GenerationReport, SearchOutcome};

/// Shows generation, best R² (= 1 − best cost) and throughput on stderr.
///
/// Hidden when stderr is not a terminal or when built `quiet`, so logs and CI
/// output stay clean.
#[derive(Debug)]
pub struct ProgressObserver {
    bar: ProgressBar,
    steps_per_candidate: Option<f64>,
}

impl ProgressObserver {
    /// A bar for a search of at most `generations` generations.
    pub fn new(generations: usize, quiet: bool) -> Self {
        let bar = if quiet || !std::io::stderr().is_terminal() {
            ProgressBar::hidden()
        } else {
            ProgressBar::with_draw_target(Some(generations as u64), ProgressDrawTarget::stderr())
        };
        if let Ok(style) =
            ProgressStyle::with_template("{elapsed_precise} [{bar:30}] gen {pos}/{len} {msg}")
        {
            bar.set_style(style.progress_chars("=> "));
        }
        Self {
            bar,
            steps_per_candidate: None,
        }
    }

    /// Also shows candidate-steps/s: evaluations/s × `steps` (integration steps
    /// per candidate, summed over experiments).
    pub fn with_steps_per_candidate(mut self, steps: f64) -> Self {
        self.steps_per_candidate = Some(steps);
        self
    }

    /// Whether the bar draws anything.
    pub fn is_hidden(&self) -> bool {
        self.bar.is_hidden()
    }

    /// The status line shown next to the bar.
    pub fn message(&self, r: &GenerationReport) -> String {
        let mut msg = format!(
            "best R² {:.6}  {:.0} cand/s",
            1.0 - r.best_cost,
            r.evals_per_s
        );
        if let Some(steps) = self.steps_per_candidate {
            msg.push_str(&format!("  {:.3e} steps/s", r.evals_per_s * steps));
        }
        if r.diverged > 0 {
            msg.push_str(&format!("  {} diverged", r.diverged));
        }
        msg
    }
}

impl Observer for ProgressObserver {
    fn observe(&mut self, report: &GenerationReport) -> Result<(), SearchError> {
        self.bar.set_position(report.generation as u64 + 1);
        self.bar.set_message(self.message(report));
        Ok(())
    }

    fn polished(&mut self, step: &PolishIteration) -> Result<(), SearchError> {
        self.bar.set_message(format!(
            "polish iteration {}: best R² {:.6}, {} start(s) moving",
            step.iteration,
            1.0 - step.best_cost,
            step.moving
        ));
        Ok(())
    }

    fn resumed(&mut self, history: &[GenerationReport]) -> Result<(), SearchError> {
        if let Some(last) = history.last() {
            self.observe(last)?;
        }
        Ok(())
    }

    fn finish(&mut self, outcome: &SearchOutcome) -> Result<(), SearchError> {
        let mut msg = format!(
            "best R² {:.6} after {} generations ({})",
            1.0 - outcome.best_cost,
            outcome.generations,
            outcome.termination
        );
        if let Some(p) = &outcome.polish {
            msg.push_str(&format!(
                ", {:.6} after {} polish iterations",
                1.0 - p.best_cost,
                p.iterations
            ));
        }
        self.bar.abandon_with_message(msg);
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quiet_bar_is_hidden_and_message_shows_r2() {
        let p = ProgressObserver::new(10, true).with_steps_per_candidate(1000.0);
        assert!(p.is_hidden());
        let r = GenerationReport {
            generation: 0,
            best_cost: 0.25,
            median_cost: 0.5,
            best_genome: vec![],
            improved: true,
            diversity: 0.1,
            evaluations: 10,
            evaluated: 10,
            evals_per_s: 100.0,
            diverged: 0,
            diverged_runs: 0,
            elapsed_s: 0.1,
        };
        let m = p.message(&r);
        assert!(m.contains("0.750000") && m.contains("1.000e5"), "{m}");
    }
}
