//! Choosing the wgpu backend explicitly: GL (Mesa llvmpipe through EGL, surfaceless) by
//! default, Vulkan (lavapipe, or a real GPU) on request. Left to itself wgpu would switch to
//! lavapipe silently once it is installed; frames must not change with what happens to be
//! installed.

use std::fmt;
use std::str::FromStr;
use thiserror::Error;

/// The environment variable that overrides the default backend.
pub const BACKEND_ENV: &str = "WGPU_BACKEND";

/// A wgpu backend the renderer can run on.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Backend {
    /// OpenGL ES through EGL: Mesa's llvmpipe on a CPU-only machine.
    #[default]
    Gl,
    /// Vulkan: Mesa's lavapipe on a CPU-only machine, or a GPU's driver.
    Vulkan,
    /// Whatever wgpu finds first among Vulkan, Metal and DX12 (a real GPU).
    Primary,
}

/// Why a backend could not be chosen or opened.
#[derive(Clone, Debug, Error, PartialEq)]
pub enum BackendError {
    /// The name is not one we know.
    #[error("unknown backend {0:?} (from {1}); expected gl, vulkan or primary")]
    Unknown(String, String),
    /// No adapter: the system lacks the driver.
    #[error("no {backend} adapter found: {hint}")]
    NoAdapter {
        /// The backend asked for.
        backend: Backend,
        /// What to install.
        hint: &'static str,
    },
    /// The adapter refused a device.
    #[error("the {backend} adapter {adapter:?} refused a device: {reason}")]
    Device {
        /// The backend.
        backend: Backend,
        /// The adapter's name.
        adapter: String,
        /// wgpu's message.
        reason: String,
    },
}

impl fmt::Display for Backend {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Backend::Gl => "gl",
            Backend::Vulkan => "vulkan",
            Backend::Primary => "primary",
        })
    }
}

impl FromStr for Backend {
    type Err = BackendError;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s.trim().to_ascii_lowercase().as_str() {
            "gl" | "gles" | "opengl" => Ok(Backend::Gl),
            "vulkan" | "vk" => Ok(Backend::Vulkan),
            "primary" | "gpu" => Ok(Backend::Primary),
            other => Err(BackendError::Unknown(
                other.to_string(),
                "the command line".into(),
            )),
        }
    }
}

impl Backend {
    /// The backend to use: `flag` (a command-line value) if given, else `WGPU_BACKEND`,
    /// else GL.
    pub fn choose(flag: Option<&str>) -> Result<Backend, BackendError> {
        if let Some(flag) = flag {
            return flag.parse();
        }
        match std::env::var(BACKEND_ENV) {
            Ok(value) if !value.trim().is_empty() => value.parse().map_err(|e| match e {
                BackendError::Unknown(name, _) => BackendError::Unknown(name, BACKEND_ENV.into()),
                other => other,
            }),
            _ => Ok(Backend::Gl),
        }
    }

    /// wgpu's backend bits for this choice.
    pub fn wgpu_backends(self) -> wgpu::Backends {
        match self {
            Backend::Gl => wgpu::Backends::GL,
            Backend::Vulkan => wgpu::Backends::VULKAN,
            Backend::Primary => wgpu::Backends::PRIMARY,
        }
    }

    /// What to install when this backend has no adapter.
    pub fn install_hint(self) -> &'static str {
        match self {
            Backend::Gl => {
                "install Mesa's EGL and llvmpipe (Debian: apt-get install libegl1 libegl-mesa0 \
                 libgl1-mesa-dri), or choose another backend with --backend or WGPU_BACKEND"
            }
            Backend::Vulkan => {
                "install a Vulkan driver (Debian: apt-get install mesa-vulkan-drivers for \
                 lavapipe), or use --backend gl"
            }
            Backend::Primary => "no GPU driver found; use --backend gl on a CPU-only machine",
        }
    }
}
