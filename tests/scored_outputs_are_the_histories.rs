//! What the polish asks of the CPU lanes, the scored output alone
//! (`Evaluator::scored_outputs`, the scoring rig's output 0 without the
//! rest of the report), is its full histories' scored output, bit for bit:
//! on channel campaigns (an experiment scored on an output other than the
//! rig's first), on a closed loop with a controller, for runs advanced
//! together and for runs of clock offsets of their own.

use std::path::Path;

use rigfit::campaign::Campaign;
use rigfit::eval::{CpuEvaluator, Evaluator};

fn campaign(name: &str) -> Campaign {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("campaigns")
        .join(name);
    Campaign::load(&path).unwrap()
}

fn check(name: &str, n: usize) {
    let c = campaign(name);
    // Candidates spread over the genes' bounds, seeded by their index.
    let genomes: Vec<Vec<f64>> = (0..n)
        .map(|i| {
            c.genes
                .iter()
                .enumerate()
                .map(|(j, g)| {
                    let u = ((i * 7 + j * 3) % 11) as f64 / 10.0;
                    g.lower + (g.upper - g.lower) * (0.25 + 0.5 * u)
                })
                .collect()
        })
        .collect();
    let mut batch = c.batch(&genomes);
    // The last candidate on a clock offset of its own in every experiment:
    // it runs apart from the others.
    for offsets in &mut batch.offsets {
        if let Some(last) = offsets.last_mut() {
            *last += 1e-7;
        }
    }
    let which: Vec<usize> = (0..n).collect();
    let mut cpu = CpuEvaluator::new(c.problem.clone(), 0);
    let hist = cpu.histories(&batch, &which).unwrap();
    let scored = cpu.scored_outputs(&batch, &which).unwrap();
    assert_eq!(scored.len(), n);
    let mut compared = 0;
    for (i, (s, h)) in scored.iter().zip(&hist).enumerate() {
        assert_eq!(s.len(), c.problem.experiments.len());
        for (e, (se, he)) in s.iter().zip(h).enumerate() {
            let want = &he.outputs[c.problem.experiments[e].output];
            assert_eq!(se.len(), want.len(), "{name} candidate {i} run {e}");
            for (k, (x, y)) in se.iter().zip(want).enumerate() {
                assert_eq!(
                    x.to_bits(),
                    y.to_bits(),
                    "{name} candidate {i} run {e} sample {k}: {x} vs {y}"
                );
                compared += 1;
            }
        }
    }
    assert!(compared > 0);
}

#[test]
fn bearing_channels_scored_outputs_are_the_histories() {
    let c = campaign("bearing_2dof_channels_synthetic.json");
    assert!(c.problem.experiments.iter().any(|x| x.output != 0));
    check("bearing_2dof_channels_synthetic.json", 12);
}

#[test]
fn quarter_car_channels_scored_outputs_are_the_histories() {
    check("quarter_car_channels_synthetic.json", 12);
}

#[test]
fn emps_closed_loop_scored_outputs_are_the_histories() {
    check("emps_closed_loop.json", 6);
}
