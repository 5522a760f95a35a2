//! The residuals the polish minimises are the fitness's: their sum of squares
//! over the record's variation is the campaign's `1 − R²`, and a run that blew
//! up or stopped short has none. With them, the history candidates a job keeps
//! put the best first, once.
mod oracle;

mod tensile_common;

use rigfit::eval::{Scores, score_one, simulate_history, window_residuals};
use rigfit::gpu::with_best;
use tensile_common::{REFERENCE, ix, reference_problem};

#[test]
fn sum_of_squares_over_ss_tot_is_the_fitness() {
    let mut problem = reference_problem();
    problem.experiments[0].window = 200..1500;
    let mut p = REFERENCE;
    p[ix::K1] *= 1.1;
    let h = simulate_history(&problem, 0, &p, 0.0);
    let exp = &problem.experiments[0];
    let r = window_residuals(exp, &h).unwrap();
    assert_eq!(r.len(), 1300);
    let ssr: f64 = r.iter().map(|x| x * x).sum();
    let (fit, diverged) = score_one(&problem, 0, &p, 0.0);
    assert!(!diverged);
    assert!(
        (ssr / exp.ss_tot() / fit - 1.0).abs() < 1e-12,
        "{ssr} vs {fit}"
    );
}

#[test]
fn a_blown_up_or_short_run_has_no_residuals() {
    let problem = reference_problem();
    let exp = &problem.experiments[0];
    let mut h = simulate_history(&problem, 0, &REFERENCE, 0.0);
    h.outputs[0][10] = f64::NAN;
    assert!(window_residuals(exp, &h).is_none());
    h.outputs[0].truncate(5);
    assert!(window_residuals(exp, &h).is_none());
}

#[test]
fn with_best_puts_the_best_candidate_first_once() {
    let problem = reference_problem();
    let scores = Scores {
        experiments: 1,
        values: vec![0.3, 0.1, rigfit::eval::DIVERGED, 0.2],
        diverged: 1,
    };
    assert_eq!(with_best(&problem, &scores, &[3]), vec![1, 3]);
    assert_eq!(with_best(&problem, &scores, &[1, 0]), vec![1, 0]);
}
