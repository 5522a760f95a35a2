//! The shipped campaign with its rig given each way (a shipped rig's id, a
//! rig file, the rig inline): each calibrates the shipped record (CPU path): R² ≥ 0.999 and the parameters the record pins down within
//! 3 % of the values that made it.

use std::path::Path;

use rigfit::campaign::Campaign;
use rigfit::eval::CpuEvaluator;
use rigfit::job::{self, JobOptions};
use serde_json::Value;

fn campaign_with(rig: Value) -> (tempfile::TempDir, Result<Campaign, String>) {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("campaigns");
    let mut v: Value = serde_json::from_str(
        &std::fs::read_to_string(dir.join("aa2024_t3_synthetic.json")).unwrap(),
    )
    .unwrap();
    let obj = v.as_object_mut().unwrap();
    obj.insert("rig".into(), rig);
    let csv = dir.join("aa2024_t3_v2_synthetic.csv");
    v["experiments"][0]["data"]["file"] = Value::String(csv.display().to_string());
    let tmp = tempfile::tempdir().unwrap();
    let path = tmp.path().join("c.json");
    std::fs::write(&path, v.to_string()).unwrap();
    let c = Campaign::load(&path).map_err(|e| e.to_string());
    (tmp, c)
}

#[test]
fn a_shipped_rig_by_id_calibrates_the_shipped_record() {
    let (_tmp, c) = campaign_with(Value::String("tensile4".into()));
    let mut c = c.unwrap();
    assert_eq!(c.model.id(), "tensile4");
    c.search.population = 512;
    c.search.generations = 150;
    c.search.target_fitness = Some(6e-5);
    let out = tempfile::tempdir().unwrap();
    let opts = JobOptions::quiet(out.path());
    let ev = Box::new(CpuEvaluator::new(c.problem.clone(), 0));
    let s = job::run(&c, ev, &opts).unwrap();
    let r2 = s.experiments[0].r2;
    println!("R² = {r2}");
    assert!(r2 >= 0.999, "R² = {r2}");
    let truth: Value = serde_json::from_str(
        &std::fs::read_to_string(
            Path::new(env!("CARGO_MANIFEST_DIR")).join("campaigns/aa2024_t3_reference_params.json"),
        )
        .unwrap(),
    )
    .unwrap();
    for name in ["k1", "v2.e_fracture"] {
        let p = s.parameters.iter().find(|p| p.name == name).unwrap();
        let t = truth["params"][name].as_f64().unwrap();
        let err = (p.value / t - 1.0).abs();
        println!(
            "{name}: {:.5e} (true {t:.5e}, error {:.2} %)",
            p.value,
            100.0 * err
        );
        assert!(err < 0.03, "{name} off by {err}");
    }
}

#[test]
fn a_rig_can_be_inline_and_its_errors_name_the_campaign_and_path() {
    let text = rigfit::rig::SHIPPED[0].1;
    let mut rig: Value = serde_json::from_str(text).unwrap();
    let (_tmp, c) = campaign_with(rig.clone());
    assert!(c.is_ok(), "{c:?}");
    rig["elements"][2]["spring"]["k"] = Value::String("k33".into());
    let (_tmp, c) = campaign_with(rig);
    let err = c.unwrap_err();
    assert!(
        err.contains("c.json: rig.elements[2].spring.k: expected a parameter"),
        "{err}"
    );
}

#[test]
fn an_unknown_rig_is_refused() {
    let (_tmp, c) = campaign_with(Value::String("tensile5".into()));
    let err = c.unwrap_err();
    assert!(
        err.contains(": rig: expected a shipped rig (tensile4, duffing_base, stick_slip, "),
        "{err}"
    );
}
