//! The compiled rigs' fitness kernel reads the measured values from a
//! uniform-buffer copy where they fit the device's uniform binding, and from
//! the storage buffer otherwise (src/gpu/shaders.rs, `datum_fn`): the two give
//! the same bits, on every shipped rig campaign in both precisions (force
//! tables sit in the same buffer after the records), and a record too long for
//! the uniform binding falls back to the storage buffer and still matches the
//! CPU reference. The kernel's other layouts, meant for speed alone
//! (`GpuOptions::threads`), give the same bits at any workgroup size and the
//! same fitness, to within the kernels' tolerance, with other vote groups;
//! and the kernels compiled without wgpu's runtime checks
//! (`GpuOptions::runtime_checks`) give the same bits as with them.
mod oracle;
mod tensile_common;

mod gpu_common;
use gpu_common as common;

use std::path::Path;

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rigfit::campaign::Campaign;
use rigfit::eval::{CpuEvaluator, Evaluator, Precision, Problem};
use rigfit::gpu::{GpuContext, GpuEvaluator, GpuOptions, Threads};
use rigfit::job::gene_specs;

/// The campaigns under `campaigns/`, each shortened to at most 400 samples
/// (but those that fit several measured channels, whose kernels come in one
/// group per channel: `gpu_channels_parity.rs`).
fn campaigns() -> Vec<Campaign> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("campaigns");
    let mut out = vec![];
    for p in common::campaign_files() {
        let v: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(&p).unwrap()).unwrap();
        let name = p.file_name().unwrap().to_string_lossy().to_string();
        let Ok(mut c) = Campaign::from_str(&v.to_string(), &dir, &name) else {
            continue;
        };
        if c.problem.experiments.iter().any(|x| x.output != 0) {
            continue;
        }
        for e in &mut c.problem.experiments {
            let n = e.measured.len().min(400);
            e.measured.truncate(n);
            e.window = e.window.start.min(n)..n;
        }
        out.push(c);
    }
    assert!(out.len() >= 2, "too few rig campaigns: {}", out.len());
    out
}

/// Twelve genomes spread over the campaign's search box, seeded.
fn genomes(c: &Campaign) -> Vec<Vec<f64>> {
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    let genes = gene_specs(c);
    (0..12)
        .map(|_| genes.iter().map(|g| g.at_fraction(rng.random())).collect())
        .collect()
}

fn evaluator(ctx: &GpuContext, p: &Problem, precision: Precision, uniform: bool) -> GpuEvaluator {
    let options = GpuOptions {
        uniform_record: uniform,
        ..GpuOptions::default()
    };
    GpuEvaluator::new(ctx.clone(), p.clone(), precision, options).unwrap()
}

fn precisions(ctx: &GpuContext) -> Vec<Precision> {
    let mut v = vec![Precision::F32];
    if ctx.has_f64() {
        v.push(Precision::F64);
    }
    v
}

#[test]
fn the_uniform_copy_and_the_storage_buffer_give_the_same_bits() {
    let Some(ctx) = common::gpu() else { return };
    let mut uniform = 0;
    for c in campaigns() {
        let batch = c.batch(&genomes(&c));
        for precision in precisions(&ctx) {
            let mut on = evaluator(&ctx, &c.problem, precision, true);
            let mut off = evaluator(&ctx, &c.problem, precision, false);
            // A campaign whose drive tables make the data too long for
            // the binding reads storage both ways (EMPS's measured drive).
            assert!(!off.record_in_uniform());
            uniform += usize::from(on.record_in_uniform());
            let a = on.fitness(&batch).unwrap();
            let b = off.fitness(&batch).unwrap();
            let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
            assert_eq!(
                bits(&a.values),
                bits(&b.values),
                "{} {precision:?}",
                c.problem.experiments[0].name
            );
            assert!(
                a.values.iter().any(|&x| x > 0.0 && x < 1.0),
                "no fit at all"
            );
        }
    }
    assert!(
        uniform >= 4,
        "only {uniform} campaign runs used the uniform copy"
    );
}

#[test]
fn a_record_longer_than_the_uniform_binding_is_read_from_storage() {
    let Some(ctx) = common::gpu() else { return };
    let limit = ctx.device.limits().max_uniform_buffer_binding_size as usize;
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("campaigns/aa2024_t3_synthetic.json");
    let mut c = Campaign::load(&path).unwrap();
    // More f32 samples than the binding holds, the measured force repeated
    // (the fit window stays where it was).
    let e = &mut c.problem.experiments[0];
    let n = limit / 4 + 64;
    let f = e.measured.clone();
    e.measured = (0..n).map(|i| f[i % f.len()]).collect();
    let batch = c.batch(&genomes(&c)[..4]);
    let cpu = CpuEvaluator::new(c.problem.clone(), 1)
        .fitness(&batch)
        .unwrap();
    for precision in precisions(&ctx) {
        let mut gpu = evaluator(&ctx, &c.problem, precision, true);
        assert!(
            !gpu.record_in_uniform(),
            "{n} samples fit a {limit}-byte binding"
        );
        let g = gpu.fitness(&batch).unwrap();
        let tol = match precision {
            Precision::F32 => 2e-3,
            Precision::F64 => 1e-9,
        };
        for (a, b) in g.values.iter().zip(&cpu.values) {
            assert!(
                (a - b).abs() <= tol * b.abs().max(1e-3),
                "{precision:?}: {a} vs {b}"
            );
        }
    }
}

#[test]
fn every_workgroup_size_gives_the_same_bits_and_every_vote_group_the_same_fitness() {
    let Some(ctx) = common::gpu() else { return };
    let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    // (workgroup, vote lanes, bit for bit): the vote groups are the same runs
    // at any workgroup size; other vote groups send other steps through the
    // crossed-step code, whose step without a switch rounds as the flat
    // loop's does only to within the kernels' tolerance.
    let layouts = [
        (128, 8, true),
        (16, 8, true),
        (64, 32, false),
        (64, 1, false),
    ];
    for c in campaigns() {
        let batch = c.batch(&genomes(&c));
        for precision in precisions(&ctx) {
            let reference = evaluator(&ctx, &c.problem, precision, true)
                .fitness(&batch)
                .unwrap();
            let tol = match precision {
                Precision::F64 => rigfit::gpu::F64_HISTORY_TOLERANCE,
                Precision::F32 => rigfit::gpu::F32_HISTORY_TOLERANCE,
            };
            for (workgroup, vote_lanes, exact) in layouts {
                let threads = Threads {
                    workgroup,
                    vote_lanes,
                };
                let options = GpuOptions {
                    threads,
                    ..GpuOptions::default()
                };
                let mut e =
                    GpuEvaluator::new(ctx.clone(), c.problem.clone(), precision, options).unwrap();
                let got = e.fitness(&batch).unwrap();
                let what = format!(
                    "{} {precision:?} {threads:?}",
                    c.problem.experiments[0].name
                );
                if exact {
                    assert_eq!(bits(&reference.values), bits(&got.values), "{what}");
                    continue;
                }
                for (&r, &g) in reference.values.iter().zip(&got.values) {
                    assert!(
                        (g - r).abs() <= 1e3 * tol * r.max(1e-3),
                        "{what}: {g} vs {r}"
                    );
                }
            }
        }
    }
    // A layout the kernels cannot take is refused before any work.
    let c = &campaigns()[0];
    let options = GpuOptions {
        threads: Threads {
            workgroup: 48,
            vote_lanes: 8,
        },
        ..GpuOptions::default()
    };
    let e = GpuEvaluator::new(ctx.clone(), c.problem.clone(), Precision::F32, options);
    let Err(e) = e else {
        panic!("a workgroup of 48 was taken")
    };
    assert!(e.to_string().contains("power of two"), "{e}");
}

#[test]
fn the_kernels_without_runtime_checks_give_the_same_bits() {
    let Some(ctx) = common::gpu() else { return };
    let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    let unchecked = GpuOptions {
        runtime_checks: false,
        ..GpuOptions::default()
    };
    for c in campaigns() {
        // 96 runs: past specialise::MIN_RUNS, so the specialised kernel
        // scores it too (one generic pass, one specialised).
        let mut g = genomes(&c);
        g = g.iter().cycle().take(96).cloned().collect();
        let batch = c.batch(&g);
        for precision in precisions(&ctx) {
            for specialise in [false, true] {
                let with = |o: GpuOptions| {
                    let o = GpuOptions { specialise, ..o };
                    GpuEvaluator::new(ctx.clone(), c.problem.clone(), precision, o)
                        .unwrap()
                        .fitness(&batch)
                        .unwrap()
                };
                let checked = with(GpuOptions::default());
                let got = with(unchecked);
                assert_eq!(
                    bits(&checked.values),
                    bits(&got.values),
                    "{} {precision:?} specialised {specialise}",
                    c.problem.experiments[0].name
                );
            }
        }
    }
}
