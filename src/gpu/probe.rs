//! Runs `shaders/exp_probe.wgsl`: the kernel precision's exp, expm1, ln, sin and
//! cos at given points, for tests against the standard library's.

use crate::eval::Precision;

use super::pack::{from_real_bytes, real_size, to_real_bytes};
use super::pipeline;
use super::shaders::Kernel;
use super::{GpuContext, GpuError};

/// The kernels' functions at one point.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Probed {
    /// `exp_r(x)`.
    pub exp: f64,
    /// `expm1_r(x)`.
    pub expm1: f64,
    /// `ln_r(|x|)`.
    pub ln: f64,
    /// `sin_r(x)`.
    pub sin: f64,
    /// `cos_r(x)`.
    pub cos: f64,
}

/// `(exp(x), expm1(x))` for each `x`, computed on the device at `precision`.
pub fn probe_exp(
    ctx: &GpuContext,
    precision: Precision,
    xs: &[f64],
) -> Result<Vec<(f64, f64)>, GpuError> {
    Ok(probe_math(ctx, precision, xs)?
        .into_iter()
        .map(|p| (p.exp, p.expm1))
        .collect())
}

/// Every probed function at each `x`, computed on the device at `precision`.
pub fn probe_math(
    ctx: &GpuContext,
    precision: Precision,
    xs: &[f64],
) -> Result<Vec<Probed>, GpuError> {
    let kernel = pipeline::build(ctx, None, precision, Kernel::ExpProbe, None)?;
    let size = 5 * xs.len() as u64 * real_size(precision);
    let groups = pipeline::workgroups(ctx, xs.len(), kernel.workgroup_x)?;
    use wgpu::BufferUsages as U;
    let readback = pipeline::scoped(ctx, "exp probe", || {
        let input = ctx.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("probe x"),
            size: (xs.len() as u64 * real_size(precision)).max(8),
            usage: U::STORAGE | U::COPY_DST,
            mapped_at_creation: false,
        });
        ctx.queue
            .write_buffer(&input, 0, &to_real_bytes(xs, precision));
        let out = pipeline::buffer(ctx, "probe out", size, U::STORAGE | U::COPY_SRC);
        let readback = pipeline::buffer(ctx, "probe read-back", size, U::MAP_READ | U::COPY_DST);
        let bind = pipeline::bind(ctx, "probe bind group", &kernel, &[&input, &out]);
        let mut enc = ctx
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("exp probe"),
            });
        super::dispatch::encode_dispatches(&mut enc, "exp probe", &kernel, &[(&bind, groups)], 1);
        enc.copy_buffer_to_buffer(&out, 0, &readback, 0, size);
        ctx.queue.submit([enc.finish()]);
        readback
    })?;
    let v = pipeline::read_back(ctx, &readback, size, |b| from_real_bytes(b, precision))?;
    Ok(v.chunks(5)
        .map(|c| Probed {
            exp: c[0],
            expm1: c[1],
            ln: c[2],
            sin: c[3],
            cos: c[4],
        })
        .collect())
}
