//! Records lent from memory ([`rigfit::record::lent`]; the Python package's
//! `Campaign.set_data` lends a DataFrame's columns so): a campaign built from
//! a record's columns in memory holds the very samples its file gives, is
//! never read from disk under the lent path, names the record's format as
//! `memory` with the SHA-256 of what it read, and reads an initial state from
//! a column of such a record as from a CSV file's.

use std::path::Path;
use std::sync::Arc;

use rigfit::campaign::Campaign;
use rigfit::record::lent::{Lent, Loan, record_of};
use rigfit::record::{Format, Record};
use serde_json::{Value, json};
use sha2::{Digest, Sha256};

fn shipped_csv_campaign() -> (std::path::PathBuf, Value) {
    let path =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("campaigns/formats/aa2024_t3_v2_csv.json");
    let text = std::fs::read_to_string(&path).unwrap();
    (path, serde_json::from_str(&text).unwrap())
}

/// The channels of the CSV file at `path` as arrays in memory.
fn columns_of(path: &Path) -> Record {
    let bytes = std::fs::read(path).unwrap();
    let csv = rigfit::record::detect::read_any(Format::Csv, &bytes, path).unwrap();
    let names = csv.channels.iter().map(|c| c.name.clone()).collect();
    let columns = csv.channels.into_iter().map(|c| c.values).collect();
    record_of(names, columns).unwrap()
}

#[test]
fn a_record_lent_from_memory_builds_what_its_file_builds() {
    let (path, raw) = shipped_csv_campaign();
    let dir = path.parent().unwrap();
    let from_file = Campaign::load(&path).unwrap();
    let csv = dir.join(raw["experiments"][0]["data"]["file"].as_str().unwrap());
    let record = Arc::new(columns_of(&csv));

    // Under a name no file has: a read from disk would fail.
    let mut raw = raw.clone();
    raw["experiments"][0]["data"]["file"] = json!("<memory:v2>.csv");
    let lent_path = dir.join("<memory:v2>.csv");
    assert!(!lent_path.exists());
    let mut lent = Lent::none();
    lent.lend(lent_path.clone(), Loan::Record(record.clone()));
    let origin = path.to_str().unwrap();
    let c = Campaign::from_str_lent(&raw.to_string(), dir, origin, &lent, None).unwrap();

    let (a, b) = (&from_file.problem.experiments[0], &c.problem.experiments[0]);
    assert_eq!(a.t_first.to_bits(), b.t_first.to_bits());
    assert_eq!(a.dt.to_bits(), b.dt.to_bits());
    assert_eq!(a.window, b.window);
    let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    assert_eq!(bits(&a.measured), bits(&b.measured));
    assert_eq!(from_file.solver.substeps, c.solver.substeps);

    let used = &c.records[0];
    assert_eq!(used.format, "memory");
    assert_eq!(used.file, lent_path);
    let digest = Loan::Record(record).digest_bytes().into_owned();
    assert_eq!(used.sha256, <[u8; 32]>::from(Sha256::digest(&digest)));
    assert_eq!(from_file.records[0].format, "csv");
    assert_eq!(
        from_file.records[0].sha256,
        <[u8; 32]>::from(Sha256::digest(std::fs::read(&csv).unwrap()))
    );
    // Nothing lent: the same text names a file that does not exist.
    let none = Campaign::from_str_lent(&raw.to_string(), dir, origin, &Lent::none(), None);
    let Err(e) = none else {
        panic!("no file under the lent name")
    };
    assert!(e.to_string().contains("<memory:v2>.csv"), "{e}");
}

#[test]
fn an_initial_state_is_read_from_a_column_of_a_record_in_memory() {
    let dt = 1e-4;
    let n = 200;
    let t: Vec<f64> = (0..n).map(|k| k as f64 * dt).collect();
    let force = t.iter().map(|t| (t * 300.0).sin()).collect();
    let pos = t.iter().map(|t| 0.002 + 0.3 * t).collect();
    let names = ["t_s", "force_N", "pos_m"].map(String::from).to_vec();
    let record = record_of(names, vec![t, force, pos]).unwrap();
    let v = json!({
        "name": "initial-from-memory",
        "rig": {
            "id": "msd",
            "params": [
                {"name": "m", "unit": "kg", "default": 1.0},
                {"name": "k", "unit": "N/m", "default": 1e4},
                {"name": "c", "unit": "N·s/m", "default": 2.0}
            ],
            "nodes": [{"name": "mass", "mass": "m"}],
            "elements": [{"name": "spring", "between": ["ground", "mass"],
                "spring": {"law": "linear", "k": "k"}, "damper": {"law": "viscous", "c": "c"}}],
            "outputs": [{"name": "force", "unit": "N", "sum": [{"force": "spring"}]}]
        },
        "params": {"k": {"min": 1e3, "max": 1e5}},
        "experiments": [{
            "name": "e1",
            "data": {"file": "e1", "time_column": "t_s", "force_column": "force_N"},
            "initial": {"x_mass": {"column": "pos_m"}, "v_mass": {"column": "pos_m"}}
        }],
        "solver": {"substeps": 4, "backend": "cpu"}
    });
    let dir = tempfile::tempdir().unwrap();
    let mut lent = Lent::none();
    lent.lend(dir.path().join("e1"), Loan::Record(Arc::new(record)));
    let c = Campaign::from_str_lent(&v.to_string(), dir.path(), "c.json", &lent, None).unwrap();
    let params = c.model.params();
    let ix = |name: &str| params.iter().position(|p| p.name == name).unwrap();
    let (x0, v0) = (
        c.base[0][ix("initial_x_mass")],
        c.base[0][ix("initial_v_mass")],
    );
    assert_eq!(x0, 0.002);
    // The slope of the first three samples.
    assert!((v0 - 0.3).abs() < 1e-9, "{v0}");
}
