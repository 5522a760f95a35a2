//! rigfit's command line reads HDF5 in a child process (`rigfit
//! __read-hdf5`, `src/record/hdf5_child.rs`): what it reads there is what
//! the library reads in process, bit for bit, and a file on which libhdf5
//! crashes is an error naming the file (exit code 2), not the end of rigfit.
//!
//! `tests/data/records/hdf5_crash_1_10.h5` crashes Debian 12's libhdf5
//! 1.10.8 (SIGSEGV); where the libhdf5 linked reports an error on it
//! instead, the tests hold the error to the same file and exit code and do
//! not ask for the word "crashed".

#![cfg(feature = "hdf5")]

use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::{Command, Output, Stdio};

use rigfit::record::{Format, Record, detect, hdf5_child};
use serde_json::{Value, json};

fn record_file(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/records")
        .join(name)
}

fn rigfit(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_rigfit"))
        .args(args)
        .output()
        .unwrap()
}

/// `rigfit __read-hdf5` with `bytes` on its stdin.
fn child(bytes: &[u8]) -> Output {
    let mut child = Command::new(env!("CARGO_BIN_EXE_rigfit"))
        .arg(hdf5_child::SUBCOMMAND)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut stdin = child.stdin.take().unwrap();
    let _ = stdin.write_all(bytes);
    drop(stdin);
    child.wait_with_output().unwrap()
}

/// Whether `out` is a process killed by a signal.
fn killed(out: &Output) -> bool {
    use std::os::unix::process::ExitStatusExt;
    out.status.signal().is_some()
}

fn stderr(out: &Output) -> String {
    String::from_utf8_lossy(&out.stderr).into_owned()
}

/// A channel's name, unit, and the bits of its timing and values.
type ChannelBits = (String, Option<String>, Option<[u64; 2]>, Vec<u64>);

/// Every channel of a record, its numbers as bits.
fn bits(record: &Record) -> Vec<ChannelBits> {
    let channel = |c: &rigfit::record::Channel| {
        let timing = c.timing.map(|w| [w.start.to_bits(), w.increment.to_bits()]);
        let values = c.values.iter().map(|v| v.to_bits()).collect();
        (c.name.clone(), c.unit.clone(), timing, values)
    };
    record.channels.iter().map(channel).collect()
}

#[test]
fn the_child_answers_what_the_library_reads_in_process_bit_for_bit() {
    for name in ["hdf5_tensile.h5", "hdf5_mat73.mat", "hdf5_strings_only.h5"] {
        let bytes = std::fs::read(record_file(name)).unwrap();
        let out = child(&bytes);
        assert!(out.status.success(), "{name}: {}", stderr(&out));
        // The answer holds every bit of the record (or every field of the
        // error), so equal answers are equal reads.
        assert!(
            out.stdout == hdf5_child::answer(&bytes),
            "{name}: the child's answer differs from the one read in process"
        );
    }
}

#[test]
fn inspect_lists_the_channels_the_library_reads() {
    let file = record_file("hdf5_tensile.h5");
    let bytes = std::fs::read(&file).unwrap();
    let here = detect::read(Format::Hdf5, &bytes).unwrap();
    let out = rigfit(&["inspect", file.to_str().unwrap(), "--json"]);
    assert!(out.status.success(), "{}", stderr(&out));
    let listed: Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(listed["format"], "hdf5");
    let channels = listed["channels"].as_array().unwrap();
    assert_eq!(channels.len(), here.channels.len());
    for (i, (shown, c)) in channels.iter().zip(&here.channels).enumerate() {
        let finite = c.values.iter().copied().filter(|v| v.is_finite());
        let min = finite.clone().reduce(f64::min).unwrap();
        let max = finite.reduce(f64::max).unwrap();
        let expected = json!({
            "index": i,
            "name": c.name,
            "unit": c.unit,
            "samples": c.values.len(),
            "start_s": c.timing.map(|w| w.start),
            "increment_s": c.timing.map(|w| w.increment),
            "rate_hz": c.timing.map(|w| 1.0 / w.increment),
            "min": min,
            "max": max,
        });
        assert_eq!(shown, &expected, "channel {i}");
    }
}

#[test]
fn a_file_that_crashes_libhdf5_is_an_error_naming_it() {
    let file = record_file("hdf5_crash_1_10.h5");
    let bytes = std::fs::read(&file).unwrap();
    let crashes = killed(&child(&bytes));
    let name = file.to_str().unwrap();
    for json in [false, true] {
        let mut args = vec!["inspect", name];
        if json {
            args.push("--json");
        }
        let out = rigfit(&args);
        assert!(!killed(&out), "rigfit itself died: {}", stderr(&out));
        assert_eq!(out.status.code(), Some(2), "{}", stderr(&out));
        let e = stderr(&out);
        assert!(e.contains(name) && e.contains("HDF5"), "{e}");
        if crashes {
            assert!(e.contains("libhdf5 crashed reading it (signal"), "{e}");
        }
        if json {
            let doc: Value = serde_json::from_slice(&out.stdout).unwrap();
            assert_eq!(doc["exit_code"], 2);
            assert!(doc["error"].as_str().unwrap().contains(name), "{doc}");
        }
    }
}

#[test]
fn a_campaign_whose_record_crashes_libhdf5_is_refused_naming_it() {
    let formats = Path::new(env!("CARGO_MANIFEST_DIR")).join("campaigns/formats");
    let dir = tempfile::tempdir().unwrap();
    let text = std::fs::read_to_string(formats.join("aa2024_t3_v2_h5.json")).unwrap();
    let mut campaign: Value = serde_json::from_str(&text).unwrap();
    campaign["output"] = json!("out");
    let crash = record_file("hdf5_crash_1_10.h5");
    std::fs::copy(&crash, dir.path().join("aa2024_t3_v2.h5")).unwrap();
    let file = dir.path().join("campaign.json");
    std::fs::write(&file, serde_json::to_string_pretty(&campaign).unwrap()).unwrap();
    let out = rigfit(&["check", file.to_str().unwrap(), "--no-measure", "--quiet"]);
    assert!(!killed(&out), "rigfit itself died: {}", stderr(&out));
    assert_eq!(out.status.code(), Some(2), "{}", stderr(&out));
    let e = stderr(&out);
    assert!(e.contains("aa2024_t3_v2.h5"), "{e}");
    if killed(&child(&std::fs::read(&crash).unwrap())) {
        assert!(e.contains("libhdf5 crashed"), "{e}");
    }
}

#[test]
fn the_library_reads_in_the_child_once_asked() {
    let bytes = std::fs::read(record_file("hdf5_tensile.h5")).unwrap();
    let here = detect::read(Format::Hdf5, &bytes).unwrap();
    let mat = std::fs::read(record_file("hdf5_mat73.mat")).unwrap();
    let mat_here = detect::read(Format::Mat, &mat).unwrap();
    // From here on every HDF5 read of this test process starts the binary
    // (the other tests compare against reads that give the same bits).
    hdf5_child::read_in_child(PathBuf::from(env!("CARGO_BIN_EXE_rigfit")));
    let there = detect::read(Format::Hdf5, &bytes).unwrap();
    assert_eq!(bits(&there), bits(&here));
    assert_eq!(there.format, Format::Hdf5);
    let mat_there = detect::read(Format::Mat, &mat).unwrap();
    assert_eq!(bits(&mat_there), bits(&mat_here));
    assert_eq!(mat_there.format, Format::Mat);

    let crash = std::fs::read(record_file("hdf5_crash_1_10.h5")).unwrap();
    let e = detect::read(Format::Hdf5, &crash).unwrap_err();
    assert_eq!((e.format, e.at.as_str()), (Format::Hdf5, "file"), "{e}");
    if killed(&child(&crash)) {
        assert_eq!(e.expected, "an HDF5 file libhdf5 reads", "{e}");
        assert!(
            e.found.starts_with("libhdf5 crashed reading it (signal "),
            "{e}"
        );
    }
    let e = detect::read(Format::Hdf5, b"no signature").unwrap_err();
    assert!(e.found.contains("no HDF5 signature"), "{e}");
}
