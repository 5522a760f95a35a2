//! Getting a device: the [`GpuContext`] is built once per job and handed to every
//! evaluator and test that runs on it.

use super::GpuError;
use crate::base::text::echo_bare;

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
    /// PCI bus id (`0000:17:00.0`), empty where the driver gives none.
    pub pci_bus_id: String,
}

/// Name of the environment variable that picks the adapter when `--adapter`
/// is not given (same forms as `--adapter`).
pub const ADAPTER_ENV: &str = "RIGFIT_ADAPTER";

/// The adapter a selector chose (named in the device description that
/// result.json records).
#[derive(Debug, Clone, PartialEq, Eq, serde::Serialize)]
pub struct AdapterChoice {
    /// How it was asked for: `--adapter X` or `RIGFIT_ADAPTER=X`.
    pub selected_by: String,
    /// Its index in `rigfit devices`.
    pub index: usize,
    /// Adapter name.
    pub name: String,
    /// PCI bus id, empty where the driver gives none.
    pub pci_bus_id: String,
    /// Driver name and version.
    pub driver: String,
}

/// The adapter selector in force: `flag` (from `--adapter`) or else
/// `RIGFIT_ADAPTER`, as `(selector, how it was given)` (the value cut short
/// and escaped for messages); `None` for the default adapter.
pub fn requested_adapter(flag: Option<&str>) -> Option<(String, String)> {
    match flag {
        Some(f) => Some((f.to_string(), format!("--adapter {}", echo_bare(f)))),
        None => std::env::var(ADAPTER_ENV)
            .ok()
            .filter(|v| !v.trim().is_empty())
            .map(|v| (v.clone(), format!("{ADAPTER_ENV}={}", echo_bare(&v)))),
    }
}

/// Which of `adapters` `selector` names: an index as `rigfit devices` lists
/// them, a PCI bus id, or a piece of one adapter's name (any case). The error
/// says why none or several match.
pub fn choose_adapter(selector: &str, adapters: &[AdapterSummary]) -> Result<usize, String> {
    let sel = selector.trim();
    if adapters.is_empty() {
        return Err("no GPU adapter found".into());
    }
    if let Ok(i) = sel.parse::<usize>() {
        return if i < adapters.len() {
            Ok(i)
        } else {
            Err(format!(
                "there is no adapter [{i}]; the indices run from 0 to {}",
                adapters.len() - 1
            ))
        };
    }
    if let Some(i) = adapters
        .iter()
        .position(|a| !a.pci_bus_id.is_empty() && a.pci_bus_id.eq_ignore_ascii_case(sel))
    {
        return Ok(i);
    }
    let lower = sel.to_lowercase();
    let matching: Vec<usize> = (0..adapters.len())
        .filter(|&i| !lower.is_empty() && adapters[i].name.to_lowercase().contains(&lower))
        .collect();
    match matching[..] {
        [i] => Ok(i),
        [] => Err("no adapter's index, PCI bus id or name matches it".into()),
        _ => Err(format!(
            "it matches {} adapters ({}); give the index or the PCI bus id",
            matching.len(),
            matching
                .iter()
                .map(|i| format!("[{i}]"))
                .collect::<Vec<_>>()
                .join(", ")
        )),
    }
}

/// The adapters as `rigfit devices` lists them, one per line, for errors.
pub fn adapter_list(adapters: &[AdapterSummary]) -> String {
    if adapters.is_empty() {
        return "no GPU adapter found".into();
    }
    adapters
        .iter()
        .enumerate()
        .map(|(i, a)| {
            let bus = if a.pci_bus_id.is_empty() {
                String::new()
            } else {
                format!(", PCI {}", a.pci_bus_id)
            };
            format!("[{i}] {} ({} {}{bus})", a.name, a.backend, a.device_type)
        })
        .collect::<Vec<_>>()
        .join("; ")
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
    /// The adapter `--adapter` or `RIGFIT_ADAPTER` chose, if one did.
    pub chosen: Option<AdapterChoice>,
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

/// Every adapter the instance can see, in the order `rigfit devices` lists
/// them.
fn enumerate() -> Vec<wgpu::Adapter> {
    without_driver_noise(|| {
        let instance = instance();
        pollster::block_on(instance.enumerate_adapters(wgpu::Backends::all()))
    })
}

/// Every adapter the instance can see.
pub fn list_adapters() -> Vec<AdapterSummary> {
    summarise(&enumerate())
}

fn summarise(adapters: &[wgpu::Adapter]) -> Vec<AdapterSummary> {
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
                pci_bus_id: info.device_pci_bus_id.clone(),
            }
        })
        .collect()
}

impl GpuContext {
    /// Opens the device of the adapter `RIGFIT_ADAPTER` names, or else the
    /// default adapter's (see [`GpuContext::select`]).
    pub fn new() -> Result<Self, GpuError> {
        Self::select(None)
    }

    /// Opens the device of the adapter `flag` (`--adapter`) or else
    /// `RIGFIT_ADAPTER` names ([`choose_adapter`]), or else the default
    /// (high-performance) adapter's, enabling `SHADER_F64` where the adapter
    /// has it and asking for the adapter's own limits. The choice a selector
    /// made is kept in [`GpuContext::chosen`].
    pub fn select(flag: Option<&str>) -> Result<Self, GpuError> {
        let Some((selector, selected_by)) = requested_adapter(flag) else {
            return Self::open_default();
        };
        let mut adapters = enumerate();
        let summaries = summarise(&adapters);
        let index =
            choose_adapter(&selector, &summaries).map_err(|why| GpuError::NoSuchAdapter {
                selected_by: selected_by.clone(),
                why,
                adapters: adapter_list(&summaries),
            })?;
        let s = &summaries[index];
        let choice = AdapterChoice {
            selected_by,
            index,
            name: s.name.clone(),
            pci_bus_id: s.pci_bus_id.clone(),
            driver: s.driver.clone(),
        };
        let mut ctx = Self::open(adapters.swap_remove(index))?;
        ctx.chosen = Some(choice);
        Ok(ctx)
    }

    fn open_default() -> Result<Self, GpuError> {
        let adapter = without_driver_noise(|| {
            let instance = instance();
            pollster::block_on(instance.request_adapter(&wgpu::RequestAdapterOptions {
                power_preference: wgpu::PowerPreference::HighPerformance,
                ..Default::default()
            }))
        })
        .map_err(|e| GpuError::NoAdapter(e.to_string()))?;
        Self::open(adapter)
    }

    fn open(adapter: wgpu::Adapter) -> Result<Self, GpuError> {
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
            chosen: None,
        }
    }

    /// Whether kernels may use f64.
    pub fn has_f64(&self) -> bool {
        self.device.features().contains(wgpu::Features::SHADER_F64)
    }

    /// A one-line description of the adapter (with its PCI bus id where the
    /// driver gives one, so that jobs on a node of several GPUs tell them apart).
    pub fn describe(&self) -> String {
        let bus = &self.info.device_pci_bus_id;
        let mut s = format!(
            "{} ({:?}, {:?}",
            self.info.name, self.info.backend, self.info.device_type
        );
        if !bus.is_empty() {
            s += &format!(", PCI {bus}");
        }
        if let Some(c) = &self.chosen {
            s += &format!(", adapter [{}] chosen by {}", c.index, c.selected_by);
        }
        s + ")"
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn adapter(name: &str, bus: &str) -> AdapterSummary {
        AdapterSummary {
            name: name.into(),
            backend: "Vulkan".into(),
            device_type: "DiscreteGpu".into(),
            driver: String::new(),
            shader_f64: true,
            pci_bus_id: bus.into(),
        }
    }

    #[test]
    fn adapters_are_chosen_by_index_bus_id_or_one_name() {
        let list = [
            adapter("NVIDIA H100 80GB HBM3", "0000:17:00.0"),
            adapter("NVIDIA H100 80GB HBM3", "0000:65:00.0"),
            adapter("llvmpipe (LLVM 15.0.6, 256 bits)", ""),
        ];
        assert_eq!(choose_adapter("1", &list), Ok(1));
        assert_eq!(choose_adapter(" 0000:65:00.0 ", &list), Ok(1));
        assert_eq!(choose_adapter("LLVMpipe", &list), Ok(2));
        let several = choose_adapter("h100", &list).unwrap_err();
        assert!(several.contains("[0], [1]"), "{several}");
        assert!(choose_adapter("3", &list).unwrap_err().contains("0 to 2"));
        assert!(choose_adapter("radeon", &list).is_err());
        assert!(choose_adapter("", &list).is_err());
        assert!(choose_adapter("0", &[]).is_err());
        assert!(
            adapter_list(&list)
                .contains("[1] NVIDIA H100 80GB HBM3 (Vulkan DiscreteGpu, PCI 0000:65:00.0)")
        );
    }
}
