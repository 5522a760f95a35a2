//! What the commands read and where they write is checked before any work:
//! a FIFO or a device given as a rig, campaign, parameter or data file is
//! refused unread (it would block for ever or never end), and so is a file
//! over the size limit; an `--out` of `identify`, `fit-specimen` or
//! `ringdown` in a missing folder or onto a folder exits 2, as `run` does;
//! `ringdown --start` must be a time on the record; and a byte-order mark is
//! read alike by every command.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::time::{Duration, Instant};

use serde_json::{Value, json};

fn rigfit() -> Command {
    Command::new(env!("CARGO_BIN_EXE_rigfit"))
}

fn repo() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

/// Runs `cmd` with a deadline: a command that blocks on a FIFO fails the
/// test instead of hanging it.
fn bounded(cmd: &mut Command) -> Output {
    let mut child = cmd
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    let started = Instant::now();
    while child.try_wait().unwrap().is_none() {
        if started.elapsed() > Duration::from_secs(60) {
            child.kill().unwrap();
            panic!("{cmd:?} did not end: it is reading something that never ends");
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    child.wait_with_output().unwrap()
}

/// The shipped campaign in `dir` (its record beside it), spoilt by `spoil`.
fn campaign(dir: &Path, spoil: impl FnOnce(&mut Value)) -> PathBuf {
    let text = std::fs::read_to_string(repo().join("campaigns/aa2024_t3_synthetic.json")).unwrap();
    let mut c: Value = serde_json::from_str(&text).unwrap();
    std::fs::copy(
        repo().join("campaigns/aa2024_t3_v2_synthetic.csv"),
        dir.join("v2.csv"),
    )
    .unwrap();
    c["experiments"][0]["data"]["file"] = json!("v2.csv");
    c["search"]["population"] = json!(8);
    c["search"]["generations"] = json!(1);
    c["search"]["polish"] = json!({"enabled": false});
    c["solver"]["backend"] = json!("cpu");
    c["output"] = json!("out");
    spoil(&mut c);
    let path = dir.join("c.json");
    std::fs::write(&path, serde_json::to_string_pretty(&c).unwrap()).unwrap();
    path
}

fn fifo(path: &Path) {
    let made = Command::new("mkfifo").arg(path).status().unwrap();
    assert!(made.success());
}

fn refused(o: &Output, fragments: &[&str]) {
    let err = stderr(o);
    assert_eq!(o.status.code(), Some(2), "{err}");
    for f in fragments {
        assert!(err.contains(f), "expected {f:?} in {err}");
    }
}

#[test]
fn a_fifo_or_a_device_as_an_input_file_is_refused_unread() {
    let dir = tempfile::tempdir().unwrap();
    let pipe = dir.path().join("pipe");
    fifo(&pipe);
    let pipe_s = pipe.to_str().unwrap().to_string();
    // As the rig, the record and the campaign itself.
    for (what, input) in [("rig", pipe_s.as_str()), ("rig", "/dev/zero")] {
        let c = campaign(dir.path(), |c| c[what] = json!(input));
        for cmd in ["check", "run"] {
            let o = bounded(rigfit().arg(cmd).arg(&c));
            refused(&o, &[input, "expected a regular file"]);
            assert!(!dir.path().join("out").exists());
        }
    }
    for input in [pipe_s.as_str(), "/dev/zero"] {
        let c = campaign(dir.path(), |c| {
            c["experiments"][0]["data"]["file"] = json!(input)
        });
        for cmd in ["check", "run"] {
            let o = bounded(rigfit().arg(cmd).arg(&c));
            refused(&o, &[input, "expected a regular file"]);
        }
        let o = bounded(rigfit().arg("check").arg(input));
        refused(&o, &[input, "expected a regular file"]);
        let c = campaign(dir.path(), |_| {});
        let o = bounded(
            rigfit()
                .arg("simulate")
                .arg(&c)
                .arg("--params")
                .arg(input)
                .arg("--out")
                .arg(dir.path().join("sim.csv")),
        );
        refused(&o, &[input, "expected a regular file"]);
        for args in [
            &["ringdown", input][..],
            &["fit-specimen", input][..],
            &["identify", "idim", input, "--position", "1", "--force", "2"][..],
        ] {
            let o = bounded(rigfit().args(args));
            refused(&o, &[input, "expected a regular file"]);
        }
    }
}

#[test]
fn an_input_file_over_the_size_limit_is_refused_before_it_is_read() {
    let dir = tempfile::tempdir().unwrap();
    // Sparse: the size is there, the bytes are not.
    let huge = dir.path().join("huge.csv");
    std::fs::File::create(&huge)
        .unwrap()
        .set_len(rigfit::base::fsutil::MAX_RECORD_BYTES + 1)
        .unwrap();
    let c = campaign(dir.path(), |c| {
        c["experiments"][0]["data"]["file"] = json!("huge.csv")
    });
    let o = bounded(rigfit().arg("check").arg(&c));
    refused(&o, &["huge.csv", "expected at most 512 MiB"]);
    let o = bounded(rigfit().arg("ringdown").arg(&huge));
    refused(&o, &["huge.csv", "expected at most 512 MiB"]);
    let rig = dir.path().join("huge_rig.json");
    std::fs::File::create(&rig)
        .unwrap()
        .set_len(rigfit::base::fsutil::MAX_DESCRIPTION_BYTES + 1)
        .unwrap();
    let c = campaign(dir.path(), |c| c["rig"] = json!("huge_rig.json"));
    let o = bounded(rigfit().arg("check").arg(&c));
    refused(&o, &["huge_rig.json", "expected at most 64 MiB"]);
}

/// A ringdown record: a decaying 50 Hz sine sampled at 10 kHz, from t = 0.
fn ringing_record(path: &Path, bom: bool) {
    let mut s = String::from(if bom {
        "\u{feff}t_s,force_N\n"
    } else {
        "t_s,force_N\n"
    });
    for k in 0..4000 {
        let t = k as f64 * 1e-4;
        let f = (-3.0 * t).exp() * (2.0 * std::f64::consts::PI * 50.0 * t).sin();
        s += &format!("{t:.6e},{f:.6e}\n");
    }
    std::fs::write(path, s).unwrap();
}

#[test]
fn an_out_in_a_missing_folder_or_onto_a_folder_is_bad_input() {
    let dir = tempfile::tempdir().unwrap();
    let record = dir.path().join("rec.csv");
    ringing_record(&record, false);
    let r = record.to_str().unwrap();
    let missing = dir.path().join("no_such_folder").join("f.json");
    let folder = dir.path().join("a_folder");
    std::fs::create_dir(&folder).unwrap();
    for args in [
        &["ringdown", r][..],
        &["fit-specimen", r][..],
        &[
            "identify",
            "idim",
            r,
            "--position",
            "2",
            "--force",
            "2",
            "--sample-rate",
            "1000",
        ][..],
        &[
            "identify", "frf", r, "--input", "force_N", "--output", "force_N",
        ][..],
    ] {
        let o = rigfit()
            .args(args)
            .arg("--out")
            .arg(&missing)
            .output()
            .unwrap();
        refused(&o, &["--out", "no_such_folder", "does not exist"]);
        let o = rigfit()
            .args(args)
            .arg("--out")
            .arg(&folder)
            .output()
            .unwrap();
        refused(&o, &["--out", "a_folder", "found an existing folder"]);
        assert_eq!(std::fs::read_dir(&folder).unwrap().count(), 0);
    }
    let o = rigfit()
        .args(["ringdown", r, "--svg"])
        .arg(&missing)
        .output()
        .unwrap();
    refused(&o, &["--svg", "does not exist"]);
    assert!(!missing.parent().unwrap().exists());
}

#[test]
fn ringdown_start_off_the_record_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let record = dir.path().join("rec.csv");
    ringing_record(&record, false);
    let out = dir.path().join("f.json");
    for start in ["-1", "nan", "inf", "0.4", "7"] {
        let o = rigfit()
            .arg("ringdown")
            .arg(&record)
            .arg(format!("--start={start}"))
            .arg("--out")
            .arg(&out)
            .output()
            .unwrap();
        refused(
            &o,
            &["--start", "expected a time on the record's time axis"],
        );
        assert!(!out.exists());
    }
    let o = rigfit()
        .arg("ringdown")
        .arg(&record)
        .arg("--start=0.05")
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
}

#[test]
fn a_byte_order_mark_is_read_alike_by_every_command() {
    let dir = tempfile::tempdir().unwrap();
    let plain = dir.path().join("plain.csv");
    let marked = dir.path().join("marked.csv");
    ringing_record(&plain, false);
    ringing_record(&marked, true);
    let json_of = |record: &Path, args: &[&str]| -> Value {
        let o = rigfit()
            .arg("--json")
            .args(args)
            .arg(record)
            .output()
            .unwrap();
        assert!(
            o.status.success(),
            "{args:?} {}: {}",
            record.display(),
            stderr(&o)
        );
        serde_json::from_slice(&o.stdout).unwrap()
    };
    for args in [&["ringdown"][..], &["fit-specimen"][..]] {
        let a = json_of(&plain, args);
        let b = json_of(&marked, args);
        assert_eq!(a["fragment"], b["fragment"], "{args:?}");
    }
    for column in ["force_N", "t_s"] {
        let args = [
            "identify", "frf", "--input", column, "--output", "force_N", "--time", "t_s",
        ];
        let run = |record: &Path| {
            let o = rigfit()
                .arg("--json")
                .args(&args[..2])
                .arg(record)
                .args(&args[2..])
                .output()
                .unwrap();
            (o.status.code(), stderr(&o).replace("marked", "plain"))
        };
        assert_eq!(run(&plain), run(&marked), "{column}");
    }
    // A rig file, a campaign and a parameter file saved with a mark.
    let mark = |path: &Path| {
        let text = std::fs::read_to_string(path).unwrap();
        std::fs::write(path, format!("\u{feff}{text}")).unwrap();
    };
    let rig = dir.path().join("rig.json");
    std::fs::copy(repo().join("rigs/tensile4.json"), &rig).unwrap();
    mark(&rig);
    let c = campaign(dir.path(), |c| c["rig"] = json!("rig.json"));
    mark(&c);
    let params = dir.path().join("p.json");
    std::fs::copy(
        repo().join("campaigns/aa2024_t3_reference_params.json"),
        &params,
    )
    .unwrap();
    mark(&params);
    let o = rigfit().arg("check").arg(&c).output().unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    let o = rigfit()
        .arg("simulate")
        .arg(&c)
        .arg("--params")
        .arg(&params)
        .arg("--out")
        .arg(dir.path().join("sim.csv"))
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
}
