//! The driver's own statistics of a compiled kernel, through Vulkan's
//! `VK_KHR_pipeline_executable_properties`: what an NVIDIA driver reports of
//! each pipeline it compiles (its registers per thread among them), which wgpu
//! does not expose. The kernel's WGSL is written to SPIR-V by naga as wgpu
//! writes it for the same device (the same bounds-check policies, loop bounds
//! and workgroup-memory initialisation, or none of the checks where the kernel
//! is compiled without them), then built into a compute pipeline on a Vulkan
//! device of its own with the statistics captured.
//!
//! A driver without the extension (Mesa 22.3's lavapipe) still builds every
//! pipeline, which checks the SPIR-V; it only has no statistics to give.
#![allow(unsafe_code)]
#![allow(dead_code, reason = "the bench and a test each use a part")]

use std::ffi::CStr;

use ash::vk;
use rigfit::eval::Precision;
use rigfit::gpu::shaders::{self, Kernel};

/// A Vulkan device opened for the statistics.
pub struct VkStats {
    _entry: ash::Entry,
    instance: ash::Instance,
    device: ash::Device,
    /// The device's name, driver and what it reports of its width.
    pub about: String,
    /// Whether the driver gives pipeline statistics.
    pub offered: bool,
    api: u32,
    robust2: bool,
    zero_init: bool,
    f64: bool,
}

/// One statistic of one of a pipeline's executables.
pub struct Statistic {
    /// The executable's name (`Compute Shader`, …).
    pub executable: String,
    /// The statistic's name (`Register Count`, …).
    pub name: String,
    /// Its value as text.
    pub value: String,
}

/// A NUL-terminated string of one of Vulkan's fixed arrays.
fn text(chars: &[std::ffi::c_char]) -> String {
    let bytes: Vec<u8> = chars
        .iter()
        .take_while(|&&c| c != 0)
        .map(|&c| c as u8)
        .collect();
    String::from_utf8_lossy(&bytes).into_owned()
}

impl VkStats {
    /// Opens the physical device whose name contains `adapter` (any case), or
    /// the first discrete GPU, or the first device.
    pub fn open(adapter: Option<&str>) -> Result<Self, String> {
        // SAFETY: loads the system's Vulkan loader, as wgpu does.
        let entry = unsafe { ash::Entry::load() }.map_err(|e| format!("no Vulkan loader: {e}"))?;
        let app = vk::ApplicationInfo::default()
            .application_name(c"rigfit kernel statistics")
            .api_version(vk::API_VERSION_1_3);
        // SAFETY: a plain instance with no layers and no extensions.
        let instance = unsafe {
            entry.create_instance(
                &vk::InstanceCreateInfo::default().application_info(&app),
                None,
            )
        }
        .map_err(|e| format!("vkCreateInstance: {e}"))?;
        // SAFETY: the instance is live for every call below.
        let devices = unsafe { instance.enumerate_physical_devices() }
            .map_err(|e| format!("vkEnumeratePhysicalDevices: {e}"))?;
        let props = |pd: vk::PhysicalDevice| unsafe { instance.get_physical_device_properties(pd) };
        let name = |pd: vk::PhysicalDevice| text(&props(pd).device_name);
        let chosen = match adapter {
            Some(a) => devices
                .iter()
                .copied()
                .find(|&pd| name(pd).to_lowercase().contains(&a.to_lowercase())),
            None => devices
                .iter()
                .copied()
                .find(|&pd| props(pd).device_type == vk::PhysicalDeviceType::DISCRETE_GPU)
                .or(devices.first().copied()),
        };
        let Some(pd) = chosen else {
            return Err(format!(
                "no Vulkan device{} among {:?}",
                adapter
                    .map(|a| format!(" named like {a:?}"))
                    .unwrap_or_default(),
                devices.iter().map(|&pd| name(pd)).collect::<Vec<_>>()
            ));
        };
        let p = props(pd);
        // SAFETY: `pd` came from this instance.
        let extensions = unsafe { instance.enumerate_device_extension_properties(pd) }
            .map_err(|e| format!("vkEnumerateDeviceExtensionProperties: {e}"))?;
        let has = |n: &CStr| {
            extensions
                .iter()
                .any(|e| e.extension_name_as_c_str() == Ok(n))
        };
        let offered = has(ash::khr::pipeline_executable_properties::NAME);
        let sm = has(ash::nv::shader_sm_builtins::NAME);
        let mut subgroup = vk::PhysicalDeviceSubgroupProperties::default();
        let mut sm_props = vk::PhysicalDeviceShaderSMBuiltinsPropertiesNV::default();
        let mut driver = vk::PhysicalDeviceDriverProperties::default();
        {
            let mut p2 = vk::PhysicalDeviceProperties2::default()
                .push_next(&mut subgroup)
                .push_next(&mut driver);
            if sm {
                p2 = p2.push_next(&mut sm_props);
            }
            // SAFETY: the chain holds structures of Vulkan 1.1–1.2 core and,
            // where the device has the extension, VK_NV_shader_sm_builtins.
            unsafe { instance.get_physical_device_properties2(pd, &mut p2) };
        }
        let mut robust = vk::PhysicalDeviceRobustness2FeaturesEXT::default();
        let has_robust2 = has(ash::ext::robustness2::NAME);
        let v13 = p.api_version >= vk::API_VERSION_1_3;
        let mut f13 = vk::PhysicalDeviceVulkan13Features::default();
        let core = {
            let mut f2 = vk::PhysicalDeviceFeatures2::default();
            if has_robust2 {
                f2 = f2.push_next(&mut robust);
            }
            if v13 {
                f2 = f2.push_next(&mut f13);
            }
            // SAFETY: as above.
            unsafe { instance.get_physical_device_features2(pd, &mut f2) };
            f2.features
        };
        let f64 = core.shader_float64 == vk::TRUE;
        let robust2 = has_robust2 && robust.robust_buffer_access2 == vk::TRUE;
        // Workgroup memory zeroed by the driver where it can, as wgpu asks.
        let zero_init = v13 && f13.shader_zero_initialize_workgroup_memory == vk::TRUE;
        // SAFETY: as above.
        let families = unsafe { instance.get_physical_device_queue_family_properties(pd) };
        let family = families
            .iter()
            .position(|f| f.queue_flags.contains(vk::QueueFlags::COMPUTE))
            .ok_or("the device has no compute queue")? as u32;
        let priorities = [1.0];
        let queues = [vk::DeviceQueueCreateInfo::default()
            .queue_family_index(family)
            .queue_priorities(&priorities)];
        let mut names = vec![];
        if offered {
            names.push(ash::khr::pipeline_executable_properties::NAME.as_ptr());
        }
        let features = vk::PhysicalDeviceFeatures::default()
            .shader_float64(f64)
            .robust_buffer_access(core.robust_buffer_access == vk::TRUE);
        let mut exec = vk::PhysicalDevicePipelineExecutablePropertiesFeaturesKHR::default()
            .pipeline_executable_info(true);
        let mut info = vk::DeviceCreateInfo::default()
            .queue_create_infos(&queues)
            .enabled_extension_names(&names)
            .enabled_features(&features);
        let mut want13 = vk::PhysicalDeviceVulkan13Features::default()
            .shader_zero_initialize_workgroup_memory(true);
        if offered {
            info = info.push_next(&mut exec);
        }
        if zero_init {
            info = info.push_next(&mut want13);
        }
        // SAFETY: the features and extensions asked for are the device's own.
        let device = unsafe { instance.create_device(pd, &info, None) }
            .map_err(|e| format!("vkCreateDevice: {e}"))?;
        let width = if sm {
            format!(
                "; {} multiprocessors of {} warps",
                sm_props.shader_sm_count, sm_props.shader_warps_per_sm
            )
        } else {
            String::new()
        };
        let about = format!(
            "{} ({}, {}); Vulkan {}.{}; subgroups of {}{width}; robustBufferAccess2 {}; \
             pipeline statistics {}",
            text(&p.device_name),
            text(&driver.driver_name),
            text(&driver.driver_info),
            vk::api_version_major(p.api_version),
            vk::api_version_minor(p.api_version),
            subgroup.subgroup_size,
            if robust2 { "yes" } else { "no" },
            if offered {
                "offered"
            } else {
                "not offered (no VK_KHR_pipeline_executable_properties)"
            },
        );
        Ok(VkStats {
            _entry: entry,
            instance,
            device,
            about,
            offered,
            api: p.api_version,
            robust2,
            zero_init,
            f64,
        })
    }

    /// `wgsl`, the source of `kernel`, written to SPIR-V as wgpu writes it for
    /// this device, with wgpu's runtime checks or (`trusted`) without them;
    /// parsed and validated as the evaluator does ([`shaders::reflect`]).
    pub fn spirv(
        &self,
        wgsl: &str,
        kernel: Kernel,
        precision: Precision,
        trusted: bool,
    ) -> Result<(Vec<u32>, naga::Module), String> {
        use naga::back::spv;
        use naga::proc::{BoundsCheckPolicies, BoundsCheckPolicy as P};
        if precision == Precision::F64 && !self.f64 {
            return Err("the device has no shaderFloat64".into());
        }
        let shaders::Reflected { module, info, .. } =
            shaders::reflect(wgsl, precision, kernel).map_err(|e| e.to_string())?;
        let checked = |p| if trusted { P::Unchecked } else { p };
        let options = spv::Options {
            lang_version: if self.api >= vk::API_VERSION_1_3 {
                (1, 6)
            } else {
                (1, 5)
            },
            flags: spv::WriterFlags::empty(),
            bounds_check_policies: BoundsCheckPolicies {
                index: checked(P::Restrict),
                buffer: checked(if self.robust2 {
                    P::Unchecked
                } else {
                    P::Restrict
                }),
                image_load: P::Unchecked,
                binding_array: P::Unchecked,
            },
            zero_initialize_workgroup_memory: if self.zero_init {
                spv::ZeroInitializeWorkgroupMemoryMode::Native
            } else {
                spv::ZeroInitializeWorkgroupMemoryMode::Polyfill
            },
            force_loop_bounding: !trusted,
            emit_int_div_checks: !trusted,
            ..spv::Options::default()
        };
        let pipeline = spv::PipelineOptions {
            shader_stage: naga::ShaderStage::Compute,
            entry_point: kernel.entry_point().to_string(),
        };
        let words = spv::write_vec(&module, &info, &options, Some(&pipeline))
            .map_err(|e| format!("naga's SPIR-V writer: {e}"))?;
        Ok((words, module))
    }

    /// Builds `wgsl`, the source of `kernel`, into a compute pipeline and
    /// returns the driver's statistics of it (none where the driver offers
    /// none).
    pub fn statistics(
        &self,
        wgsl: &str,
        kernel: Kernel,
        precision: Precision,
        trusted: bool,
    ) -> Result<Vec<Statistic>, String> {
        let (words, module) = self.spirv(wgsl, kernel, precision, trusted)?;
        // Group 0's bindings, as the shader declares them.
        let bindings: Vec<vk::DescriptorSetLayoutBinding> = module
            .global_variables
            .iter()
            .filter_map(|(_, g)| {
                let b = g.binding.as_ref()?;
                let kind = match g.space {
                    naga::AddressSpace::Uniform => vk::DescriptorType::UNIFORM_BUFFER,
                    naga::AddressSpace::Storage { .. } => vk::DescriptorType::STORAGE_BUFFER,
                    _ => return None,
                };
                Some(
                    vk::DescriptorSetLayoutBinding::default()
                        .binding(b.binding)
                        .descriptor_type(kind)
                        .descriptor_count(1)
                        .stage_flags(vk::ShaderStageFlags::COMPUTE),
                )
            })
            .collect();
        let d = &self.device;
        // SAFETY: every object is created on this device and destroyed below,
        // after the pipeline that uses it; the SPIR-V is naga's, validated.
        unsafe {
            let shader = d
                .create_shader_module(&vk::ShaderModuleCreateInfo::default().code(&words), None)
                .map_err(|e| format!("vkCreateShaderModule: {e}"))?;
            let set = d
                .create_descriptor_set_layout(
                    &vk::DescriptorSetLayoutCreateInfo::default().bindings(&bindings),
                    None,
                )
                .map_err(|e| format!("vkCreateDescriptorSetLayout: {e}"))?;
            let sets = [set];
            let layout = d
                .create_pipeline_layout(
                    &vk::PipelineLayoutCreateInfo::default().set_layouts(&sets),
                    None,
                )
                .map_err(|e| format!("vkCreatePipelineLayout: {e}"))?;
            let name = std::ffi::CString::new(kernel.entry_point()).map_err(|e| e.to_string())?;
            let stage = vk::PipelineShaderStageCreateInfo::default()
                .stage(vk::ShaderStageFlags::COMPUTE)
                .module(shader)
                .name(&name);
            let flags = if self.offered {
                vk::PipelineCreateFlags::CAPTURE_STATISTICS_KHR
            } else {
                vk::PipelineCreateFlags::empty()
            };
            let info = vk::ComputePipelineCreateInfo::default()
                .stage(stage)
                .layout(layout)
                .flags(flags);
            let built = d.create_compute_pipelines(vk::PipelineCache::null(), &[info], None);
            let out = match built {
                Ok(p) => {
                    let stats = self.read(p[0]);
                    d.destroy_pipeline(p[0], None);
                    stats
                }
                Err((_, e)) => Err(format!("vkCreateComputePipelines: {e}")),
            };
            d.destroy_pipeline_layout(layout, None);
            d.destroy_descriptor_set_layout(set, None);
            d.destroy_shader_module(shader, None);
            out
        }
    }

    /// The statistics of `pipeline`'s executables.
    fn read(&self, pipeline: vk::Pipeline) -> Result<Vec<Statistic>, String> {
        if !self.offered {
            return Ok(vec![]);
        }
        let ext =
            ash::khr::pipeline_executable_properties::Device::new(&self.instance, &self.device);
        let mut out = vec![];
        // SAFETY: the pipeline was built with CAPTURE_STATISTICS on this device.
        let executables = unsafe {
            ext.get_pipeline_executable_properties(
                &vk::PipelineInfoKHR::default().pipeline(pipeline),
            )
        }
        .map_err(|e| format!("vkGetPipelineExecutablePropertiesKHR: {e}"))?;
        for (i, x) in executables.iter().enumerate() {
            let which = vk::PipelineExecutableInfoKHR::default()
                .pipeline(pipeline)
                .executable_index(i as u32);
            // SAFETY: as above, for an executable index the driver listed.
            let stats = unsafe { ext.get_pipeline_executable_statistics(&which) }
                .map_err(|e| format!("vkGetPipelineExecutableStatisticsKHR: {e}"))?;
            for s in stats {
                // SAFETY: the union's member is the one `format` names.
                let value = unsafe {
                    match s.format {
                        vk::PipelineExecutableStatisticFormatKHR::BOOL32 => {
                            (s.value.b32 == vk::TRUE).to_string()
                        }
                        vk::PipelineExecutableStatisticFormatKHR::INT64 => s.value.i64.to_string(),
                        vk::PipelineExecutableStatisticFormatKHR::UINT64 => s.value.u64.to_string(),
                        vk::PipelineExecutableStatisticFormatKHR::FLOAT64 => {
                            format!("{:.4}", s.value.f64)
                        }
                        _ => "?".into(),
                    }
                };
                out.push(Statistic {
                    executable: text(&x.name),
                    name: text(&s.name),
                    value,
                });
            }
        }
        Ok(out)
    }
}

impl Drop for VkStats {
    fn drop(&mut self) {
        // SAFETY: nothing created on the device outlives this call.
        unsafe {
            self.device.destroy_device(None);
            self.instance.destroy_instance(None);
        }
    }
}
