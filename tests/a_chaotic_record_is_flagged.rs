//! A chaotic record is flagged, not given zero-width intervals: the forced
//! double-well Duffing oscillator `x'' + 0.3 x' − x + x³ = 0.5 sin(1.2 t)`
//! (Guckenheimer and Holmes, "Nonlinear Oscillations, Dynamical Systems, and
//! Bifurcations of Vector Fields", 1983) over 400 s, sampled at 20 Hz with
//! 0.01 m of noise, fitted for its stiffnesses and damping. A change of 1e-8
//! in a parameter grows until it changes the response as much as the
//! response itself, so no fit's intervals mean anything beyond that time:
//! the job says from when the response is sensitive, marks no parameter
//! determined, suggests a window that ends before it, and advises no step
//! count out of reach. A shipped record that is not chaotic gets none of it.

use std::path::Path;

use rand::SeedableRng;
use rigfit::campaign::Campaign;
use rigfit::eval::{CpuEvaluator, simulate_history};
use rigfit::job::{self, JobOptions, JobSummary};
use serde_json::{Value, json};

const DT: f64 = 0.05;
const SAMPLES: usize = 8000;
const SIGMA: f64 = 0.01;

fn rig() -> Value {
    json!({
        "id": "double_well",
        "doc": "A mass in a double-well potential (negative linear, positive cubic stiffness), damped, under a sine force.",
        "params": [
            {"name": "m", "unit": "kg", "doc": "mass", "scale": "log"},
            {"name": "k", "unit": "N/m", "doc": "linear stiffness (negative: the well's hump)"},
            {"name": "k3", "unit": "N/m^3", "doc": "cubic stiffness"},
            {"name": "c", "unit": "N·s/m", "doc": "viscous damping"},
            {"name": "amplitude", "unit": "N", "doc": "force amplitude"},
            {"name": "frequency", "unit": "Hz", "doc": "force frequency"}
        ],
        "nodes": [{"name": "mass", "mass": "m"}],
        "elements": [{
            "name": "spring",
            "between": ["ground", "mass"],
            "spring": {"law": "polynomial", "coeffs": [0.0, "k", 0.0, "k3"]},
            "damper": {"law": "viscous", "c": "c"}
        }],
        "drives": [{"node": "mass", "law": {"type": "sine", "quantity": "force",
                    "amplitude": "amplitude", "frequency": "frequency"}}],
        "outputs": [{"name": "x", "unit": "m", "sum": [{"displacement": "mass"}]}],
        "reach": {"elongation": 2.5, "rate": 3.0}
    })
}

fn campaign_json(file: &str) -> String {
    json!({
        "name": "double-well",
        "rig": rig(),
        "params": {
            "m": 1.0,
            "k": {"min": -1.05, "max": -0.95},
            "k3": {"min": 0.95, "max": 1.05},
            "c": {"min": 0.285, "max": 0.315},
            "amplitude": 0.5,
            "frequency": 1.2 / (2.0 * std::f64::consts::PI)
        },
        "experiments": [{"name": "forced", "data": {"file": file}}],
        "solver": {"substeps": 4, "backend": "cpu"},
        "search": {"population": 32, "generations": 3, "seed": 2,
                   "polish": {"starts": 3, "max_iterations": 10}}
    })
    .to_string()
}

fn write_csv(path: &Path, values: impl Iterator<Item = f64>) {
    let mut s = String::from("t_s,x_m\n");
    for (k, x) in values.enumerate() {
        s += &format!("{:e},{x:e}\n", k as f64 * DT);
    }
    std::fs::write(path, s).unwrap();
}

/// The record: the true rig at 64 steps per sample, with Gaussian noise.
fn chaotic_campaign(dir: &Path) -> Campaign {
    let placeholder = (0..SAMPLES).map(|k| (k as f64 * DT).sin());
    write_csv(&dir.join("record.csv"), placeholder);
    let c = Campaign::from_str(&campaign_json("record.csv"), dir, "double_well.json").unwrap();
    let mut fine = c.problem.clone();
    fine.substeps = 64;
    let truth: Vec<f64> = c
        .genes
        .iter()
        .map(|g| match g.name.as_str() {
            "k" => -1.0,
            "k3" => 1.0,
            "c" => 0.3,
            other => panic!("gene {other}"),
        })
        .collect();
    let (p, offset) = c.full_params(&truth).remove(0);
    let h = simulate_history(&fine, 0, &p, offset);
    assert_eq!(h.outputs[0].len(), SAMPLES);
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(11);
    let noisy: Vec<f64> = h.outputs[0]
        .iter()
        .map(|x| x + SIGMA * rigfit::base::noise::gaussian(&mut rng))
        .collect();
    // It crosses between the wells: the chaotic regime, not a periodic orbit
    // in one well.
    let crossings = h.outputs[0]
        .windows(2)
        .filter(|w| w[0] * w[1] < 0.0)
        .count();
    assert!(crossings > 20, "{crossings} crossings");
    write_csv(&dir.join("record.csv"), noisy.into_iter());
    Campaign::from_str(&campaign_json("record.csv"), dir, "double_well.json").unwrap()
}

fn fit(c: &Campaign, out: &Path) -> JobSummary {
    job::run(
        c,
        Box::new(CpuEvaluator::new(c.problem.clone(), 0)),
        &JobOptions::quiet(out),
    )
    .unwrap()
}

fn sensitive_warning(s: &JobSummary) -> Option<&String> {
    s.warnings
        .iter()
        .find(|w| w.starts_with("the response is sensitive to tiny changes"))
}

#[test]
fn a_chaotic_record_is_flagged_with_no_parameter_determined() {
    let tmp = tempfile::tempdir().unwrap();
    let c = chaotic_campaign(tmp.path());
    let out = tmp.path().join("out");
    let s = fit(&c, &out);
    for p in s.parameters.iter().filter(|p| p.free) {
        println!(
            "{} = {:.6} ± {:?} {:?} determined {:?}",
            p.name, p.value, p.std_error, p.interval_95, p.determined
        );
    }
    println!("verdict: {}\n{:#?}", s.verdict.line, s.warnings);
    let sens = s.sensitivity.as_ref().expect("a check after the polish");
    println!("{sens:?}");
    assert!(sens.sensitive);
    let e = &sens.experiments[0];
    let t = e.sensitive_from_s.unwrap();
    assert!(t > 0.0 && t < SAMPLES as f64 * DT, "{t}");
    let [start, end] = e.suggested_window_s.unwrap();
    assert!(
        start == 0.0 && end > 0.0 && end < t,
        "[{start}, {end}] against {t}"
    );
    // No parameter is determined, each says why.
    for p in s.parameters.iter().filter(|p| p.free) {
        assert_eq!(p.determined, Some(false), "{}", p.name);
        let note = p.uncertainty_note.as_deref().unwrap_or_default();
        assert!(
            note.contains("sensitive to tiny changes"),
            "{}: {note}",
            p.name
        );
    }
    assert_eq!(s.verdict.determined, 0);
    assert!(
        s.verdict
            .flags
            .iter()
            .any(|f| f.starts_with("response sensitive to tiny changes")),
        "{:?}",
        s.verdict.flags
    );
    let w = sensitive_warning(&s).unwrap_or_else(|| panic!("{:?}", s.warnings));
    assert!(
        w.contains("\"fit_window\": {\"start\": 0, \"end\": "),
        "{w}"
    );
    // No integration-error advice beyond 64 times the job's steps.
    for w in &s.warnings {
        if let Some(i) = w.find("\"substeps\": ") {
            let n: usize = w[i + 12..]
                .split(|c: char| !c.is_ascii_digit())
                .next()
                .unwrap()
                .parse()
                .unwrap();
            assert!(n <= 64 * c.solver.substeps, "{w}");
        }
    }
    // result.json says the same.
    let r: Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("result.json")).unwrap()).unwrap();
    assert_eq!(r["sensitivity"]["sensitive"], true);
    assert!(
        r["verdict"]["line"]
            .as_str()
            .unwrap()
            .contains("0 of 3 parameters determined")
    );
    assert!(
        r["parameters"]
            .as_array()
            .unwrap()
            .iter()
            .filter(|p| p["free"] == true)
            .all(|p| p["determined"] == false)
    );
}

#[test]
fn a_record_that_is_not_chaotic_is_not_flagged() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("campaigns/aa2024_t3_synthetic.json");
    let mut c = Campaign::load(&path).unwrap();
    c.search.population = 64;
    c.search.generations = 12;
    let tmp = tempfile::tempdir().unwrap();
    let s = fit(&c, &tmp.path().join("out"));
    let sens = s.sensitivity.as_ref().expect("a check after the polish");
    println!("{sens:?}\nverdict: {}", s.verdict.line);
    assert!(!sens.sensitive);
    assert!(
        sens.experiments
            .iter()
            .all(|e| e.sensitive_from_s.is_none())
    );
    // The linear part dominates: the check sees the response's own scale.
    assert!(
        sens.experiments
            .iter()
            .all(|e| e.largest_nonlinear_share < 0.1),
        "{sens:?}"
    );
    assert!(sensitive_warning(&s).is_none(), "{:?}", s.warnings);
    assert!(s.parameters.iter().filter(|p| p.free).all(|p| {
        !p.uncertainty_note
            .as_deref()
            .is_some_and(|n| n.contains("sensitive"))
    }));
    assert!(s.verdict.determined > 0, "{}", s.verdict.line);
}
