//! The validation layer's messages: routed to the `log` crate and counted, so that tests can
//! assert that a render produced none.

use std::ffi::{c_void, CStr};
use std::sync::atomic::{AtomicU32, Ordering};

use ash::vk;

/// Counts of the messages the validation layer sent (through `VK_EXT_debug_utils`).
#[derive(Debug, Default)]
pub struct ValidationMessages {
    errors: AtomicU32,
    warnings: AtomicU32,
}

impl ValidationMessages {
    /// Number of error messages so far.
    pub fn errors(&self) -> u32 {
        self.errors.load(Ordering::SeqCst)
    }

    /// Number of warning messages so far.
    pub fn warnings(&self) -> u32 {
        self.warnings.load(Ordering::SeqCst)
    }

    /// Errors plus warnings.
    pub fn total(&self) -> u32 {
        self.errors() + self.warnings()
    }
}

/// The messenger's create info, pointing at `messages` (which must outlive the messenger).
pub(crate) fn messenger_create_info(
    messages: &ValidationMessages,
) -> vk::DebugUtilsMessengerCreateInfoEXT<'static> {
    vk::DebugUtilsMessengerCreateInfoEXT::default()
        .message_severity(
            vk::DebugUtilsMessageSeverityFlagsEXT::ERROR
                | vk::DebugUtilsMessageSeverityFlagsEXT::WARNING
                | vk::DebugUtilsMessageSeverityFlagsEXT::INFO,
        )
        .message_type(
            vk::DebugUtilsMessageTypeFlagsEXT::GENERAL
                | vk::DebugUtilsMessageTypeFlagsEXT::VALIDATION
                | vk::DebugUtilsMessageTypeFlagsEXT::PERFORMANCE,
        )
        .pfn_user_callback(Some(on_message))
        .user_data(messages as *const ValidationMessages as *mut c_void)
}

/// Logs one message and counts it when it is a warning or an error.
unsafe extern "system" fn on_message(
    severity: vk::DebugUtilsMessageSeverityFlagsEXT,
    kind: vk::DebugUtilsMessageTypeFlagsEXT,
    data: *const vk::DebugUtilsMessengerCallbackDataEXT<'_>,
    user_data: *mut c_void,
) -> vk::Bool32 {
    let text = if data.is_null() || (*data).p_message.is_null() {
        "(no message)".into()
    } else {
        CStr::from_ptr((*data).p_message).to_string_lossy()
    };
    let messages = &*(user_data as *const ValidationMessages);
    if severity.contains(vk::DebugUtilsMessageSeverityFlagsEXT::ERROR) {
        messages.errors.fetch_add(1, Ordering::SeqCst);
        log::error!("vulkan {kind:?}: {text}");
    } else if severity.contains(vk::DebugUtilsMessageSeverityFlagsEXT::WARNING) {
        messages.warnings.fetch_add(1, Ordering::SeqCst);
        log::warn!("vulkan {kind:?}: {text}");
    } else {
        log::debug!("vulkan {kind:?}: {text}");
    }
    vk::FALSE
}
