//! Every shipped sweep file (`campaigns/design/*.sweep.json`) reads and
//! validates against its campaign and rig: its variables name the rig's
//! parameters, its metrics the rig's outputs, its formulas the metrics
//! before them. The calibration a sweep names in `"params"` (a job's
//! `result.json` under `results/`) is made by `rigfit run`, not shipped, so
//! it and the `"uncertainty"` that reads it are left out here;
//! `tests/sweep_bands_cover_the_truth.rs` runs both.

use std::path::Path;

use rigfit::design::Sweep;

#[test]
fn shipped_sweep_files_validate() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("campaigns/design");
    let mut files: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.to_string_lossy().ends_with(".sweep.json"))
        .collect();
    files.sort();
    assert!(files.len() >= 4, "{files:?}");
    for f in files {
        let mut v: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(&f).unwrap()).unwrap();
        let o = v.as_object_mut().unwrap();
        o.remove("params");
        o.remove("uncertainty");
        let s = Sweep::from_text(&v.to_string(), &f).unwrap_or_else(|e| panic!("{e}"));
        assert!(s.points() >= 16, "{}: {} points", f.display(), s.points());
    }
}
