//! Getting a device: the [`GpuContext`] is built once per job and handed to every
//! evaluator and test that runs on it.

use super::GpuError;

/// One adapter as `rigfit devices` prints it.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct AdapterSummary {
    /// Adapter name (e.g. `llvmpipe (LLVM 15.0.6, 256 bits)`).
    pub name: String,
    /// Graphics API backend (`Vulkan`, `Metal`, …).
    pub backend: String,
    /// Discrete, integrated, virtual, CPU or other.
    pub device_type: String,
    /// Driver name and version information.
    pub driver: String,
    /// Whether shaders may use f64 (`SHADER_F64`).
    pub shader_f64: bool,
}

/// A device with its queue, ready to build pipelines on.
#[derive(Debug, Clone)]
pub struct GpuContext {
    /// The device.
    pub device: wgpu::Device,
    /// Its queue.
    pub queue: wgpu::Queue,
    /// What the adapter reported.
    pub info: wgpu::AdapterInfo,
}

/// The wgpu instance rigfit uses: `WGPU_BACKEND` if set, otherwise the primary
/// backends (Vulkan, Metal, DX12).
pub fn instance() -> wgpu::Instance {
    let mut desc = wgpu::InstanceDescriptor::new_without_display_handle_from_env();
    desc.backends = wgpu::Backends::from_env().unwrap_or(wgpu::Backends::PRIMARY);
    wgpu::Instance::new(desc)
}

/// Runs `f` (which creates an instance and finds adapters) with the process's
/// stderr sent to /dev/null when `XDG_RUNTIME_DIR` is unset or not a folder.
/// Mesa's Vulkan driver then prints "XDG_RUNTIME_DIR is invalid or not set in
/// the environment." on headless machines, before rigfit's own first line,
/// and users read it as rigfit's error. The variable itself cannot be set
/// from safe Rust once threads may run, so the driver's lines are dropped.
pub fn without_driver_noise<T>(f: impl FnOnce() -> T) -> T {
    #[cfg(unix)]
    {
        use std::io::Write as _;
        use std::os::fd::AsFd as _;
        let unset =
            std::env::var_os("XDG_RUNTIME_DIR").is_none_or(|d| !std::path::Path::new(&d).is_dir());
        if unset {
            let saved = rustix::io::dup(std::io::stderr().as_fd());
            let null = std::fs::OpenOptions::new().write(true).open("/dev/null");
            if let (Ok(saved), Ok(null)) = (saved, null) {
                let _ = std::io::stderr().flush();
                if rustix::stdio::dup2_stderr(&null).is_ok() {
                    let out = f();
                    let _ = rustix::stdio::dup2_stderr(&saved);
                    return out;
                }
            }
        }
    }
    f()
}

/// Every adapter the instance can see.
pub fn list_adapters() -> Vec<AdapterSummary> {
    let adapters = without_driver_noise(|| {
        let instance = instance();
        pollster::block_on(instance.enumerate_adapters(wgpu::Backends::all()))
    });
    adapters
        .iter()
        .map(|a| {
            let info = a.get_info();
            AdapterSummary {
                name: info.name.clone(),
                backend: format!("{:?}", info.backend),
                device_type: format!("{:?}", info.device_type),
                driver: format!("{} {}", info.driver, info.driver_info)
                    .trim()
                    .to_string(),
                shader_f64: a.features().contains(wgpu::Features::SHADER_F64),
            }
        })
        .collect()
}

impl GpuContext {
    /// Opens the default adapter's device, enabling `SHADER_F64` where the
    /// adapter has it and asking for the adapter's own limits.
    pub fn new() -> Result<Self, GpuError> {
        let adapter = without_driver_noise(|| {
            let instance = instance();
            pollster::block_on(instance.request_adapter(&wgpu::RequestAdapterOptions {
                power_preference: wgpu::PowerPreference::HighPerformance,
                ..Default::default()
            }))
        })
        .map_err(|e| GpuError::NoAdapter(e.to_string()))?;
        let features = adapter.features() & wgpu::Features::SHADER_F64;
        let (device, queue) = pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor {
            label: Some("rigfit device"),
            required_features: features,
            required_limits: adapter.limits(),
            ..Default::default()
        }))
        .map_err(|e| GpuError::RequestDevice(e.to_string()))?;
        Ok(Self::from_device(device, queue, adapter.get_info()))
    }

    /// Wraps a device the caller already has.
    pub fn from_device(device: wgpu::Device, queue: wgpu::Queue, info: wgpu::AdapterInfo) -> Self {
        Self {
            device,
            queue,
            info,
        }
    }

    /// Whether kernels may use f64.
    pub fn has_f64(&self) -> bool {
        self.device.features().contains(wgpu::Features::SHADER_F64)
    }

    /// A one-line description of the adapter.
    pub fn describe(&self) -> String {
        format!(
            "{} ({:?}, {:?})",
            self.info.name, self.info.backend, self.info.device_type
        )
    }
}
