//! `rigfit devices`.

use anyhow::Result;

use super::output::Output;
use rigfit::gpu::list_adapters;

/// Lists every adapter wgpu can see, with its f64 support, and whether the
/// CPU's lane ensemble runs native code here.
pub fn devices(out: &Output) -> Result<()> {
    let adapters = list_adapters();
    let cores = rigfit::eval::all_cores();
    let native = rigfit::compile::back::native::check_native_lanes();
    let cpu_line = match &native {
        Ok((cc, version)) => format!(
            "CPU: {cores} cores; compiled rigs' lanes run native code, built by `{cc}` ({version})"
        ),
        Err(why) => format!(
            "CPU: {cores} cores; compiled rigs' lanes interpret their code (3× slower): {why}"
        ),
    };
    let rows: Vec<serde_json::Value> = adapters
        .iter()
        .map(|a| {
            serde_json::json!({
                "name": a.name, "backend": a.backend, "type": a.device_type,
                "driver": a.driver, "shader_f64": a.shader_f64, "pci_bus_id": a.pci_bus_id,
            })
        })
        .collect();
    out.json(&serde_json::json!({
        "adapters": rows,
        "cpu": {
            "cores": cores,
            "native_lanes": native.is_ok(),
            "compiler": native.as_ref().ok().map(|(cc, _)| cc),
            "compiler_version": native.as_ref().ok().map(|(_, v)| v),
            "why_not": native.as_ref().err(),
        },
    }))?;
    out.say(|| {
        if adapters.is_empty() {
            return format!(
                "no GPU adapter found. Install a Vulkan driver: on Debian \
                 `apt-get install mesa-vulkan-drivers` gives the software adapter lavapipe; \
                 on NVIDIA/AMD machines install the vendor's Vulkan driver.\n{cpu_line}"
            );
        }
        let mut s =
            String::from("GPU adapters (precision auto picks f64 where shader_f64 is yes):\n");
        for (i, a) in adapters.iter().enumerate() {
            let bus = if a.pci_bus_id.is_empty() {
                String::new()
            } else {
                format!(", PCI {}", a.pci_bus_id)
            };
            s += &format!(
                "  [{i}] {} — {} {}{bus}, driver {}, shader_f64: {}\n",
                a.name,
                a.backend,
                a.device_type,
                a.driver,
                if a.shader_f64 { "yes" } else { "no" }
            );
        }
        s += "pick one with `rigfit run --adapter I` (index, PCI bus id or a piece of the name) \
              or RIGFIT_ADAPTER\n";
        s += &cpu_line;
        s
    });
    Ok(())
}
