//! A job's memory is estimated before any work: one that will not fit is
//! refused with the estimate and the limit, and a valid large population runs
//! in bounded memory, its evaluation chunked through the evaluator with the
//! same costs as in one piece.

use std::path::{Path, PathBuf};
use std::process::Command;

use serde_json::{Value, json};

use rigfit::campaign::Campaign;
use rigfit::eval::CpuEvaluator;
use rigfit::job::CampaignCost;
use rigfit::job::memory::{MIB, MemoryEstimate};
use rigfit::search::{BatchCost, ResidualCost};

fn rigfit() -> Command {
    Command::new(env!("CARGO_BIN_EXE_rigfit"))
}

fn repo() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

/// The shipped campaign with `experiments` copies of its experiment, each fit
/// over the record's first `samples` samples with its own parameters fixed
/// (five genes in all), on the CPU, without the polish, written to
/// `dir/c.json` with `output` = `out`.
fn campaign(dir: &Path, experiments: usize, samples: usize, population: usize) -> PathBuf {
    let text = std::fs::read_to_string(repo().join("campaigns/aa2024_t3_synthetic.json")).unwrap();
    let mut c: Value = serde_json::from_str(&text).unwrap();
    let record = repo().join("campaigns/aa2024_t3_v2_synthetic.csv");
    let mut exp = c["experiments"][0].clone();
    exp["data"]["file"] = json!(record.to_str().unwrap());
    // The record's samples are 1 µs apart.
    exp["fit_window"] = json!({"start": 0.0, "end": (samples - 1) as f64 * 1e-6});
    exp["params"]["k_lin"] = json!(8.63e7);
    exp["params"]["e_fracture"] = json!(1e-3);
    c["experiments"] = (0..experiments)
        .map(|i| {
            let mut e = exp.clone();
            e["name"] = json!(format!("v{i}"));
            e
        })
        .collect();
    c["search"]["population"] = json!(population);
    c["search"]["generations"] = json!(2);
    c["search"]["polish"] = json!({"enabled": false});
    c["solver"]["backend"] = json!("cpu");
    c["output"] = json!("out");
    let path = dir.join("c.json");
    std::fs::write(&path, serde_json::to_string_pretty(&c).unwrap()).unwrap();
    path
}

#[test]
fn a_billion_candidates_are_refused_with_the_estimate_and_the_limit() {
    let dir = tempfile::tempdir().unwrap();
    let c = campaign(dir.path(), 1, 20, 1_000_000_000);
    // From the campaign, against the memory available now and against a flag.
    for extra in [&[][..], &["--max-memory", "1G"][..]] {
        let o = rigfit().arg("run").arg(&c).args(extra).output().unwrap();
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(2), "{err}");
        assert!(
            err.contains("c.json: search.population: expected a job that fits in"),
            "{err}"
        );
        assert!(
            err.contains("the search's 1000000000 genomes of 5 genes"),
            "{err}"
        );
        assert!(err.contains("GiB"), "{err}");
        assert_eq!(err.lines().count(), 1, "{err}");
        assert!(
            !dir.path().join("out").exists(),
            "the output folder was created"
        );
    }
    // `check` tells, and leaves the refusal to `run`.
    let o = rigfit().arg("check").arg(&c).output().unwrap();
    let text = String::from_utf8_lossy(&o.stdout);
    assert_eq!(
        o.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    assert!(
        text.contains("memory at population 1000000000: about"),
        "{text}"
    );
    assert!(text.contains("(run will refuse it"), "{text}");
    let o = rigfit()
        .arg("run")
        .arg(&c)
        .args(["--population", "1000000000", "--max-memory", "1G"])
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(
        err.contains(
            "--population 1000000000: expected a job that fits in 1.00 GiB (--max-memory)"
        ),
        "{err}"
    );
    assert!(err.contains("raise --max-memory"), "{err}");
    assert!(!dir.path().join("out").exists());
}

#[test]
fn a_population_that_fits_only_in_chunks_runs_within_max_memory() {
    let dir = tempfile::tempdir().unwrap();
    let population = 50_000;
    let c = campaign(dir.path(), 16, 12, population);
    let limit = 100.0 * MIB;
    // The premise: evaluated whole, a fifth of this population would not fit;
    // in chunks, all of it does.
    let estimate = MemoryEstimate::of(&Campaign::load(&c).unwrap(), None);
    assert!(estimate.chunk < population / 4, "{estimate}");
    assert!(estimate.total <= limit, "{estimate}");
    let whole = estimate.total - estimate.evaluation + estimate.unchunked_evaluation;
    assert!(whole > limit, "{estimate}");
    let fits_whole = (limit - estimate.base - estimate.histories)
        / ((estimate.search + estimate.unchunked_evaluation) / population as f64);
    assert!(
        population as f64 > 3.0 * fits_whole,
        "{fits_whole} {estimate}"
    );

    let o = rigfit()
        .arg("run")
        .arg(&c)
        .args(["--max-memory", "100M", "--threads", "2"])
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(0), "{err}");
    let result: Value =
        serde_json::from_slice(&std::fs::read(dir.path().join("out/result.json")).unwrap())
            .unwrap();
    assert_eq!(result["evaluations"], json!(2 * population - 2), "{result}");
    // Where the system reports it, the measured peak stays under the limit.
    if let Some(peak) = result["peak_memory_mib"].as_f64() {
        assert!(
            peak * MIB <= limit,
            "peak {peak} MiB over the 100 MiB limit"
        );
    }
}

#[test]
fn chunked_costs_and_residuals_are_those_of_one_piece() {
    let dir = tempfile::tempdir().unwrap();
    let c = Campaign::load(&campaign(dir.path(), 2, 30, 8)).unwrap();
    let genomes: Vec<Vec<f64>> = (0..37)
        .map(|i| {
            let s = i as f64 / 37.0;
            c.genes
                .iter()
                .map(|g| g.lower + s * (g.upper - g.lower))
                .collect()
        })
        .collect();
    let cost = |fitness: usize, histories: usize| {
        let ev = Box::new(CpuEvaluator::new(c.problem.clone(), 2));
        CampaignCost::new(&c, ev, false, 2).with_chunks(fitness, histories)
    };
    let (mut whole, mut chunked) = (cost(1 << 20, 1 << 20), cost(5, 3));
    let (a, b) = (
        whole.cost(&genomes).unwrap(),
        chunked.cost(&genomes).unwrap(),
    );
    assert_eq!(a.costs.len(), genomes.len());
    let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    assert_eq!(bits(&a.costs), bits(&b.costs));
    assert_eq!(a.diverged, b.diverged);
    let (ra, rb) = (
        whole.residuals(&genomes[..11]).unwrap(),
        chunked.residuals(&genomes[..11]).unwrap(),
    );
    assert_eq!(ra.len(), 11);
    for (x, y) in ra.iter().zip(&rb) {
        assert_eq!(bits(x.as_ref().unwrap()), bits(y.as_ref().unwrap()));
    }
}
