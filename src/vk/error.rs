//! Errors of the Vulkan layer. Each says what we were doing and, where the user can act, how
//! to fix it, so that the CLI can print it as one line.

use ash::vk;

/// Something went wrong talking to Vulkan.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum VkError {
    /// `libvulkan.so.1` could not be loaded.
    #[error("cannot load the Vulkan loader ({0}); install it with `apt-get install libvulkan1`")]
    LoaderMissing(String),
    /// The loader found no driver (ICD), or the driver found no device.
    #[error("no Vulkan driver or device found ({0}); install a driver, e.g. `apt-get install mesa-vulkan-drivers` for the CPU device (lavapipe), and check VK_DRIVER_FILES / VK_ICD_FILENAMES")]
    NoDriver(String),
    /// Devices exist, but none has a queue that can run compute shaders.
    #[error("no Vulkan device has a compute queue (devices: {0})")]
    NoComputeDevice(String),
    /// `--require-gpu` was given and the chosen device is not a GPU.
    #[error("a GPU was required (--require-gpu), but the chosen device '{name}' is a {kind}")]
    NotAGpu {
        /// The device's name.
        name: String,
        /// Its type, in words.
        kind: String,
    },
    /// `--device` named no device.
    #[error(
        "no Vulkan device matches '{selector}' (run `vkpath devices`; available: {available})"
    )]
    DeviceNotFound {
        /// What the user asked for.
        selector: String,
        /// The devices that exist.
        available: String,
    },
    /// The device could not be chosen as `--device`, `VKPATH_DEVICE` or
    /// `CUDA_VISIBLE_DEVICES` asks (the message names the variable and what to change).
    #[error("{0}")]
    Choice(String),
    /// Validation was asked for, but the layer is not installed.
    #[error("the validation layer VK_LAYER_KHRONOS_validation is not installed; install it with `apt-get install vulkan-validationlayers`")]
    ValidationLayerMissing,
    /// A Vulkan call failed.
    #[error("{what} failed: {result}")]
    Call {
        /// What we were doing.
        what: &'static str,
        /// The result code.
        result: vk::Result,
    },
    /// A GPU memory allocation failed.
    #[error("allocating {what} on '{device}' failed: {error}; use a smaller image or scene, or a device with more memory")]
    Allocation {
        /// What the memory was for.
        what: String,
        /// The device's name.
        device: String,
        /// The allocator's error (in the message, not chained: the message says it all).
        error: gpu_allocator::AllocationError,
    },
    /// A submitted frame did not finish in time.
    #[error("the device '{device}' did not finish a frame within {seconds} s (hung, or a frame too long for it): use fewer --samples-per-frame")]
    Timeout {
        /// The device's name.
        device: String,
        /// The limit.
        seconds: u64,
    },
    /// The device was lost (a driver crash, a GPU reset, a hang the driver gave up on).
    #[error("the device '{0}' was lost (driver crash, GPU reset or hang)")]
    DeviceLost(String),
    /// SPIR-V that Vulkan cannot take.
    #[error("invalid SPIR-V: {0}")]
    InvalidSpirv(String),
    /// Data beyond one of the device's limits (the message names the data and the limit).
    #[error("{0}")]
    TooLarge(String),
    /// The device lacks an optional feature that the work needs (the message names both).
    #[error("{0}")]
    Unsupported(String),
}

/// Result of the Vulkan layer.
pub type VkResult<T> = Result<T, VkError>;

/// Adds context to a raw `vk::Result` error.
pub(crate) trait CallContext<T> {
    /// Names the call that failed.
    fn during(self, what: &'static str) -> VkResult<T>;
}

impl<T> CallContext<T> for Result<T, vk::Result> {
    fn during(self, what: &'static str) -> VkResult<T> {
        self.map_err(|result| VkError::Call { what, result })
    }
}
