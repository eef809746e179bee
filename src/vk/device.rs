//! Physical-device choice and the logical device with its one graphics+compute queue.

use super::instance::Instance;
use super::pipeline_cache::PipelineCache;
use super::surface::Surface;
use crate::error::{Error, Result, VkContext};
use ash::{ext, khr, vk};
use std::path::Path;

/// Formats the renderer uses and the features each must offer with optimal tiling.
pub const HDR_FORMAT: vk::Format = vk::Format::R16G16B16A16_SFLOAT;
pub const DEPTH_FORMAT: vk::Format = vk::Format::D32_SFLOAT;
/// The HDR texels' bits as four 16-bit words: the visibility pass stores rest positions in them
/// and the shading pass replaces those with radiance in place (glsl/common.glsl).
pub const HDR_BITS_FORMAT: vk::Format = vk::Format::R16G16B16A16_UINT;

fn required_format_features() -> [(vk::Format, vk::FormatFeatureFlags, &'static str); 3] {
    use vk::FormatFeatureFlags as F;
    [
        (
            HDR_FORMAT,
            F::COLOR_ATTACHMENT
                | F::STORAGE_IMAGE
                | F::SAMPLED_IMAGE_FILTER_LINEAR
                | F::BLIT_SRC
                | F::BLIT_DST
                | F::TRANSFER_SRC,
            "R16G16B16A16_SFLOAT as colour attachment, storage, linear-filtered blit source and destination",
        ),
        // Sampled: the shading pass reads the camera's depth and the sun's shadow map.
        (DEPTH_FORMAT, F::DEPTH_STENCIL_ATTACHMENT | F::SAMPLED_IMAGE, "D32_SFLOAT as sampled depth attachment"),
        (HDR_BITS_FORMAT, F::COLOR_ATTACHMENT | F::STORAGE_IMAGE, "R16G16B16A16_UINT as colour attachment and storage"),
    ]
}

pub struct Device {
    pub raw: ash::Device,
    pub physical: vk::PhysicalDevice,
    pub queue: vk::Queue,
    pub queue_family: u32,
    pub name: String,
    pub properties: vk::PhysicalDeviceProperties,
    pub memory_properties: vk::PhysicalDeviceMemoryProperties,
    pub timestamp_valid_bits: u32,
    pub anisotropy: bool,
    /// Whether DEPTH_FORMAT filters linearly (optional in Vulkan): the shadow map's comparisons
    /// are then blended over 2 x 2 texels (else the nearest texel decides).
    pub depth_filter_linear: bool,
    pub subgroups: Subgroups,
    /// Whether pipeline statistics queries exist (the pipelineStatisticsQuery feature, enabled).
    pub pipeline_statistics: bool,
    /// VK_EXT_calibrated_timestamps, where the device samples its counter together with the
    /// host clock of our traces (clock::HOST_DOMAIN).
    pub calibrated_timestamps: Option<ext::calibrated_timestamps::Device>,
    pub debug_utils: Option<ext::debug_utils::Device>,
    /// VK_KHR_swapchain's functions, when the device was opened for a window.
    pub swapchain: Option<khr::swapchain::Device>,
    /// Every pipeline is created through it; kept on disk between runs (pipeline_cache.rs).
    pub pipeline_cache: PipelineCache,
    /// Whether the device is ours to destroy (false: a host's, borrowed by `from_host`).
    owned: bool,
}

/// What a host enabled on the device it hands over: Vulkan has no query for the features a
/// device was created with, so the host states them (a false statement is a broken
/// precondition the validation layer reports, not something we can detect).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct HostEnabled {
    /// Vulkan 1.3's synchronization2 feature (required).
    pub synchronization2: bool,
    /// Vulkan 1.3's dynamicRendering feature (required).
    pub dynamic_rendering: bool,
    /// samplerAnisotropy (optional: the sky map is then filtered isotropically).
    pub sampler_anisotropy: bool,
    /// pipelineStatisticsQuery (optional: profiling only).
    pub pipeline_statistics_query: bool,
    /// VK_EXT_calibrated_timestamps (optional: GPU spans on the host's clock).
    pub calibrated_timestamps: bool,
}

fn type_rank(t: vk::PhysicalDeviceType) -> u32 {
    match t {
        vk::PhysicalDeviceType::DISCRETE_GPU => 0,
        vk::PhysicalDeviceType::INTEGRATED_GPU => 1,
        vk::PhysicalDeviceType::VIRTUAL_GPU => 2,
        vk::PhysicalDeviceType::CPU => 3,
        _ => 4,
    }
}

struct Candidate {
    physical: vk::PhysicalDevice,
    name: String,
    properties: vk::PhysicalDeviceProperties,
    queue_family: u32,
    timestamp_valid_bits: u32,
    anisotropy: bool,
    depth_filter_linear: bool,
    subgroups: Subgroups,
    pipeline_statistics: bool,
    calibrated_timestamps: bool,
}

/// What the device's subgroups offer (Vulkan 1.1 core properties).
#[derive(Clone, Copy, Debug)]
pub struct Subgroups {
    pub size: u32,
    pub stages: vk::ShaderStageFlags,
    pub operations: vk::SubgroupFeatureFlags,
}

impl Subgroups {
    /// Whether compute shaders have subgroups of at least `lanes` invocations with every one of
    /// `operations`.
    pub fn compute_offers(&self, lanes: u32, operations: vk::SubgroupFeatureFlags) -> bool {
        self.size >= lanes
            && self.stages.contains(vk::ShaderStageFlags::COMPUTE)
            && self.operations.contains(operations)
    }
}

/// Checks one physical device; Err names the first thing it lacks. With a surface, the queue must
/// present to it and the device must have VK_KHR_swapchain.
fn check(instance: &Instance, physical: vk::PhysicalDevice, surface: Option<&Surface>) -> Result<Candidate> {
    let raw = &instance.raw;
    // SAFETY: `physical` comes from vkEnumeratePhysicalDevices on this instance.
    let properties = unsafe { raw.get_physical_device_properties(physical) };
    let name = properties.device_name_as_c_str().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default();
    let missing = |feature: &str| Error::MissingFeature { device: name.clone(), feature: feature.into() };
    if properties.api_version < vk::API_VERSION_1_3 {
        return Err(missing("Vulkan 1.3"));
    }
    let mut f13 = vk::PhysicalDeviceVulkan13Features::default();
    let mut features = vk::PhysicalDeviceFeatures2::default().push_next(&mut f13);
    // SAFETY: as above; `features` chains only locals.
    unsafe { raw.get_physical_device_features2(physical, &mut features) };
    let anisotropy = features.features.sampler_anisotropy == vk::TRUE;
    let pipeline_statistics = features.features.pipeline_statistics_query == vk::TRUE;
    let mut p11 = vk::PhysicalDeviceVulkan11Properties::default();
    let mut properties2 = vk::PhysicalDeviceProperties2::default().push_next(&mut p11);
    // SAFETY: as above; `properties2` chains only locals.
    unsafe { raw.get_physical_device_properties2(physical, &mut properties2) };
    let subgroups = Subgroups {
        size: p11.subgroup_size,
        stages: p11.subgroup_supported_stages,
        operations: p11.subgroup_supported_operations,
    };
    if f13.synchronization2 != vk::TRUE {
        return Err(missing("the synchronization2 feature"));
    }
    if f13.dynamic_rendering != vk::TRUE {
        return Err(missing("the dynamicRendering feature"));
    }
    for (format, needed, what) in required_format_features() {
        // SAFETY: as above.
        let props = unsafe { raw.get_physical_device_format_properties(physical, format) };
        if !props.optimal_tiling_features.contains(needed) {
            return Err(missing(what));
        }
    }
    // SAFETY: as above.
    let depth_props = unsafe { raw.get_physical_device_format_properties(physical, DEPTH_FORMAT) };
    let depth_filter_linear =
        depth_props.optimal_tiling_features.contains(vk::FormatFeatureFlags::SAMPLED_IMAGE_FILTER_LINEAR);
    // SAFETY: as above.
    let families = unsafe { raw.get_physical_device_queue_family_properties(physical) };
    let wanted = vk::QueueFlags::GRAPHICS | vk::QueueFlags::COMPUTE;
    let (queue_family, family) = families
        .iter()
        .enumerate()
        .find(|(_, f)| f.queue_flags.contains(wanted))
        .ok_or_else(|| missing("a graphics and compute queue"))?;
    // SAFETY: as above.
    let extensions = unsafe { raw.enumerate_device_extension_properties(physical) }
        .during("vkEnumerateDeviceExtensionProperties")?;
    let calibrated_timestamps =
        extensions.iter().any(|e| e.extension_name_as_c_str() == Ok(ext::calibrated_timestamps::NAME))
            && calibrates_with_host(instance, physical);
    if let Some(surface) = surface {
        if !extensions.iter().any(|e| e.extension_name_as_c_str() == Ok(khr::swapchain::NAME)) {
            return Err(missing("VK_KHR_swapchain"));
        }
        // One queue does everything; a device whose graphics queue cannot present is passed over.
        if !surface.supports(physical, queue_family as u32) {
            return Err(missing("presentation to this window from its graphics queue"));
        }
    }
    Ok(Candidate {
        physical,
        name,
        properties,
        queue_family: queue_family as u32,
        timestamp_valid_bits: family.timestamp_valid_bits,
        anisotropy,
        depth_filter_linear,
        subgroups,
        pipeline_statistics,
        calibrated_timestamps,
    })
}

/// Whether the device's calibrateable time domains include its own and the host's.
fn calibrates_with_host(instance: &Instance, physical: vk::PhysicalDevice) -> bool {
    let Some(host) = super::clock::HOST_DOMAIN else { return false };
    let calibrated = ext::calibrated_timestamps::Instance::new(&instance.entry, &instance.raw);
    // SAFETY: `physical` belongs to this instance, which exposes the device extension's query.
    match unsafe { calibrated.get_physical_device_calibrateable_time_domains(physical) } {
        Ok(domains) => domains.contains(&vk::TimeDomainEXT::DEVICE) && domains.contains(&host),
        Err(_) => false,
    }
}

/// Whether `physical` has everything the ocean needs (Vulkan 1.3, synchronization2,
/// dynamicRendering, a graphics and compute queue, the formats' features); Err names the first
/// thing it lacks.
pub fn supports(instance: &Instance, physical: vk::PhysicalDevice) -> Result<()> {
    check(instance, physical, None).map(|_| ())
}

impl Device {
    /// Picks discrete > integrated > virtual > CPU among devices that have what we need, or the
    /// first device whose name contains `name_filter` (case-insensitive).
    /// `cache_dir` holds the pipeline cache files (None: the cache lives for this run only).
    /// `surface`: the device must present to it (and is opened with VK_KHR_swapchain).
    pub fn new(
        instance: &Instance,
        name_filter: Option<&str>,
        cache_dir: Option<&Path>,
        surface: Option<&Surface>,
    ) -> Result<Device> {
        // SAFETY: enumeration on a live instance.
        let physicals = unsafe { instance.raw.enumerate_physical_devices() }.during("vkEnumeratePhysicalDevices")?;
        if physicals.is_empty() {
            return Err(Error::NoDevice(
                "the Vulkan loader reports no device (Debian: install mesa-vulkan-drivers)".into(),
            ));
        }
        let mut rejected = Vec::new();
        let mut candidates = Vec::new();
        for p in physicals {
            match check(instance, p, surface) {
                Ok(c) => candidates.push(c),
                Err(e) => rejected.push(e.to_string()),
            }
        }
        if let Some(filter) = name_filter {
            let filter = filter.to_lowercase();
            candidates.retain(|c| c.name.to_lowercase().contains(&filter));
            if candidates.is_empty() {
                return Err(Error::NoDevice(format!("no suitable device matches --device {filter:?}")));
            }
        }
        candidates.sort_by_key(|c| type_rank(c.properties.device_type));
        let Some(chosen) = candidates.into_iter().next() else {
            return Err(Error::NoDevice(rejected.join("; ")));
        };
        Self::open(instance, chosen, cache_dir, surface.is_some())
    }

    /// A host's device, borrowed: never destroyed here. `physical` must be the device `raw` was
    /// created from and `queue` a queue of `queue_family` on it; the ocean records into the
    /// host's command buffers and never submits to it. Fails naming the first thing that the
    /// physical device lacks or that the host did not enable.
    pub fn from_host(
        instance: &Instance,
        physical: vk::PhysicalDevice,
        raw: ash::Device,
        queue_family: u32,
        queue: vk::Queue,
        enabled: HostEnabled,
        cache_dir: Option<&Path>,
    ) -> Result<Device> {
        let c = check(instance, physical, None)?;
        let missing = |feature: &str| Error::MissingFeature { device: c.name.clone(), feature: feature.into() };
        if !enabled.synchronization2 {
            return Err(missing("synchronization2 enabled on the host's device (VkPhysicalDeviceVulkan13Features)"));
        }
        if !enabled.dynamic_rendering {
            return Err(missing("dynamicRendering enabled on the host's device (VkPhysicalDeviceVulkan13Features)"));
        }
        // SAFETY: `physical` comes from the host's instance (checked above through it).
        let families = unsafe { instance.raw.get_physical_device_queue_family_properties(physical) };
        let wanted = vk::QueueFlags::GRAPHICS | vk::QueueFlags::COMPUTE;
        let family = families
            .get(queue_family as usize)
            .filter(|f| f.queue_flags.contains(wanted))
            .ok_or_else(|| missing(&format!("graphics and compute on queue family {queue_family}")))?;
        let c = Candidate {
            queue_family,
            timestamp_valid_bits: family.timestamp_valid_bits,
            anisotropy: c.anisotropy && enabled.sampler_anisotropy,
            pipeline_statistics: c.pipeline_statistics && enabled.pipeline_statistics_query,
            calibrated_timestamps: c.calibrated_timestamps && enabled.calibrated_timestamps,
            ..c
        };
        let pipeline_cache = PipelineCache::open(&raw, &c.properties, cache_dir)?;
        Ok(Self::assemble(instance, c, raw, queue, pipeline_cache, false, false))
    }

    fn open(instance: &Instance, c: Candidate, cache_dir: Option<&Path>, present: bool) -> Result<Device> {
        let priorities = [1.0];
        let queue_info =
            [vk::DeviceQueueCreateInfo::default().queue_family_index(c.queue_family).queue_priorities(&priorities)];
        let mut f13 = vk::PhysicalDeviceVulkan13Features::default().synchronization2(true).dynamic_rendering(true);
        let base = vk::PhysicalDeviceFeatures::default()
            .sampler_anisotropy(c.anisotropy)
            .pipeline_statistics_query(c.pipeline_statistics);
        let mut extensions = if present { vec![khr::swapchain::NAME.as_ptr()] } else { vec![] };
        if c.calibrated_timestamps {
            extensions.push(ext::calibrated_timestamps::NAME.as_ptr());
        }
        let info = vk::DeviceCreateInfo::default()
            .queue_create_infos(&queue_info)
            .enabled_extension_names(&extensions)
            .enabled_features(&base)
            .push_next(&mut f13);
        // SAFETY: the features requested were checked as supported; pointers refer to locals.
        let raw = unsafe { instance.raw.create_device(c.physical, &info, None) }.during("vkCreateDevice")?;
        // SAFETY: queue 0 of a family we created one queue in.
        let queue = unsafe { raw.get_device_queue(c.queue_family, 0) };
        let pipeline_cache = match PipelineCache::open(&raw, &c.properties, cache_dir) {
            Ok(cache) => cache,
            Err(e) => {
                // SAFETY: nothing was created on the device yet.
                unsafe { raw.destroy_device(None) };
                return Err(e);
            }
        };
        Ok(Self::assemble(instance, c, raw, queue, pipeline_cache, present, true))
    }

    /// The device's wrapper around `raw`, with the extension functions it was opened with.
    fn assemble(
        instance: &Instance,
        c: Candidate,
        raw: ash::Device,
        queue: vk::Queue,
        pipeline_cache: PipelineCache,
        present: bool,
        owned: bool,
    ) -> Device {
        // SAFETY: plain query on a live physical device.
        let memory_properties = unsafe { instance.raw.get_physical_device_memory_properties(c.physical) };
        let debug_utils = instance.debug_utils.as_ref().map(|_| ext::debug_utils::Device::new(&instance.raw, &raw));
        let swapchain = present.then(|| khr::swapchain::Device::new(&instance.raw, &raw));
        let calibrated_timestamps =
            c.calibrated_timestamps.then(|| ext::calibrated_timestamps::Device::new(&instance.raw, &raw));
        let device = Device {
            raw,
            physical: c.physical,
            queue,
            queue_family: c.queue_family,
            name: c.name,
            properties: c.properties,
            memory_properties,
            timestamp_valid_bits: c.timestamp_valid_bits,
            anisotropy: c.anisotropy,
            depth_filter_linear: c.depth_filter_linear,
            subgroups: c.subgroups,
            pipeline_statistics: c.pipeline_statistics,
            calibrated_timestamps,
            debug_utils,
            swapchain,
            pipeline_cache,
            owned,
        };
        if owned {
            device.set_name(device.queue, "main queue");
        }
        device.set_name(device.pipeline_cache.raw, "ocean pipeline cache");
        device
    }

    /// Gives a Vulkan object a debug name (shown by validation messages, RenderDoc, Nsight).
    pub fn set_name<H: vk::Handle>(&self, handle: H, name: &str) {
        let Some(du) = &self.debug_utils else { return };
        let Ok(name) = std::ffi::CString::new(name) else {
            return;
        };
        let info = vk::DebugUtilsObjectNameInfoEXT::default().object_handle(handle).object_name(&name);
        // SAFETY: `handle` is a live object of this device; naming failure is harmless.
        let _ = unsafe { du.set_debug_utils_object_name(&info) };
    }

    pub fn wait_idle(&self) -> Result<()> {
        // SAFETY: the device is live.
        unsafe { self.raw.device_wait_idle() }.during("vkDeviceWaitIdle")
    }
}

impl Drop for Device {
    fn drop(&mut self) {
        // SAFETY: owners of child objects drop first (Gpu's field order), after wait_idle; a
        // host's device outlives this wrapper (a documented precondition of `from_host`).
        unsafe {
            let _ = self.raw.device_wait_idle();
            self.raw.destroy_pipeline_cache(self.pipeline_cache.raw, None);
            if self.owned {
                self.raw.destroy_device(None);
            }
        }
    }
}
