//! The device: instance, adapter and device on exactly the chosen backend (or on an OpenGL
//! context of the caller's), and the lock under which the renderers of one display take
//! turns.

use super::RenderError;
use crate::camera::backend::{Backend, BackendError};

/// The device a renderer draws with, its queue, and the display it takes turns on.
pub(super) struct Gpu {
    pub device: wgpu::Device,
    pub queue: wgpu::Queue,
    /// The adapter in use, e.g. `llvmpipe (LLVM 15.0.6, 256 bits) (Gl)`.
    pub adapter_name: String,
    /// Whether it renders on a context of the caller's (Mesa's software device) rather than
    /// on wgpu's own display: which renderers it takes turns with (see [`display_lock`]).
    pub external: bool,
}

impl Gpu {
    /// Instance, adapter and device on exactly `backend`; on the caller's current OpenGL
    /// context when `external_gl` gives its entry points (see `Renderer::on_current_gl`).
    /// To be called with [`display_lock`] held.
    pub fn open(
        backend: Backend,
        external_gl: Option<&dyn Fn(&str) -> *const std::ffi::c_void>,
    ) -> Result<Gpu, RenderError> {
        let mut instance_descriptor = wgpu::InstanceDescriptor::new_without_display_handle();
        instance_descriptor.backends = backend.wgpu_backends();
        // Without indirect-call validation: with it, every device builds compute pipelines
        // to check indirect draws (device creation 2–8 ms instead of 0.5–0.8 ms here), and
        // none is ever issued.
        instance_descriptor.flags = wgpu::InstanceFlags::from_build_config()
            .with_env()
            .difference(wgpu::InstanceFlags::VALIDATION_INDIRECT_CALL);
        let instance = wgpu::Instance::new(instance_descriptor);
        let no_adapter = || BackendError::NoAdapter {
            backend,
            hint: backend.install_hint(),
        };
        let adapter = match external_gl {
            None => pollster::block_on(instance.request_adapter(&wgpu::RequestAdapterOptions {
                power_preference: wgpu::PowerPreference::HighPerformance,
                force_fallback_adapter: false,
                compatible_surface: None,
                apply_limit_buckets: false,
            }))
            .map_err(|_| no_adapter())?,
            Some(proc_address) => {
                // SAFETY: the caller's context is current on this thread, and stays so for
                // as long as this renderer lives (see `on_current_gl`).
                let exposed = unsafe {
                    wgpu::hal::gles::Adapter::new_external(proc_address, Default::default())
                }
                .ok_or_else(no_adapter)?;
                // SAFETY: a GLES adapter belongs to no instance's handle.
                unsafe { instance.create_adapter_from_hal(exposed) }
            }
        };
        let adapter_name = format!(
            "{} ({:?})",
            adapter.get_info().name,
            adapter.get_info().backend
        );
        let (device, queue) = pollster::block_on(adapter.request_device(&wgpu::DeviceDescriptor {
            label: Some("carfollow camera"),
            required_features: wgpu::Features::empty(),
            required_limits:
                wgpu::Limits::downlevel_webgl2_defaults().using_resolution(adapter.limits()),
            ..Default::default()
        }))
        .map_err(|e| BackendError::Device {
            backend,
            adapter: adapter_name.clone(),
            reason: e.to_string(),
        })?;
        Ok(Gpu {
            device,
            queue,
            adapter_name,
            external: external_gl.is_some(),
        })
    }
}

/// One renderer of a display at a time. Mesa's llvmpipe rasterises every GL context of an
/// EGL display on one shared rasteriser, so two renderers of one display on two threads
/// only take turns anyway; but unserialised, its shared scene lists race: test binaries that
/// ran closed loops on two threads died of a segmentation fault inside `swrast_dri.so`, now
/// and then, under load. Renderers on wgpu's own display (`external` false) take one lock,
/// those on contexts of the caller's (Mesa's software EGL device, one display too: see
/// `software_device`) the other, so one of each renders alongside the other, as `run`'s
/// two renderers do. Held while a frame is submitted and read back, and while a device is
/// created.
pub(super) fn display_lock(external: bool) -> std::sync::MutexGuard<'static, ()> {
    static WGPU_DISPLAY: std::sync::Mutex<()> = std::sync::Mutex::new(());
    static SOFTWARE_DEVICE: std::sync::Mutex<()> = std::sync::Mutex::new(());
    let lock = if external {
        &SOFTWARE_DEVICE
    } else {
        &WGPU_DISPLAY
    };
    // A renderer that panicked holding it left nothing half-done that the lock protects.
    lock.lock()
        .unwrap_or_else(std::sync::PoisonError::into_inner)
}
