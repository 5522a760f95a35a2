//! `rigfit devices`.

use anyhow::Result;

use super::output::Output;
use rigfit::gpu::list_adapters;
use rigfit::job::backend::{self, KeptChoice};

/// Lists every adapter wgpu can see, with its f64 support, whether the
/// CPU's lane ensemble runs native code here, and the choices `--backend
/// auto` measured and keeps for this processor and these adapters.
pub fn devices(out: &Output) -> Result<()> {
    let adapters = list_adapters();
    let choices = backend::kept_choices(&backend::adapters_key(&adapters));
    let choices_text = choices_text(&choices);
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
        "auto_choices": choices,
    }))?;
    out.say(|| {
        if adapters.is_empty() {
            return format!(
                "no GPU adapter found. Install a Vulkan driver: on Debian \
                 `apt-get install mesa-vulkan-drivers` gives the software adapter lavapipe; \
                 on NVIDIA/AMD machines install the vendor's Vulkan driver.\n{cpu_line}\n{choices_text}"
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
        s += "\n";
        s += &choices_text;
        s
    });
    Ok(())
}

/// What `--backend auto` chose for each job it measured here, as kept in
/// its cache, or how to get a choice measured.
fn choices_text(choices: &[KeptChoice]) -> String {
    if choices.is_empty() {
        return "backend auto keeps no measured choice for these adapters yet: a run with \
                --backend auto long enough for a trial, or `rigfit check`, measures one"
            .into();
    }
    let file = backend::cache_file()
        .map(|f| f.display().to_string())
        .unwrap_or_default();
    let mut s = format!("backend auto's measured choices on this machine ({file}):");
    for c in choices {
        let campaign =
            (c.trial.campaign.clone()).unwrap_or_else(|| format!("campaign {}", c.digest));
        s += &format!(
            "\n  {campaign}, precision {}, population {}: {}",
            c.precision,
            c.population,
            c.trial.line().trim_start_matches("backend auto ")
        );
    }
    s
}
