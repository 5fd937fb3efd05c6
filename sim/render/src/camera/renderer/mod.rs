//! The off-screen renderer. [`Renderer::render`] reads top to bottom like wgpu's
//! `render_to_texture` example: poses and culling, the sun's frustum fitted to the camera's,
//! the geometry drawn made resident, uniforms, one command encoder with the shadow pass,
//! the main pass and the copy to a staging buffer, one submission, map and read, then the
//! sensor model and the ground truth.
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
//!
//! As in wgpu's shadow example, each pass is a value holding its pipelines, the bind group
//! they draw with and its uniforms (`pipelines::Pass`), and a frame encodes them in order;
//! as in rapier's physics pipeline, what the renderer does is spread over files by phase:
//! - `device`: instance, adapter and device, and the display's lock;
//! - `resident`: the scene's geometry on the device, the part of it the frames draw;
//! - `resources`: the maps from the sun, the frame's targets, the ground's textures, the
//!   samplers;
//! - `uniforms`: the shader's `Globals` and the buffers that hold them;
//! - `pipelines`: the shader, the layouts, and each pass's pipelines and bind groups;
//! - `culling`: the camera, the draw items and the frustum, the casters of a map;
//! - `light`: the sun's frusta fitted to what the camera sees;
//! - `shadow_pass`: the casters into the frame's own map and the board's fine map;
//! - `slots_pass`: the static shadow tiles' slots, and the vehicles drawn over them;
//! - `main_pass`: the frame, front to back, with the hood's rows scissored away;
//! - `readback`: the staging buffer, map and read, interlacing and the sensor;
//! - `rain`: the rain's streaks on the frame read back, before the sensor.

mod culling;
mod device;
mod light;
mod main_pass;
mod pipelines;
mod rain;
mod readback;
mod resident;
mod resources;
mod shadow_pass;
mod slots_pass;
mod uniforms;
mod view;
mod wet_road;

use super::backend::{Backend, BackendError};
use super::frame::{Field, Frame, FrameInput, GroundTruth};
use super::rig::CameraRig;
use super::sensor::blur_reach_px;
use super::shadow_tiles::TileFrame;
use crate::scene::{AutoGain, Braking, Scene, StreetLights};
use culling::{gather_items, DrawItem};
use device::{display_lock, Gpu};
use image::GrayImage;
use light::{Light, Sunlight};
use main_pass::{Hood, MainPass};
use nalgebra::{Isometry3, Point3, Vector3};
use pipelines::Builder;
use pipelines::SunMap;
use readback::{interlace, Readback};
use resident::Resident;
use resources::{ShadowMaps, ShadowSamplers, SurfaceTextures, Targets};
use shadow_pass::ShadowPass;
use slots_pass::{SlotsPass, Vehicles};
use std::sync::Arc;
use thiserror::Error;
use tracker::PixelRect;
use uniforms::{ground_params, SlotUniforms, Uniforms};
use view::CameraView;
use wet_road::Speeds;

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
    /// How near the camera a static chunk comes for it to be uploaded with what a frame
    /// draws, metres (see `resident`). Only memory and time depend on it, never a pixel:
    /// the device holds the road within about this distance of the camera, uploaded again
    /// each time a frame draws what is not there (with the far plane at 250 m, after about
    /// `resident_m` − 250 m of travel; at every new chunk below 250 m).
    pub resident_m: f64,
}

impl Default for RenderOptions {
    /// GL, a 512² shadow map over 60 m, cached static shadows, no MSAA, the chunks within
    /// 500 m uploaded.
    fn default() -> Self {
        RenderOptions {
            backend: Backend::Gl,
            shadow_map_size: 512,
            shadow_distance_m: 60.0,
            msaa_samples: 1,
            cached_shadows: true,
            resident_m: 500.0,
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
    /// A frame's actor poses are not one per description actor.
    #[error(
        "the frame poses {got} actors, but the scene's description has {expected} \
         (`FrameInput::world_from_actors` takes one pose per actor, in order)"
    )]
    Actors {
        /// The description's actors.
        expected: usize,
        /// The poses given (the frame's, or its earlier field's).
        got: usize,
    },
    /// Reading the frame back failed.
    #[error("reading the frame back from the {backend} device failed: {reason}")]
    Readback {
        /// The backend.
        backend: Backend,
        /// wgpu's message.
        reason: String,
    },
}

impl RenderOptions {
    /// Whether the options are in range, and the backend one an external OpenGL context
    /// (`external`) can take.
    fn check(&self, external: bool) -> Result<(), RenderError> {
        if ![1, 4].contains(&self.msaa_samples) {
            return Err(RenderError::Options(format!(
                "msaa_samples must be 1 or 4, got {}",
                self.msaa_samples
            )));
        }
        if !(64..=4096).contains(&self.shadow_map_size) {
            return Err(RenderError::Options(format!(
                "shadow_map_size must be 64..=4096, got {}",
                self.shadow_map_size
            )));
        }
        if !(self.resident_m.is_finite() && self.resident_m >= 0.0) {
            return Err(RenderError::Options(format!(
                "resident_m must be a distance of 0 m or more, got {}",
                self.resident_m
            )));
        }
        if external && self.backend != Backend::Gl {
            return Err(RenderError::Options(format!(
                "an external OpenGL context needs the gl backend, not {}",
                self.backend
            )));
        }
        Ok(())
    }
}

/// Renders frames of one scene from the chase camera.
pub struct Renderer {
    /// Shared (read only) with whoever needs the scene while the renderer is busy.
    scene: Arc<Scene>,
    rig: CameraRig,
    options: RenderOptions,
    /// The device, its queue, and the display it takes turns on.
    gpu: Gpu,
    /// The scene's vertices and indices: the part of them the frames draw.
    geometry: Resident,
    /// The grass's parameters in the shader's `Globals` ([`uniforms::ground_params`]).
    ground: [f32; 4],
    /// Every piece of geometry the frame may draw (kept to avoid allocating every frame).
    items: Vec<DrawItem>,
    /// The sun's pass into the frame's own map: every caster, or with the static shadows
    /// cached, the vehicles alone (their draws then go into the slots instead).
    shadow: ShadowPass,
    /// The sun's pass into the board's fine map, with soft shadows on the target.
    board_shadow: ShadowPass,
    /// The static shadow tiles' slots, and the vehicles drawn into them.
    slots: SlotsPass,
    /// The frame, shaded from the camera.
    main: MainPass,
    /// The staging buffer the frame is read back through.
    readback: Readback,
    stats: DrawStats,
    /// Where the lit street lights' light comes from (world; empty by day or without
    /// street lights).
    street_lights: Vec<[f64; 3]>,
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
    /// Opens the backend and compiles the pipelines (the scene's geometry is uploaded as
    /// the frames draw it).
    pub fn new(
        scene: Arc<Scene>,
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
        scene: Arc<Scene>,
        rig: CameraRig,
        options: &RenderOptions,
        proc_address: &dyn Fn(&str) -> *const std::ffi::c_void,
    ) -> Result<Renderer, RenderError> {
        Self::open(scene, rig, options, Some(proc_address))
    }

    /// The device, then its resources, then the passes over them.
    fn open(
        scene: Arc<Scene>,
        rig: CameraRig,
        options: &RenderOptions,
        external_gl: Option<&dyn Fn(&str) -> *const std::ffi::c_void>,
    ) -> Result<Renderer, RenderError> {
        options.check(external_gl.is_some())?;
        let _one_at_a_time = display_lock(external_gl.is_some());
        let gpu = Gpu::open(options.backend, external_gl)?;
        let device = &gpu.device;
        let description = scene.description();
        let street_lights = if StreetLights::lit(description) {
            StreetLights::sources(&scene)
        } else {
            Vec::new()
        };

        // Resources: the geometry, the maps from the sun, the frame's targets, the
        // ground's textures, the samplers, the staging buffer.
        let geometry = Resident::new(&gpu, &scene, options.resident_m);
        let maps = ShadowMaps::new(device, options);
        let targets = Targets::new(device, &rig, options.msaa_samples);
        let surfaces = SurfaceTextures::upload(&gpu, description);
        let samplers = ShadowSamplers::new(device);
        let readback = Readback::new(device, &rig);

        // Passes, each with its pipelines, bind group and uniforms: the frame's uniforms
        // (the main pass's, which the passes from the sun bind too), and the same for each
        // of the draws into the static shadow tiles' slots.
        let builder = Builder::new(
            device,
            options.msaa_samples,
            description.extinction_per_m().is_some(),
            description.headlamps.is_some(),
            description.raining().is_some(),
            description.has_tail_lamps(),
            StreetLights::lit(description),
            description.raining().is_some_and(|r| r.spray),
            description.raining().is_some_and(|r| r.lamp_reflections),
        );
        let lookups = builder.lookups(&maps, &surfaces, &samplers);
        let frame_uniforms = Uniforms::new(device, "frame uniforms");
        let frame_group = builder.frame_bind_group(&frame_uniforms);
        let shadow = ShadowPass::new(&builder, frame_group.clone(), SunMap::Own, maps.own);
        let board_shadow =
            ShadowPass::new(&builder, frame_group.clone(), SunMap::Board, maps.board);
        let ground = ground_params(scene.grass_key());
        let tiles = TileFrame::new(
            Light::axes(description.sun.lighting().direction()),
            scene.chunks().iter().map(|c| (c.centre, c.radius)),
        );
        let slot_uniforms = SlotUniforms::new(device);
        let slots = SlotsPass::new(&builder, slot_uniforms, tiles, maps.slots, ground);
        let main = MainPass::new(
            builder.main_pass(
                frame_uniforms,
                frame_group,
                description.textures.enabled,
                description.sun.soft_shadows,
            ),
            lookups,
            targets,
            &rig,
            Hood::new(&rig, &description.chase),
        );
        Ok(Renderer {
            scene,
            rig,
            options: options.clone(),
            gpu,
            geometry,
            ground,
            items: Vec::new(),
            shadow,
            board_shadow,
            slots,
            main,
            readback,
            stats: DrawStats::default(),
            street_lights,
        })
    }

    /// The adapter in use, e.g. `llvmpipe (LLVM 15.0.6, 256 bits) (Gl)`.
    pub fn adapter_name(&self) -> &str {
        &self.gpu.adapter_name
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
        let _one_at_a_time = display_lock(self.gpu.external);
        self.render_part_locked(input, needed)
    }

    /// [`Renderer::render_part`], with the display's lock held.
    fn render_part_locked(
        &mut self,
        input: &FrameInput,
        needed: Option<PixelRect>,
    ) -> Result<Frame, RenderError> {
        let description = self.scene.description();
        let expected = description.actors.len();
        let fields = std::iter::once(&input.world_from_actors)
            .chain(input.earlier_field.as_ref().map(|f| &f.world_from_actors));
        for poses in fields {
            if poses.len() != expected {
                return Err(RenderError::Actors {
                    expected,
                    got: poses.len(),
                });
            }
        }
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
        let speeds = Speeds {
            frame_index: input.frame_index,
            lead_mps: input.lead_speed_mps,
            actors_mps: &input.actor_speeds_mps,
        };
        let mut image = self.draw_field(
            &input.field(),
            input.auto_gain,
            input.braking,
            &speeds,
            scissor,
        )?;
        if let Some(earlier) = &input.earlier_field {
            // An interlaced camera: the odd rows are the earlier field's.
            let other =
                self.draw_field(earlier, input.auto_gain, input.braking, &speeds, scissor)?;
            interlace(&mut image, &other);
        }
        self.draw_rain(&mut image, input);
        self.apply_sensor(
            &mut image,
            input.frame_index,
            input.auto_gain,
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

    /// Draws the scene as it stands in `field`, with the automatic gain `auto_gain` and the
    /// brake lamps of the vehicles `braking` lit, the vehicles at `speeds`, in the
    /// pixels `scissor` of the frame, and reads back the rows `scissor` spans (the other
    /// rows are zero, and the pixels of those rows outside `scissor` the sky's grey).
    fn draw_field(
        &mut self,
        field: &Field,
        auto_gain: f64,
        braking: Braking,
        speeds: &Speeds,
        scissor: PixelRect,
    ) -> Result<GrayImage, RenderError> {
        let description = self.scene.description();
        let hood_rows = self
            .main
            .hood
            .rows(&self.rig, &description.chase, field.camera_pan_rad);

        // Poses: the camera from the chase chassis; every moving object's transform.
        let view = CameraView::new(&self.rig, field);
        let textured = self.main.textured();
        let placed = gather_items(&mut self.items, &self.scene, field, &view, textured);
        // Light fitting: the sun's frusta, fitted to the part of the camera's frustum drawn.
        let sun = self.fit_sun(&view, placed.board_centre, scissor);
        // The sensor's brightness, with the automatic gain: the shading's and the sky's.
        let brightness = description.sensor.brightness() * auto_gain;
        // In fog or rain, a ray that meets nothing crosses an infinite path of it: the sky
        // is their airlight (`SceneDescription::sky_light`). Below the horizon, the sky's light is the twilight's (`Sun::lighting`).
        let sun_light = description.sun.lighting();
        let sky_light = description.sky_light(&sun_light);
        let sky = (sky_light * brightness).clamp(0.0, 1.0);
        // Culling: what each pass draws; the geometry it draws made resident.
        let slot_work = self.cull(&view, &sun, scissor);
        if sun.window.is_some() {
            let vehicles = Vehicles {
                items: &self.items,
                draws: &self.shadow.draws,
                world_from_object: &placed.world_from_object,
                eye: &view.eye,
            };
            self.slots
                .prepare(self.scene.chunks(), &slot_work, &vehicles);
        }
        self.hold_drawn(&sun, &view.eye);
        // Uniforms: the frame's, written once.
        let sprayed = self.write_uniforms(&view, &sun, &placed, brightness, braking, field, speeds);

        // One encoder: the passes from the sun, the main pass, the copy to the staging
        // buffer; one submission.
        let mut encoder = self
            .gpu
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("frame"),
            });
        self.encode_sun_passes(&mut encoder, &sun);
        let from_tiles = sun.window.is_some();
        let geometry = &self.geometry;
        self.main.encode(
            &mut encoder,
            geometry,
            sky,
            scissor,
            hood_rows,
            from_tiles,
            sprayed,
        );
        // Only the rows of the part drawn come back.
        let rows = scissor.y0 as u32..scissor.y1 as u32;
        self.readback
            .copy(&mut encoder, &self.main.targets.color, rows.clone());
        self.gpu.queue.submit([encoder.finish()]);
        self.readback
            .read(&self.gpu.device, self.options.backend, rows)
    }

    /// Makes what the frame's passes draw resident (see `resident`), the camera at `eye`.
    fn hold_drawn(&mut self, sun: &Sunlight, eye: &Vector3<f64>) {
        let geometry = &mut self.geometry;
        for range in self.main.ranges() {
            geometry.want(range);
        }
        let [solid, leafy] = self.shadow.draws.lists();
        if sun.window.is_some() {
            for range in self.slots.ranges() {
                geometry.want(range);
            }
        } else {
            for range in solid.iter().chain(leafy) {
                geometry.want(range);
            }
        }
        if sun.board.is_some() {
            let [solid, leafy] = self.board_shadow.draws.lists();
            for range in solid.iter().chain(leafy) {
                geometry.want(range);
            }
        }
        geometry.hold(&self.gpu, &self.scene, eye);
    }

    /// How many times the geometry on the device has been made (a frame that draws what is
    /// not on it makes it again).
    pub fn geometry_loads(&self) -> u32 {
        self.geometry.loads()
    }

    /// The target's true position in the image and in the camera frame, for these poses.
    pub fn ground_truth(
        &self,
        world_from_chase: &Isometry3<f64>,
        world_from_lead: &Isometry3<f64>,
        camera_pan_rad: f64,
    ) -> GroundTruth {
        if self.scene.description().without_lead {
            return GroundTruth::ABSENT;
        }
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
    let inside = |x: f64, y: f64| {
        let p = camera_from_target * Point3::new(x, y, 0.0);
        rig.intrinsics
            .project([p.x, p.y, p.z])
            .is_some_and(|[u, v]| {
                (-0.5..f64::from(rig.width) - 0.5).contains(&u)
                    && (-0.5..f64::from(rig.height) - 0.5).contains(&v)
            })
    };
    let in_view = target.corners_m().iter().all(|&[x, y]| inside(x, y));
    // Some of the target in the image, not all: a point of a grid over the target's face
    // (its corners' bounding box, PARTLY_GRID points a side) projects inside.
    let partly_in_view = !in_view && {
        let [[x0, y0], [x1, y1]] = bounding_box(target.corners_m());
        let at = |a: f64, b: f64, k: usize| a + (b - a) * k as f64 / (PARTLY_GRID - 1) as f64;
        (0..PARTLY_GRID).any(|i| (0..PARTLY_GRID).any(|j| inside(at(x0, x1, i), at(y0, y1, j))))
    };
    GroundTruth {
        c_x,
        c_y,
        scale: target.nominal_range_m() / centre.z,
        target_cam_m,
        in_view,
        partly_in_view,
    }
}

/// Points a side of the grid over the target's face that tells a target partly in view
/// from one wholly out of it: a sliver narrower than 1/16 of the target counts as out.
const PARTLY_GRID: usize = 17;

/// The smallest and largest x and y of `points`.
fn bounding_box(points: &[[f64; 2]]) -> [[f64; 2]; 2] {
    points.iter().fold(
        [[f64::INFINITY; 2], [f64::NEG_INFINITY; 2]],
        |[[x0, y0], [x1, y1]], &[x, y]| [[x0.min(x), y0.min(y)], [x1.max(x), y1.max(y)]],
    )
}
