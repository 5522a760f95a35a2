//! Running on a device: pipelines built from the stitched WGSL, labelled
//! buffers, error scopes and read-back. Nothing here picks a device.

use wgpu::util::DeviceExt;

use crate::eval::Precision;
use crate::model::GpuModel;

use super::shaders::{self, Kernel};
use super::{GpuContext, GpuError};

/// A compute pipeline with the workgroup size read back from its WGSL.
#[derive(Debug, Clone)]
pub struct Kernelled {
    /// The pipeline (auto layout, bind group 0).
    pub pipeline: wgpu::ComputePipeline,
    /// `@workgroup_size(x, …)` of the entry point.
    pub workgroup_x: u32,
}

/// Runs `f` inside validation and out-of-memory error scopes, returning the
/// first error raised as a [`GpuError`].
pub fn scoped<T>(ctx: &GpuContext, what: &str, f: impl FnOnce() -> T) -> Result<T, GpuError> {
    let oom = ctx.device.push_error_scope(wgpu::ErrorFilter::OutOfMemory);
    let validation = ctx.device.push_error_scope(wgpu::ErrorFilter::Validation);
    let out = f();
    let v = pollster::block_on(validation.pop());
    let o = pollster::block_on(oom.pop());
    match v.or(o) {
        Some(e) => Err(GpuError::Device {
            during: what.to_string(),
            message: e.to_string(),
        }),
        None => Ok(out),
    }
}

/// What one binding of an explicit bind group layout holds.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Binding {
    /// `var<uniform>`.
    Uniform,
    /// `var<storage, read>`.
    Read,
    /// `var<storage, read_write>`.
    ReadWrite,
}

/// An explicit layout (bind group 0 only), shared by every variant of a kernel
/// so that one bind group serves them all.
#[derive(Debug, Clone)]
pub struct Layout {
    /// Bind group 0.
    pub group: wgpu::BindGroupLayout,
    /// The pipeline layout over it.
    pub pipeline: wgpu::PipelineLayout,
}

/// An explicit layout whose binding `i` holds `bindings[i]`, visible to compute.
pub fn layout(ctx: &GpuContext, label: &str, bindings: &[Binding]) -> Layout {
    let entries: Vec<wgpu::BindGroupLayoutEntry> = bindings
        .iter()
        .enumerate()
        .map(|(i, b)| wgpu::BindGroupLayoutEntry {
            binding: i as u32,
            visibility: wgpu::ShaderStages::COMPUTE,
            ty: wgpu::BindingType::Buffer {
                ty: match b {
                    Binding::Uniform => wgpu::BufferBindingType::Uniform,
                    Binding::Read => wgpu::BufferBindingType::Storage { read_only: true },
                    Binding::ReadWrite => wgpu::BufferBindingType::Storage { read_only: false },
                },
                has_dynamic_offset: false,
                min_binding_size: None,
            },
            count: None,
        })
        .collect();
    let group = ctx
        .device
        .create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some(label),
            entries: &entries,
        });
    let pipeline = ctx
        .device
        .create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some(label),
            bind_group_layouts: &[Some(&group)],
            immediate_size: 0,
        });
    Layout { group, pipeline }
}

/// A kernel's WGSL, validated by naga, with its workgroup size read back:
/// everything but the driver's compile (milliseconds, against tens of them
/// for lavapipe's compile).
#[derive(Debug, Clone)]
pub struct Prepared {
    src: String,
    kernel: Kernel,
    /// Compiled without wgpu's runtime checks ([`shaders::ProblemShape::trusted`]).
    trusted: bool,
    /// `@workgroup_size(x, …)` of the entry point.
    pub workgroup_x: u32,
}

impl Prepared {
    /// The kernel's WGSL.
    pub fn source(&self) -> &str {
        &self.src
    }
}

/// Stitches and validates `kernel` for `model` (with its problem's shape and
/// baked per-run values, see [`shaders::param_fn`]) at `precision`.
pub fn prepare(
    model: Option<(&GpuModel, shaders::ProblemShape, &[Option<f64>])>,
    precision: Precision,
    kernel: Kernel,
) -> Result<Prepared, GpuError> {
    let (src, trusted) = match model {
        Some((m, shape, baked)) => (
            shaders::source(m, precision, kernel, shape, baked),
            shape.trusted,
        ),
        None => (shaders::probe_source(precision), false),
    };
    let reflected = shaders::reflect(&src, precision, kernel)?;
    Ok(Prepared {
        src,
        kernel,
        trusted,
        workgroup_x: reflected.workgroup_size[0],
    })
}

/// The driver's compile of a [`Prepared`] kernel: the pipeline, with `layout`
/// or else the layout wgpu derives from the shader.
pub fn compile(
    ctx: &GpuContext,
    prepared: &Prepared,
    layout: Option<&Layout>,
) -> Result<Kernelled, GpuError> {
    let kernel = prepared.kernel;
    let pipeline = scoped(ctx, kernel.file(), || {
        let desc = wgpu::ShaderModuleDescriptor {
            label: Some(kernel.file()),
            source: wgpu::ShaderSource::Wgsl(prepared.src.as_str().into()),
        };
        let module = if prepared.trusted {
            trusted_module(ctx, desc)
        } else {
            ctx.device.create_shader_module(desc)
        };
        ctx.device
            .create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
                label: Some(kernel.entry_point()),
                layout: layout.map(|l| &l.pipeline),
                module: &module,
                entry_point: Some(kernel.entry_point()),
                compilation_options: Default::default(),
                cache: None,
            })
    })?;
    Ok(Kernelled {
        pipeline,
        workgroup_x: prepared.workgroup_x,
    })
}

/// `desc`'s module compiled without wgpu's runtime checks
/// ([`shaders::ProblemShape::trusted`]).
#[allow(unsafe_code)]
fn trusted_module(ctx: &GpuContext, desc: wgpu::ShaderModuleDescriptor) -> wgpu::ShaderModule {
    // SAFETY: the kernels are ours, stitched by shaders::source from the
    // files under shaders/ and the emitter's rig functions, never a user's
    // WGSL. Every index into an array in function memory is in bounds by
    // construction (a transition's index below the program's transition
    // count, a vote group's index taken modulo the array's length), and
    // every loop ends: counted loops, the run loop's budget that each
    // pass lowers, the crossing search's LOCATE_ITERATIONS, and the sample
    // clock's catch-up, whose instant grows by one period each pass; and
    // every integer division is by a constant or by the experiment count,
    // never zero (docs/engineering/kernels.md, "Unsafe code"). Buffer reads
    // and writes keep the device's robust buffer access, which wgpu enables
    // where the device has it, whatever the checks.
    unsafe {
        ctx.device
            .create_shader_module_trusted(desc, wgpu::ShaderRuntimeChecks::unchecked())
    }
}

/// [`prepare`], then [`compile`].
pub fn build(
    ctx: &GpuContext,
    model: Option<(&GpuModel, shaders::ProblemShape, &[Option<f64>])>,
    precision: Precision,
    kernel: Kernel,
    layout: Option<&Layout>,
) -> Result<Kernelled, GpuError> {
    compile(ctx, &prepare(model, precision, kernel)?, layout)
}

/// A kernel compiled on a thread of its own while the job goes on (error
/// scopes are per thread, so its errors stay its own), taken where it is
/// first needed.
#[derive(Debug)]
pub struct Pending {
    /// The compile, until it is waited for.
    compiling: Option<std::thread::JoinHandle<Result<Kernelled, GpuError>>>,
    /// Its outcome once waited for: the kernel, or why there is none.
    done: Option<Result<Kernelled, String>>,
}

impl Pending {
    /// Starts compiling `prepared` on `layout` on a new thread.
    pub fn spawn(ctx: &GpuContext, prepared: Prepared, layout: &Layout) -> Self {
        let (ctx, layout) = (ctx.clone(), layout.clone());
        let handle = std::thread::spawn(move || compile(&ctx, &prepared, Some(&layout)));
        Pending {
            compiling: Some(handle),
            done: None,
        }
    }

    /// The kernel, waiting for its compile where it is still running.
    pub fn wait(&mut self) -> Result<&Kernelled, GpuError> {
        if let Some(handle) = self.compiling.take() {
            self.done = Some(match handle.join() {
                Ok(Ok(k)) => Ok(k),
                Ok(Err(e)) => Err(e.to_string()),
                Err(_) => Err("its thread panicked".into()),
            });
        }
        match self.done.as_ref().expect("joined above") {
            Ok(k) => Ok(k),
            Err(message) => Err(GpuError::Device {
                during: "compiling a kernel".into(),
                message: message.clone(),
            }),
        }
    }
}

/// A compile still running when its evaluator goes is waited for, so that no
/// thread is left inside the driver when the process exits.
impl Drop for Pending {
    fn drop(&mut self) {
        if let Some(handle) = self.compiling.take() {
            let _ = handle.join();
        }
    }
}

/// A buffer of `usage` initialised with `bytes`, zero-padded to at least 16
/// bytes.
fn buffer_init(
    ctx: &GpuContext,
    label: &str,
    bytes: &[u8],
    usage: wgpu::BufferUsages,
) -> wgpu::Buffer {
    let mut contents = bytes.to_vec();
    contents.resize(contents.len().max(16), 0);
    ctx.device
        .create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some(label),
            contents: &contents,
            usage,
        })
}

/// A storage buffer initialised with `bytes` (at least 16 bytes).
pub fn storage_init(ctx: &GpuContext, label: &str, bytes: &[u8], writable: bool) -> wgpu::Buffer {
    let mut usage = wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_DST;
    if writable {
        usage |= wgpu::BufferUsages::COPY_SRC;
    }
    buffer_init(ctx, label, bytes, usage)
}

/// A uniform buffer initialised with `bytes` (at least 16 bytes).
pub fn uniform_init(ctx: &GpuContext, label: &str, bytes: &[u8]) -> wgpu::Buffer {
    buffer_init(ctx, label, bytes, wgpu::BufferUsages::UNIFORM)
}

/// An uninitialised buffer of `size` bytes (at least 16).
pub fn buffer(ctx: &GpuContext, label: &str, size: u64, usage: wgpu::BufferUsages) -> wgpu::Buffer {
    ctx.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some(label),
        size: size.max(16).next_multiple_of(8),
        usage,
        mapped_at_creation: false,
    })
}

/// A bind group for `kernel`'s own layout over `buffers`, binding i ← buffers\[i\].
pub fn bind(
    ctx: &GpuContext,
    label: &str,
    kernel: &Kernelled,
    buffers: &[&wgpu::Buffer],
) -> wgpu::BindGroup {
    bind_with(
        ctx,
        label,
        &kernel.pipeline.get_bind_group_layout(0),
        buffers,
    )
}

/// A bind group for `layout` over `buffers`, binding i ← buffers\[i\].
pub fn bind_with(
    ctx: &GpuContext,
    label: &str,
    layout: &wgpu::BindGroupLayout,
    buffers: &[&wgpu::Buffer],
) -> wgpu::BindGroup {
    let entries: Vec<wgpu::BindGroupEntry<'_>> = buffers
        .iter()
        .enumerate()
        .map(|(i, b)| wgpu::BindGroupEntry {
            binding: i as u32,
            resource: b.as_entire_binding(),
        })
        .collect();
    ctx.device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: Some(label),
        layout,
        entries: &entries,
    })
}

/// Maps `readback` (already filled by a submitted copy), waits, and returns
/// what `read` makes of its first `size` bytes, read where they are mapped (a
/// history pass's tens of megabytes are not copied out first).
pub fn read_back<T>(
    ctx: &GpuContext,
    readback: &wgpu::Buffer,
    size: u64,
    read: impl FnOnce(&[u8]) -> T,
) -> Result<T, GpuError> {
    let slice = readback.slice(..size);
    let (tx, rx) = std::sync::mpsc::channel();
    slice.map_async(wgpu::MapMode::Read, move |r| {
        let _ = tx.send(r);
    });
    ctx.device
        .poll(wgpu::PollType::wait_indefinitely())
        .map_err(|e| GpuError::Device {
            during: "waiting for the GPU".into(),
            message: e.to_string(),
        })?;
    rx.recv()
        .map_err(|e| GpuError::Device {
            during: "mapping the read-back buffer".into(),
            message: e.to_string(),
        })?
        .map_err(|e| GpuError::Device {
            during: "mapping the read-back buffer".into(),
            message: e.to_string(),
        })?;
    let mapped = slice.get_mapped_range().map_err(|e| GpuError::Device {
        during: "reading the read-back buffer".into(),
        message: e.to_string(),
    })?;
    let out = read(&mapped);
    drop(mapped);
    readback.unmap();
    Ok(out)
}

/// Workgroups to cover `n` invocations, refusing more than the device allows.
pub fn workgroups(ctx: &GpuContext, n: usize, workgroup_x: u32) -> Result<u32, GpuError> {
    let groups = n.div_ceil(workgroup_x as usize);
    let max = ctx.device.limits().max_compute_workgroups_per_dimension as usize;
    if groups > max {
        return Err(GpuError::TooLarge {
            runs: n,
            max: max * workgroup_x as usize,
        });
    }
    Ok(groups as u32)
}
