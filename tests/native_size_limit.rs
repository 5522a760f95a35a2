//! A rig whose C is over `NATIVE_MAX_C_BYTES` is not built: its lanes
//! interpret from the first batch, the log says why once, and no C compiler
//! is started for it; `RIGFIT_NATIVE=always` still builds it. A larger C
//! waits for more work before it is built (`native_after`).

mod chain;

use std::os::unix::fs::PermissionsExt as _;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use rigfit::compile::back::c;
use rigfit::compile::back::native::{NATIVE_AFTER, NATIVE_MAX_C_BYTES, native_after};
use rigfit::compile::exec::lane_code::LaneCode;
use rigfit::compile::exec::native_calls::Arith;
use rigfit::compile::exec::tape::Tape;

use chain::chain;
use serde_json::json;

/// The size of the f64 C of a chain of `n` masses (bytes).
fn c_bytes(n: usize) -> usize {
    let desc = serde_json::from_value(chain(n)).unwrap();
    let lowered = rigfit::compile::lower(&desc, "chain").unwrap();
    let prog = &lowered.programs[0];
    let code = LaneCode::new(prog, &Tape::new(prog));
    c::source(&code, Arith::F64, 64).len()
}

/// Masses in the chain the jobs below run: its C is over the limit.
const OVER: usize = 200;

#[test]
fn the_limit_falls_between_a_chain_of_100_and_one_of_200_masses() {
    let (small, large) = (c_bytes(100), c_bytes(OVER));
    assert!(small < NATIVE_MAX_C_BYTES, "{small} bytes");
    assert!(large > NATIVE_MAX_C_BYTES, "{large} bytes");
    assert!(native_after(small) > NATIVE_AFTER, "{small} bytes");
    assert_eq!(native_after(c_bytes(10)), NATIVE_AFTER);
}

/// A C compiler that writes each build it is asked for (its arguments
/// name a `.c` file) into `starts` and fails it; anything else (the
/// kept build's probe) goes to `cc`.
fn recording_cc(dir: &Path, starts: &Path) -> PathBuf {
    let path = dir.join("recording-cc");
    let body = format!(
        "#!/bin/sh\nfor a; do case \"$a\" in *.c) echo \"$@\" >> '{}'; exit 1;; esac; done\nexec cc \"$@\"\n",
        starts.display()
    );
    std::fs::write(&path, body).unwrap();
    std::fs::set_permissions(&path, std::fs::Permissions::from_mode(0o755)).unwrap();
    path
}

/// A short CPU job on a chain of [`OVER`] masses in `dir`, with
/// `RIGFIT_NATIVE` as `native` (unset for `None`) and the recording
/// compiler; its output and the builds the compiler was asked for.
fn job(dir: &Path, native: Option<&str>) -> (Output, String) {
    std::fs::write(dir.join("chain.json"), chain(OVER).to_string()).unwrap();
    let mut csv = String::from("t_s,x_m\n");
    for i in 0..50 {
        csv += &format!("{},{}\n", f64::from(i) * 0.01, 1e-3 * f64::from(i % 7));
    }
    std::fs::write(dir.join("d.csv"), csv).unwrap();
    let campaign = json!({
        "name": "chain", "rig": "chain.json",
        "params": {"m": 1.0, "k": {"min": 1e3, "max": 1e4}, "c": 1.0},
        "search": {"population": 8, "generations": 1, "polish": {"enabled": false}},
        "experiments": [{"name": "e", "data": {"file": "d.csv", "time_column": "t_s", "force_column": "x_m"}, "drive": "velocity"}]
    });
    std::fs::write(dir.join("c.json"), campaign.to_string()).unwrap();
    let starts = dir.join("starts.txt");
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_rigfit"));
    cmd.args(["run", "c.json", "--out", "out", "--backend", "cpu"])
        .current_dir(dir)
        .env("RIGFIT_CC", recording_cc(dir, &starts))
        .env("RIGFIT_CACHE_DIR", dir.join("cache"))
        .env("TMPDIR", dir)
        .env_remove("RUST_LOG");
    match native {
        Some(v) => cmd.env("RIGFIT_NATIVE", v),
        None => cmd.env_remove("RIGFIT_NATIVE"),
    };
    let out = cmd.output().unwrap();
    (out, std::fs::read_to_string(starts).unwrap_or_default())
}

#[test]
fn a_rig_over_the_limit_interprets_says_so_once_and_starts_no_compiler() {
    let dir = tempfile::tempdir().unwrap();
    let (o, starts) = job(dir.path(), None);
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(0), "{err}");
    let said = format!("over the {NATIVE_MAX_C_BYTES} (NATIVE_MAX_C_BYTES)");
    assert_eq!(err.matches(&said).count(), 1, "{err}");
    assert!(
        err.contains("the lane ensemble interprets instead"),
        "{err}"
    );
    assert!(
        starts.is_empty(),
        "the compiler was asked to build: {starts}"
    );
    assert!(dir.path().join("out/result.json").exists());
}

#[test]
fn rigfit_native_always_still_builds_a_rig_over_the_limit() {
    let dir = tempfile::tempdir().unwrap();
    let (o, starts) = job(dir.path(), Some("always"));
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(0), "{err}");
    assert!(starts.contains("lanes.c"), "no build was started: {err}");
    assert!(!err.contains("NATIVE_MAX_C_BYTES"), "{err}");
}
