//! Proves the history observer writes a complete `history.csv`, also across a
//! resume.

use std::sync::Arc;
use std::sync::atomic::AtomicBool;

use rigfit::base::Scale;
use rigfit::search::{
    Executor, FnCost, GeneSpec, GeneticAlgorithm, HISTORY_COLUMNS, HistoryCsvObserver, ObserverMode,
};

mod common;
use common::{InterruptAt, settings, sphere};

fn genes() -> Vec<GeneSpec> {
    vec![
        GeneSpec::new("k", 1e-2, 1e2, Scale::Log),
        GeneSpec::new("x", -2.0, 2.0, Scale::Linear),
    ]
}

#[test]
fn history_csv_has_one_row_per_generation_across_resume() {
    let dir = tempfile::tempdir().unwrap();
    let (csv, cp) = (dir.path().join("history.csv"), dir.path().join("cp.json"));
    let flag = Arc::new(AtomicBool::new(false));
    let ga = || GeneticAlgorithm::new(settings(10, 12, 3), genes()).unwrap();
    Executor::new(ga(), FnCost(sphere(&[1.0, 0.0])))
        .checkpoint_to(&cp)
        .interrupt(flag.clone())
        .observe(InterruptAt { at: 4, flag }, ObserverMode::Always)
        .observe(
            HistoryCsvObserver::new(&csv, &genes()),
            ObserverMode::Every(3),
        )
        .run()
        .unwrap();
    let text = std::fs::read_to_string(&csv).unwrap();
    assert_eq!(text.lines().count(), 1 + 5);

    Executor::new(ga(), FnCost(sphere(&[1.0, 0.0])))
        .resume_from(&cp)
        .unwrap()
        .observe(
            HistoryCsvObserver::new(&csv, &genes()),
            ObserverMode::Always,
        )
        .run()
        .unwrap();
    let text = std::fs::read_to_string(&csv).unwrap();
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    assert_eq!(&header[..HISTORY_COLUMNS.len()], HISTORY_COLUMNS);
    assert_eq!(&header[HISTORY_COLUMNS.len()..], ["best_k", "best_x"]);
    let gens: Vec<usize> = lines
        .map(|l| l.split(',').next().unwrap().parse().unwrap())
        .collect();
    assert_eq!(gens, (0..12).collect::<Vec<_>>());
}
