//! The crate's error type: every failure a user can cause or meet is one clear line.

use ash::vk;
use std::path::PathBuf;

#[derive(Debug, thiserror::Error)]
pub enum Error {
    #[error("scene {file}: {message}")]
    Scene { file: String, message: String },
    #[error("invalid argument: {0}")]
    Argument(String),
    #[error("Vulkan loader not found ({0}); install libvulkan1 and a driver such as mesa-vulkan-drivers")]
    Loader(String),
    #[error("no usable Vulkan device: {0}")]
    NoDevice(String),
    #[error("Vulkan device {device} lacks {feature}")]
    MissingFeature { device: String, feature: String },
    #[error("validation layer requested but {0}")]
    ValidationUnavailable(String),
    #[error("no window surface: {0}")]
    NoSurface(String),
    #[error("Vulkan call {call} failed: {result}")]
    Vulkan { call: &'static str, result: vk::Result },
    #[error("out of GPU memory for {name} ({bytes} bytes)")]
    OutOfMemory { name: String, bytes: u64 },
    #[error("{path}: {message}")]
    Io { path: PathBuf, message: String },
}

impl Error {
    /// A failed file operation on `path`, with what the system said.
    pub fn io(path: &std::path::Path, e: impl std::fmt::Display) -> Error {
        Error::Io { path: path.to_owned(), message: e.to_string() }
    }
}

impl From<vk::Result> for Error {
    fn from(result: vk::Result) -> Self {
        Error::Vulkan { call: "vkCall", result }
    }
}

pub type Result<T, E = Error> = std::result::Result<T, E>;

/// Names the failing Vulkan entry point: `unsafe { device.create_image(..) }.during("vkCreateImage")?`.
pub trait VkContext<T> {
    fn during(self, call: &'static str) -> Result<T>;
}

impl<T> VkContext<T> for std::result::Result<T, vk::Result> {
    fn during(self, call: &'static str) -> Result<T> {
        self.map_err(|result| Error::Vulkan { call, result })
    }
}
