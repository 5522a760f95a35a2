//! `gpu::open_evaluator` picks the evaluator the CLI asked for: `cpu` always the
//! f64 reference, `gpu` the device at the chosen precision, `auto` the GPU when
//! an adapter exists (f64 where it has SHADER_F64); `list_adapters` reports the
//! adapters with their f64 support.
mod oracle;
mod tensile_common;

mod gpu_common;
use gpu_common as common;

use rigfit::eval::{Backend, Precision, PrecisionChoice};
use rigfit::gpu::{list_adapters, open_evaluator};
use tensile_common::reference_problem;

#[test]
fn cpu_backend_opens_the_reference_without_a_note() {
    let opened = open_evaluator(reference_problem(), Backend::Cpu, PrecisionChoice::Auto).unwrap();
    let info = opened.evaluator.info();
    assert_eq!(info.backend, "cpu");
    assert_eq!(info.precision, Precision::F64);
    assert!(opened.note.is_none());
}

#[test]
fn auto_and_gpu_backends_use_the_adapter_when_there_is_one() {
    let Some(ctx) = common::gpu() else {
        let opened =
            open_evaluator(reference_problem(), Backend::Auto, PrecisionChoice::Auto).unwrap();
        assert_eq!(opened.evaluator.info().backend, "cpu");
        assert!(opened.note.is_some(), "falling back must say so");
        return;
    };
    let auto = open_evaluator(reference_problem(), Backend::Auto, PrecisionChoice::Auto).unwrap();
    let info = auto.evaluator.info();
    assert_eq!(info.backend, "gpu");
    let expected = if ctx.has_f64() {
        Precision::F64
    } else {
        Precision::F32
    };
    assert_eq!(info.precision, expected);
    assert!(auto.note.is_none());

    let f32 = open_evaluator(reference_problem(), Backend::Gpu, PrecisionChoice::F32).unwrap();
    assert_eq!(f32.evaluator.info().precision, Precision::F32);
}

#[test]
fn list_adapters_reports_f64_support() {
    let adapters = list_adapters();
    for a in &adapters {
        eprintln!(
            "{} | {} | {} | {} | f64: {}",
            a.name, a.backend, a.device_type, a.driver, a.shader_f64
        );
        assert!(!a.name.is_empty());
    }
    if let Some(ctx) = common::gpu() {
        assert!(!adapters.is_empty());
        assert!(adapters.iter().any(|a| a.name == ctx.info.name));
    }
}
