//! The record's noise estimated from the record itself: on every shipped
//! synthetic record (whose header says the noise it was made with) the
//! estimate is within 20 % of that noise, and a job reports it with the fit's
//! cost as a multiple of the floor it implies.

use std::path::Path;

use rigfit::base::noise::noise_sigma;
use rigfit::campaign::Campaign;
use serde_json::Value;

/// The `sigma = X` a synthetic record's header states, if any.
fn stated_sigma(csv: &Path) -> Option<f64> {
    let text = std::fs::read_to_string(csv).ok()?;
    let at = text.find("sigma = ")? + "sigma = ".len();
    text[at..].split_whitespace().next()?.parse().ok()
}

#[test]
fn every_synthetic_record_s_noise_is_found_within_twenty_percent() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("campaigns");
    let mut checked = 0;
    for entry in std::fs::read_dir(&dir).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_none_or(|e| e != "json") {
            continue;
        }
        let raw: Value = serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
        let Some(exps) = raw["experiments"].as_array() else {
            continue;
        };
        let c = Campaign::load(&path).unwrap();
        for (raw_e, e) in exps.iter().zip(&c.problem.experiments) {
            let Some(file) = raw_e["data"]["file"].as_str() else {
                continue;
            };
            let Some(sigma) = stated_sigma(&dir.join(file)) else {
                continue;
            };
            let est = noise_sigma(&e.measured[e.window.clone()]).unwrap();
            println!(
                "{} {}: stated {sigma:e}, estimated {est:e}",
                path.display(),
                e.name
            );
            assert!(
                (est / sigma - 1.0).abs() <= 0.2,
                "{} {}: estimated {est:e} against {sigma:e}",
                path.display(),
                e.name
            );
            checked += 1;
        }
    }
    assert!(checked >= 8, "only {checked} synthetic records checked");
}
