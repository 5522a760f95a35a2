//! `rigfit simulate` makes a synthetic record in one command: without a data
//! file (`--dt` with `--duration` or `--samples`), the drive from the rig's own
//! laws or from a column of a `--drive` file, the drive column kept in its
//! output so the campaign reads the record as it stands, noise in the measured
//! output's unit, flat parameter files, a constant placeholder column accepted;
//! and a length too large for the step or memory limits refused before any
//! work.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use serde_json::{Value, json};

fn rigfit() -> Command {
    Command::new(env!("CARGO_BIN_EXE_rigfit"))
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// One mass on a spring and a damper to ground, its displacement measured,
/// pushed either by its own sine force (drive "velocity", the default) or by
/// the experiment's force table.
fn rig() -> Value {
    json!({
        "id": "sdof",
        "params": [{"name": "m", "unit": "kg"}, {"name": "k", "unit": "N/m", "scale": "log"},
                   {"name": "c", "unit": "N·s/m"}],
        "nodes": [{"name": "mass", "mass": "m"}],
        "elements": [{"name": "suspension", "between": ["mass", "ground"],
                      "spring": {"law": "linear", "k": "k"}, "damper": {"law": "viscous", "c": "c"}}],
        "drives": [
            {"node": "mass", "law": {"type": "sine", "quantity": "force", "amplitude": 10.0, "frequency": 15.0}},
            {"mode": "force", "node": "mass", "law": {"type": "force_table"}}
        ],
        "outputs": [{"name": "displacement", "unit": "m", "sum": [{"displacement": "mass"}]}]
    })
}

/// A campaign in `dir` whose record `e1.csv` need not exist, with `drive`.
fn campaign(dir: &Path, drive: Value) -> PathBuf {
    std::fs::write(dir.join("sdof.json"), rig().to_string()).unwrap();
    let c = json!({
        "name": "sdof",
        "rig": "sdof.json",
        "params": {"m": 2.0, "k": {"min": 1e3, "max": 1e6}, "c": {"min": 0.0, "max": 200.0}},
        "experiments": [{"name": "e1",
                         "data": {"file": "e1.csv", "time_column": "t_s", "force_column": "x_m"},
                         "drive": drive}],
        "search": {"population": 16, "generations": 2, "seed": 1}
    });
    let path = dir.join("c.json");
    std::fs::write(&path, serde_json::to_string_pretty(&c).unwrap()).unwrap();
    path
}

/// Header and rows of a CSV, comment lines skipped.
fn table(path: &Path) -> (Vec<String>, Vec<Vec<f64>>) {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines().filter(|l| !l.starts_with('#'));
    let header = lines.next().unwrap().split(',').map(String::from).collect();
    let rows = lines
        .map(|l| l.split(',').map(|x| x.parse().unwrap()).collect())
        .collect();
    (header, rows)
}

fn simulate(campaign: &Path, args: &[&str]) -> Output {
    rigfit()
        .args(["--quiet", "simulate"])
        .arg(campaign)
        .args(args)
        .output()
        .unwrap()
}

#[test]
fn a_record_is_made_from_the_rigs_own_drive_without_a_data_file() {
    let dir = tempfile::tempdir().unwrap();
    let c = campaign(dir.path(), json!("velocity"));
    assert!(!dir.path().join("e1.csv").exists());
    let truth = dir.path().join("truth.json");
    std::fs::write(&truth, r#"{"k": 4.0e4, "c": 12.0}"#).unwrap();
    let rec = dir.path().join("e1.csv");
    let o = simulate(
        &c,
        &[
            "--params",
            truth.to_str().unwrap(),
            "--duration",
            "0.5",
            "--dt",
            "1e-3",
            "--noise",
            "1e-6",
            "--seed",
            "3",
            "--out",
            rec.to_str().unwrap(),
        ],
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let (header, rows) = table(&rec);
    assert_eq!(header, ["t_s", "x_m"], "the columns the campaign reads");
    assert_eq!(rows.len(), 501, "0.5 s at 1 ms, both ends");
    assert_eq!(rows[0][0], 0.0);
    assert!((rows[500][0] - 0.5).abs() < 1e-12);
    let text = std::fs::read_to_string(&rec).unwrap();
    assert!(
        text.contains("sigma = 1e-6 m on output displacement"),
        "{text}"
    );
    // The sine's static response is about F/k = 2.5e-4 m, far above the noise.
    let peak = rows.iter().fold(0.0_f64, |m, r| m.max(r[1].abs()));
    assert!(peak > 1e-4 && peak < 1e-2, "{peak}");

    // The campaign now reads it as it stands.
    let o = rigfit().arg("check").arg(&c).output().unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    // Without noise the values on the record are the truth's.
    let clean = dir.path().join("clean.csv");
    let o = simulate(
        &c,
        &[
            "--params",
            truth.to_str().unwrap(),
            "--out",
            clean.to_str().unwrap(),
        ],
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let (header, clean_rows) = table(&clean);
    assert_eq!(header[..2], ["t_s", "displacement_m"]);
    let rms = (rows
        .iter()
        .zip(&clean_rows)
        .map(|(a, b)| (a[1] - b[1]).powi(2))
        .sum::<f64>()
        / rows.len() as f64)
        .sqrt();
    assert!(
        (rms / 1e-6 - 1.0).abs() < 0.15,
        "noise RMS {rms} m, asked 1e-6 m"
    );
}

#[test]
fn a_flat_parameter_file_sets_what_a_wrapped_one_sets() {
    let dir = tempfile::tempdir().unwrap();
    let c = campaign(dir.path(), json!("velocity"));
    let flat = dir.path().join("flat.json");
    let wrapped = dir.path().join("wrapped.json");
    std::fs::write(&flat, r#"{"k": 4.0e4, "c": 12.0}"#).unwrap();
    std::fs::write(
        &wrapped,
        r#"{"params": {"k": 4.0e4, "c": 12.0}, "other": [1]}"#,
    )
    .unwrap();
    let mut texts = Vec::new();
    for (p, name) in [(&flat, "a.csv"), (&wrapped, "b.csv")] {
        let out = dir.path().join(name);
        let o = simulate(
            &c,
            &[
                "--params",
                p.to_str().unwrap(),
                "--samples",
                "200",
                "--dt",
                "1e-3",
                "--out",
                out.to_str().unwrap(),
            ],
        );
        assert!(o.status.success(), "{}", stderr(&o));
        texts.push(std::fs::read_to_string(&out).unwrap());
    }
    assert_eq!(texts[0], texts[1]);
    // Mid-range values give another history: the file was applied.
    let mid = dir.path().join("mid.csv");
    let o = simulate(
        &c,
        &[
            "--samples",
            "200",
            "--dt",
            "1e-3",
            "--out",
            mid.to_str().unwrap(),
        ],
    );
    assert!(o.status.success(), "{}", stderr(&o));
    assert_ne!(std::fs::read_to_string(&mid).unwrap(), texts[0]);

    // A flat file's bad value is named by its key.
    std::fs::write(&flat, r#"{"k": "stiff"}"#).unwrap();
    let o = simulate(
        &c,
        &[
            "--params",
            flat.to_str().unwrap(),
            "--samples",
            "9",
            "--dt",
            "1e-3",
            "--out",
            mid.to_str().unwrap(),
        ],
    );
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    let err = stderr(&o);
    assert!(err.contains("flat.json") && err.contains("k:"), "{err}");
    assert!(err.contains("flat object"), "{err}");
    std::fs::write(&flat, r#"{"kk": 1.0}"#).unwrap();
    let o = simulate(
        &c,
        &[
            "--params",
            flat.to_str().unwrap(),
            "--samples",
            "9",
            "--dt",
            "1e-3",
            "--out",
            mid.to_str().unwrap(),
        ],
    );
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("unknown parameter 'kk'"),
        "{}",
        stderr(&o)
    );
}

#[test]
fn a_drive_column_comes_from_a_drive_file_and_stays_in_the_record() {
    let dir = tempfile::tempdir().unwrap();
    let c = campaign(dir.path(), json!({"force": {"column": "force_N"}}));
    let rec = dir.path().join("e1.csv");
    let grid = ["--samples", "400", "--dt", "1e-3"];

    // Without a file to read the column from, the message says where it goes.
    let o = simulate(&c, &[&grid[..], &["--out", rec.to_str().unwrap()]].concat());
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    let err = stderr(&o);
    assert!(
        err.contains("experiments[0].drive.force.column") && err.contains("--drive"),
        "{err}"
    );
    assert!(!rec.exists());

    // A drive sampled at 2 ms: the record carries it at 1 ms, as the run took it.
    let drive = dir.path().join("drive.csv");
    let mut text = String::from("t_s,force_N\n");
    for k in 0..200 {
        let t = k as f64 * 2e-3;
        text += &format!("{t},{}\n", 10.0 * (40.0 * t).sin());
    }
    std::fs::write(&drive, text).unwrap();
    for noise in [None, Some("1e-6")] {
        let out = dir.path().join(if noise.is_some() {
            "e1.csv"
        } else {
            "clean.csv"
        });
        let mut args = vec![
            "--drive",
            drive.to_str().unwrap(),
            "--out",
            out.to_str().unwrap(),
        ];
        args.extend(grid);
        if let Some(s) = noise {
            args.extend(["--noise", s]);
        }
        let o = simulate(&c, &args);
        assert!(o.status.success(), "{}", stderr(&o));
        let (header, rows) = table(&out);
        let col = header
            .iter()
            .position(|h| h == "force_N")
            .expect("drive column kept");
        assert_eq!(rows.len(), 400);
        for (k, r) in rows.iter().enumerate() {
            let t = k as f64 * 1e-3;
            // Linear between the drive file's samples, held after its last.
            let (i, w) = if t >= 0.398 {
                (198, 1.0)
            } else {
                ((t / 2e-3).floor() as usize, (t / 2e-3).fract())
            };
            let f = |i: usize| 10.0 * (40.0 * i as f64 * 2e-3).sin();
            let want = f(i) + w * (f((i + 1).min(199)) - f(i));
            assert!(
                (r[col] - want).abs() < 1e-9,
                "t = {t}: {} vs {want}",
                r[col]
            );
        }
        if noise.is_some() {
            assert_eq!(header, ["t_s", "x_m", "force_N"]);
        }
    }
    // The record with its drive column runs the campaign as it stands, and the
    // clean history's drive matches the record's.
    let o = rigfit().arg("check").arg(&c).output().unwrap();
    assert!(o.status.success(), "{}", stderr(&o));

    // --drive names a file only where a drive column is read.
    let v = campaign(dir.path(), json!("velocity"));
    let out = dir.path().join("v.csv");
    let o = simulate(
        &v,
        &[
            &grid[..],
            &[
                "--drive",
                drive.to_str().unwrap(),
                "--out",
                out.to_str().unwrap(),
            ],
        ]
        .concat(),
    );
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("reads no drive column"),
        "{}",
        stderr(&o)
    );
}

#[test]
fn a_constant_placeholder_column_is_simulated_but_not_fitted() {
    let dir = tempfile::tempdir().unwrap();
    let c = campaign(dir.path(), json!({"force": {"column": "force_N"}}));
    let mut text = String::from("t_s,x_m,force_N\n");
    for k in 0..300 {
        let t = k as f64 * 1e-3;
        text += &format!("{t},0,{}\n", if k > 10 { 5.0 } else { 0.0 });
    }
    std::fs::write(dir.path().join("e1.csv"), text).unwrap();
    let out = dir.path().join("sim.csv");
    let o = simulate(&c, &["--out", out.to_str().unwrap(), "--noise", "0"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let (header, rows) = table(&out);
    assert_eq!(header, ["t_s", "x_m", "force_N"]);
    assert_eq!(rows.len(), 300);
    assert!(rows[299][1] > 0.0, "the step force moved the mass");
    // A fit still needs a record that varies.
    let o = rigfit().arg("check").arg(&c).output().unwrap();
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("fit_window"), "{}", stderr(&o));
}

#[test]
fn the_noise_is_in_the_measured_outputs_unit() {
    let dir = tempfile::tempdir().unwrap();
    let c = campaign(dir.path(), json!("velocity"));
    let out = dir.path().join("sim.csv");
    let o = simulate(
        &c,
        &[
            "--samples",
            "10",
            "--dt",
            "1e-3",
            "--noise",
            "-1",
            "--out",
            out.to_str().unwrap(),
        ],
    );
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    let err = stderr(&o);
    assert!(err.contains("--noise -1") && err.contains("(m)"), "{err}");
    assert!(!out.exists());
}

#[test]
fn a_length_beyond_the_step_or_memory_limit_is_refused_before_any_work() {
    let dir = tempfile::tempdir().unwrap();
    let c = campaign(dir.path(), json!("velocity"));
    let out = dir.path().join("sim.csv");
    let o_str = out.to_str().unwrap();
    for args in [
        vec!["--samples", "1000000000000", "--dt", "1e-3"],
        vec!["--duration", "1e9", "--dt", "1e-3"],
    ] {
        let o = simulate(&c, &[&args[..], &["--out", o_str]].concat());
        assert_eq!(o.status.code(), Some(2), "{args:?}: {}", stderr(&o));
        let err = stderr(&o);
        assert!(err.contains("--max-steps") && err.contains("1e8"), "{err}");
        assert!(err.contains("e12"), "the size: {err}");
        assert!(!out.exists());
    }
    // With the step limit raised, the memory limit holds.
    let o = simulate(
        &c,
        &[
            "--samples",
            "1000000000000",
            "--dt",
            "1e-3",
            "--max-steps",
            "1e13",
            "--max-memory",
            "1G",
            "--out",
            o_str,
        ],
    );
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    let err = stderr(&o);
    assert!(
        err.contains("1.00 GiB") && err.contains("--max-memory"),
        "{err}"
    );
    assert!(err.contains("1000000000000 samples"), "{err}");
    assert!(!out.exists());

    // And at the record's own interval, as before.
    let mut text = String::from("t_s,x_m\n");
    for k in 0..100 {
        text += &format!("{},{}\n", k as f64 * 1e-3, k % 3);
    }
    std::fs::write(dir.path().join("e1.csv"), text).unwrap();
    let o = simulate(&c, &["--samples", "1000000000000", "--out", o_str]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("--max-steps"), "{}", stderr(&o));
    assert!(!out.exists());
}

#[test]
fn a_shipped_record_is_made_again_from_its_campaign_in_one_command() {
    let repo = PathBuf::from(env!("CARGO_MANIFEST_DIR"));
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("friction_sdof_synthetic.csv");
    let c = repo.join("campaigns/friction_sdof_synthetic.json");
    let truth = repo.join("campaigns/friction_sdof_reference_params.json");
    let o = simulate(
        &c,
        &[
            "--params",
            truth.to_str().unwrap(),
            "--samples",
            "5000",
            "--dt",
            "1e-4",
            "--noise",
            "0.1",
            "--seed",
            "4",
            "--out",
            out.to_str().unwrap(),
        ],
    );
    assert!(o.status.success(), "{}", stderr(&o));
    let (header, rows) = table(&out);
    let (shipped_header, shipped) = table(&repo.join("campaigns/friction_sdof_synthetic.csv"));
    assert_eq!(header, shipped_header);
    assert_eq!(rows.len(), shipped.len());
    for (a, b) in rows.iter().zip(&shipped) {
        assert_eq!(a[0], b[0], "sample times");
        // The same noise draws; the run itself within 1 % of the 0.1 N noise.
        assert!(
            (a[1] - b[1]).abs() <= 1e-3,
            "t = {}: {} vs {}",
            a[0],
            a[1],
            b[1]
        );
    }
}

#[test]
fn only_the_simulated_experiment_reads_a_drive_file() {
    let dir = tempfile::tempdir().unwrap();
    let c = campaign(dir.path(), json!("velocity"));
    let mut v: Value = serde_json::from_str(&std::fs::read_to_string(&c).unwrap()).unwrap();
    let mut e2 = v["experiments"][0].clone();
    e2["name"] = json!("e2");
    e2["data"]["file"] = json!("e2.csv");
    e2["drive"] = json!({"force": {"column": "force_N"}});
    v["experiments"].as_array_mut().unwrap().push(e2);
    std::fs::write(&c, v.to_string()).unwrap();
    let out = dir.path().join("e1.csv");
    let grid = [
        "--samples",
        "50",
        "--dt",
        "1e-3",
        "--out",
        out.to_str().unwrap(),
    ];
    let o = simulate(&c, &[&grid[..], &["--experiment", "e1"]].concat());
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(table(&out).1.len(), 50);
    let o = simulate(
        &c,
        &[&grid[..], &["--experiment", "e2", "--overwrite"]].concat(),
    );
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(
        stderr(&o).contains("experiments[1].drive.force.column"),
        "{}",
        stderr(&o)
    );
}

#[test]
fn the_drive_file_and_a_missing_folder_are_refused_as_outputs() {
    let dir = tempfile::tempdir().unwrap();
    let c = campaign(dir.path(), json!({"force": {"column": "force_N"}}));
    let drive = dir.path().join("drive.csv");
    let text: String = std::iter::once("t_s,force_N\n".to_string())
        .chain((0..50).map(|k| format!("{},{}\n", k as f64 * 1e-3, k as f64)))
        .collect();
    std::fs::write(&drive, &text).unwrap();
    let grid = ["--samples", "50", "--dt", "1e-3"];
    let d = drive.to_str().unwrap();

    // The drive file is an input: never written over, not even with --overwrite.
    let o = simulate(
        &c,
        &[&grid[..], &["--drive", d, "--out", d, "--overwrite"]].concat(),
    );
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("input"), "{}", stderr(&o));
    assert_eq!(std::fs::read_to_string(&drive).unwrap(), text);

    // An --out in a folder that does not exist is bad input, before any work.
    let missing = dir.path().join("no/such/folder/e1.csv");
    let o = simulate(
        &c,
        &[
            &grid[..],
            &["--drive", d, "--out", missing.to_str().unwrap()],
        ]
        .concat(),
    );
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(!dir.path().join("no").exists());
}
