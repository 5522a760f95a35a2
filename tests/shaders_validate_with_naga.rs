//! Every kernel, for every shipped rig and both precisions, parses and validates
//! with naga, and what the Rust side assumes about it (struct sizes, entry
//! points, 1-D workgroups, shared constants) agrees with the WGSL.

use rigfit::base::{Drive, PiecewiseLinear};
use rigfit::eval::Precision;
use rigfit::gpu::layout::{ExpInfo, Settings, run_stride, shared_constants};
use rigfit::gpu::shaders::{self, Kernel, ProblemShape};
use rigfit::model::GpuModel;
use rigfit::model::compiled::CompiledRig;

/// Every shipped rig's kernels, for each of its drive modes.
fn gpu_models() -> Vec<(String, GpuModel)> {
    let mut models: Vec<(String, GpuModel)> = Vec::new();
    let force = Drive::Force(PiecewiseLinear {
        t: vec![0.0, 1.0],
        value: vec![0.0, 1.0],
    });
    for (id, _) in rigfit::rig::SHIPPED {
        let desc = rigfit::rig::shipped(id).expect("shipped");
        let rig = CompiledRig::shared(desc, id).expect("compiles");
        let mut any = false;
        for drive in [&Drive::Velocity, &force] {
            if let Some(g) = rig.gpu(drive) {
                models.push((format!("rig {id} {:?}", rig.program_for(drive)), g));
                any = true;
            }
        }
        assert!(any, "rig {id} has no GPU kernels");
    }
    models
}

fn sources() -> Vec<(String, Precision, Kernel, String)> {
    let mut out = Vec::new();
    for (id, model) in gpu_models() {
        for precision in [Precision::F32, Precision::F64] {
            for kernel in Kernel::ALL {
                // Both drive flags; the measured values from `data` and
                // from a uniform copy (one vec4, and 64 KiB's worth); the
                // tables' search paths kept and compiled out.
                for (force_drive, record_vec4s, exact_tables) in [
                    (false, None, false),
                    (true, Some(1), true),
                    (false, Some(4096), false),
                ] {
                    let shape = ProblemShape {
                        force_drive,
                        record_vec4s,
                        exact_tables,
                        threads: Default::default(),
                        trusted: false,
                    };
                    let src = match kernel {
                        Kernel::ExpProbe => shaders::probe_source(precision),
                        _ => shaders::source(&model, precision, kernel, shape, &[]),
                    };
                    out.push((format!("{id} {shape:?}"), precision, kernel, src));
                }
                if kernel == Kernel::Fitness {
                    // Every per-run value baked (specialise.rs): literals of
                    // both signs, tiny and large, an integer and a negative zero.
                    let stride = run_stride(model.slot_names().len()) as usize;
                    let values = [1.5e-3, -2.25e7, 1e-30, 3.0e38, 4.0, -0.0, 0.1];
                    let baked: Vec<Option<f64>> = (0..stride)
                        .map(|i| Some(values[i % values.len()]))
                        .collect();
                    let src =
                        shaders::source(&model, precision, kernel, Default::default(), &baked);
                    let param = shaders::param_fn(&baked, precision);
                    assert_eq!(param.matches("case ").count(), stride);
                    assert!(src.contains(&param), "{id}: param() not baked");
                    out.push((format!("{id} all baked"), precision, kernel, src));
                }
            }
        }
    }
    out
}

#[test]
fn every_kernel_parses_and_validates_in_both_precisions() {
    for (id, precision, kernel, src) in sources() {
        if let Err(e) = shaders::reflect(&src, precision, kernel) {
            panic!("{id} {precision:?} {}: {e}", kernel.file());
        }
    }
}

#[test]
fn workgroups_are_one_dimensional_and_read_back_from_wgsl() {
    for (id, precision, kernel, src) in sources() {
        let r = shaders::reflect(&src, precision, kernel).unwrap();
        let [x, y, z] = r.workgroup_size;
        assert!(
            x >= 1 && y == 1 && z == 1,
            "{id} {}: {:?}",
            kernel.file(),
            r.workgroup_size
        );
    }
}

fn struct_size(module: &naga::Module, name: &str) -> u32 {
    let mut layouter = naga::proc::Layouter::default();
    layouter.update(module.to_ctx()).unwrap();
    let (handle, _) = module
        .types
        .iter()
        .find(|(_, t)| t.name.as_deref() == Some(name))
        .unwrap_or_else(|| panic!("no struct {name}"));
    layouter[handle].size
}

#[test]
fn host_structs_match_wgsl_sizes() {
    for (id, precision, kernel, src) in sources() {
        if kernel == Kernel::ExpProbe {
            continue;
        }
        let m = shaders::reflect(&src, precision, kernel).unwrap().module;
        assert_eq!(
            struct_size(&m, "Settings") as usize,
            size_of::<Settings>(),
            "{id}"
        );
        assert_eq!(
            struct_size(&m, "ExpInfo") as usize,
            size_of::<ExpInfo>(),
            "{id}"
        );
    }
}

#[test]
fn shared_constants_reach_the_shader_unchanged() {
    for (id, model) in gpu_models() {
        let shape = ProblemShape {
            force_drive: true,
            record_vec4s: None,
            exact_tables: false,
            threads: Default::default(),
            trusted: false,
        };
        let src = shaders::source(&model, Precision::F32, Kernel::Fitness, shape, &[]);
        let m = shaders::reflect(&src, Precision::F32, Kernel::Fitness)
            .unwrap()
            .module;
        for (name, value) in shared_constants(
            &model.slot_names(),
            model.state_stride(),
            model.hist_values(),
        ) {
            let (_, c) = m
                .constants
                .iter()
                .find(|(_, c)| c.name.as_deref() == Some(name.as_str()))
                .unwrap_or_else(|| panic!("{id}: constant {name} missing"));
            match m.global_expressions[c.init] {
                naga::Expression::Literal(naga::Literal::U32(v)) => {
                    assert_eq!(v, value, "{name}")
                }
                ref other => panic!("{name}: unexpected {other:?}"),
            }
        }
    }
}

/// The fitness kernel runs the rig's fitness variant (src/compile/analysis/liveness.rs):
/// tensile4's slack and yield switches armed only while the specimen is whole;
/// the history kernel arms every switch on its own mode alone.
#[test]
fn the_fitness_kernel_skips_the_switches_behind_the_break() {
    let desc = rigfit::rig::shipped("tensile4").expect("shipped");
    let rig = CompiledRig::shared(desc, "tensile4").expect("compiles");
    let model = rig.gpu(&Drive::Velocity).expect("GPU kernels");
    let hits = |kernel: Kernel| {
        let src = shaders::source(&model, Precision::F32, kernel, Default::default(), &[]);
        let at = src.find("fn rig_hits(").expect("rig_hits");
        let body = &src[at..at + src[at..].find("\n}\n").expect("end")];
        body.lines()
            .filter(|l| l.contains("hits |="))
            .map(|l| l.matches("rg.r").count())
            .collect::<Vec<_>>()
    };
    // Five transitions; fracture (one mode test) is never guarded.
    let fitness = hits(Kernel::Fitness);
    assert_eq!(fitness.len(), 5);
    assert_eq!(
        fitness.iter().filter(|&&n| n == 2).count(),
        4,
        "{fitness:?}"
    );
    assert_eq!(hits(Kernel::History), vec![1; 5]);
}

#[test]
fn the_fitness_kernels_threads_reach_its_source() {
    use rigfit::gpu::Threads;
    for (id, model) in gpu_models() {
        for (workgroup, vote_lanes) in [(256, 32), (8, 1)] {
            let shape = ProblemShape {
                threads: Threads {
                    workgroup,
                    vote_lanes,
                },
                ..Default::default()
            };
            for precision in [Precision::F32, Precision::F64] {
                let src = shaders::source(&model, precision, Kernel::Fitness, shape, &[]);
                let m = shaders::reflect(&src, precision, Kernel::Fitness)
                    .unwrap_or_else(|e| panic!("{id} {workgroup}x{vote_lanes}: {e}"));
                assert_eq!(m.workgroup_size[0], workgroup, "{id}");
                let vote = format!("const VOTE_LANES: u32 = {vote_lanes}u;");
                assert!(src.contains(&vote), "{id}: no {vote}");
                // The history kernel keeps its own workgroup size.
                let src = shaders::source(&model, precision, Kernel::History, shape, &[]);
                let h = shaders::reflect(&src, precision, Kernel::History).unwrap();
                assert_eq!(h.workgroup_size[0], 16, "{id}");
                assert!(src.contains(&vote), "{id}: history: no {vote}");
            }
        }
    }
}
