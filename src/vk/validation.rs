//! Debug-utils messenger: counts validation errors and warnings by message id and logs each id's
//! first occurrences. Tests and reports read the counts; any error fails a test.

use ash::vk;
use std::collections::BTreeMap;
use std::ffi::CStr;
use std::sync::Mutex;

/// How many times one message id is printed before it is only counted.
const PRINT_PER_ID: u32 = 3;

#[derive(Default, Debug, Clone, PartialEq, Eq)]
pub struct MessageCounts {
    pub errors: BTreeMap<String, u32>,
    pub warnings: BTreeMap<String, u32>,
}

impl MessageCounts {
    pub fn error_total(&self) -> u32 {
        self.errors.values().sum()
    }
    pub fn warning_total(&self) -> u32 {
        self.warnings.values().sum()
    }
}

#[derive(Default)]
pub struct ValidationLog {
    counts: Mutex<MessageCounts>,
}

impl ValidationLog {
    pub fn snapshot(&self) -> MessageCounts {
        self.counts.lock().map(|c| c.clone()).unwrap_or_default()
    }

    fn record(&self, severity: vk::DebugUtilsMessageSeverityFlagsEXT, id: &str, message: &str) {
        let Ok(mut counts) = self.counts.lock() else {
            return;
        };
        let (map, label) = if severity.contains(vk::DebugUtilsMessageSeverityFlagsEXT::ERROR) {
            (&mut counts.errors, "error")
        } else {
            (&mut counts.warnings, "warning")
        };
        let n = map.entry(id.to_owned()).or_insert(0);
        *n += 1;
        if *n <= PRINT_PER_ID {
            eprintln!("vulkan {label} [{id}]: {message}");
        }
    }
}

pub fn messenger_info(log: &ValidationLog) -> vk::DebugUtilsMessengerCreateInfoEXT<'static> {
    vk::DebugUtilsMessengerCreateInfoEXT::default()
        .message_severity(vk::DebugUtilsMessageSeverityFlagsEXT::ERROR | vk::DebugUtilsMessageSeverityFlagsEXT::WARNING)
        .message_type(
            vk::DebugUtilsMessageTypeFlagsEXT::GENERAL
                | vk::DebugUtilsMessageTypeFlagsEXT::VALIDATION
                | vk::DebugUtilsMessageTypeFlagsEXT::PERFORMANCE,
        )
        .pfn_user_callback(Some(on_message))
        .user_data(log as *const ValidationLog as *mut std::ffi::c_void)
}

unsafe extern "system" fn on_message(
    severity: vk::DebugUtilsMessageSeverityFlagsEXT,
    _types: vk::DebugUtilsMessageTypeFlagsEXT,
    data: *const vk::DebugUtilsMessengerCallbackDataEXT<'_>,
    user: *mut std::ffi::c_void,
) -> vk::Bool32 {
    // SAFETY: the layer passes valid callback data for the call's duration, and `user` is the
    // ValidationLog the Instance keeps alive (boxed) until after the messenger is destroyed.
    let (log, data) = unsafe { (&*(user as *const ValidationLog), &*data) };
    let text = |p: *const std::ffi::c_char| {
        if p.is_null() {
            String::new()
        } else {
            // SAFETY: the layer passes NUL-terminated strings, live for the call.
            unsafe { CStr::from_ptr(p) }.to_string_lossy().into_owned()
        }
    };
    let id = text(data.p_message_id_name);
    let id = if id.is_empty() { format!("{:#x}", data.message_id_number) } else { id };
    log.record(severity, &id, &text(data.p_message));
    vk::FALSE
}
