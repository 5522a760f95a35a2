//! A search cut short by its generation limit while its best was still
//! falling says so: the shipped example with 12 generations of 64 warns that
//! the search was still improving, in the job's warnings and in result.json.

use std::path::Path;

use rigfit::campaign::Campaign;
use rigfit::eval::CpuEvaluator;
use rigfit::job::{self, JobOptions};

#[test]
fn a_search_stopped_while_improving_warns() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("campaigns/aa2024_t3_synthetic.json");
    let mut c = Campaign::load(&path).unwrap();
    c.search.population = 64;
    c.search.generations = 12;
    c.search.stall_generations = None;
    let tmp = tempfile::tempdir().unwrap();
    let out = tmp.path().join("out");
    let s = job::run(
        &c,
        Box::new(CpuEvaluator::new(c.problem.clone(), 0)),
        &JobOptions::quiet(&out),
    )
    .unwrap();
    println!(
        "{} after {} generations: {:?}",
        s.stop_reason, s.generations, s.warnings
    );
    assert_eq!(s.stop_reason, "maximum number of generations reached");
    let w = s
        .warnings
        .iter()
        .find(|w| w.starts_with("the search was still improving when it stopped"))
        .unwrap_or_else(|| panic!("no warning in {:?}", s.warnings));
    assert!(w.contains("generations"), "{w}");
    let r = std::fs::read_to_string(out.join("result.json")).unwrap();
    assert!(r.contains("the search was still improving"), "{r}");
}
