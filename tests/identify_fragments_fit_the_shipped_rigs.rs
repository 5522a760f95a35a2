//! Each `rigfit identify` method, run as a command on a record of the shipped
//! rig it is meant for (simulated by rigfit, or the real EMPS record), writes a
//! fragment whose parameters the shipped campaign takes: merged into
//! `campaigns/*.json`, the campaign loads (the validation `rigfit check` and
//! `rigfit run` do before any work) and the estimates are its free genes.

mod paper_rigs_common;

use std::f64::consts::PI;
use std::path::Path;

use paper_rigs_common::{outputs, params, rig, shipped, truth};
use rigfit::campaign::Campaign;
use rigfit::model::compiled::CompiledRig;
use serde_json::Value;

/// Runs `rigfit identify ARGS… --out FRAGMENT --overwrite` and returns the
/// fragment (a test may write it more than once).
fn identify(args: &[&str], dir: &Path) -> Value {
    let frag = dir.join("fragment.json");
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_rigfit"))
        .arg("identify")
        .args(args)
        .arg("--out")
        .arg(&frag)
        .arg("--overwrite")
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_str(&std::fs::read_to_string(&frag).unwrap()).unwrap()
}

/// The shipped campaign `file` with the fragment's parameters in place of its own.
fn merged(file: &str, fragment: &Value) -> Result<Campaign, rigfit::campaign::CampaignError> {
    let path = shipped(file);
    let mut c: Value = serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
    for (name, entry) in fragment["params"].as_object().unwrap() {
        c["params"][name] = entry.clone();
    }
    Campaign::from_str(&c.to_string(), path.parent().unwrap(), file)
}

/// Merges and checks that every estimated (free) parameter of the fragment is
/// a gene of the loaded campaign, seeded at the estimate.
fn accepted(file: &str, fragment: &Value) -> Campaign {
    let c = merged(file, fragment).unwrap_or_else(|e| panic!("{file}: {e}\n{fragment:#}"));
    for (name, entry) in fragment["params"].as_object().unwrap() {
        if let Some(init) = entry.get("init") {
            let g = c
                .genes
                .iter()
                .find(|g| &g.name == name)
                .unwrap_or_else(|| panic!("{name} is not a gene of {file}"));
            assert_eq!(g.init, init.as_f64(), "{name}");
        }
    }
    println!("{file} takes {}", fragment["params"]);
    c
}

fn write_csv(path: &Path, header: &str, columns: &[&[f64]]) {
    let mut text = format!("{header}\n");
    for i in 0..columns[0].len() {
        let row: Vec<String> = columns.iter().map(|c| format!("{:.17e}", c[i])).collect();
        text += &(row.join(",") + "\n");
    }
    std::fs::write(path, text).unwrap();
}

#[test]
fn a_name_the_rig_lacks_is_refused() {
    let e = merged(
        "quarter_car_synthetic.json",
        &serde_json::json!({"params": {"no_such_parameter": 1.0}}),
    );
    assert!(e.is_err());
}

#[test]
fn arx_fragments_fit_the_quarter_car() {
    let dir = tempfile::tempdir().unwrap();
    let rig = rig("quarter_car");
    let mut v = truth("quarter_car_reference_params.json");
    v.insert("sweep.f_start".into(), 0.2.into());
    v.insert("sweep.rate".into(), 0.4.into());
    let fs = 600.0;
    let h = outputs(&rig, &params(&rig, &v), 1.0 / fs, 60_000, 2);
    let t: Vec<f64> = (0..h[0].len()).map(|i| i as f64 / fs).collect();
    let csv = dir.path().join("car.csv");
    write_csv(
        &csv,
        "t_s,wheel_pan,unsprung,sprung",
        &[&t, &h[2], &h[1], &h[0]],
    );
    let svg = dir.path().join("strut.svg");
    let strut = identify(
        &[
            "arx",
            csv.to_str().unwrap(),
            "--input",
            "unsprung",
            "--output",
            "sprung",
            "--mass",
            "350",
            "--f-min",
            "0.5",
            "--f-max",
            "30",
            "--segment",
            "4096",
            "--svg",
            svg.to_str().unwrap(),
        ],
        dir.path(),
    );
    assert!(std::fs::read_to_string(&svg).unwrap().contains("<svg"));
    // The shipped rig's strut is nonlinear (saturating damper, backlash): the
    // linear element fit gives an equivalent stiffness and damping near the
    // low-speed values, inside the campaign's bounds.
    let k2 = strut["params"]["k2"]["init"].as_f64().unwrap();
    let c2 = strut["params"]["c2"]["init"].as_f64().unwrap();
    println!("strut of the nonlinear car: k2 = {k2:.4e}, c2 = {c2:.4e}");
    assert!(k2 > 5e3 && k2 < 1e5 && c2 > 100.0 && c2 < 1e4);
    accepted("quarter_car_synthetic.json", &strut);
    let tire = identify(
        &[
            "arx",
            csv.to_str().unwrap(),
            "--input",
            "wheel_pan",
            "--output",
            "unsprung,sprung",
            "--mass",
            "40,350",
            "--names",
            "k1,c1",
            "--f-min",
            "0.5",
            "--f-max",
            "30",
            "--segment",
            "4096",
            "--fixed",
        ],
        dir.path(),
    );
    let k1 = tire["params"]["k1"].as_f64().unwrap();
    assert!((k1 / v["k1"].as_f64().unwrap() - 1.0).abs() < 0.02, "{k1}");
    accepted("quarter_car_synthetic.json", &tire);
}

#[test]
fn rfs_fragment_fits_the_inertial_sdof_rig() {
    let dir = tempfile::tempdir().unwrap();
    let rig = rig("inertial_sdof");
    let v = truth("inertial_sdof_reference_params.json");
    let m = v["m"].as_f64().unwrap();
    let fs = 2000.0;
    let h = outputs(&rig, &params(&rig, &v), 1.0 / fs, 4000, 4);
    let t: Vec<f64> = (0..h[0].len()).map(|i| i as f64 / fs).collect();
    // f = −m·(a + ẍ) ⇒ the base acceleration a = −f/m − ẍ.
    let a: Vec<f64> = h[1]
        .iter()
        .zip(&h[3])
        .map(|(f, xdd)| -f / m - xdd)
        .collect();
    let csv = dir.path().join("sdof.csv");
    write_csv(&csv, "t_s,x_m,a_ms2", &[&t, &h[0], &a]);
    let fragment = identify(
        &[
            "rfs",
            csv.to_str().unwrap(),
            "--x",
            "x_m",
            "--accel",
            "a_ms2",
            "--mass",
            &m.to_string(),
            "--terms",
            "linear,cubic,viscous",
        ],
        dir.path(),
    );
    let kf1 = fragment["params"]["kf1"]["init"].as_f64().unwrap();
    println!("kf1 = {kf1:.4e}");
    accepted("inertial_sdof_synthetic.json", &fragment);
}

/// `friction_sdof` driven by a force sweep instead of its single sine, so
/// that the reverse path sees every line of its band.
fn swept_friction_rig() -> CompiledRig {
    let text = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("rigs/friction_sdof.json"),
    )
    .unwrap();
    let mut d: Value = serde_json::from_str(&text).unwrap();
    d["drives"][0]["law"] = serde_json::json!({
        "type": "chirp", "quantity": "force", "amplitude": "amplitude",
        "f_start": "frequency", "rate": 2.0
    });
    let desc = rigfit::rig::parse(
        &d.to_string(),
        &rigfit::rig::RigSource::File("friction_sdof (swept)".into()),
    )
    .unwrap();
    CompiledRig::new(desc, "friction_sdof (swept)").unwrap()
}

#[test]
fn nimiso_fragment_fits_the_friction_rig() {
    let dir = tempfile::tempdir().unwrap();
    let rig = swept_friction_rig();
    let mut v = truth("friction_sdof_reference_params.json");
    v.insert("f10.frequency".into(), 2.0.into());
    v.insert("f10.amplitude".into(), 60.0.into());
    let fs = 1000.0;
    let n = 40_000;
    let h = outputs(&rig, &params(&rig, &v), 1.0 / fs, n, 4);
    let t: Vec<f64> = (0..n).map(|i| i as f64 / fs).collect();
    let force: Vec<f64> = t
        .iter()
        .map(|&t| 60.0 * (2.0 * PI * (2.0 * t + t * t)).sin())
        .collect();
    let csv = dir.path().join("friction.csv");
    write_csv(&csv, "t_s,x_m,force_N", &[&t, &h[2], &force]);
    let fragment = identify(
        &[
            "nimiso",
            csv.to_str().unwrap(),
            "--motion",
            "x_m",
            "--force",
            "force_N",
            "--nonlinear",
            "sign-velocity",
            "--f-min",
            "5",
            "--f-max",
            "40",
        ],
        dir.path(),
    );
    for (name, truth_value) in [("k", 6.4e4), ("f_c", 10.0)] {
        let got = fragment["params"][name]["init"].as_f64().unwrap();
        println!("{name} = {got:.4e} (rig {truth_value:.4e})");
    }
    accepted("friction_sdof_synthetic.json", &fragment);
}

#[test]
fn idim_fragment_fits_the_emps_rig() {
    let dir = tempfile::tempdir().unwrap();
    let data =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/emps/emps_position_voltage.csv");
    let fragment = identify(
        &[
            "idim",
            data.to_str().unwrap(),
            "--position",
            "position_m",
            "--force",
            "controller_voltage_V",
            "--gain",
            "35.15065188248547",
            "--sample-rate",
            "1000",
        ],
        dir.path(),
    );
    accepted("emps_closed_loop.json", &fragment);
}
