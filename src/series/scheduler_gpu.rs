//! Which GPU the scheduler gave this process, as an adapter selector.
//!
//! Slurm gives a task its GPU by environment: `SLURM_STEP_GPUS` or
//! `SLURM_JOB_GPUS` (the node's GPU numbers, which on NVIDIA nodes are the
//! device minor numbers of `/dev/nvidia<N>`), and `CUDA_VISIBLE_DEVICES` or
//! `ROCR_VISIBLE_DEVICES` for CUDA and ROCm programs. Vulkan reads none of
//! these: every Vulkan program on a node sees every GPU it may open, in the
//! driver's order. A task that took "the first adapter" would put every task
//! of an array on the same GPU. So the number or UUID the scheduler gave is
//! turned here into the GPU's PCI bus id, which wgpu reports for each Vulkan
//! adapter (`AdapterInfo::device_pci_bus_id`, written `dddd:bb:dd.f` in
//! lowercase hex) and which `--adapter` matches.
//!
//! The bus id is found through the driver's own files:
//! `/proc/driver/nvidia/gpus/<bus id>/information` (its `Device Minor:` and
//! `GPU UUID:` lines) on NVIDIA nodes, and the AMD display devices under
//! `/sys/bus/pci/devices` (in bus id order, ROCm's order) otherwise.

use std::path::Path;

/// The GPU the scheduler gave this process.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SchedulerGpu {
    /// Its PCI bus id as wgpu reports it (`0000:3b:00.0`): an `--adapter`
    /// selector.
    pub selector: String,
    /// How it was found (`SLURM_JOB_GPUS=1 → NVIDIA minor 1 → PCI
    /// 0000:3b:00.0`), for the status file and messages.
    pub how: String,
}

/// The variables read, in order: the first one set (and not empty) decides.
const VARIABLES: [&str; 4] = [
    "SLURM_STEP_GPUS",
    "SLURM_JOB_GPUS",
    "CUDA_VISIBLE_DEVICES",
    "ROCR_VISIBLE_DEVICES",
];

/// The GPU the scheduler gave this process, from its environment and the
/// machine's `/proc` and `/sys`: `None` when no variable names one, an
/// error naming the variable when it names a GPU this machine does not have.
pub fn scheduler_gpu() -> Result<Option<SchedulerGpu>, String> {
    scheduler_gpu_in(|name| std::env::var(name).ok(), Path::new("/"))
}

/// [`scheduler_gpu`] with the environment read through `env` and the
/// filesystem rooted at `root` (`/proc/driver/nvidia` is
/// `root/proc/driver/nvidia`).
pub fn scheduler_gpu_in(
    env: impl Fn(&str) -> Option<String>,
    root: &Path,
) -> Result<Option<SchedulerGpu>, String> {
    for var in VARIABLES {
        let Some(value) = env(var) else { continue };
        let value = value.trim().to_string();
        // Slurm writes `NoDevFiles` for a GRES without device files.
        if value.is_empty() || value == "NoDevFiles" {
            continue;
        }
        let given: Vec<&str> = value
            .split(',')
            .map(str::trim)
            .filter(|s| !s.is_empty())
            .collect();
        let first = given[0];
        let several = if given.len() > 1 {
            format!(" (the first of {} GPUs given)", given.len())
        } else {
            String::new()
        };
        let found = match var {
            "ROCR_VISIBLE_DEVICES" => amd_gpu(root, first),
            "CUDA_VISIBLE_DEVICES" => {
                let order = env("CUDA_DEVICE_ORDER").unwrap_or_default();
                nvidia_gpu(
                    root,
                    first,
                    Numbering::CudaIndex {
                        pci_order: order.trim() == "PCI_BUS_ID",
                    },
                )
            }
            _ if nvidia_gpus(root).is_empty() => amd_gpu(root, first),
            _ => nvidia_gpu(root, first, Numbering::Minor),
        };
        return match found {
            Ok((bus, via)) => Ok(Some(SchedulerGpu {
                how: format!("{var}={value} → {via} → PCI {bus}{several}"),
                selector: bus,
            })),
            Err(reason) => Err(format!("{var}={value}: GPU \"{first}\" {reason}")),
        };
    }
    Ok(None)
}

/// What a number in a variable means on an NVIDIA machine.
#[derive(Debug, Clone, Copy)]
enum Numbering {
    /// The device minor number (`/dev/nvidia<N>`), as Slurm's GPU numbers.
    Minor,
    /// CUDA's index. In bus id order with `CUDA_DEVICE_ORDER=PCI_BUS_ID`;
    /// CUDA's default order (fastest first) puts equal GPUs in bus id
    /// order too, which is all a node of one model has.
    CudaIndex { pci_order: bool },
}

/// One NVIDIA GPU as `/proc/driver/nvidia/gpus/<bus id>/information` says.
#[derive(Debug, Clone)]
struct NvidiaGpu {
    bus: String,
    minor: Option<u32>,
    uuid: Option<String>,
}

/// The NVIDIA GPUs of the machine, in bus id order; empty without the driver.
fn nvidia_gpus(root: &Path) -> Vec<NvidiaGpu> {
    let dir = root.join("proc/driver/nvidia/gpus");
    let Ok(entries) = std::fs::read_dir(&dir) else {
        return Vec::new();
    };
    let mut gpus = Vec::new();
    for entry in entries.flatten() {
        let name = entry.file_name().to_string_lossy().into_owned();
        let Some(bus) = normalise_bus_id(&name) else {
            continue;
        };
        let text = std::fs::read_to_string(entry.path().join("information")).unwrap_or_default();
        let field = |key: &str| {
            text.lines().find_map(|l| {
                l.trim_start()
                    .strip_prefix(key)
                    .map(|v| v.trim().to_string())
            })
        };
        gpus.push(NvidiaGpu {
            bus,
            minor: field("Device Minor:").and_then(|m| m.parse().ok()),
            uuid: field("GPU UUID:"),
        });
    }
    gpus.sort_by(|a, b| a.bus.cmp(&b.bus));
    gpus
}

/// The bus id of the NVIDIA GPU `given` names (a number or a `GPU-…` UUID),
/// with how it was matched.
fn nvidia_gpu(root: &Path, given: &str, numbering: Numbering) -> Result<(String, String), String> {
    let gpus = nvidia_gpus(root);
    if gpus.is_empty() {
        return Err(format!(
            "cannot be matched to a PCI bus id: `{}` lists no NVIDIA GPU (is the NVIDIA driver loaded?)",
            root.join("proc/driver/nvidia/gpus").display()
        ));
    }
    let listed = || {
        gpus.iter()
            .map(|g| match g.minor {
                Some(m) => format!("minor {m} at {}", g.bus),
                None => g.bus.clone(),
            })
            .collect::<Vec<_>>()
            .join(", ")
    };
    if given.starts_with("GPU-") || given.starts_with("MIG-") {
        let uuid = given.to_ascii_lowercase();
        return gpus
            .iter()
            .find(|g| {
                g.uuid
                    .as_ref()
                    .is_some_and(|u| u.to_ascii_lowercase() == uuid)
            })
            .map(|g| (g.bus.clone(), format!("NVIDIA {given}")))
            .ok_or_else(|| format!("is no NVIDIA GPU's UUID here (GPUs: {})", listed()));
    }
    let Ok(n) = given.parse::<u32>() else {
        return Err("is neither a GPU number nor a GPU-… UUID".into());
    };
    match numbering {
        Numbering::Minor => gpus
            .iter()
            .find(|g| g.minor == Some(n))
            .map(|g| (g.bus.clone(), format!("NVIDIA minor {n}")))
            .ok_or_else(|| format!("is no NVIDIA device minor here (GPUs: {})", listed())),
        Numbering::CudaIndex { pci_order } => gpus
            .get(n as usize)
            .map(|g| {
                let order = if pci_order {
                    "CUDA index in PCI order"
                } else {
                    "CUDA index taken in PCI order"
                };
                (g.bus.clone(), format!("{order} {n}"))
            })
            .ok_or_else(|| format!("is past the {} NVIDIA GPUs here ({})", gpus.len(), listed())),
    }
}

/// The bus id of the AMD GPU `given` names: an index into the AMD display
/// devices in bus id order (ROCm's order).
fn amd_gpu(root: &Path, given: &str) -> Result<(String, String), String> {
    let dir = root.join("sys/bus/pci/devices");
    let mut gpus: Vec<String> = std::fs::read_dir(&dir)
        .into_iter()
        .flatten()
        .flatten()
        .filter(|e| {
            let read = |f: &str| std::fs::read_to_string(e.path().join(f)).unwrap_or_default();
            read("vendor").trim() == "0x1002" && {
                let class = read("class");
                let class = class.trim();
                class.starts_with("0x0300") || class.starts_with("0x0380")
            }
        })
        .filter_map(|e| normalise_bus_id(&e.file_name().to_string_lossy()))
        .collect();
    gpus.sort();
    if gpus.is_empty() {
        return Err(format!(
            "cannot be matched to a PCI bus id: neither `{}` nor `{}` lists a GPU",
            root.join("proc/driver/nvidia/gpus").display(),
            dir.display()
        ));
    }
    let Ok(n) = given.parse::<usize>() else {
        return Err("is not a GPU number (an AMD GPU is matched by its index)".into());
    };
    gpus.get(n)
        .map(|bus| (bus.clone(), format!("AMD GPU {n} in PCI order")))
        .ok_or_else(|| {
            format!(
                "is past the {} AMD GPUs here ({})",
                gpus.len(),
                gpus.join(", ")
            )
        })
}

/// A PCI address (`0000:3B:00.0`, or without the domain) in wgpu's form:
/// `{domain:04x}:{bus:02x}:{device:02x}.{function}`.
fn normalise_bus_id(text: &str) -> Option<String> {
    let (rest, function) = text.rsplit_once('.')?;
    let parts: Vec<&str> = rest.split(':').collect();
    let (domain, bus, device) = match parts[..] {
        [d, b, dev] => (d, b, dev),
        [b, dev] => ("0", b, dev),
        _ => return None,
    };
    let hex = |s: &str| u32::from_str_radix(s, 16).ok();
    Some(format!(
        "{:04x}:{:02x}:{:02x}.{}",
        hex(domain)?,
        hex(bus)?,
        hex(device)?,
        function.parse::<u32>().ok()?
    ))
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::HashMap;

    /// A fake node: NVIDIA GPUs at the given bus ids, with minors and UUIDs.
    fn nvidia_node(gpus: &[(&str, u32, &str)]) -> tempfile::TempDir {
        let dir = tempfile::tempdir().unwrap();
        for (bus, minor, uuid) in gpus {
            let d = dir.path().join("proc/driver/nvidia/gpus").join(bus);
            std::fs::create_dir_all(&d).unwrap();
            std::fs::write(
                d.join("information"),
                format!(
                    "Model: \t\t NVIDIA H100 80GB HBM3\nIRQ:   \t\t 0\nGPU UUID: \t {uuid}\n\
                     Bus Type: \t PCIe\nBus Location: \t {bus}\nDevice Minor: \t {minor}\nGPU Excluded:\t No\n"
                ),
            )
            .unwrap();
        }
        dir
    }

    fn env(vars: &[(&str, &str)]) -> impl Fn(&str) -> Option<String> {
        let map: HashMap<String, String> = vars
            .iter()
            .map(|(k, v)| (k.to_string(), v.to_string()))
            .collect();
        move |k| map.get(k).cloned()
    }

    /// Minors deliberately not in bus order, so that a lookup by position
    /// and a lookup by minor give different answers.
    fn four_gpus() -> tempfile::TempDir {
        nvidia_node(&[
            ("0000:1b:00.0", 2, "GPU-aaaa"),
            ("0000:3b:00.0", 0, "GPU-bbbb"),
            ("0000:86:00.0", 1, "GPU-cccc"),
            ("0000:DB:00.0", 3, "GPU-dddd"),
        ])
    }

    #[test]
    fn nothing_set_is_none() {
        let node = four_gpus();
        assert_eq!(scheduler_gpu_in(env(&[]), node.path()), Ok(None));
        let empty = env(&[
            ("CUDA_VISIBLE_DEVICES", ""),
            ("SLURM_JOB_GPUS", "NoDevFiles"),
        ]);
        assert_eq!(scheduler_gpu_in(empty, node.path()), Ok(None));
    }

    #[test]
    fn slurm_gpus_are_device_minors() {
        let node = four_gpus();
        let g = scheduler_gpu_in(env(&[("SLURM_JOB_GPUS", "1")]), node.path())
            .unwrap()
            .unwrap();
        assert_eq!(g.selector, "0000:86:00.0");
        assert!(
            g.how.contains("SLURM_JOB_GPUS=1") && g.how.contains("minor 1"),
            "{}",
            g.how
        );
        // The bus id comes out lowercase, as wgpu writes it.
        let g = scheduler_gpu_in(env(&[("SLURM_JOB_GPUS", "3")]), node.path())
            .unwrap()
            .unwrap();
        assert_eq!(g.selector, "0000:db:00.0");
    }

    #[test]
    fn slurm_wins_over_cuda_and_step_over_job() {
        let node = four_gpus();
        // Under ConstrainDevices CUDA_VISIBLE_DEVICES is renumbered from 0;
        // Slurm's own number is the one that names the GPU on the node.
        let vars = env(&[("SLURM_JOB_GPUS", "2"), ("CUDA_VISIBLE_DEVICES", "0")]);
        assert_eq!(
            scheduler_gpu_in(vars, node.path())
                .unwrap()
                .unwrap()
                .selector,
            "0000:1b:00.0"
        );
        let vars = env(&[("SLURM_STEP_GPUS", "0"), ("SLURM_JOB_GPUS", "2")]);
        assert_eq!(
            scheduler_gpu_in(vars, node.path())
                .unwrap()
                .unwrap()
                .selector,
            "0000:3b:00.0"
        );
    }

    #[test]
    fn several_gpus_take_the_first_and_say_so() {
        let node = four_gpus();
        let g = scheduler_gpu_in(env(&[("SLURM_JOB_GPUS", "3,1")]), node.path())
            .unwrap()
            .unwrap();
        assert_eq!(g.selector, "0000:db:00.0");
        assert!(g.how.contains("first of 2"), "{}", g.how);
    }

    #[test]
    fn cuda_indices_count_in_bus_order_and_uuids_match() {
        let node = four_gpus();
        let vars = env(&[
            ("CUDA_VISIBLE_DEVICES", "1,2"),
            ("CUDA_DEVICE_ORDER", "PCI_BUS_ID"),
        ]);
        let g = scheduler_gpu_in(vars, node.path()).unwrap().unwrap();
        assert_eq!(g.selector, "0000:3b:00.0");
        let g = scheduler_gpu_in(env(&[("CUDA_VISIBLE_DEVICES", "GPU-CCCC")]), node.path())
            .unwrap()
            .unwrap();
        assert_eq!(g.selector, "0000:86:00.0");
    }

    #[test]
    fn unmatched_gpus_are_errors_naming_the_variable() {
        let node = four_gpus();
        let e = scheduler_gpu_in(env(&[("SLURM_JOB_GPUS", "7")]), node.path()).unwrap_err();
        assert!(
            e.starts_with("SLURM_JOB_GPUS=7") && e.contains("minor 3 at 0000:db:00.0"),
            "{e}"
        );
        let e = scheduler_gpu_in(env(&[("CUDA_VISIBLE_DEVICES", "GPU-ffff")]), node.path())
            .unwrap_err();
        assert!(e.contains("UUID"), "{e}");
        let e = scheduler_gpu_in(env(&[("CUDA_VISIBLE_DEVICES", "x")]), node.path()).unwrap_err();
        assert!(e.contains("neither"), "{e}");
        let bare = tempfile::tempdir().unwrap();
        let e = scheduler_gpu_in(env(&[("SLURM_JOB_GPUS", "0")]), bare.path()).unwrap_err();
        assert!(e.contains("lists a GPU"), "{e}");
    }

    #[test]
    fn amd_gpus_count_display_devices_in_bus_order() {
        let dir = tempfile::tempdir().unwrap();
        for (bus, vendor, class) in [
            ("0000:c1:00.0", "0x1002", "0x038000"),
            ("0000:03:00.0", "0x1002", "0x030000"),
            ("0000:02:00.0", "0x1002", "0x040300"), // its audio function
            ("0000:01:00.0", "0x8086", "0x030000"),
        ] {
            let d = dir.path().join("sys/bus/pci/devices").join(bus);
            std::fs::create_dir_all(&d).unwrap();
            std::fs::write(d.join("vendor"), format!("{vendor}\n")).unwrap();
            std::fs::write(d.join("class"), format!("{class}\n")).unwrap();
        }
        let g = scheduler_gpu_in(env(&[("ROCR_VISIBLE_DEVICES", "1")]), dir.path())
            .unwrap()
            .unwrap();
        assert_eq!(g.selector, "0000:c1:00.0");
        let g = scheduler_gpu_in(env(&[("SLURM_JOB_GPUS", "0")]), dir.path())
            .unwrap()
            .unwrap();
        assert_eq!(g.selector, "0000:03:00.0");
        assert!(scheduler_gpu_in(env(&[("ROCR_VISIBLE_DEVICES", "2")]), dir.path()).is_err());
    }

    #[test]
    fn bus_ids_take_wgpus_form() {
        assert_eq!(
            normalise_bus_id("0000:3B:00.0").as_deref(),
            Some("0000:3b:00.0")
        );
        assert_eq!(normalise_bus_id("3b:00.1").as_deref(), Some("0000:3b:00.1"));
        assert_eq!(
            normalise_bus_id("10000:01:00.0").as_deref(),
            Some("10000:01:00.0")
        );
        assert_eq!(normalise_bus_id("nvidia"), None);
    }
}
