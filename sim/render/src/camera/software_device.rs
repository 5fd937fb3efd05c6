//! A second llvmpipe in this process: Mesa's software EGL device.
//!
//! llvmpipe rasterises every GL context of one EGL display on one shared rasteriser, so two
//! renderers on wgpu's own (surfaceless) display only take turns. Mesa also offers its
//! software renderer as an EGL device (`EGL_MESA_device_software`), whose display is a
//! separate llvmpipe screen with a rasteriser of its own: a renderer on it renders alongside
//! one on wgpu's display, on another thread of the same process. wgpu takes such a context
//! as an external adapter, which must be current whenever wgpu calls GL for it, so a
//! [`SoftwareContext`] is made current on the thread that opens it, and everything made
//! from it stays on that thread. The device has one display, so two such contexts in a
//! process share its rasteriser: their renderers take turns (`renderer::display_lock`).
//!
//! The context is the one wgpu makes for itself on Mesa's surfaceless display (desktop
//! OpenGL 3.3 with robust access), on the same driver, so its frames are the same bit for
//! bit (tests compare them).

use khronos_egl as egl;
use std::ffi::{c_char, c_void, CStr};

type Egl = egl::DynamicInstance<egl::EGL1_5>;

/// `EGL_PLATFORM_DEVICE_EXT`.
const PLATFORM_DEVICE: egl::Enum = 0x313F;
/// `eglQueryDevicesEXT`.
type QueryDevices = unsafe extern "system" fn(egl::Int, *mut *mut c_void, *mut egl::Int) -> u32;
/// `eglQueryDeviceStringEXT`.
type QueryDeviceString = unsafe extern "system" fn(*mut c_void, egl::Int) -> *const c_char;

/// An OpenGL context on Mesa's software EGL device, current on the thread that opened it.
/// Not `Send`: it must be used, and dropped, on that thread.
pub struct SoftwareContext {
    egl: Egl,
    display: egl::Display,
    context: egl::Context,
    _not_send: std::marker::PhantomData<*const ()>,
}

impl SoftwareContext {
    /// Opens the software device's display and makes a context on it current on this
    /// thread. `Err` says why it cannot (no libEGL, no device enumeration, no software
    /// device, no context): the caller then renders some other way.
    pub fn open() -> Result<SoftwareContext, String> {
        // SAFETY: libEGL is Khronos' EGL library (its symbols are checked on loading).
        let egl = unsafe { Egl::load_required() }.map_err(|e| format!("libEGL: {e}"))?;
        let client = egl
            .query_string(None, egl::EXTENSIONS)
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_default();
        for needed in ["EGL_EXT_device_enumeration", "EGL_EXT_platform_device"] {
            if !client.split_whitespace().any(|e| e == needed) {
                return Err(format!("EGL has no {needed}"));
            }
        }
        let function = |name: &str| {
            egl.get_proc_address(name)
                .ok_or_else(|| format!("EGL has no {name}"))
        };
        // SAFETY: the extensions above define these entry points with these signatures.
        let query_devices: QueryDevices =
            unsafe { std::mem::transmute(function("eglQueryDevicesEXT")?) };
        let query_string: QueryDeviceString =
            unsafe { std::mem::transmute(function("eglQueryDeviceStringEXT")?) };
        let mut devices = [std::ptr::null_mut(); 16];
        let mut count = 0;
        // SAFETY: `devices` holds 16 handles; `count` receives how many were written.
        if unsafe { query_devices(devices.len() as egl::Int, devices.as_mut_ptr(), &mut count) }
            == 0
        {
            return Err("EGL could not list its devices".into());
        }
        let software = devices[..count.clamp(0, 16) as usize]
            .iter()
            .copied()
            .find(|&device| {
                // SAFETY: a device handle EGL just returned; the string is EGL's own.
                let extensions = unsafe { query_string(device, egl::EXTENSIONS) };
                !extensions.is_null()
                    && unsafe { CStr::from_ptr(extensions) }
                        .to_string_lossy()
                        .split_whitespace()
                        .any(|e| e == "EGL_MESA_device_software")
            })
            .ok_or("EGL has no software device")?;
        // SAFETY: the platform takes an EGL device handle as its native display.
        let display =
            unsafe { egl.get_platform_display(PLATFORM_DEVICE, software, &[egl::ATTRIB_NONE]) }
                .map_err(|e| format!("the software device's display: {e}"))?;
        egl.initialize(display)
            .map_err(|e| format!("the software device's display: {e}"))?;
        let context = Self::context_on(&egl, display)?;
        Ok(SoftwareContext {
            egl,
            display,
            context,
            _not_send: std::marker::PhantomData,
        })
    }

    /// wgpu's own context on Mesa: desktop OpenGL 3.3, robust access; made current.
    fn context_on(egl: &Egl, display: egl::Display) -> Result<egl::Context, String> {
        let config = egl
            .choose_first_config(
                display,
                // Its configurations are for pixel buffers only (the default asks for windows).
                &[
                    egl::RENDERABLE_TYPE,
                    egl::OPENGL_BIT,
                    egl::SURFACE_TYPE,
                    egl::PBUFFER_BIT,
                    egl::NONE,
                ],
            )
            .map_err(|e| format!("no OpenGL configuration: {e}"))?
            .ok_or("no OpenGL configuration")?;
        egl.bind_api(egl::OPENGL_API)
            .map_err(|e| format!("no OpenGL: {e}"))?;
        let context = egl
            .create_context(
                display,
                config,
                None,
                &[
                    egl::CONTEXT_MAJOR_VERSION,
                    3,
                    egl::CONTEXT_MINOR_VERSION,
                    3,
                    egl::CONTEXT_OPENGL_ROBUST_ACCESS,
                    egl::TRUE as egl::Int,
                    egl::NONE,
                ],
            )
            .map_err(|e| format!("no OpenGL 3.3 context: {e}"))?;
        if let Err(e) = egl.make_current(display, None, None, Some(context)) {
            let _ = egl.destroy_context(display, context);
            return Err(format!("cannot make the context current: {e}"));
        }
        Ok(context)
    }

    /// The GL entry point `name`, for wgpu's loader.
    pub fn proc_address(&self, name: &str) -> *const c_void {
        self.egl
            .get_proc_address(name)
            .map_or(std::ptr::null(), |f| f as *const c_void)
    }
}

impl Drop for SoftwareContext {
    /// Releases and destroys the context. The display stays initialised: EGL gives every
    /// caller the one display of the device, so another context of this process may be on it.
    fn drop(&mut self) {
        let _ = self.egl.make_current(self.display, None, None, None);
        let _ = self.egl.destroy_context(self.display, self.context);
    }
}
