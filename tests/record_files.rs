//! Record files beyond CSV as a campaign reads them: the format told by the
//! content whatever the name, or stated; the time from a channel's own
//! waveform timing; the unit a file records checked against the rig output's
//! through the scale; and `rigfit inspect` listing what a file holds.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use serde_json::{Value, json};

fn formats() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("campaigns/formats")
}

fn rigfit(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_rigfit"))
        .args(args)
        .output()
        .unwrap()
}

/// The TDMS campaign of `campaigns/formats/` with its data object changed
/// by `edit`, written with the record (copied as `record_name`) into a
/// temporary folder; `rigfit check --no-measure` on it.
fn check_with(record_name: &str, edit: impl FnOnce(&mut Value)) -> (Output, tempfile::TempDir) {
    let dir = tempfile::tempdir().unwrap();
    let text = std::fs::read_to_string(formats().join("aa2024_t3_v2_tdms.json")).unwrap();
    let mut campaign: Value = serde_json::from_str(&text).unwrap();
    std::fs::copy(
        formats().join("aa2024_t3_v2.tdms"),
        dir.path().join(record_name),
    )
    .unwrap();
    let data = &mut campaign["experiments"][0]["data"];
    data["file"] = json!(record_name);
    edit(data);
    campaign["output"] = json!("out");
    let file = dir.path().join("campaign.json");
    std::fs::write(&file, serde_json::to_string_pretty(&campaign).unwrap()).unwrap();
    let out = rigfit(&["check", file.to_str().unwrap(), "--no-measure", "--quiet"]);
    (out, dir)
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

#[test]
fn the_format_is_told_by_the_content_whatever_the_extension() {
    let (o, _dir) = check_with("export.dat", |_| {});
    assert!(o.status.success(), "{}", stderr(&o));
    let (o, _dir) = check_with("export.dat", |d| d["format"] = json!("mat"));
    assert_eq!(o.status.code(), Some(2));
    let e = stderr(&o);
    assert!(
        e.contains("MAT-file") && e.contains("export.dat"),
        "a stated format is read as stated: {e}"
    );
    let (o, _dir) = check_with("export.dat", |d| d["format"] = json!("xlsx"));
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("\"tdms\""), "{}", stderr(&o));
}

#[test]
fn a_channel_with_its_own_timing_needs_no_time_column() {
    let (o, _dir) = check_with("r.tdms", |d| {
        d.as_object_mut().unwrap().remove("time_column");
    });
    assert!(o.status.success(), "{}", stderr(&o));
    // Its timing is in seconds: a time scale cannot apply.
    let (o, _dir) = check_with("r.tdms", |d| {
        d.as_object_mut().unwrap().remove("time_column");
        d["time_scale"] = json!(1e-3);
    });
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("waveform timing"), "{}", stderr(&o));
}

#[test]
fn a_recorded_unit_the_scale_does_not_convert_is_refused() {
    // The file records N; the rig's load_cell_force is in N: 1e3 is a kN scale.
    let (o, _dir) = check_with("r.tdms", |d| d["scale"] = json!(1e3));
    assert_eq!(o.status.code(), Some(2));
    let e = stderr(&o);
    assert!(
        e.contains("experiments[0].data.scale") && e.contains("the record is in N"),
        "{e}"
    );
    // A calibration correction within a factor of 2 agrees.
    let (o, _dir) = check_with("r.tdms", |d| d["scale"] = json!(1.02));
    assert!(o.status.success(), "{}", stderr(&o));
    // A time channel in seconds read as milliseconds.
    let (o, _dir) = check_with("r.tdms", |d| d["time_scale"] = json!(1e-3));
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("time_scale"), "{}", stderr(&o));
}

/// A CSV of the shipped record with its force header renamed `header`.
fn csv_with_header(dir: &Path, header: &str) -> PathBuf {
    let src = formats().join("../aa2024_t3_v2_synthetic.csv");
    let text = std::fs::read_to_string(src).unwrap();
    let text = text.replacen("t_s,force_N", &format!("t_s,{header}"), 1);
    let path = dir.join("r.csv");
    std::fs::write(&path, text).unwrap();
    path
}

#[test]
fn a_csv_header_in_brackets_states_a_unit() {
    for (header, scale, ok) in [
        ("force [mV]", 1.0, false),
        ("force [mV]", 2.5, true),
        ("force [kN]", 1.0, false),
        ("force [kN]", 1e-3, false),
        ("force [N]", 1.0, true),
    ] {
        let dir = tempfile::tempdir().unwrap();
        csv_with_header(dir.path(), header);
        let (o, _d) = check_with("unused.tdms", |d| {
            d["file"] = json!(dir.path().join("r.csv"));
            d["time_column"] = json!("t_s");
            d["force_column"] = json!(header);
            d["scale"] = json!(scale);
        });
        assert_eq!(o.status.success(), ok, "{header} × {scale}: {}", stderr(&o));
        if !ok {
            assert!(stderr(&o).contains("data.scale"), "{}", stderr(&o));
        }
    }
}

#[test]
fn inspect_lists_channels_units_and_timing() {
    let file = formats().join("aa2024_t3_v2.tdms");
    let o = rigfit(&["inspect", file.to_str().unwrap(), "--json"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let v: Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(v["format"], "tdms");
    let channels = v["channels"].as_array().unwrap();
    assert_eq!(channels.len(), 2);
    assert_eq!(channels[1]["name"], "tensile/force_N");
    assert_eq!(channels[1]["unit"], "N");
    assert_eq!(channels[1]["samples"], 2501);
    assert!((channels[1]["rate_hz"].as_f64().unwrap() - 1e6).abs() < 1e-3);
    assert_eq!(v["campaign_data"]["time_column"], "tensile/t_s");
    let text = rigfit(&["inspect", file.to_str().unwrap()]);
    let text = String::from_utf8_lossy(&text.stdout);
    assert!(
        text.contains("tensile/force_N") && text.contains("1e6 Hz"),
        "{text}"
    );
    // Every format of the folder lists the two channels.
    for f in [
        "aa2024_t3_v2.h5",
        "aa2024_t3_v2_v5.mat",
        "aa2024_t3_v2_v73.mat",
        "aa2024_t3_v2.uff",
    ] {
        let o = rigfit(&["inspect", formats().join(f).to_str().unwrap(), "--json"]);
        assert!(o.status.success(), "{f}: {}", stderr(&o));
        let v: Value = serde_json::from_slice(&o.stdout).unwrap();
        assert_eq!(v["channels"].as_array().unwrap().len(), 2, "{f}: {v}");
    }
}

#[test]
fn inspect_refuses_what_it_cannot_read_naming_the_file() {
    let dir = tempfile::tempdir().unwrap();
    let bad = dir.path().join("cut.tdms");
    let bytes = std::fs::read(formats().join("aa2024_t3_v2.tdms")).unwrap();
    std::fs::write(&bad, &bytes[..100]).unwrap();
    let o = rigfit(&["inspect", bad.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2));
    let e = stderr(&o);
    assert!(e.contains("cut.tdms") && e.contains("TDMS"), "{e}");
    let o = rigfit(&["inspect", bad.to_str().unwrap(), "--format", "xlsx"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(stderr(&o).contains("--format"), "{}", stderr(&o));
}
