//! Every shipped rig's generated code, kept under `tests/snapshots/` so that a
//! change to an emitter is reviewed as a diff of the text it writes, not only
//! as a test outcome: for each rig and drive mode, the WGSL functions the GPU
//! kernels are stitched around (`GpuRig::source`, and the fitness variant's
//! where its liveness analysis skips events) and the C of the native lanes in
//! f64 and f32 (`c::source`).
//!
//! `RIGFIT_BLESS=1 cargo test --test generated_code_snapshots` rewrites the
//! snapshots from the emitters; without it a snapshot that differs from what
//! the emitter writes now fails, naming the first line that differs.

use std::path::{Path, PathBuf};

use rigfit::compile::back::c;
use rigfit::compile::{Arith, GpuRig, LaneCode, Tape, lower};

fn snapshot_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/snapshots")
}

/// A literal as the f64 kernels write it (`shaders::real_literal`'s form).
fn literal(v: f64) -> String {
    format!("real({v:e})")
}

/// `(file name, text)` of every snapshot, in a fixed order.
fn generated() -> Vec<(String, String)> {
    let mut out = Vec::new();
    for (id, _) in rigfit::rig::SHIPPED {
        let desc = rigfit::rig::shipped(id).expect("a shipped rig");
        let lowered = lower(&desc, id).expect("a shipped rig lowers");
        for prog in &lowered.programs {
            let stem = format!("{id}.{}", prog.mode);
            let fitted = rigfit::compile::analysis::liveness::skipping_variant(prog);
            let gpu = GpuRig::with_fitness(prog, fitted).expect("a shipped rig emits WGSL");
            out.push((format!("{stem}.wgsl"), gpu.source(&literal)));
            if !std::ptr::eq(gpu.fitness(), &gpu) {
                out.push((
                    format!("{stem}.fitness.wgsl"),
                    gpu.fitness().source(&literal),
                ));
            }
            let tape = Tape::new(prog);
            let code = LaneCode::new(prog, &tape);
            out.push((format!("{stem}.f64.c"), c::source(&code, Arith::F64, 64)));
            out.push((format!("{stem}.f32.c"), c::source(&code, Arith::F32, 64)));
        }
    }
    out
}

#[test]
fn generated_code_matches_its_snapshots() {
    let dir = snapshot_dir();
    let files = generated();
    assert!(files.len() >= 3 * rigfit::rig::SHIPPED.len());
    if std::env::var_os("RIGFIT_BLESS").is_some_and(|v| v != "0") {
        std::fs::create_dir_all(&dir).unwrap();
        for (name, text) in &files {
            std::fs::write(dir.join(name), text).unwrap();
        }
        return;
    }
    let mut stale = Vec::new();
    for (name, text) in &files {
        let path = dir.join(name);
        let Ok(kept) = std::fs::read_to_string(&path) else {
            stale.push(format!("{name}: no snapshot"));
            continue;
        };
        if kept != *text {
            let line = kept
                .lines()
                .zip(text.lines())
                .position(|(a, b)| a != b)
                .unwrap_or_else(|| kept.lines().count().min(text.lines().count()));
            stale.push(format!("{name}: differs from line {}", line + 1));
        }
    }
    // A snapshot no emitter writes any more (a rig or drive mode removed).
    let names: Vec<&str> = files.iter().map(|(n, _)| n.as_str()).collect();
    for entry in std::fs::read_dir(&dir).unwrap() {
        let name = entry.unwrap().file_name().to_string_lossy().to_string();
        if !names.contains(&name.as_str()) {
            stale.push(format!("{name}: written by no emitter"));
        }
    }
    assert!(
        stale.is_empty(),
        "generated code differs from tests/snapshots/ (review the diff, then \
         RIGFIT_BLESS=1 cargo test --test generated_code_snapshots):\n  {}",
        stale.join("\n  ")
    );
}
