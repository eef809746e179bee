//! Vulkan instance: loader, optional validation (with synchronization validation) and the
//! debug-utils messenger, chained into instance creation so creation messages are caught too.

use super::validation::{messenger_info, ValidationLog};
use crate::error::{Error, Result, VkContext};
use ash::{ext, vk};
use std::ffi::CStr;

const VALIDATION_LAYER: &CStr = c"VK_LAYER_KHRONOS_validation";

pub struct Instance {
    pub entry: ash::Entry,
    pub raw: ash::Instance,
    pub debug_utils: Option<ext::debug_utils::Instance>,
    messenger: vk::DebugUtilsMessengerEXT,
    /// Boxed so its address, given to the layer as user data, never moves.
    pub log: Box<ValidationLog>,
    /// Whether this instance is ours to destroy (false: a host's, borrowed by `from_host`).
    owned: bool,
}

impl Instance {
    pub fn new(validation: bool) -> Result<Instance> {
        Self::with_extensions(Self::load()?, validation, &[])
    }

    /// Loads the system's Vulkan loader.
    pub fn load() -> Result<ash::Entry> {
        // SAFETY: loading the system loader library; its symbols are only used through ash.
        unsafe { ash::Entry::load() }.map_err(|e| Error::Loader(e.to_string()))
    }

    /// An instance with `extra` extensions enabled too (a window's surface extensions), each
    /// checked to be available by the caller.
    pub fn with_extensions(entry: ash::Entry, validation: bool, extra: &[&CStr]) -> Result<Instance> {
        // SAFETY: plain enumeration calls on a loaded entry.
        let layers =
            unsafe { entry.enumerate_instance_layer_properties() }.during("vkEnumerateInstanceLayerProperties")?;
        // SAFETY: plain enumeration on a loaded entry.
        let extensions = unsafe { entry.enumerate_instance_extension_properties(None) }
            .during("vkEnumerateInstanceExtensionProperties")?;
        let has_layer = layers.iter().any(|l| l.layer_name_as_c_str() == Ok(VALIDATION_LAYER));
        let has_debug_utils = extensions.iter().any(|e| e.extension_name_as_c_str() == Ok(ext::debug_utils::NAME));
        if validation && !has_layer {
            return Err(Error::ValidationUnavailable(
                "VK_LAYER_KHRONOS_validation is not installed (Debian: vulkan-validationlayers)".into(),
            ));
        }
        if validation && !has_debug_utils {
            return Err(Error::ValidationUnavailable("VK_EXT_debug_utils is not available".into()));
        }

        let log = Box::<ValidationLog>::default();
        let app = vk::ApplicationInfo::default()
            .application_name(c"ocean")
            .application_version(1)
            .engine_name(c"ocean")
            .api_version(vk::API_VERSION_1_3);
        let layer_names = if validation { vec![VALIDATION_LAYER.as_ptr()] } else { vec![] };
        let mut extension_names: Vec<_> = extra.iter().map(|e| e.as_ptr()).collect();
        if has_debug_utils {
            extension_names.push(ext::debug_utils::NAME.as_ptr());
        }
        let enables = [vk::ValidationFeatureEnableEXT::SYNCHRONIZATION_VALIDATION];
        let mut features = vk::ValidationFeaturesEXT::default().enabled_validation_features(&enables);
        let mut creation_messenger = messenger_info(&log);
        let mut info = vk::InstanceCreateInfo::default()
            .application_info(&app)
            .enabled_layer_names(&layer_names)
            .enabled_extension_names(&extension_names);
        if validation {
            info = info.push_next(&mut features).push_next(&mut creation_messenger);
        }
        // SAFETY: every pointer in `info` refers to locals that outlive the call.
        let raw = unsafe { entry.create_instance(&info, None) }.map_err(|result| match result {
            vk::Result::ERROR_INCOMPATIBLE_DRIVER => {
                Error::NoDevice("no Vulkan 1.3 driver is installed (Debian: mesa-vulkan-drivers)".into())
            }
            result => Error::Vulkan { call: "vkCreateInstance", result },
        })?;

        let (debug_utils, messenger) = if has_debug_utils {
            let debug_utils = ext::debug_utils::Instance::new(&entry, &raw);
            let messenger = if validation {
                // SAFETY: `log` is boxed and outlives the messenger (destroyed first in Drop).
                unsafe { debug_utils.create_debug_utils_messenger(&messenger_info(&log), None) }
                    .during("vkCreateDebugUtilsMessengerEXT")?
            } else {
                vk::DebugUtilsMessengerEXT::null()
            };
            (Some(debug_utils), messenger)
        } else {
            (None, vk::DebugUtilsMessengerEXT::null())
        };
        Ok(Instance { entry, raw, debug_utils, messenger, log, owned: true })
    }

    /// A host's instance, borrowed: never destroyed here. `debug_utils`: the host enabled
    /// VK_EXT_debug_utils on it (our passes then carry debug labels and names). Validation
    /// messages go to the host's own messenger, so `log` stays empty.
    pub fn from_host(entry: ash::Entry, raw: ash::Instance, debug_utils: bool) -> Instance {
        let debug_utils = debug_utils.then(|| ext::debug_utils::Instance::new(&entry, &raw));
        Instance {
            entry,
            raw,
            debug_utils,
            messenger: vk::DebugUtilsMessengerEXT::null(),
            log: Box::default(),
            owned: false,
        }
    }
}

impl Drop for Instance {
    fn drop(&mut self) {
        if !self.owned {
            return; // the host's: it destroys it, after our device wrapper is gone
        }
        // SAFETY: every child object (device, messenger) is destroyed before the instance; the
        // Device owner drops before this Instance.
        unsafe {
            if let Some(du) = &self.debug_utils {
                if self.messenger != vk::DebugUtilsMessengerEXT::null() {
                    du.destroy_debug_utils_messenger(self.messenger, None);
                }
            }
            self.raw.destroy_instance(None);
        }
    }
}
