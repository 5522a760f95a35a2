//! The bench's reader of a driver's kernel statistics
//! (`benches/common/vk_stats.rs`, `RIGFIT_BENCH_STATS=1`): every fitness kernel
//! an evaluator compiles, checked or without wgpu's runtime checks, specialised
//! or generic, in both precisions, goes through naga's SPIR-V writer and builds
//! into a Vulkan compute pipeline on the same adapter; a driver that offers
//! statistics gives some for each; a kernel that does not validate is refused
//! with naga's message.
#[path = "../benches/common/vk_stats.rs"]
mod vk_stats;

mod oracle;
mod tensile_common;

mod gpu_common;
use gpu_common as common;

use std::path::Path;

use rigfit::campaign::Campaign;
use rigfit::eval::{Evaluator, Precision};
use rigfit::gpu::shaders::Kernel;
use rigfit::gpu::{GpuEvaluator, GpuOptions};
use rigfit::job::gene_specs;

#[test]
fn every_fitness_kernel_builds_into_a_pipeline_with_the_drivers_statistics() {
    let Some(ctx) = common::gpu() else { return };
    let stats = vk_stats::VkStats::open(std::env::var("RIGFIT_ADAPTER").ok().as_deref())
        .unwrap_or_else(|e| panic!("{e}"));
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("campaigns/aa2024_t3_synthetic.json");
    let mut c = Campaign::load(&path).unwrap();
    for e in &mut c.problem.experiments {
        e.measured.truncate(200);
        e.window = e.window.start.min(200)..200;
    }
    let genes = gene_specs(&c);
    let genomes: Vec<Vec<f64>> = (0..96)
        .map(|i| {
            genes
                .iter()
                .map(|g| g.at_fraction((i as f64 + 0.5) / 96.0))
                .collect()
        })
        .collect();
    let batch = c.batch(&genomes);
    let mut precisions = vec![Precision::F32];
    if ctx.has_f64() {
        precisions.push(Precision::F64);
    }
    let mut built = 0;
    for precision in precisions {
        for (specialise, runtime_checks) in [(false, true), (true, true), (true, false)] {
            let options = GpuOptions {
                specialise,
                runtime_checks,
                ..GpuOptions::default()
            };
            let mut e =
                GpuEvaluator::new(ctx.clone(), c.problem.clone(), precision, options).unwrap();
            e.fitness(&batch).unwrap();
            assert_eq!(e.specialised_constants().is_some(), specialise);
            let (src, trusted) = e.fitness_source();
            assert_eq!(trusted, !runtime_checks);
            let got = stats
                .statistics(&src, Kernel::Fitness, precision, trusted)
                .unwrap_or_else(|why| panic!("{precision:?} {options:?}: {why}"));
            assert_eq!(
                got.is_empty(),
                !stats.offered,
                "{precision:?} {options:?}: {} statistics from {}",
                got.len(),
                stats.about
            );
            built += 1;
        }
        // The unchecked kernel's SPIR-V has no loop counters: it is shorter.
        let (src, _) = GpuEvaluator::new(
            ctx.clone(),
            c.problem.clone(),
            precision,
            GpuOptions::default(),
        )
        .unwrap()
        .fitness_source();
        let checked = stats
            .spirv(&src, Kernel::Fitness, precision, false)
            .unwrap()
            .0;
        let unchecked = stats
            .spirv(&src, Kernel::Fitness, precision, true)
            .unwrap()
            .0;
        assert!(
            unchecked.len() < checked.len(),
            "{precision:?}: {} words unchecked, {} checked",
            unchecked.len(),
            checked.len()
        );
    }
    assert!(built >= 3);
    // A kernel that does not validate never reaches the driver.
    let (src, _) = GpuEvaluator::new(
        ctx.clone(),
        c.problem.clone(),
        Precision::F32,
        GpuOptions::default(),
    )
    .unwrap()
    .fitness_source();
    let broken = src.replace("fn run_close(", "fn run_closed(");
    let Err(why) = stats.statistics(&broken, Kernel::Fitness, Precision::F32, false) else {
        panic!("a kernel calling an undefined function was built")
    };
    assert!(why.contains("run_close"), "{why}");
}
