//! The chase vehicle's camera: a pinhole ([`tracker::Camera`] intrinsics, so the tracker's
//! stage 8 and the renderer agree) on a mount that follows the chase chassis, rendered
//! off-screen with wgpu into 256×242 8-bit grey frames with sun shadows and sensor noise.
//!
//! Image convention (shared with the tracker): origin at the top-left corner, **pixel
//! centres at integer coordinates** (pixel (i, j) is centred at x = i, y = j).

mod backend;
mod frame;
mod occlusion;
mod rain_streaks;
mod renderer;
mod rig;
mod sensor;
mod shadow_tiles;
mod software_device;
mod texture_cache;
mod textures;

pub use backend::{Backend, BackendError};
pub use frame::{Field, Frame, FrameInput, GroundTruth};
pub use occlusion::target_occluded;
pub use renderer::{ground_truth_of, DrawStats, RenderError, RenderOptions, Renderer};
pub use rig::{CameraRig, FAR_M, NEAR_M};
pub use sensor::{apply_sensor, blur_reach_px, sensor_noise_sigma_grey, shift_noise};
pub use software_device::SoftwareContext;
pub use textures::{GroundTextures, TextureLayer, LAYERS, TEXTURE_SIZE, TILE_M};
