//! The off-screen renderer. [`Renderer::new`] uploads the scene's geometry once (it never
//! changes); [`Renderer::render`] reads top to bottom like wgpu's `render_to_texture`
//! example: poses and culling, the sun's frustum fitted to the camera's, uniforms, one
//! command encoder with the shadow pass, the main pass and the copy to a staging buffer,
//! one submission, map and read, then the sensor model and the ground truth.
//!
//! On llvmpipe the cost is mostly per rasterised 4×4 block, whether or not it survives the
//! depth test. So the main pass draws front to back (hood, lead, other vehicles, clutter,
//! road, grass last) with back faces culled, scissors away the rows the hood covers, and
//! passes face-constant lighting un-interpolated; the shadow map is 512² by default (1024²
//! cost about 1 ms a frame on clearing alone). llvmpipe runs both sides of a branch,
//! masked, so a pipeline leaves out what its faces never need: the grass's hashes are only
//! in the ground layer's pipelines (the `grass_faces` override), and with soft shadows on
//! the target only the draws that can lie within the board's fine map take the soft-shadow
//! pipelines. A fragment makes one shadow lookup, in the static tiles' slots, which hold the
//! vehicles too (`shadow_tiles`).

use super::backend::{Backend, BackendError};
use super::frame::{Field, Frame, FrameInput, GroundTruth};
use super::rig::CameraRig;
use super::sensor::{apply_sensor_to_rows, blur_reach_px};
use super::shadow_tiles::{self, Cell, SlotWork, Slots, TexelRect, TileFrame};
use super::texture_cache::ground_texels;
use super::textures::{LAYERS, TEXTURE_SIZE, TILE_M};
use crate::scene::{AutoGain, Layer, ObjectSlot, Scene, Vertex, GRASS_ALBEDO_RANGE, GROUND_CELL_M};
use bytemuck::{Pod, Zeroable};
use image::GrayImage;
use nalgebra::{Isometry3, Matrix4, Point3, Translation3, Vector3};
use std::ops::Range;
use std::sync::Arc;
use thiserror::Error;
use tracker::PixelRect;

/// Options that trade quality for speed; none changes the scene.
#[derive(Clone, Debug, PartialEq)]
pub struct RenderOptions {
    /// The wgpu backend (see [`Backend::choose`]).
    pub backend: Backend,
    /// Side of the square shadow map, texels. 512 over the fitted ~60 m frustum gives
    /// ~11 cm texels: a pole's 26 cm shadow is two to three texels wide, and the bilinear
    /// comparison softens edges over about one texel (3–4 px at 10 m, a soft sun edge).
    /// 1024 halves the texel but costs llvmpipe ~1 ms a frame in clearing and filling.
    pub shadow_map_size: u32,
    /// How far from the camera shadows are drawn, metres. The tracker works at 5–30 m;
    /// beyond 60 m a shadow is a few pixels.
    pub shadow_distance_m: f64,
    /// Multisample anti-aliasing: 1 (off) or 4. A real CCD integrates over each pixel;
    /// 4× gets closer to that at some cost in speed.
    pub msaa_samples: u32,
    /// Cached static shadows: the static scenery's shadows come from tiles of the sun's
    /// depth map drawn once and kept (10 cm texels; see `shadow_tiles`), and each frame
    /// draws only the moving vehicles into its own map. Off, every caster is drawn into
    /// each frame's map, as the renderer did before the cache.
    pub cached_shadows: bool,
}

impl Default for RenderOptions {
    /// GL, a 512² shadow map over 60 m, cached static shadows, no MSAA.
    fn default() -> Self {
        RenderOptions {
            backend: Backend::Gl,
            shadow_map_size: 512,
            shadow_distance_m: 60.0,
            msaa_samples: 1,
            cached_shadows: true,
        }
    }
}

/// Why a frame could not be rendered.
#[derive(Debug, Error)]
pub enum RenderError {
    /// The backend could not be opened.
    #[error(transparent)]
    Backend(#[from] BackendError),
    /// The options are out of range.
    #[error("render options: {0}")]
    Options(String),
    /// Reading the frame back failed.
    #[error("reading the frame back from the {backend} device failed: {reason}")]
    Readback {
        /// The backend.
        backend: Backend,
        /// wgpu's message.
        reason: String,
    },
}

/// How far (metres) along the sun's direction casters may stand beyond the receivers the
/// camera sees: taller than any building (20 m) at the lowest sensible sun (15°).
const CASTER_REACH_M: f64 = 80.0;
/// Height range of receivers, metres: nothing stands below the ground or above 25 m.
const RECEIVER_TOP_M: f64 = 25.0;
/// Shadow lookups start this many texels off the surface along its normal, which removes
/// acne without detaching shadows from their casters.
const NORMAL_OFFSET_TEXELS: f64 = 1.5;
/// The board's own shadow map: a second, fine map around the target board, so that shadow
/// edges on the target are as crisp as real ones. Side, texels.
const BOARD_SHADOW_SIZE: u32 = 256;
/// Half the side of the square it covers around the board's centre, metres: 4 m over 256
/// texels is 1.6 cm a texel (half a pixel at 5 m), and holds the 2.3 × 1.7 m board at any
/// sun angle.
const BOARD_SHADOW_HALF_M: f64 = 2.0;
/// How far towards the sun its casters may stand from the board, metres: a building's
/// height at a low sun.
const BOARD_CASTER_REACH_M: f64 = 40.0;
/// How far beyond the board's receivers' box (`BOARD_SHADOW_HALF_M` about its centre) a
/// draw's bounding sphere must stay to be drawn without the board's fine map: the normal
/// offset of its lookup (1.5 of its 1.6 cm texels) and f32 rounding, with room to spare.
const BOARD_RECEIVER_MARGIN_M: f64 = 0.1;
/// The sun's angular diameter, degrees. A shadow's penumbra, seen across its edge, is as
/// wide as the sun's disc seen from the receiver across the distance to the occluder:
/// 2 tan(0.265°) ≈ 0.93 cm for every metre.
const SUN_DIAMETER_DEG: f64 = 0.53;
/// Depth format of both passes.
const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;
/// Colour format: 8-bit grey, what the frame grabber delivers.
const COLOR_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::R8Unorm;

/// Draw-order class of the chase vehicle's hood: drawn first, unscissored.
const HOOD_CLASS: u8 = 0;
/// Draw-order class of the first static layer: below it, the moving objects.
const FIRST_STATIC_CLASS: u8 = 3;

/// The uniform block `Globals` of `scene.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct Globals {
    view_proj: [[f32; 4]; 4],
    light_view_proj: [[f32; 4]; 4],
    sun: [f32; 4],
    params: [f32; 4],
    ground: [f32; 4],
    origin: [f32; 4],
    board_view_proj: [[f32; 4]; 4],
    board: [f32; 4],
    textures: [f32; 4],
    strength: [f32; 4],
    lookup_view_proj: [[f32; 4]; 4],
    lookup_scale: [f32; 4],
    lookup_bounds: [f32; 4],
}

/// The strength of the paint's texture relative to the other materials': paint fills the
/// asphalt's pores, so its grain is faint.
const PAINT_DETAIL: f64 = 0.3;

/// Which pipeline of the main pass draws a piece of geometry.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Shading {
    /// Flat albedo: `fs_main`.
    Plain,
    /// The grass's mottle (the ground layer, untextured): `fs_main` with grass faces.
    PlainGrass,
    /// Perforated canopies: `fs_foliage`, both faces.
    Foliage,
    /// Textured road surfaces: `fs_ground`.
    Ground,
    /// Textured grass: `fs_ground` with grass faces.
    GroundGrass,
}

/// A draw of the main pass: an index range, its pipeline, and whether it may lie within
/// the board's fine shadow map (then the soft-shadow pipelines draw it; see
/// `BOARD_RECEIVER_MARGIN_M`).
type MainDraw = (Range<u32>, Shading, bool);

/// The main pass's pipelines, one for each [`Shading`] the scene uses.
struct ShadedPipelines {
    /// Everything but the ground and the canopies.
    main: wgpu::RenderPipeline,
    /// The grass, when the scene's textures are off.
    grass: Option<wgpu::RenderPipeline>,
    /// The textured road surfaces' and grass's pipelines, when the scene's textures are on.
    ground: Option<[wgpu::RenderPipeline; 2]>,
    foliage: wgpu::RenderPipeline,
}

impl ShadedPipelines {
    /// The pipeline that draws `shading`.
    fn of(&self, shading: Shading) -> &wgpu::RenderPipeline {
        match shading {
            Shading::Plain => &self.main,
            Shading::PlainGrass => self
                .grass
                .as_ref()
                .expect("untextured grass only without the ground's pipelines"),
            Shading::Foliage => &self.foliage,
            Shading::Ground | Shading::GroundGrass => {
                let [road, grass] = self
                    .ground
                    .as_ref()
                    .expect("ground draws only with the ground's pipelines");
                if shading == Shading::Ground {
                    road
                } else {
                    grass
                }
            }
        }
    }
}

/// Renders frames of one scene from the chase camera.
pub struct Renderer {
    /// Shared (read only) with whoever needs the scene while the renderer is busy.
    scene: Arc<Scene>,
    rig: CameraRig,
    options: RenderOptions,
    adapter_name: String,
    /// Whether it renders on a context of the caller's (Mesa's software device) rather than
    /// on wgpu's own display: which renderers it takes turns with (see [`display_lock`]).
    external: bool,
    device: wgpu::Device,
    queue: wgpu::Queue,
    shadow_pipeline: wgpu::RenderPipeline,
    board_shadow_pipeline: wgpu::RenderPipeline,
    /// The main pass's pipelines, with the frame's shadow map and tiles alone.
    pipelines: ShadedPipelines,
    /// With soft shadows on the target: the same with the board's fine map too, for what
    /// can lie within it (see `BOARD_RECEIVER_MARGIN_M`).
    soft_pipelines: Option<ShadedPipelines>,
    foliage_shadow_pipeline: wgpu::RenderPipeline,
    foliage_board_shadow_pipeline: wgpu::RenderPipeline,
    frame_uniforms: Uniforms,
    frame_bind_group: wgpu::BindGroup,
    /// The main pass's textures, its shadow lookups reading the slots' texture of the
    /// static tiles and the vehicles (`shadow_tiles`)...
    shadow_bind_group: wgpu::BindGroup,
    /// ...or the frame's own map, which then holds every caster.
    own_map_bind_group: wgpu::BindGroup,
    vertex_buffer: wgpu::Buffer,
    index_buffer: wgpu::Buffer,
    shadow_view: wgpu::TextureView,
    board_shadow_view: wgpu::TextureView,
    color_texture: wgpu::Texture,
    color_view: wgpu::TextureView,
    msaa_view: Option<wgpu::TextureView>,
    depth_view: wgpu::TextureView,
    /// Sets the main pass's depth back to the cleared depth under the scissor, its colour
    /// left alone (`vs_far`, `fs_far`): instead of clearing the whole depth target.
    main_far_pipeline: wgpu::RenderPipeline,
    staging: wgpu::Buffer,
    padded_row: u32,
    stats: DrawStats,
    /// The scene's grass hash key (see [`Scene::grass_key`]).
    grass_key: u32,
    /// The first image row from which the hood covers every pixel to the bottom, for the
    /// camera straight ahead (the hood moves with the camera, so this changes only when the
    /// camera pans); later draws are scissored above it.
    hood_row: u32,
    /// The same for the last panned angle seen, as (angle's bits, row).
    panned_hood_row: Option<(u64, u32)>,
    /// The static shadow tiles' frame, which tile each slot of their texture holds and
    /// where the vehicles were drawn, the texture as a render target, the uniforms of its
    /// draws (one entry a tile or the vehicles over a tile, picked by dynamic offset), and
    /// its pipelines: `vs_far` (writes the cleared depth wherever it is scissored to),
    /// the casters and the canopies.
    tile_frame: TileFrame,
    slots: Slots,
    slots_view: wgpu::TextureView,
    slot_uniforms: SlotUniforms,
    slot_bind_group: wgpu::BindGroup,
    slot_pipelines: [wgpu::RenderPipeline; 3],
    /// Per-frame scratch lists, kept to avoid allocating every frame.
    items: Vec<DrawItem>,
    /// The indices of the items the main pass's frustum holds.
    seen_items: Vec<usize>,
    main_draws: Vec<MainDraw>,
    shadow_draws: Vec<Range<u32>>,
    board_shadow_draws: Vec<Range<u32>>,
    foliage_shadow_draws: Vec<Range<u32>>,
    foliage_board_shadow_draws: Vec<Range<u32>>,
}

/// What the last frame drew: triangles in each pass after culling.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct DrawStats {
    /// Triangles drawn from the camera.
    pub main_triangles: u32,
    /// Of those, the triangles drawn with soft shadows on the target (the board's fine
    /// map): what can lie within it.
    pub soft_triangles: u32,
    /// Triangles drawn into the shadow map.
    pub shadow_triangles: u32,
    /// Draw calls in both passes.
    pub draw_calls: u32,
    /// Static shadow tiles drawn whole for the frame (their slot held another).
    pub shadow_tiles_drawn: u32,
}

impl Renderer {
    /// Opens the backend, compiles the pipelines and uploads the scene's geometry.
    pub fn new(
        scene: &Scene,
        rig: CameraRig,
        options: &RenderOptions,
    ) -> Result<Renderer, RenderError> {
        Self::open(scene, rig, options, None)
    }

    /// A renderer on an OpenGL context of the caller's that is current on this thread (wgpu's
    /// external adapter; `proc_address` gives its entry points): for a second llvmpipe in
    /// this process on a display of its own (see `software_device`), which renders
    /// alongside renderers on wgpu's display. The renderer must be used and dropped on this
    /// thread, with the context still current. `options.backend` must be GL.
    pub fn on_current_gl(
        scene: &Scene,
        rig: CameraRig,
        options: &RenderOptions,
        proc_address: &dyn Fn(&str) -> *const std::ffi::c_void,
    ) -> Result<Renderer, RenderError> {
        Self::open(scene, rig, options, Some(proc_address))
    }

    fn open(
        scene: &Scene,
        rig: CameraRig,
        options: &RenderOptions,
        external_gl: Option<&dyn Fn(&str) -> *const std::ffi::c_void>,
    ) -> Result<Renderer, RenderError> {
        if ![1, 4].contains(&options.msaa_samples) {
            return Err(RenderError::Options(format!(
                "msaa_samples must be 1 or 4, got {}",
                options.msaa_samples
            )));
        }
        if !(64..=4096).contains(&options.shadow_map_size) {
            return Err(RenderError::Options(format!(
                "shadow_map_size must be 64..=4096, got {}",
                options.shadow_map_size
            )));
        }
        let backend = options.backend;
        if external_gl.is_some() && backend != Backend::Gl {
            return Err(RenderError::Options(format!(
                "an external OpenGL context needs the gl backend, not {backend}"
            )));
        }
        let external = external_gl.is_some();
        let _one_at_a_time = display_lock(external);

        // Instance, adapter and device on exactly the chosen backend.
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

        // Geometry: uploaded once, never changes (moving objects move by their transforms).
        let mesh = scene.mesh();
        let vertex_buffer = buffer_init(
            &device,
            &queue,
            "vertices",
            bytemuck::cast_slice(&mesh.vertices),
            wgpu::BufferUsages::VERTEX,
        );
        let index_buffer = buffer_init(
            &device,
            &queue,
            "indices",
            bytemuck::cast_slice(&mesh.indices),
            wgpu::BufferUsages::INDEX,
        );

        // Uniforms: the per-frame globals and the object transforms, and the same for each
        // of the draws into the static shadow tiles' slots.
        let frame_uniforms = Uniforms::new(&device, "frame uniforms");
        let slot_uniforms = SlotUniforms::new(&device);

        // Textures: the shadow map, the grey target (and its multisampled twin), depth.
        let size = |w, h| wgpu::Extent3d {
            width: w,
            height: h,
            depth_or_array_layers: 1,
        };
        let texture = |label, extent, format, samples, usage| {
            device.create_texture(&wgpu::TextureDescriptor {
                label: Some(label),
                size: extent,
                mip_level_count: 1,
                sample_count: samples,
                dimension: wgpu::TextureDimension::D2,
                format,
                usage,
                view_formats: &[],
            })
        };
        let s = options.shadow_map_size;
        let shadow_texture = texture(
            "shadow map",
            size(s, s),
            DEPTH_FORMAT,
            1,
            wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING,
        );
        let shadow_view = shadow_texture.create_view(&wgpu::TextureViewDescriptor::default());
        let board_shadow_texture = texture(
            "board shadow map",
            size(BOARD_SHADOW_SIZE, BOARD_SHADOW_SIZE),
            DEPTH_FORMAT,
            1,
            wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING,
        );
        let board_shadow_view =
            board_shadow_texture.create_view(&wgpu::TextureViewDescriptor::default());
        // The static shadow tiles' slots (a small stand-in when the cache is off: the
        // layout binds a texture either way).
        let slots_side = if options.cached_shadows {
            shadow_tiles::SLOTS_TEXELS
        } else {
            1
        };
        let slots_view = texture(
            "shadow tiles",
            size(slots_side, slots_side),
            DEPTH_FORMAT,
            1,
            wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING,
        )
        .create_view(&wgpu::TextureViewDescriptor::default());
        let tile_frame = TileFrame::new(
            Light::axes(scene.description().sun.direction()),
            scene.chunks().iter().map(|c| (c.centre, c.radius)),
        );
        let frame_size = size(rig.width, rig.height);
        let color_texture = texture(
            "frame",
            frame_size,
            COLOR_FORMAT,
            1,
            wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
        );
        let color_view = color_texture.create_view(&wgpu::TextureViewDescriptor::default());
        let samples = options.msaa_samples;
        let msaa_view = (samples > 1).then(|| {
            texture(
                "frame msaa",
                frame_size,
                COLOR_FORMAT,
                samples,
                wgpu::TextureUsages::RENDER_ATTACHMENT,
            )
            .create_view(&wgpu::TextureViewDescriptor::default())
        });
        let depth_view = texture(
            "depth",
            frame_size,
            DEPTH_FORMAT,
            samples,
            wgpu::TextureUsages::RENDER_ATTACHMENT,
        )
        .create_view(&wgpu::TextureViewDescriptor::default());

        // Ground textures: generated from the scene's seed (or read from the cache of an
        // earlier run), every mip level uploaded (a 1×1 stand-in when they are off: the
        // layout binds a texture either way).
        let textures = &scene.description().textures;
        let generated = textures
            .enabled
            .then(|| ground_texels(scene.description().seed));
        let (side, levels) = match &generated {
            Some(g) => (TEXTURE_SIZE as u32, g.len() as u32),
            None => (1, 1),
        };
        let ground_texture = device.create_texture(&wgpu::TextureDescriptor {
            label: Some("ground textures"),
            size: wgpu::Extent3d {
                width: side,
                height: side,
                depth_or_array_layers: LAYERS as u32,
            },
            mip_level_count: levels,
            sample_count: 1,
            dimension: wgpu::TextureDimension::D2,
            format: wgpu::TextureFormat::R8Unorm,
            usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
            view_formats: &[],
        });
        for level in 0..levels {
            let s = side >> level;
            let stand_in = [128; LAYERS];
            let texels = match &generated {
                Some(g) => &g[level as usize][..],
                None => &stand_in[..],
            };
            queue.write_texture(
                wgpu::TexelCopyTextureInfo {
                    texture: &ground_texture,
                    mip_level: level,
                    origin: wgpu::Origin3d::ZERO,
                    aspect: wgpu::TextureAspect::All,
                },
                texels,
                wgpu::TexelCopyBufferLayout {
                    offset: 0,
                    bytes_per_row: Some(s),
                    rows_per_image: Some(s),
                },
                wgpu::Extent3d {
                    width: s,
                    height: s,
                    depth_or_array_layers: LAYERS as u32,
                },
            );
        }
        let ground_view = ground_texture.create_view(&wgpu::TextureViewDescriptor {
            dimension: Some(wgpu::TextureViewDimension::D2Array),
            ..Default::default()
        });
        // Trilinear, tiling.
        let ground_sampler = device.create_sampler(&wgpu::SamplerDescriptor {
            label: Some("ground textures"),
            address_mode_u: wgpu::AddressMode::Repeat,
            address_mode_v: wgpu::AddressMode::Repeat,
            mag_filter: wgpu::FilterMode::Linear,
            min_filter: wgpu::FilterMode::Linear,
            mipmap_filter: wgpu::MipmapFilterMode::Linear,
            ..Default::default()
        });

        // Readback buffer: rows padded to wgpu's 256-byte copy alignment.
        let padded_row = rig.width.div_ceil(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT)
            * wgpu::COPY_BYTES_PER_ROW_ALIGNMENT;
        let staging = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("staging"),
            size: u64::from(padded_row) * u64::from(rig.height),
            usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
            mapped_at_creation: false,
        });

        // Bind groups: per-frame uniforms (both passes), the shadow map (main pass only).
        let uniform_entry = |binding, has_dynamic_offset| wgpu::BindGroupLayoutEntry {
            binding,
            visibility: wgpu::ShaderStages::VERTEX_FRAGMENT,
            ty: wgpu::BindingType::Buffer {
                ty: wgpu::BufferBindingType::Uniform,
                has_dynamic_offset,
                min_binding_size: None,
            },
            count: None,
        };
        let frame_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("frame"),
            entries: &[uniform_entry(0, false), uniform_entry(1, false)],
        });
        let shadow_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("shadow"),
            entries: &[
                wgpu::BindGroupLayoutEntry {
                    binding: 0,
                    visibility: wgpu::ShaderStages::FRAGMENT,
                    ty: wgpu::BindingType::Texture {
                        sample_type: wgpu::TextureSampleType::Depth,
                        view_dimension: wgpu::TextureViewDimension::D2,
                        multisampled: false,
                    },
                    count: None,
                },
                wgpu::BindGroupLayoutEntry {
                    binding: 1,
                    visibility: wgpu::ShaderStages::FRAGMENT,
                    ty: wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Comparison),
                    count: None,
                },
                wgpu::BindGroupLayoutEntry {
                    binding: 2,
                    visibility: wgpu::ShaderStages::FRAGMENT,
                    ty: wgpu::BindingType::Texture {
                        sample_type: wgpu::TextureSampleType::Depth,
                        view_dimension: wgpu::TextureViewDimension::D2,
                        multisampled: false,
                    },
                    count: None,
                },
                wgpu::BindGroupLayoutEntry {
                    binding: 3,
                    visibility: wgpu::ShaderStages::FRAGMENT,
                    ty: wgpu::BindingType::Texture {
                        sample_type: wgpu::TextureSampleType::Float { filterable: true },
                        view_dimension: wgpu::TextureViewDimension::D2Array,
                        multisampled: false,
                    },
                    count: None,
                },
                wgpu::BindGroupLayoutEntry {
                    binding: 4,
                    visibility: wgpu::ShaderStages::FRAGMENT,
                    ty: wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Filtering),
                    count: None,
                },
                wgpu::BindGroupLayoutEntry {
                    binding: 5,
                    visibility: wgpu::ShaderStages::FRAGMENT,
                    ty: wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Comparison),
                    count: None,
                },
            ],
        });
        // A bilinear comparison sampler (a 2 × 2-texel percentage-closer filter).
        let comparison_sampler = |label, address_mode| {
            device.create_sampler(&wgpu::SamplerDescriptor {
                label: Some(label),
                address_mode_u: address_mode,
                address_mode_v: address_mode,
                mag_filter: wgpu::FilterMode::Linear,
                min_filter: wgpu::FilterMode::Linear,
                compare: Some(wgpu::CompareFunction::LessEqual),
                ..Default::default()
            })
        };
        let shadow_sampler = comparison_sampler("shadow", wgpu::AddressMode::ClampToEdge);
        // The slots' texture wraps around (see `shadow_tiles`).
        let slots_sampler = comparison_sampler("shadow tiles", wgpu::AddressMode::Repeat);
        let uniforms_group = |label, uniforms: &Uniforms| {
            device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some(label),
                layout: &frame_layout,
                entries: &[
                    wgpu::BindGroupEntry {
                        binding: 0,
                        resource: uniforms.globals(),
                    },
                    wgpu::BindGroupEntry {
                        binding: 1,
                        resource: uniforms.objects(),
                    },
                ],
            })
        };
        let frame_bind_group = uniforms_group("frame", &frame_uniforms);
        // The draws into the slots: the same uniforms, an entry a draw.
        let slot_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("slot"),
            entries: &[uniform_entry(0, true), uniform_entry(1, true)],
        });
        let slot_bind_group = device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("slot"),
            layout: &slot_layout,
            entries: &[
                wgpu::BindGroupEntry {
                    binding: 0,
                    resource: slot_uniforms.0.globals(),
                },
                wgpu::BindGroupEntry {
                    binding: 1,
                    resource: slot_uniforms.0.objects(),
                },
            ],
        });
        let lookup_group = |label, view, sampler| {
            device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some(label),
                layout: &shadow_layout,
                entries: &[
                    wgpu::BindGroupEntry {
                        binding: 0,
                        resource: wgpu::BindingResource::TextureView(view),
                    },
                    wgpu::BindGroupEntry {
                        binding: 1,
                        resource: wgpu::BindingResource::Sampler(sampler),
                    },
                    wgpu::BindGroupEntry {
                        binding: 2,
                        resource: wgpu::BindingResource::TextureView(&board_shadow_view),
                    },
                    wgpu::BindGroupEntry {
                        binding: 3,
                        resource: wgpu::BindingResource::TextureView(&ground_view),
                    },
                    wgpu::BindGroupEntry {
                        binding: 4,
                        resource: wgpu::BindingResource::Sampler(&ground_sampler),
                    },
                    wgpu::BindGroupEntry {
                        binding: 5,
                        resource: wgpu::BindingResource::Sampler(&shadow_sampler),
                    },
                ],
            })
        };
        let shadow_bind_group = lookup_group("shadow tiles", &slots_view, &slots_sampler);
        let own_map_bind_group = lookup_group("shadow map", &shadow_view, &shadow_sampler);

        // Pipelines: depth-only from the sun; shaded grey from the camera.
        let shader = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("scene.wgsl"),
            source: wgpu::ShaderSource::Wgsl(include_str!("scene.wgsl").into()),
        });
        let vertex_layout = wgpu::VertexBufferLayout {
            array_stride: std::mem::size_of::<Vertex>() as u64,
            step_mode: wgpu::VertexStepMode::Vertex,
            attributes: &wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x3, 2 => Float32, 3 => Uint32],
        };
        let shadow_pipeline_layout =
            device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some("shadow"),
                bind_group_layouts: &[Some(&frame_layout)],
                immediate_size: 0,
            });
        let slot_pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("slot"),
            bind_group_layouts: &[Some(&slot_layout)],
            immediate_size: 0,
        });
        let main_pipeline_layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("main"),
            bind_group_layouts: &[Some(&frame_layout), Some(&shadow_layout)],
            immediate_size: 0,
        });
        // Depth only, from the sun: the main shadow map (`vs_shadow`) and the board's
        // (`vs_board_shadow`); canopies with a fragment stage that discards their holes.
        let depth_only_pipeline =
            |label: &str, layout: &wgpu::PipelineLayout, entry: &str, fragment: Option<&str>| {
                device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                    label: Some(label),
                    layout: Some(layout),
                    vertex: wgpu::VertexState {
                        module: &shader,
                        entry_point: Some(entry),
                        compilation_options: Default::default(),
                        buffers: &[Some(vertex_layout.clone())],
                    },
                    // Every closed mesh is wound counter-clockwise seen from outside
                    // (`Mesh::orient_faces`), open ones are two-sided: back faces never show.
                    // A canopy's clumps cast from their sunlit side alone (as the outer leaves
                    // of a real clump do most of its shading).
                    primitive: wgpu::PrimitiveState {
                        cull_mode: Some(wgpu::Face::Back),
                        ..Default::default()
                    },
                    depth_stencil: Some(wgpu::DepthStencilState {
                        format: DEPTH_FORMAT,
                        depth_write_enabled: Some(true),
                        depth_compare: Some(wgpu::CompareFunction::LessEqual),
                        stencil: wgpu::StencilState::default(),
                        // A little slope-scaled bias on top of the normal offset, for grazing light.
                        bias: wgpu::DepthBiasState {
                            constant: 2,
                            slope_scale: 1.5,
                            clamp: 0.0,
                        },
                    }),
                    multisample: wgpu::MultisampleState::default(),
                    fragment: fragment.map(|entry| wgpu::FragmentState {
                        module: &shader,
                        entry_point: Some(entry),
                        compilation_options: Default::default(),
                        targets: &[],
                    }),
                    multiview_mask: None,
                    cache: None,
                })
            };
        let shadow = &shadow_pipeline_layout;
        let shadow_pipeline = depth_only_pipeline("shadow", shadow, "vs_shadow", None);
        let board_shadow_pipeline =
            depth_only_pipeline("board shadow", shadow, "vs_board_shadow", None);
        let foliage_shadow_pipeline = depth_only_pipeline(
            "foliage shadow",
            shadow,
            "vs_foliage_shadow",
            Some("fs_foliage_shadow"),
        );
        let foliage_board_shadow_pipeline = depth_only_pipeline(
            "foliage board shadow",
            shadow,
            "vs_foliage_board_shadow",
            Some("fs_foliage_shadow"),
        );
        // Writes the cleared depth (1) wherever it is scissored to, whatever was there (the
        // main pass's depth set back under the scissor, a slot's vehicles' texels set back).
        let far_pipeline = |label,
                            layout: &wgpu::PipelineLayout,
                            multisample,
                            fragment: Option<wgpu::FragmentState>| {
            device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                label: Some(label),
                layout: Some(layout),
                vertex: wgpu::VertexState {
                    module: &shader,
                    entry_point: Some("vs_far"),
                    compilation_options: Default::default(),
                    buffers: &[],
                },
                primitive: wgpu::PrimitiveState::default(),
                depth_stencil: Some(wgpu::DepthStencilState {
                    format: DEPTH_FORMAT,
                    depth_write_enabled: Some(true),
                    depth_compare: Some(wgpu::CompareFunction::Always),
                    stencil: wgpu::StencilState::default(),
                    bias: wgpu::DepthBiasState::default(),
                }),
                multisample,
                fragment,
                multiview_mask: None,
                cache: None,
            })
        };
        let main_far_pipeline = far_pipeline(
            "main far",
            &main_pipeline_layout,
            wgpu::MultisampleState {
                count: samples,
                ..Default::default()
            },
            Some(wgpu::FragmentState {
                module: &shader,
                entry_point: Some("fs_far"),
                compilation_options: Default::default(),
                targets: &[Some(wgpu::ColorTargetState {
                    format: COLOR_FORMAT,
                    blend: None,
                    write_mask: wgpu::ColorWrites::empty(),
                })],
            }),
        );
        let far = far_pipeline(
            "far",
            &slot_pipeline_layout,
            wgpu::MultisampleState::default(),
            None,
        );
        let slot = &slot_pipeline_layout;
        let slot_pipelines = [
            far,
            depth_only_pipeline("tile shadow", slot, "vs_shadow", None),
            depth_only_pipeline(
                "tile foliage shadow",
                slot,
                "vs_foliage_shadow",
                Some("fs_foliage_shadow"),
            ),
        ];
        // `grass`: whether it draws grass faces (the `grass_faces` override); `soft`:
        // whether it takes soft shadows on the target from the board's fine map and the
        // sun's disc (the fragment shader's `_soft` entry).
        let shaded_pipeline =
            |label: &str, vertex: &str, fragment: &str, cull, grass: bool, soft: bool| {
                let constants = [("grass_faces", f64::from(u8::from(grass)))];
                device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                    label: Some(label),
                    layout: Some(&main_pipeline_layout),
                    vertex: wgpu::VertexState {
                        module: &shader,
                        entry_point: Some(vertex),
                        compilation_options: Default::default(),
                        buffers: &[Some(vertex_layout.clone())],
                    },
                    // Every closed mesh is wound counter-clockwise seen from outside
                    // (`Mesh::orient_faces`), open ones are two-sided: back faces never show
                    // (canopies' do, through their holes).
                    primitive: wgpu::PrimitiveState {
                        cull_mode: cull,
                        ..Default::default()
                    },
                    depth_stencil: Some(wgpu::DepthStencilState {
                        format: DEPTH_FORMAT,
                        depth_write_enabled: Some(true),
                        depth_compare: Some(wgpu::CompareFunction::Less),
                        stencil: wgpu::StencilState::default(),
                        bias: wgpu::DepthBiasState::default(),
                    }),
                    multisample: wgpu::MultisampleState {
                        count: samples,
                        ..Default::default()
                    },
                    fragment: Some(wgpu::FragmentState {
                        module: &shader,
                        entry_point: Some(&if soft {
                            format!("{fragment}_soft")
                        } else {
                            fragment.to_string()
                        }),
                        compilation_options: wgpu::PipelineCompilationOptions {
                            constants: &constants,
                            ..Default::default()
                        },
                        targets: &[Some(wgpu::ColorTargetState {
                            format: COLOR_FORMAT,
                            blend: None,
                            write_mask: wgpu::ColorWrites::ALL,
                        })],
                    }),
                    multiview_mask: None,
                    cache: None,
                })
            };
        let back = Some(wgpu::Face::Back);
        let shaded_pipelines = |soft: bool| ShadedPipelines {
            main: shaded_pipeline("main", "vs_main", "fs_main", back, false, soft),
            grass: (!textures.enabled)
                .then(|| shaded_pipeline("grass", "vs_main", "fs_main", back, true, soft)),
            ground: textures.enabled.then(|| {
                [false, true].map(|grass| {
                    shaded_pipeline("ground", "vs_ground", "fs_ground", back, grass, soft)
                })
            }),
            foliage: shaded_pipeline("foliage", "vs_foliage", "fs_foliage", None, false, soft),
        };
        let pipelines = shaded_pipelines(false);
        // Soft shadows on the target: the board's fine map and the sun's disc.
        let soft_pipelines = scene
            .description()
            .sun
            .soft_shadows
            .then(|| shaded_pipelines(true));

        let hood_row = hood_row(&rig, &scene.description().chase, 0.0);
        Ok(Renderer {
            scene: Arc::new(scene.clone()),
            rig,
            options: options.clone(),
            adapter_name,
            external,
            device,
            queue,
            shadow_pipeline,
            board_shadow_pipeline,
            pipelines,
            soft_pipelines,
            foliage_shadow_pipeline,
            foliage_board_shadow_pipeline,
            frame_uniforms,
            frame_bind_group,
            shadow_bind_group,
            own_map_bind_group,
            vertex_buffer,
            index_buffer,
            shadow_view,
            board_shadow_view,
            color_texture,
            color_view,
            msaa_view,
            depth_view,
            main_far_pipeline,
            staging,
            padded_row,
            stats: DrawStats::default(),
            grass_key: scene.grass_key(),
            hood_row,
            panned_hood_row: None,
            tile_frame,
            slots: Slots::default(),
            slots_view,
            slot_uniforms,
            slot_bind_group,
            slot_pipelines,
            items: Vec::new(),
            seen_items: Vec::new(),
            main_draws: Vec::new(),
            shadow_draws: Vec::new(),
            board_shadow_draws: Vec::new(),
            foliage_shadow_draws: Vec::new(),
            foliage_board_shadow_draws: Vec::new(),
        })
    }

    /// The adapter in use, e.g. `llvmpipe (LLVM 15.0.6, 256 bits) (Gl)`.
    pub fn adapter_name(&self) -> &str {
        &self.adapter_name
    }

    /// What the last frame drew.
    pub fn stats(&self) -> DrawStats {
        self.stats
    }

    /// The camera rig.
    pub fn rig(&self) -> &CameraRig {
        &self.rig
    }

    /// The scene.
    pub fn scene(&self) -> &Scene {
        &self.scene
    }

    /// The scene, to keep while the renderer is away (on a thread of its own).
    pub fn shared_scene(&self) -> Arc<Scene> {
        Arc::clone(&self.scene)
    }

    /// Renders one frame and reads it back.
    pub fn render(&mut self, input: &FrameInput) -> Result<Frame, RenderError> {
        self.render_part(input, None)
    }

    /// Renders the part of one frame the tracker will read (`needed`; the whole frame when
    /// `None`) and reads it back. The colour pass is scissored to `needed` grown by the
    /// sensor blur's reach, so each pixel of `needed` (the frame's [`Frame::exact`], with
    /// the automatic gain control's metering window when it is on) is bit for bit what
    /// [`Renderer::render`] gives; everything else (shadows, the sensor
    /// noise, the ground truth) is the whole frame's, and the pixels outside are unspecified.
    pub fn render_part(
        &mut self,
        input: &FrameInput,
        needed: Option<PixelRect>,
    ) -> Result<Frame, RenderError> {
        let _one_at_a_time = display_lock(self.external);
        self.render_part_locked(input, needed)
    }

    /// [`Renderer::render_part`], with [`display_lock`] held.
    fn render_part_locked(
        &mut self,
        input: &FrameInput,
        needed: Option<PixelRect>,
    ) -> Result<Frame, RenderError> {
        let description = self.scene.description();
        let whole = PixelRect::whole(self.rig.width as usize, self.rig.height as usize);
        // With automatic gain control, its metering window is always exact too.
        let exact = match (needed, description.sensor.auto_gain) {
            (None, _) => whole,
            (Some(r), None) => r.intersection(&whole),
            (Some(r), Some(_)) => r
                .union(&AutoGain::metering_window(whole.x1, whole.y1))
                .intersection(&whole),
        };
        let scissor = exact.grown(blur_reach_px(&description.sensor), whole.x1, whole.y1);
        let mut image = self.draw_field(&input.field(), input.auto_gain, scissor)?;
        if let Some(earlier) = &input.earlier_field {
            // An interlaced camera: the odd rows are the earlier field's.
            let other = self.draw_field(earlier, input.auto_gain, scissor)?;
            interlace(&mut image, &other);
        }

        // The sensor: blur and noise, seeded per frame.
        let description = self.scene.description();
        // The read noise only on the rows drawn (the only ones read back).
        apply_sensor_to_rows(
            &mut image,
            &description.sensor,
            &self.rig.intrinsics,
            description.seed,
            input.frame_index,
            scissor.y0..scissor.y1,
        );

        let truth = self.ground_truth(
            &input.world_from_chase,
            &input.world_from_lead,
            input.camera_pan_rad,
        );
        Ok(Frame {
            image,
            truth,
            exact,
        })
    }

    /// Draws the scene as it stands in `field`, with the automatic gain `auto_gain`, in the
    /// pixels `scissor` of the frame, and reads back the rows `scissor` spans (the other
    /// rows are zero, and the pixels of those rows outside `scissor` the sky's grey).
    fn draw_field(
        &mut self,
        field: &Field,
        auto_gain: f64,
        scissor: PixelRect,
    ) -> Result<GrayImage, RenderError> {
        let hood_rows = self.hood_rows(field.camera_pan_rad);
        let rig = &self.rig;
        let description = self.scene.description();
        let whole = PixelRect::whole(rig.width as usize, rig.height as usize);

        // Poses: the camera from the chase chassis; every moving object's transform.
        let world_from_camera =
            rig.world_from_camera_panned(&field.world_from_chase, field.camera_pan_rad);
        let camera_from_world = world_from_camera.inverse();
        // Positions reach the GPU relative to the camera (the origin), with every transform
        // composed in f64: in f32, world coordinates kilometres from the world's origin
        // lose millimetres, enough for the board to show through paint standing 3 mm proud
        // of it.
        let eye = world_from_camera.translation.vector;
        let world_from_relative = Translation3::from(eye).to_homogeneous();
        let relative_from_world = Translation3::from(-eye).to_homogeneous();
        let view_proj =
            rig.clip_from_camera() * camera_from_world.to_homogeneous() * world_from_relative;
        let mut world_from_object = [[[0f32; 4]; 4]; ObjectSlot::COUNT as usize];
        world_from_object[ObjectSlot::WORLD as usize] = to_f32(&relative_from_world);
        let mut items = std::mem::take(&mut self.items);
        items.clear();
        let mut board_centre = None;
        for object in self.scene.objects() {
            // Off the route: the zero matrix collapses it to nothing.
            if let Some(pose) = self.scene.world_from_object(
                object,
                &field.world_from_chase,
                &field.world_from_lead,
                field.time_s,
            ) {
                world_from_object[object.slot as usize] =
                    to_f32(&(relative_from_world * pose.to_homogeneous()));
                if object.slot == ObjectSlot::LEAD {
                    board_centre = Some(pose * self.scene.lead_from_target() * Point3::origin());
                }
                let c = pose * Point3::from(object.centre);
                // The hood hides the bottom of the frame and the lead the middle: drawn
                // first, they let depth testing reject what lies behind them unshaded.
                let class = match object.slot {
                    ObjectSlot::CHASE => HOOD_CLASS,
                    ObjectSlot::LEAD => 1,
                    _ => 2,
                };
                items.push(DrawItem {
                    indices: object.indices.clone(),
                    centre: [c.x, c.y, c.z],
                    radius: object.radius,
                    casts_shadow: object.casts_shadow,
                    class,
                    distance_m: (c.coords - eye).norm(),
                    shading: Shading::Plain,
                    chunk: None,
                });
            }
        }
        let textured = self.pipelines.ground.is_some();
        for (index, chunk) in self.scene.chunks().iter().enumerate() {
            items.push(DrawItem {
                chunk: Some(index),
                indices: chunk.indices.clone(),
                centre: chunk.centre,
                radius: chunk.radius,
                casts_shadow: chunk.casts_shadow,
                class: FIRST_STATIC_CLASS + chunk.layer as u8,
                distance_m: (Vector3::from(chunk.centre) - eye).norm(),
                // Only the ground layer has grass faces (`Scene`'s invariant): the other
                // pipelines leave the grass's hashes out.
                shading: match (chunk.layer, textured) {
                    (Layer::Foliage, _) => Shading::Foliage,
                    (Layer::Surface, true) => Shading::Ground,
                    (Layer::Ground, true) => Shading::GroundGrass,
                    (Layer::Ground, false) => Shading::PlainGrass,
                    _ => Shading::Plain,
                },
            });
        }

        // With soft shadows on the target, only what can lie within the board's fine map
        // takes the soft-shadow pipelines: the rest would run the board's lookups for
        // nothing (llvmpipe runs both sides of a branch).
        let sun = &description.sun;
        let board_receivers = board_centre.filter(|_| sun.soft_shadows).map(|c| {
            Light::around(
                c.coords,
                sun.direction(),
                BOARD_SHADOW_HALF_M,
                BOARD_SHADOW_HALF_M,
                BOARD_SHADOW_SIZE,
            )
        });
        let soft = |centre: [f64; 3], radius: f64| {
            board_receivers
                .as_ref()
                .is_some_and(|l| l.holds(centre, radius + BOARD_RECEIVER_MARGIN_M))
        };

        // Main pass: what the camera's frustum holds, front to back (by class, then by
        // distance), so early depth testing rejects hidden fragments before shading them.
        let frustum = Frustum::of_part(rig, &camera_from_world, scissor);
        let mut main_draws = std::mem::take(&mut self.main_draws);
        main_draws.clear();
        // Only what the frustum holds is sorted (a tenth of the items, typically); the
        // sort is stable, so the order is the whole list's, sorted and then filtered.
        let mut in_view = std::mem::take(&mut self.seen_items);
        in_view.clear();
        in_view
            .extend((0..items.len()).filter(|&i| frustum.sees(items[i].centre, items[i].radius)));
        in_view.sort_by(|&a, &b| {
            let (a, b) = (&items[a], &items[b]);
            (a.class, a.distance_m)
                .partial_cmp(&(b.class, b.distance_m))
                .expect("finite distances")
        });
        let mut hood_draws = 0;
        let chunks = self.scene.chunks();
        for item in in_view.iter().map(|&i| &items[i]) {
            if item.class == HOOD_CLASS {
                main_draws.push((
                    item.indices.clone(),
                    item.shading,
                    soft(item.centre, item.radius),
                ));
                hood_draws = main_draws.len();
                continue;
            }
            // A chunk's parts that the frustum holds, in order (the whole of the chunk's
            // range when it holds them all); an object's whole range.
            let parts = item.chunk.map_or(&[][..], |c| &chunks[c].parts[..]);
            let whole = std::iter::once((item.indices.clone(), item.centre, item.radius))
                .filter(|_| parts.is_empty());
            let visible = parts
                .iter()
                .filter(|p| frustum.sees(p.centre, p.radius))
                .map(|p| (p.indices.clone(), p.centre, p.radius));
            for (range, centre, radius) in whole.chain(visible) {
                let draw = (range, item.shading, soft(centre, radius));
                if main_draws.len() == hood_draws {
                    // Never joined to the hood's draw: what follows is scissored.
                    main_draws.push(draw);
                    continue;
                }
                // Joined to the last draw when they touch and share a pipeline.
                match main_draws.last_mut() {
                    Some((last, shading, soft))
                        if last.end == draw.0.start && (*shading, *soft) == (draw.1, draw.2) =>
                    {
                        last.end = draw.0.end
                    }
                    _ => main_draws.push(draw),
                }
            }
        }

        // The sun's frustum, fitted to the part of the camera's frustum within the shadow
        // distance; casters culled against it. Order does not matter here (depth only), so
        // ranges are sorted and joined into as few draws as possible.
        let light = Light::fit(
            rig,
            &world_from_camera,
            sun.direction(),
            self.options.shadow_distance_m,
            self.options.shadow_map_size,
        );
        // Static shadows from the cached tiles under the fitted map, and the vehicles drawn
        // into them (see `shadow_tiles`); else every caster into the frame's own map.
        let window = if self.options.cached_shadows {
            shadow_tiles::window([light.min[0], light.min[1]], [light.max[0], light.max[1]])
        } else {
            None
        };
        let with_static = window.is_none();
        let mut shadow_draws = std::mem::take(&mut self.shadow_draws);
        let mut foliage_shadow_draws = std::mem::take(&mut self.foliage_shadow_draws);
        // Only the texels the part of the frame asked for can sample: of the frame's map,
        // or of the window's square of tiles (`window_light`).
        let window_light = window.as_ref().map(|w| {
            let (min, max) = self.tile_frame.window_box(w.corner);
            Light::of_box(self.tile_frame.axes, min, max, shadow_tiles::SLOTS_TEXELS)
        });
        let (lookup, size) = match &window_light {
            Some(l) => (l, shadow_tiles::SLOTS_TEXELS),
            None => (&light, self.options.shadow_map_size),
        };
        let seen = if scissor == whole {
            PixelRect::whole(size as usize, size as usize)
        } else {
            lookup.texels_seen(rig, &world_from_camera, scissor, size)
        };
        let texels = Some((seen, size));
        caster_draws(
            &items,
            lookup,
            texels,
            false,
            with_static,
            &mut shadow_draws,
        );
        caster_draws(
            &items,
            lookup,
            texels,
            true,
            with_static,
            &mut foliage_shadow_draws,
        );
        let slot_work = match (&window, &window_light) {
            (Some(w), Some(l)) => {
                // Each moving caster's texels, as far as the fitted map reaches (the static
                // tiles reach further; the vehicles' shadows, as far as they always did).
                let rects: Vec<TexelRect> = items
                    .iter()
                    .filter(|d| {
                        d.moving_caster()
                            && light.holds(d.centre, d.radius)
                            && l.holds(d.centre, d.radius)
                    })
                    .map(|d| {
                        let one = l.caster_texels(d, size).intersection(&seen);
                        TexelRect::of_window_texels(w.corner, one)
                    })
                    .filter(|r| !r.is_empty())
                    .collect();
                self.slots.frame(w, &rects)
            }
            _ => SlotWork::default(),
        };
        // The board's shadow map: a fine one around the target board, with its casters.
        let board_light = board_centre.filter(|_| sun.soft_shadows).map(|c| {
            Light::around(
                c.coords,
                sun.direction(),
                BOARD_SHADOW_HALF_M,
                BOARD_CASTER_REACH_M,
                BOARD_SHADOW_SIZE,
            )
        });
        let mut board_shadow_draws = std::mem::take(&mut self.board_shadow_draws);
        let mut foliage_board_shadow_draws = std::mem::take(&mut self.foliage_board_shadow_draws);
        board_shadow_draws.clear();
        foliage_board_shadow_draws.clear();
        if let Some(light) = &board_light {
            caster_draws(&items, light, None, false, true, &mut board_shadow_draws);
            caster_draws(
                &items,
                light,
                None,
                true,
                true,
                &mut foliage_board_shadow_draws,
            );
        }
        self.items = items;
        self.seen_items = in_view;

        let triangles =
            |draws: &[Range<u32>]| -> u32 { draws.iter().map(|r| (r.end - r.start) / 3).sum() };
        let mut stats = DrawStats {
            main_triangles: main_draws.iter().map(|(r, ..)| (r.end - r.start) / 3).sum(),
            soft_triangles: main_draws
                .iter()
                .filter(|(_, _, soft)| *soft)
                .map(|(r, ..)| (r.end - r.start) / 3)
                .sum(),
            shadow_triangles: triangles(&shadow_draws) + triangles(&foliage_shadow_draws),
            draw_calls: (main_draws.len() + shadow_draws.len() + foliage_shadow_draws.len()) as u32,
            shadow_tiles_drawn: slot_work.tiles.len() as u32,
        };

        // Uniforms. A fragment looks its sunlight up in the slots' texture (texture
        // coordinates straight from the lookup) or in the frame's own map (from its clip
        // space, as the shadow pass drew it).
        let own_map = light.clip_from_world * world_from_relative;
        let (lookup_view_proj, lookup_scale, lookup_bounds) = match &window {
            Some(w) => {
                let (m, bounds) = w.slots_lookup(&self.tile_frame.lookup(w.corner, &eye));
                (to_f32(&m), [1.0, 1.0, 0.0, 0.0], bounds.map(|b| b as f32))
            }
            None => (
                to_f32(&own_map),
                [0.5, -0.5, 0.5, 0.5],
                [0.0, 0.0, 1.0, 1.0],
            ),
        };
        let brightness = description.sensor.brightness() * auto_gain;
        let globals = Globals {
            view_proj: to_f32(&view_proj),
            light_view_proj: to_f32(&own_map),
            sun: [
                sun.direction()[0] as f32,
                sun.direction()[1] as f32,
                sun.direction()[2] as f32,
                sun.strength as f32,
            ],
            params: [
                sun.ambient as f32,
                brightness as f32,
                (NORMAL_OFFSET_TEXELS * lookup.texel_m) as f32,
                1.0 / self.options.shadow_map_size as f32,
            ],
            ground: self.ground_params(),
            origin: [eye.x as f32, eye.y as f32, eye.z as f32, 0.0],
            board_view_proj: board_light.as_ref().map_or([[0.0; 4]; 4], |l| {
                to_f32(&(l.clip_from_world * world_from_relative))
            }),
            board: match &board_light {
                Some(l) => {
                    let depth_m = l.max[2] - l.min[2];
                    [
                        depth_m as f32,
                        (2.0 * (0.5 * SUN_DIAMETER_DEG).to_radians().tan()) as f32,
                        l.texel_m as f32,
                        // Receivers from 2 m in front of the board's centre (towards the
                        // sun) use this map; the rest, the main one.
                        ((BOARD_CASTER_REACH_M - BOARD_SHADOW_HALF_M) / depth_m) as f32,
                    ]
                }
                // No lead in the scene: no receiver uses the board's map.
                None => [1.0, 0.0, 1.0, 2.0],
            },
            textures: [
                (1.0 / TILE_M[0]) as f32,
                (1.0 / TILE_M[1]) as f32,
                (1.0 / TILE_M[2]) as f32,
                0.0,
            ],
            strength: {
                let c = description.textures.contrast;
                [c as f32, c as f32, c as f32, (c * PAINT_DETAIL) as f32]
            },
            lookup_view_proj,
            lookup_scale,
            lookup_bounds,
        };
        self.frame_uniforms
            .write(&self.queue, &globals, &world_from_object);

        // One encoder: shadow pass, main pass, copy to the staging buffer.
        let mut encoder = self
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("frame"),
            });
        if window.is_some() {
            stats.shadow_triangles = self.encode_slots(
                &mut encoder,
                &slot_work,
                [&shadow_draws, &foliage_shadow_draws],
                &world_from_object,
                &eye,
            );
        } else {
            let mut pass = depth_pass(
                &mut encoder,
                "shadow",
                &self.shadow_view,
                wgpu::LoadOp::Clear(1.0),
            );
            pass.set_bind_group(0, &self.frame_bind_group, &[]);
            pass.set_pipeline(&self.shadow_pipeline);
            pass.set_vertex_buffer(0, self.vertex_buffer.slice(..));
            pass.set_index_buffer(self.index_buffer.slice(..), wgpu::IndexFormat::Uint32);
            if !seen.is_empty() {
                pass.set_scissor_rect(
                    seen.x0 as u32,
                    seen.y0 as u32,
                    seen.width() as u32,
                    seen.height() as u32,
                );
                for range in &shadow_draws {
                    pass.draw_indexed(range.clone(), 0, 0..1);
                }
                if !foliage_shadow_draws.is_empty() {
                    pass.set_pipeline(&self.foliage_shadow_pipeline);
                    for range in &foliage_shadow_draws {
                        pass.draw_indexed(range.clone(), 0, 0..1);
                    }
                }
            }
        }
        self.stats = stats;
        // The board's pass only with soft shadows: without them nothing samples its map.
        if board_light.is_some() {
            let mut pass = depth_pass(
                &mut encoder,
                "board shadow",
                &self.board_shadow_view,
                wgpu::LoadOp::Clear(1.0),
            );
            pass.set_pipeline(&self.board_shadow_pipeline);
            pass.set_bind_group(0, &self.frame_bind_group, &[]);
            pass.set_vertex_buffer(0, self.vertex_buffer.slice(..));
            pass.set_index_buffer(self.index_buffer.slice(..), wgpu::IndexFormat::Uint32);
            for range in &board_shadow_draws {
                pass.draw_indexed(range.clone(), 0, 0..1);
            }
            if !foliage_board_shadow_draws.is_empty() {
                pass.set_pipeline(&self.foliage_board_shadow_pipeline);
                for range in &foliage_board_shadow_draws {
                    pass.draw_indexed(range.clone(), 0, 0..1);
                }
            }
        }
        {
            let sky = (sun.sky * brightness).clamp(0.0, 1.0);
            let (view, resolve_target) = match &self.msaa_view {
                Some(msaa) => (msaa, Some(&self.color_view)),
                None => (&self.color_view, None),
            };
            // The colour is cleared whole (drawing the sky under the scissor instead shades
            // every pixel of the part, which costs more than the clear saves); the depth is
            // set back under the scissor alone, by the first draw (llvmpipe's whole-target
            // clear is a fill of every 64² tile), and stored, since a discarded target would
            // be cleared whole again before it is next loaded.
            let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
                label: Some("main"),
                color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                    view,
                    depth_slice: None,
                    resolve_target,
                    ops: wgpu::Operations {
                        load: wgpu::LoadOp::Clear(wgpu::Color {
                            r: sky,
                            g: sky,
                            b: sky,
                            a: 1.0,
                        }),
                        store: wgpu::StoreOp::Store,
                    },
                })],
                depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                    view: &self.depth_view,
                    depth_ops: Some(wgpu::Operations {
                        load: wgpu::LoadOp::Load,
                        store: wgpu::StoreOp::Store,
                    }),
                    stencil_ops: None,
                }),
                timestamp_writes: None,
                occlusion_query_set: None,
                multiview_mask: None,
            });
            pass.set_bind_group(0, &self.frame_bind_group, &[]);
            pass.set_bind_group(
                1,
                if window.is_some() {
                    &self.shadow_bind_group
                } else {
                    &self.own_map_bind_group
                },
                &[],
            );
            pass.set_vertex_buffer(0, self.vertex_buffer.slice(..));
            pass.set_index_buffer(self.index_buffer.slice(..), wgpu::IndexFormat::Uint32);
            // Only the part of the frame asked for is shaded.
            let set_scissor = |pass: &mut wgpu::RenderPass, r: PixelRect| {
                pass.set_scissor_rect(
                    r.x0 as u32,
                    r.y0 as u32,
                    r.width() as u32,
                    r.height() as u32,
                )
            };
            if scissor != whole && !scissor.is_empty() {
                set_scissor(&mut pass, scissor);
            }
            if !scissor.is_empty() {
                pass.set_pipeline(&self.main_far_pipeline);
                pass.draw(0..3, 0..1);
            }
            let mut current = None;
            for (k, (range, shading, soft)) in main_draws.iter().enumerate() {
                if scissor.is_empty() {
                    break;
                }
                if current != Some((*shading, *soft)) {
                    let pipelines = match &self.soft_pipelines {
                        Some(soft_pipelines) if *soft => soft_pipelines,
                        _ => &self.pipelines,
                    };
                    pass.set_pipeline(pipelines.of(*shading));
                    current = Some((*shading, *soft));
                }
                if k == hood_draws && hood_rows < rig.height {
                    // The rows the hood covers from edge to edge hold nothing else.
                    let above = scissor.intersection(&PixelRect {
                        y1: hood_rows as usize,
                        ..whole
                    });
                    if above.is_empty() {
                        break;
                    }
                    set_scissor(&mut pass, above);
                }
                pass.draw_indexed(range.clone(), 0, 0..1);
            }
        }
        self.main_draws = main_draws;
        self.shadow_draws = shadow_draws;
        self.board_shadow_draws = board_shadow_draws;
        self.foliage_shadow_draws = foliage_shadow_draws;
        self.foliage_board_shadow_draws = foliage_board_shadow_draws;
        // Only the rows of the part drawn come back.
        let rows = scissor.y0 as u32..scissor.y1 as u32;
        if !rows.is_empty() {
            encoder.copy_texture_to_buffer(
                wgpu::TexelCopyTextureInfo {
                    texture: &self.color_texture,
                    mip_level: 0,
                    origin: wgpu::Origin3d {
                        x: 0,
                        y: rows.start,
                        z: 0,
                    },
                    aspect: wgpu::TextureAspect::All,
                },
                wgpu::TexelCopyBufferInfo {
                    buffer: &self.staging,
                    layout: wgpu::TexelCopyBufferLayout {
                        offset: 0,
                        bytes_per_row: Some(self.padded_row),
                        rows_per_image: Some(rows.len() as u32),
                    },
                },
                wgpu::Extent3d {
                    width: rig.width,
                    height: rows.len() as u32,
                    depth_or_array_layers: 1,
                },
            );
        }
        self.queue.submit([encoder.finish()]);

        // Map and read, dropping the row padding.
        let backend = self.options.backend;
        let readback = |reason: String| RenderError::Readback { backend, reason };
        let width = rig.width as usize;
        let mut pixels = vec![0; width * rig.height as usize];
        if rows.is_empty() {
            return Ok(GrayImage::from_raw(rig.width, rig.height, pixels)
                .expect("buffer holds width × height bytes"));
        }
        let bytes = u64::from(self.padded_row) * rows.len() as u64;
        let (sender, receiver) = std::sync::mpsc::channel();
        self.staging
            .map_async(wgpu::MapMode::Read, ..bytes, move |result| {
                let _ = sender.send(result);
            });
        self.device
            .poll(wgpu::PollType::Wait {
                submission_index: None,
                timeout: None,
            })
            .map_err(|e| readback(e.to_string()))?;
        receiver
            .recv()
            .map_err(|e| readback(e.to_string()))?
            .map_err(|e| readback(e.to_string()))?;
        {
            let data = self
                .staging
                .get_mapped_range(..bytes)
                .map_err(|e| readback(e.to_string()))?;
            let drawn = &mut pixels[rows.start as usize * width..rows.end as usize * width];
            for (row, out) in data
                .chunks_exact(self.padded_row as usize)
                .zip(drawn.chunks_exact_mut(width))
            {
                out.copy_from_slice(&row[..width]);
            }
        }
        self.staging.unmap();
        Ok(GrayImage::from_raw(rig.width, rig.height, pixels)
            .expect("buffer holds width × height bytes"))
    }

    /// The grass's parameters in [`Globals`]: lattice frequency, albedo range, hash key.
    fn ground_params(&self) -> [f32; 4] {
        [
            (1.0 / GROUND_CELL_M) as f32,
            GRASS_ALBEDO_RANGE[0] as f32,
            (GRASS_ALBEDO_RANGE[1] - GRASS_ALBEDO_RANGE[0]) as f32,
            self.grass_key as f32,
        ]
    }

    /// Encodes a frame's draws into the slots' texture (`work`): the tiles drawn whole, the
    /// texels set back (the cleared depth, and the static casters there drawn again: the
    /// same draws as the tile's, so the same texels), then the vehicles (`vehicles`: the
    /// solid casters' and the canopies' draws, placed by the frame's `world_from_object`,
    /// the camera at `eye`). Returns the vehicles' triangles drawn.
    fn encode_slots(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        work: &SlotWork,
        vehicles: [&Vec<Range<u32>>; 2],
        world_from_object: &ObjectTransforms,
        eye: &Vector3<f64>,
    ) -> u32 {
        let frame = &self.tile_frame;
        // A tile's static casters within `rect` (all of them when `whole`), solid and
        // canopies: whole chunks for a whole tile, else the chunks' parts that reach it.
        let statics = |rect: TexelRect, whole: bool| {
            let (mut solid, mut leafy) = (Vec::new(), Vec::new());
            for chunk in self.scene.chunks().iter().filter(|c| c.casts_shadow) {
                let draws = if chunk.layer == Layer::Foliage {
                    &mut leafy
                } else {
                    &mut solid
                };
                if whole || chunk.parts.is_empty() {
                    if frame.reaches(rect, chunk.centre, chunk.radius) {
                        push_merged(draws, chunk.indices.clone());
                    }
                } else {
                    for part in &chunk.parts {
                        if frame.reaches(rect, part.centre, part.radius) {
                            push_merged(draws, part.indices.clone());
                        }
                    }
                }
            }
            [solid, leafy]
        };
        // A tile's uniforms: the sun's projection onto its square, its vertices relative to
        // a point of the tile (as the frame's are to the camera), the same every time.
        let static_entry = |cell: Cell| {
            let (min, max) = frame.tile_box(cell);
            let light = Light::of_box(frame.axes, min, max, shadow_tiles::TILE_TEXELS);
            let origin = frame.tile_origin(cell);
            let globals = Globals {
                light_view_proj: to_f32(
                    &(light.clip_from_world * Translation3::from(origin).to_homogeneous()),
                ),
                origin: [origin.x as f32, origin.y as f32, origin.z as f32, 0.0],
                ground: self.ground_params(),
                ..Globals::zeroed()
            };
            let mut objects = [[[0f32; 4]; 4]; ObjectSlot::COUNT as usize];
            objects[ObjectSlot::WORLD as usize] =
                to_f32(&Translation3::from(-origin).to_homogeneous());
            (globals, objects)
        };
        // The vehicles' over texels `rect`: the sun's projection onto just those texels.
        let vehicle_entry = |rect: TexelRect| {
            let (min, max) = frame.texels_box(rect);
            let size = (rect.x1 - rect.x0).max(rect.r1 - rect.r0) as u32;
            let light = Light::of_box(frame.axes, min, max, size);
            let globals = Globals {
                light_view_proj: to_f32(
                    &(light.clip_from_world * Translation3::from(*eye).to_homogeneous()),
                ),
                origin: [eye.x as f32, eye.y as f32, eye.z as f32, 0.0],
                ground: self.ground_params(),
                ..Globals::zeroed()
            };
            (globals, *world_from_object)
        };
        // Every draw: its uniforms, its viewport and scissor (x, y, width, height in the
        // texture), whether it clears them first, and its casters.
        let side = shadow_tiles::TILE_TEXELS;
        let in_tile = |cell: Cell, rect: TexelRect| {
            let (a, b) = shadow_tiles::slot(cell);
            (
                [a as u32 * side, b as u32 * side, side, side],
                rect.in_slots(),
            )
        };
        let mut entries = Vec::new();
        let mut draws = Vec::new();
        for &cell in &work.tiles {
            entries.push(static_entry(cell));
            let rect = TexelRect::of_cell(cell);
            draws.push((in_tile(cell, rect), true, statics(rect, true)));
        }
        for &(cell, rect) in &work.restore {
            entries.push(static_entry(cell));
            draws.push((in_tile(cell, rect), true, statics(rect, false)));
        }
        for &rect in &work.vehicles {
            entries.push(vehicle_entry(rect));
            let texels = rect.in_slots();
            // The moving casters that reach these texels, of those the frame draws.
            let mut casters = [Vec::new(), Vec::new()];
            for item in self
                .items
                .iter()
                .filter(|d| d.moving_caster() && frame.reaches(rect, d.centre, d.radius))
            {
                let foliage = usize::from(item.shading == Shading::Foliage);
                if vehicles[foliage]
                    .iter()
                    .any(|r| r.start <= item.indices.start && item.indices.end <= r.end)
                {
                    casters[foliage].push(item.indices.clone());
                }
            }
            for list in &mut casters {
                list.sort_by_key(|r| r.start);
                let ranges = std::mem::take(list);
                for range in ranges {
                    push_merged(list, range);
                }
            }
            draws.push(((texels, texels), false, casters));
        }
        if draws.is_empty() {
            return 0;
        }
        self.slot_uniforms.write(&self.queue, &entries);
        let [far, solid, leafy] = &self.slot_pipelines;
        let mut pass = depth_pass(
            encoder,
            "shadow tiles",
            &self.slots_view,
            wgpu::LoadOp::Load,
        );
        pass.set_vertex_buffer(0, self.vertex_buffer.slice(..));
        pass.set_index_buffer(self.index_buffer.slice(..), wgpu::IndexFormat::Uint32);
        let mut triangles = 0;
        for (k, ((viewport, [x, y, w, h]), clear, [solid_draws, leafy_draws])) in
            draws.iter().enumerate()
        {
            pass.set_bind_group(0, &self.slot_bind_group, &self.slot_uniforms.offsets(k));
            let [vx, vy, vw, vh] = viewport.map(|v| v as f32);
            pass.set_viewport(vx, vy, vw, vh, 0.0, 1.0);
            pass.set_scissor_rect(*x, *y, *w, *h);
            if *clear {
                pass.set_pipeline(far);
                pass.draw(0..3, 0..1);
            }
            for (pipeline, list) in [(solid, solid_draws), (leafy, leafy_draws)] {
                if !list.is_empty() {
                    pass.set_pipeline(pipeline);
                    for range in list {
                        pass.draw_indexed(range.clone(), 0, 0..1);
                    }
                }
            }
            if !*clear {
                triangles += solid_draws
                    .iter()
                    .chain(leafy_draws)
                    .map(|r| (r.end - r.start) / 3)
                    .sum::<u32>();
            }
        }
        triangles
    }

    /// The first row the hood covers from edge to edge, for the camera panned by `pan_rad`.
    fn hood_rows(&mut self, pan_rad: f64) -> u32 {
        if pan_rad == 0.0 {
            return self.hood_row;
        }
        match self.panned_hood_row {
            Some((bits, row)) if bits == pan_rad.to_bits() => row,
            _ => {
                let row = hood_row(&self.rig, &self.scene.description().chase, pan_rad);
                self.panned_hood_row = Some((pan_rad.to_bits(), row));
                row
            }
        }
    }

    /// The target's true position in the image and in the camera frame, for these poses.
    pub fn ground_truth(
        &self,
        world_from_chase: &Isometry3<f64>,
        world_from_lead: &Isometry3<f64>,
        camera_pan_rad: f64,
    ) -> GroundTruth {
        ground_truth_of(
            &self.rig,
            &self.scene.lead_from_target(),
            &self.scene.description().target,
            world_from_chase,
            world_from_lead,
            camera_pan_rad,
        )
    }
}

/// The target's true position in the image and in the camera frame, for a rig, where the
/// target sits on the lead (`lead_from_target`, in the lead's scene frame), and the poses.
/// The renderer's ground truth, and scenario validation's check that the target starts in
/// view.
pub fn ground_truth_of(
    rig: &CameraRig,
    lead_from_target: &Isometry3<f64>,
    target: &tracker::TargetModel,
    world_from_chase: &Isometry3<f64>,
    world_from_lead: &Isometry3<f64>,
    camera_pan_rad: f64,
) -> GroundTruth {
    let camera_from_target = rig
        .world_from_camera_panned(world_from_chase, camera_pan_rad)
        .inverse()
        * world_from_lead
        * lead_from_target;
    let centre = camera_from_target * Point3::origin();
    let target_cam_m = [centre.x, centre.y, centre.z];
    let [c_x, c_y] = rig
        .intrinsics
        .project(target_cam_m)
        .unwrap_or([f64::NAN, f64::NAN]);
    let in_view = target.corners_m().iter().all(|&[x, y]| {
        let p = camera_from_target * Point3::new(x, y, 0.0);
        rig.intrinsics
            .project([p.x, p.y, p.z])
            .is_some_and(|[u, v]| {
                (-0.5..f64::from(rig.width) - 0.5).contains(&u)
                    && (-0.5..f64::from(rig.height) - 0.5).contains(&v)
            })
    });
    GroundTruth {
        c_x,
        c_y,
        scale: target.nominal_range_m() / centre.z,
        target_cam_m,
        in_view,
    }
}

/// Replaces the odd rows of `frame` with those of `other`: the two fields of an interlaced
/// frame.
fn interlace(frame: &mut GrayImage, other: &GrayImage) {
    let width = frame.width() as usize;
    for (row, from) in frame
        .as_mut()
        .chunks_exact_mut(width)
        .zip(other.as_raw().chunks_exact(width))
        .skip(1)
        .step_by(2)
    {
        row.copy_from_slice(from);
    }
}

/// The first row from which the ray through every pixel centre below hits the hood (one
/// row of margin above that for rasterisation's edge rules); `rig.height` if there is none.
fn hood_row(rig: &CameraRig, chase: &crate::scene::ChaseVehicle, camera_pan_rad: f64) -> u32 {
    let chase_from_camera = rig.chase_from_camera_panned(camera_pan_rad);
    let eye = chase_from_camera * Point3::origin();
    let [fx, fy] = rig.intrinsics.focal_px();
    let [cx, cy] = rig.intrinsics.image_center_px;
    let min = [
        chase.hood_back_m,
        chase.hood_height_m - 0.6,
        -0.5 * chase.hood_width_m,
    ];
    let max = [
        chase.hood_front_m,
        chase.hood_height_m,
        0.5 * chase.hood_width_m,
    ];
    let hits = |u: f64, v: f64| {
        let ray = Vector3::new((u - cx) / fx, (v - cy) / fy, 1.0);
        let d = chase_from_camera.rotation * ray;
        let (mut near, mut far) = (super::rig::NEAR_M, f64::MAX);
        for k in 0..3 {
            if d[k].abs() < 1e-12 {
                if eye[k] < min[k] || eye[k] > max[k] {
                    return false;
                }
                continue;
            }
            let (a, b) = ((min[k] - eye[k]) / d[k], (max[k] - eye[k]) / d[k]);
            near = near.max(a.min(b));
            far = far.min(a.max(b));
        }
        near <= far
    };
    let mut row = rig.height;
    while row > 0 && (0..rig.width).all(|u| hits(f64::from(u), f64::from(row - 1))) {
        row -= 1;
    }
    if row < rig.height {
        row += 1;
    }
    row.min(rig.height)
}

/// A pass's uniforms, the globals and the object transforms, in one buffer (the objects at
/// the first offset a binding may start at after the globals), so that a frame writes them
/// in one `write_buffer`: each write costs a staging buffer of its own.
struct Uniforms {
    buffer: wgpu::Buffer,
    objects_offset: u64,
}

/// Draws into the slots' texture a frame may make: every slot's tile drawn whole or set
/// back, and the moving objects' texels (cut in up to four where the texture wraps).
const SLOT_ENTRIES: usize =
    shadow_tiles::WINDOW * shadow_tiles::WINDOW + 4 * ObjectSlot::COUNT as usize;

/// The uniforms of the draws into the slots' texture: [`Uniforms`]' layout once a draw,
/// `stride` bytes apart, each bound at its dynamic offset. All a frame's are written in
/// one `write_buffer`.
struct SlotUniforms(Uniforms, u64);

impl SlotUniforms {
    fn new(device: &wgpu::Device) -> SlotUniforms {
        let align = u64::from(device.limits().min_uniform_buffer_offset_alignment);
        let objects_offset = GLOBALS_BYTES.div_ceil(align) * align;
        let stride = (objects_offset + OBJECTS_BYTES).div_ceil(align) * align;
        let buffer = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("slot uniforms"),
            size: stride * SLOT_ENTRIES as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        SlotUniforms(
            Uniforms {
                buffer,
                objects_offset,
            },
            stride,
        )
    }

    /// Writes the entries `entries`, from the first.
    fn write(&self, queue: &wgpu::Queue, entries: &[(Globals, ObjectTransforms)]) {
        if entries.is_empty() {
            return;
        }
        assert!(entries.len() <= SLOT_ENTRIES, "a window's draws at most");
        let stride = self.1 as usize;
        let size = wgpu::BufferSize::new((stride * entries.len()) as u64).expect("entries");
        let mut bytes = queue
            .write_buffer_with(&self.0.buffer, 0, size)
            .expect("the write lies within the buffer");
        let offset = self.0.objects_offset as usize;
        for (k, (globals, objects)) in entries.iter().enumerate() {
            let entry = k * stride;
            bytes
                .slice(entry..entry + GLOBALS_BYTES as usize)
                .copy_from_slice(bytemuck::bytes_of(globals));
            bytes
                .slice(entry + offset..entry + offset + OBJECTS_BYTES as usize)
                .copy_from_slice(bytemuck::cast_slice(objects));
        }
    }

    /// The dynamic offsets of entry `k`.
    fn offsets(&self, k: usize) -> [u32; 2] {
        let at = (k as u64 * self.1) as u32;
        [at, at]
    }
}

/// Every object slot's transform (see `Objects` in `scene.wgsl`).
type ObjectTransforms = [[[f32; 4]; 4]; ObjectSlot::COUNT as usize];

/// Bytes of [`Globals`].
const GLOBALS_BYTES: u64 = std::mem::size_of::<Globals>() as u64;
/// Bytes of the object transforms, one 4 × 4 matrix of `f32` per slot.
const OBJECTS_BYTES: u64 = 64 * ObjectSlot::COUNT as u64;

impl Uniforms {
    fn new(device: &wgpu::Device, label: &str) -> Uniforms {
        let align = u64::from(device.limits().min_uniform_buffer_offset_alignment);
        let objects_offset = GLOBALS_BYTES.div_ceil(align) * align;
        let size = objects_offset + OBJECTS_BYTES;
        Uniforms {
            buffer: device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size,
                usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            }),
            objects_offset,
        }
    }

    fn globals(&self) -> wgpu::BindingResource<'_> {
        wgpu::BindingResource::Buffer(wgpu::BufferBinding {
            buffer: &self.buffer,
            offset: 0,
            size: wgpu::BufferSize::new(GLOBALS_BYTES),
        })
    }

    fn objects(&self) -> wgpu::BindingResource<'_> {
        wgpu::BindingResource::Buffer(wgpu::BufferBinding {
            buffer: &self.buffer,
            offset: self.objects_offset,
            size: wgpu::BufferSize::new(OBJECTS_BYTES),
        })
    }

    fn write(
        &self,
        queue: &wgpu::Queue,
        globals: &Globals,
        objects: &[[[f32; 4]; 4]; ObjectSlot::COUNT as usize],
    ) {
        // Written straight into wgpu's staging memory.
        let offset = self.objects_offset as usize;
        let size = wgpu::BufferSize::new(self.buffer.size()).expect("uniforms hold bytes");
        let mut bytes = queue
            .write_buffer_with(&self.buffer, 0, size)
            .expect("the write lies within the buffer");
        // (The padding between the two is never bound, so never read.)
        bytes
            .slice(..GLOBALS_BYTES as usize)
            .copy_from_slice(bytemuck::bytes_of(globals));
        bytes
            .slice(offset..)
            .copy_from_slice(bytemuck::cast_slice(objects));
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
fn display_lock(external: bool) -> std::sync::MutexGuard<'static, ()> {
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

/// Uploads `bytes` into a new buffer.
fn buffer_init(
    device: &wgpu::Device,
    queue: &wgpu::Queue,
    label: &str,
    bytes: &[u8],
    usage: wgpu::BufferUsages,
) -> wgpu::Buffer {
    let buffer = device.create_buffer(&wgpu::BufferDescriptor {
        label: Some(label),
        size: (bytes.len() as u64)
            .max(4)
            .next_multiple_of(wgpu::COPY_BUFFER_ALIGNMENT),
        usage: usage | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    queue.write_buffer(&buffer, 0, bytes);
    buffer
}

/// Column-major f32 copy of a matrix, as WGSL's `mat4x4<f32>` expects.
fn to_f32(m: &Matrix4<f64>) -> [[f32; 4]; 4] {
    let mut out = [[0f32; 4]; 4];
    for (c, column) in out.iter_mut().enumerate() {
        for (r, value) in column.iter_mut().enumerate() {
            *value = m[(r, c)] as f32;
        }
    }
    out
}

/// A depth-only render pass into `view`, loading (or clearing) it as `load` says and
/// storing it: the passes from the sun.
fn depth_pass<'e>(
    encoder: &'e mut wgpu::CommandEncoder,
    label: &str,
    view: &wgpu::TextureView,
    load: wgpu::LoadOp<f32>,
) -> wgpu::RenderPass<'e> {
    encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
        label: Some(label),
        color_attachments: &[],
        depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
            view,
            depth_ops: Some(wgpu::Operations {
                load,
                store: wgpu::StoreOp::Store,
            }),
            stencil_ops: None,
        }),
        timestamp_writes: None,
        occlusion_query_set: None,
        multiview_mask: None,
    })
}

/// Into `draws`: the index ranges of the items that cast shadows within `light`'s box,
/// canopies (`foliage`) or the rest, the static ones only `with_static` (else the moving
/// objects alone), sorted and joined into as few draws as possible (depth only, so order
/// does not matter).
fn caster_draws(
    items: &[DrawItem],
    light: &Light,
    texels: Option<(PixelRect, u32)>,
    foliage: bool,
    with_static: bool,
    draws: &mut Vec<Range<u32>>,
) {
    let mut ranges: Vec<Range<u32>> = items
        .iter()
        .filter(|d| {
            d.casts_shadow
                && (with_static || d.moving_caster())
                && (d.shading == Shading::Foliage) == foliage
                && light.holds(d.centre, d.radius)
                && texels.is_none_or(|(t, size)| light.reaches(t, size, d.centre, d.radius))
        })
        .map(|d| d.indices.clone())
        .collect();
    ranges.sort_by_key(|r| r.start);
    draws.clear();
    for range in ranges {
        push_merged(draws, range);
    }
}

/// Appends an index range to a draw list, joining it to the last one when they touch.
fn push_merged(draws: &mut Vec<Range<u32>>, range: Range<u32>) {
    match draws.last_mut() {
        Some(last) if last.end == range.start => last.end = range.end,
        _ => draws.push(range),
    }
}

/// A piece of geometry the frame may draw: static chunk or placed moving object.
#[derive(Clone, Debug)]
struct DrawItem {
    indices: Range<u32>,
    /// Bounding sphere, world frame.
    centre: [f64; 3],
    radius: f64,
    casts_shadow: bool,
    /// Draw-order class: hood, lead, other vehicles, then the static layers.
    class: u8,
    /// From the camera to the bounding sphere's centre, metres.
    distance_m: f64,
    /// Which pipeline draws it.
    shading: Shading,
    /// The static chunk it is (its index in [`Scene::chunks`]), whose parts the main pass
    /// culls one by one.
    chunk: Option<usize>,
}

impl DrawItem {
    /// Whether it is a moving object that casts a shadow: what a frame draws from the sun
    /// on top of the static casters' cached tiles.
    fn moving_caster(&self) -> bool {
        self.casts_shadow && self.class < FIRST_STATIC_CLASS
    }
}

/// The camera's view frustum as planes through the optical centre plus near and far, in the
/// camera frame.
struct Frustum {
    camera_from_world: Isometry3<f64>,
    sides: [Vector3<f64>; 4],
}

impl Frustum {
    /// The frustum through the pixels `part` of the frame.
    fn of_part(rig: &CameraRig, camera_from_world: &Isometry3<f64>, part: PixelRect) -> Frustum {
        let [fx, fy] = rig.intrinsics.focal_px();
        let [cx, cy] = rig.intrinsics.image_center_px;
        let left = (part.x0 as f64 - 0.5 - cx) / fx;
        let right = (part.x1 as f64 - 0.5 - cx) / fx;
        let top = (part.y0 as f64 - 0.5 - cy) / fy;
        let bottom = (part.y1 as f64 - 0.5 - cy) / fy;
        Frustum {
            camera_from_world: *camera_from_world,
            sides: [
                Vector3::new(1.0, 0.0, -left).normalize(),
                Vector3::new(-1.0, 0.0, right).normalize(),
                Vector3::new(0.0, 1.0, -top).normalize(),
                Vector3::new(0.0, -1.0, bottom).normalize(),
            ],
        }
    }

    fn sees(&self, centre: [f64; 3], radius: f64) -> bool {
        let c = (self.camera_from_world * Point3::from(centre)).coords;
        c.z > super::rig::NEAR_M - radius
            && c.z < super::rig::FAR_M + radius
            && self.sides.iter().all(|n| n.dot(&c) >= -radius)
    }
}

/// The sun's orthographic frustum, fitted to the receivers the camera can see.
struct Light {
    /// World → the shadow map's clip space (x, y in −1..1, depth 0 nearest the sun).
    clip_from_world: Matrix4<f64>,
    /// The light frame's axes (rows: x, y, towards the sun) and fitted box.
    axes: [Vector3<f64>; 3],
    min: [f64; 3],
    max: [f64; 3],
    /// Size of one shadow texel on the ground, metres (the larger side).
    texel_m: f64,
}

impl Light {
    /// The light frame's axes: x and y across the sun's rays, and the direction towards it.
    fn axes(towards_sun: [f64; 3]) -> [Vector3<f64>; 3] {
        let d = Vector3::from(towards_sun).normalize();
        let hint = if d.y.abs() > 0.99 {
            Vector3::x()
        } else {
            Vector3::y()
        };
        let x = hint.cross(&d).normalize();
        let y = d.cross(&x);
        [x, y, d]
    }

    /// The orthographic projection onto the box `min..max` (light coordinates) of a map
    /// `size` texels square.
    fn of_box(axes: [Vector3<f64>; 3], min: [f64; 3], max: [f64; 3], size: u32) -> Light {
        let [x, y, d] = axes;
        let (sx, sy, depth) = (max[0] - min[0], max[1] - min[1], max[2] - min[2]);
        let row = |axis: &Vector3<f64>, scale: f64, offset: f64| {
            [axis.x * scale, axis.y * scale, axis.z * scale, offset]
        };
        let r0 = row(&x, 2.0 / sx, -2.0 * min[0] / sx - 1.0);
        let r1 = row(&y, 2.0 / sy, -2.0 * min[1] / sy - 1.0);
        let r2 = row(&d, -1.0 / depth, max[2] / depth);
        let clip_from_world = Matrix4::new(
            r0[0], r0[1], r0[2], r0[3], //
            r1[0], r1[1], r1[2], r1[3], //
            r2[0], r2[1], r2[2], r2[3], //
            0.0, 0.0, 0.0, 1.0,
        );
        Light {
            clip_from_world,
            axes,
            min,
            max,
            texel_m: sx.max(sy) / f64::from(size),
        }
    }

    /// A map around `centre` (world): `half_m` either side across the rays and along them,
    /// and casters up to `reach_m` towards the sun.
    fn around(
        centre: Vector3<f64>,
        towards_sun: [f64; 3],
        half_m: f64,
        reach_m: f64,
        size: u32,
    ) -> Light {
        let axes = Self::axes(towards_sun);
        let c = axes.map(|a| a.dot(&centre));
        Self::of_box(
            axes,
            [c[0] - half_m, c[1] - half_m, c[2] - half_m],
            [c[0] + half_m, c[1] + half_m, c[2] + reach_m],
            size,
        )
    }

    fn fit(
        rig: &CameraRig,
        world_from_camera: &Isometry3<f64>,
        towards_sun: [f64; 3],
        distance_m: f64,
        size: u32,
    ) -> Light {
        let axes = Self::axes(towards_sun);
        // Corners of the camera's frustum from near to the shadow distance, clamped to the
        // height band receivers live in, in light coordinates.
        let [fx, fy] = rig.intrinsics.focal_px();
        let [cx, cy] = rig.intrinsics.image_center_px;
        let (mut min, mut max) = ([f64::MAX; 3], [f64::MIN; 3]);
        for z in [super::rig::NEAR_M, distance_m] {
            for (u, v) in [
                (-0.5, -0.5),
                (f64::from(rig.width) - 0.5, -0.5),
                (-0.5, f64::from(rig.height) - 0.5),
                (f64::from(rig.width) - 0.5, f64::from(rig.height) - 0.5),
            ] {
                let p_cam = Point3::new((u - cx) / fx * z, (v - cy) / fy * z, z);
                let mut p = world_from_camera * p_cam;
                p.y = p.y.clamp(0.0, RECEIVER_TOP_M);
                for k in 0..3 {
                    let value = axes[k].dot(&p.coords);
                    min[k] = min[k].min(value);
                    max[k] = max[k].max(value);
                }
            }
        }
        max[2] += CASTER_REACH_M;
        Self::of_box(axes, min, max, size)
    }

    /// The texels of this map (`size` a side) that shading the camera's pixels `part` can
    /// sample: every receiver seen through `part` lies in the camera's frustum cut to
    /// `part`, from the near to the far plane, and within the receivers' height band; that
    /// region's corners all lie on its edges clipped to the band, and the map is an
    /// orthographic projection, so their bounding box in the map holds it. Grown by the
    /// normal offset of the lookups and the bilinear comparison's texel.
    fn texels_seen(
        &self,
        rig: &CameraRig,
        world_from_camera: &Isometry3<f64>,
        part: PixelRect,
        size: u32,
    ) -> PixelRect {
        let [fx, fy] = rig.intrinsics.focal_px();
        let [cx, cy] = rig.intrinsics.image_center_px;
        let (u0, u1) = (part.x0 as f64 - 0.5, part.x1 as f64 - 0.5);
        let (v0, v1) = (part.y0 as f64 - 0.5, part.y1 as f64 - 0.5);
        let corner = |u: f64, v: f64, z: f64| {
            world_from_camera * Point3::new((u - cx) / fx * z, (v - cy) / fy * z, z)
        };
        let rect = [(u0, v0), (u1, v0), (u1, v1), (u0, v1)];
        let (near, far) = (super::rig::NEAR_M, super::rig::FAR_M);
        let mut edges = Vec::with_capacity(12);
        for k in 0..4 {
            let (a, b) = (rect[k], rect[(k + 1) % 4]);
            edges.push((corner(a.0, a.1, near), corner(a.0, a.1, far)));
            edges.push((corner(a.0, a.1, near), corner(b.0, b.1, near)));
            edges.push((corner(a.0, a.1, far), corner(b.0, b.1, far)));
        }
        let (mut lo, mut hi) = ([f64::MAX; 2], [f64::MIN; 2]);
        for (a, b) in edges {
            // The part of the edge within the receivers' height band.
            let (mut t0, mut t1) = (0.0f64, 1.0f64);
            let dy = b.y - a.y;
            for (bound, below) in [(0.0, true), (RECEIVER_TOP_M, false)] {
                if dy.abs() < 1e-12 {
                    if (below && a.y < bound) || (!below && a.y > bound) {
                        t1 = -1.0;
                    }
                    continue;
                }
                let t = (bound - a.y) / dy;
                // Inside is y >= 0 (below the band's floor is out) and y <= top.
                let entering = if below { dy > 0.0 } else { dy < 0.0 };
                if entering {
                    t0 = t0.max(t);
                } else {
                    t1 = t1.min(t);
                }
            }
            if t0 > t1 {
                continue;
            }
            for t in [t0, t1] {
                let p = a.coords + (b.coords - a.coords) * t;
                for k in 0..2 {
                    let v = self.axes[k].dot(&p);
                    lo[k] = lo[k].min(v);
                    hi[k] = hi[k].max(v);
                }
            }
        }
        if lo[0] > hi[0] {
            return PixelRect::whole(0, 0);
        }
        // Map texels: x from min[0], y from max[1] downwards (the clip y is flipped).
        let n = f64::from(size);
        let (sx, sy) = (self.max[0] - self.min[0], self.max[1] - self.min[1]);
        let margin = NORMAL_OFFSET_TEXELS + 2.0;
        let tx = |v: f64| (v - self.min[0]) / sx * n;
        let ty = |v: f64| (self.max[1] - v) / sy * n;
        let clip = |t: f64| t.clamp(0.0, n) as usize;
        PixelRect {
            x0: clip((tx(lo[0]) - margin).floor()),
            x1: clip((tx(hi[0]) + margin).ceil()),
            y0: clip((ty(hi[1]) - margin).floor()),
            y1: clip((ty(lo[1]) + margin).ceil()),
        }
    }

    /// The texels of this map (`size` a side) that draw item `d` can cover, grown by two
    /// texels (the rasteriser's rounding, with room to spare).
    fn caster_texels(&self, d: &DrawItem, size: u32) -> PixelRect {
        let n = f64::from(size);
        let (sx, sy) = (self.max[0] - self.min[0], self.max[1] - self.min[1]);
        let clip = |t: f64| t.clamp(0.0, n) as usize;
        let c = Vector3::from(d.centre);
        let tx = (self.axes[0].dot(&c) - self.min[0]) / sx * n;
        let ty = (self.max[1] - self.axes[1].dot(&c)) / sy * n;
        let (rx, ry) = (d.radius / sx * n + 2.0, d.radius / sy * n + 2.0);
        PixelRect {
            x0: clip((tx - rx).floor()),
            x1: clip((tx + rx).ceil()),
            y0: clip((ty - ry).floor()),
            y1: clip((ty + ry).ceil()),
        }
    }

    /// Whether a sphere can cover any of the texels `texels` of this map (`size` a side).
    fn reaches(&self, texels: PixelRect, size: u32, centre: [f64; 3], radius: f64) -> bool {
        let n = f64::from(size);
        let (sx, sy) = (self.max[0] - self.min[0], self.max[1] - self.min[1]);
        let c = Vector3::from(centre);
        let (x, y) = (self.axes[0].dot(&c), self.axes[1].dot(&c));
        // The texels' extent in the light frame (texel rows run down from max[1]).
        let x0 = self.min[0] + texels.x0 as f64 / n * sx;
        let x1 = self.min[0] + texels.x1 as f64 / n * sx;
        let y0 = self.max[1] - texels.y1 as f64 / n * sy;
        let y1 = self.max[1] - texels.y0 as f64 / n * sy;
        !texels.is_empty()
            && x + radius >= x0
            && x - radius <= x1
            && y + radius >= y0
            && y - radius <= y1
    }

    fn holds(&self, centre: [f64; 3], radius: f64) -> bool {
        let c = Vector3::from(centre);
        (0..3).all(|k| {
            let v = self.axes[k].dot(&c);
            v >= self.min[k] - radius && v <= self.max[k] + radius
        })
    }
}
