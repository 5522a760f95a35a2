//! The shipped example's record in every format rigfit reads calibrates alike:
//! `campaigns/formats/` holds the record of `campaigns/aa2024_t3_v2_synthetic.csv`
//! written by each format's own ecosystem writer
//! (`scripts/make-record-formats.py`: NI TDMS, HDF5, MAT v5 and v7.3, UFF
//! dataset 58 in ASCII and binary) and one campaign per format, the same
//! experiment with a short CPU search and a fixed seed. Each format's samples
//! are the CSV's f64 values bit for bit, so `rigfit run` on each campaign must
//! give fitted parameters bit-identical to the CSV campaign's, and its
//! `result.json` must name the file it read (path and SHA-256) and its format.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::OnceLock;

use serde_json::Value;
use sha2::{Digest, Sha256};

fn formats_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("campaigns/formats")
}

/// `rigfit run CAMPAIGN --out <temp>`: the result.json it leaves.
fn run(campaign: &Path) -> Value {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("result");
    let o = Command::new(env!("CARGO_BIN_EXE_rigfit"))
        .arg("run")
        .arg(campaign)
        .arg("--out")
        .arg(&out)
        .arg("--quiet")
        .output()
        .unwrap();
    assert!(
        o.status.success(),
        "rigfit run {} failed: {}",
        campaign.display(),
        String::from_utf8_lossy(&o.stderr)
    );
    let text = std::fs::read_to_string(out.join("result.json")).unwrap();
    serde_json::from_str(&text).unwrap()
}

/// Every parameter of a result.json, by name, as f64 bits (serde_json reads
/// with `float_roundtrip`: the bits the run wrote).
fn params(r: &Value) -> BTreeMap<String, u64> {
    let map = r["params"].as_object().expect("result.json has params");
    map.iter()
        .map(|(k, v)| {
            let x = v.as_f64().unwrap_or_else(|| panic!("params.{k} = {v}"));
            (k.clone(), x.to_bits())
        })
        .collect()
}

/// The CSV campaign's result, run once for every test of this file.
fn csv_result() -> &'static Value {
    static CSV: OnceLock<Value> = OnceLock::new();
    CSV.get_or_init(|| run(&formats_dir().join("aa2024_t3_v2_csv.json")))
}

fn sha256_hex(path: &Path) -> String {
    let bytes = std::fs::read(path).unwrap();
    Sha256::digest(&bytes)
        .iter()
        .map(|b| format!("{b:02x}"))
        .collect()
}

/// The `inputs` entry of `file` (named as the campaign names it), with the
/// SHA-256 of the file's bytes.
fn assert_input_digest(r: &Value, file: &str) {
    let path = formats_dir().join(file);
    let inputs = r["inputs"].as_array().expect("result.json has inputs");
    let entry = inputs
        .iter()
        .find(|i| i["path"] == file)
        .unwrap_or_else(|| panic!("no input {file} in {inputs:?}"));
    assert_eq!(entry["sha256"], sha256_hex(&path).as_str(), "{file}");
}

fn assert_same_params(format: &str, got: &Value, want: &Value) {
    let (got, want) = (params(got), params(want));
    assert_eq!(
        got.keys().collect::<Vec<_>>(),
        want.keys().collect::<Vec<_>>(),
        "{format}: parameter names differ from the CSV run's"
    );
    let differ: Vec<String> = want
        .iter()
        .filter(|(k, w)| got[*k] != **w)
        .map(|(k, w)| {
            format!(
                "{k}: {} (CSV {})",
                f64::from_bits(got[k]),
                f64::from_bits(*w)
            )
        })
        .collect();
    assert!(
        differ.is_empty(),
        "{format}: fitted parameters differ from the CSV run's: {differ:?}"
    );
}

/// result.json's entry for the experiment's record (`records[0]`: its file,
/// format, SHA-256 and the channels read with their recorded units).
fn record_entry(r: &Value) -> &Value {
    let found = &r["records"][0];
    assert!(found.is_object(), "result.json has no records[0]: {r}");
    found
}

/// The unit the file records for `channel`, as `records[0].channels` lists it.
fn recorded_unit(record: &Value, channel: &str) -> Option<String> {
    record["channels"]
        .as_array()?
        .iter()
        .find(|c| c["name"] == channel)?["unit"]
        .as_str()
        .map(str::to_string)
}

/// Runs `aa2024_t3_v2_<key>.json` and checks it against the CSV's run: the
/// same parameter bits, the file named with its digest, the format named
/// (`format_word` in `record.format`, any case) and, where the format carries
/// units, the channels' recorded units.
fn calibrates_like_the_csv(key: &str, file: &str, format_word: &str, units: &[(&str, &str)]) {
    let r = run(&formats_dir().join(format!("aa2024_t3_v2_{key}.json")));
    assert_same_params(file, &r, csv_result());
    assert_input_digest(&r, file);
    let record = record_entry(&r);
    let format = record["format"].as_str().unwrap_or_default().to_lowercase();
    assert!(
        format.contains(format_word),
        "{file}: record.format {:?}, expected it to name {format_word}",
        record["format"]
    );
    let checksum = record["sha256"].as_str().unwrap_or_default();
    assert!(
        checksum.ends_with(&sha256_hex(&formats_dir().join(file))),
        "{file}: records[0].sha256 {checksum:?}"
    );
    for (channel, unit) in units {
        assert_eq!(
            recorded_unit(record, channel).as_deref(),
            Some(*unit),
            "{file}: recorded unit of {channel} in {record}"
        );
    }
}

#[test]
fn csv_campaign_runs_and_a_renamed_copy_elsewhere_gives_the_same_bits() {
    let r = csv_result();
    // The record the other formats were written from, named with its digest.
    let csv = "../aa2024_t3_v2_synthetic.csv";
    let inputs = r["inputs"].as_array().unwrap();
    let entry = inputs.iter().find(|i| i["path"] == csv).unwrap();
    assert_eq!(
        entry["sha256"],
        sha256_hex(&formats_dir().join(csv)).as_str()
    );
    let p = params(r);
    for name in [
        "k1",
        "c1",
        "c1_post",
        "c4",
        "gap",
        "v2.k_lin",
        "v2.e_fracture",
    ] {
        assert!(
            f64::from_bits(p[name]).is_finite(),
            "{name} not fitted: {r}"
        );
    }
    // Another name, another folder, the record by absolute path: the fitted
    // bits depend on the record's samples only, so the comparison of formats
    // above compares what the readers read.
    let mut c: Value = serde_json::from_str(
        &std::fs::read_to_string(formats_dir().join("aa2024_t3_v2_csv.json")).unwrap(),
    )
    .unwrap();
    c["name"] = Value::from("renamed-elsewhere");
    let record = formats_dir().join(csv).canonicalize().unwrap();
    c["experiments"][0]["data"]["file"] = Value::from(record.to_str().unwrap());
    c.as_object_mut().unwrap().remove("output");
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("renamed.json");
    std::fs::write(&path, serde_json::to_string_pretty(&c).unwrap()).unwrap();
    let again = run(&path);
    assert_eq!(again["campaign"], "renamed-elsewhere");
    assert_same_params("the renamed CSV campaign", &again, r);
}

#[test]
fn csv_result_names_its_format() {
    // The CSV run's entry (no units in its header).
    let record = record_entry(csv_result());
    let format = record["format"].as_str().map(str::to_lowercase);
    assert_eq!(format.as_deref(), Some("csv"), "{record}");
    let csv = formats_dir().join("../aa2024_t3_v2_synthetic.csv");
    let checksum = record["sha256"].as_str().unwrap_or_default();
    assert!(checksum.ends_with(&sha256_hex(&csv)), "{checksum:?}");
}

#[test]
fn tdms_calibrates_like_the_csv() {
    let units = [("tensile/t_s", "s"), ("tensile/force_N", "N")];
    calibrates_like_the_csv("tdms", "aa2024_t3_v2.tdms", "tdms", &units);
}

#[test]
fn hdf5_calibrates_like_the_csv() {
    let units = [("/tensile/t_s", "s"), ("/tensile/force_N", "N")];
    calibrates_like_the_csv("h5", "aa2024_t3_v2.h5", "hdf5", &units);
}

#[test]
fn mat_v5_calibrates_like_the_csv() {
    calibrates_like_the_csv("mat_v5", "aa2024_t3_v2_v5.mat", "mat", &[]);
}

#[test]
fn mat_v73_calibrates_like_the_csv() {
    calibrates_like_the_csv("mat_v73", "aa2024_t3_v2_v73.mat", "mat", &[]);
}

#[test]
fn uff58_calibrates_like_the_csv() {
    let units = [("force_N/abscissa", "s"), ("force_N", "N")];
    calibrates_like_the_csv("uff", "aa2024_t3_v2.uff", "uff", &units);
}

#[test]
fn uff58_binary_calibrates_like_the_csv() {
    let units = [("force_N/abscissa", "s"), ("force_N", "N")];
    calibrates_like_the_csv("uff_58b", "aa2024_t3_v2_58b.uff", "uff", &units);
}
