//! Uniforms: the plain-data block `Globals` of `scene.wgsl` as a frame and a slot's draw fill
//! it, and the buffers that hold it with the object transforms.

use super::light::{Light, Sunlight, NORMAL_OFFSET_TEXELS};
use super::view::CameraView;
use super::wet_road::{mirror_params, spray_params, Speeds, MIRROR_VEC4S, SPRAY_VEC4S};
use super::Renderer;
use crate::camera::frame::Field;
use crate::camera::shadow_tiles::{self, TileFrame};
use crate::camera::textures::TILE_M;
use crate::scene::{
    Braking, Headlamps, ObjectSlot, Rain, SceneDescription, StreetLights, Sun, TailLamps,
    GRASS_ALBEDO_RANGE, GROUND_CELL_M,
};
use bytemuck::{Pod, Zeroable};
use nalgebra::{Matrix4, Point3, Translation3, Vector3};

/// The uniform block `Globals` of `scene.wgsl`.
#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
pub(super) struct Globals {
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
    fog: [f32; 4],
    lamps: [[f32; 4]; 5],
    rain: [f32; 4],
    glow: [[f32; 4]; GLOW_VEC4S],
    street: [[f32; 4]; STREET_VEC4S],
    spray: [[f32; 4]; SPRAY_VEC4S],
    mirror: [[f32; 4]; MIRROR_VEC4S],
}

/// `vec4`s of `Globals::glow`: a radiance for every object slot, four to a `vec4`.
const GLOW_VEC4S: usize = ObjectSlot::COUNT as usize / 4;

/// `vec4`s of `Globals::street`: one for each lamp lit in a frame, then the photometry's.
const STREET_VEC4S: usize = StreetLights::LIT_MAX + 1;

/// The strength of the paint's texture relative to the other materials': paint fills the
/// asphalt's pores, so its grain is faint.
const PAINT_DETAIL: f64 = 0.3;

impl Renderer {
    /// Writes the frame's uniforms (the main pass's, which the passes from the sun bind
    /// too): the camera's `view`, the `sun`'s maps, the moving objects as `placed`, and
    /// the sensor's `brightness` (with the automatic gain), and the brake lamps of the
    /// vehicles `braking` lit; in rain with its options, the spray of the vehicles as
    /// `field` poses them and `speeds` moves them, and the lamps the road mirrors. Returns
    /// whether any vehicle throws spray in the frame.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn write_uniforms(
        &self,
        view: &CameraView,
        sun: &Sunlight,
        placed: &Placed,
        brightness: f64,
        braking: Braking,
        field: &Field,
        speeds: &Speeds,
    ) -> bool {
        let description = self.scene.description();
        let globals = Globals::of_frame(
            view,
            sun,
            &self.slots.tiles,
            self.scene.description(),
            brightness,
            self.options.shadow_map_size,
            self.ground,
        );
        let globals = Globals {
            glow: glow_params(self.scene.description(), brightness, braking),
            street: street_params(&self.street_lights, view, brightness),
            spray: spray_params(
                description,
                field,
                speeds,
                view,
                &description.sun.lighting(),
                brightness,
            ),
            mirror: mirror_params(description, field, view, braking, brightness),
            ..globals
        };
        self.main
            .write_uniforms(&self.gpu.queue, &globals, &placed.world_from_object);
        // `spray_params`' first number: the plumes in the frame.
        globals.spray[0][0] > 0.0
    }
}

impl Globals {
    /// A frame's: the camera's `view`, the maps from the `sun`, the static tiles' frame
    /// `tiles`, the scene's `description`, the sensor's `brightness` (with the automatic
    /// gain), the side of the frame's own map and the grass's parameters ([`ground_params`]).
    ///
    /// A fragment looks its sunlight up in the slots' texture (texture coordinates straight
    /// from the lookup) or in the frame's own map (from its clip space, as the shadow pass
    /// drew it).
    pub fn of_frame(
        view: &CameraView,
        sun: &Sunlight,
        tiles: &TileFrame,
        description: &SceneDescription,
        brightness: f64,
        shadow_map_size: u32,
        ground: [f32; 4],
    ) -> Globals {
        let eye = &view.eye;
        let own_map = sun.fitted.clip_from_world * view.world_from_relative;
        let (lookup_view_proj, lookup_scale, lookup_bounds) = match &sun.window {
            Some((w, _)) => {
                let (m, bounds) = w.slots_lookup(&tiles.lookup(w.corner, eye));
                (to_f32(&m), [1.0, 1.0, 0.0, 0.0], bounds.map(|b| b as f32))
            }
            None => (
                to_f32(&own_map),
                [0.5, -0.5, 0.5, 0.5],
                [0.0, 0.0, 1.0, 1.0],
            ),
        };
        let sun_light = &description.sun.lighting();
        let towards_sun = sun_light.direction();
        Globals {
            view_proj: to_f32(&view.view_proj),
            light_view_proj: to_f32(&own_map),
            sun: [
                towards_sun[0] as f32,
                towards_sun[1] as f32,
                towards_sun[2] as f32,
                sun_light.strength as f32,
            ],
            params: [
                sun_light.ambient as f32,
                brightness as f32,
                (NORMAL_OFFSET_TEXELS * sun.lookup().texel_m) as f32,
                1.0 / shadow_map_size as f32,
            ],
            ground,
            origin: [eye.x as f32, eye.y as f32, eye.z as f32, 0.0],
            board_view_proj: sun.board.as_ref().map_or([[0.0; 4]; 4], |l| {
                to_f32(&(l.clip_from_world * view.world_from_relative))
            }),
            board: Sunlight::board_params(sun.board.as_ref()),
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
            fog: fog_params(description, sun_light, brightness),
            lamps: lamp_params(view, description, brightness),
            rain: rain_params(
                description,
                (description.sky_light(sun_light) * brightness).clamp(0.0, 1.0),
            ),
            glow: [[0.0; 4]; GLOW_VEC4S],
            street: [[0.0; 4]; STREET_VEC4S],
            spray: [[0.0; 4]; SPRAY_VEC4S],
            mirror: [[0.0; 4]; MIRROR_VEC4S],
        }
    }

    /// A draw into the slots' texture: the sun's projection `light` of positions relative to
    /// `origin` (a point of a tile, or the camera), and the grass's parameters.
    pub fn of_slot_draw(light: &Light, origin: &Vector3<f64>, ground: [f32; 4]) -> Globals {
        Globals {
            light_view_proj: to_f32(
                &(light.clip_from_world * Translation3::from(*origin).to_homogeneous()),
            ),
            origin: [origin.x as f32, origin.y as f32, origin.z as f32, 0.0],
            ground,
            ..Globals::zeroed()
        }
    }
}

/// The air's parameters in [`Globals`] (the fog's and the rain's, see
/// [`SceneDescription::extinction_per_m`]): the extinction β (per metre) and the airlight
/// under `sun_light` (the sun as it lights the scene) times the sensor's `brightness` (with
/// the automatic gain); zeros in clear air, whose pipelines never read them.
fn fog_params(description: &SceneDescription, sun_light: &Sun, brightness: f64) -> [f32; 4] {
    match description.extinction_per_m() {
        Some(beta) => [
            beta as f32,
            (Rain::airlight(sun_light) * brightness) as f32,
            0.0,
            0.0,
        ],
        None => [0.0; 4],
    }
}

/// The wet road's parameters in [`Globals`]: the factor on the road's albedo, the share a
/// water film covers, the sky's grey it mirrors (the sky drawn: `sky`, the sky's light
/// times the sensor's brightness, clamped to white) and water's reflectance at normal
/// incidence; zeros when no rain falls, whose pipelines never read them.
fn rain_params(description: &SceneDescription, sky: f64) -> [f32; 4] {
    match description.raining() {
        Some(rain) => [
            rain.wet_albedo_factor() as f32,
            rain.film_share() as f32,
            sky as f32,
            Rain::WATER_F0 as f32,
        ],
        None => [0.0; 4],
    }
}

/// The headlamps' parameters in [`Globals`]: each lamp's position relative to the camera
/// (world axes) with, in the first's w, its peak intensity in the scene's units (candela
/// over [`Headlamps::LUX_PER_UNIT`]) times the sensor's `brightness`; the chase's forward
/// and up axes with, in w, the reciprocals of the hot spot's horizontal and vertical
/// standard deviations (per radian); the aim and the cut-off's elevation (radians; the
/// cut-off far above without one), the stray share and the reciprocal of the cut-off's
/// width (per radian). Zeros with the lamps off, whose pipelines never read them.
fn lamp_params(
    view: &CameraView,
    description: &SceneDescription,
    brightness: f64,
) -> [[f32; 4]; 5] {
    let Some(beam) = description.headlamps else {
        return [[0.0; 4]; 5];
    };
    let lamp = Headlamps::of(beam);
    let chase = &view.world_from_chase;
    let at = |p: [f64; 3]| {
        let w = chase * Point3::new(p[0], p[1], p[2]);
        w.coords - view.eye
    };
    let [left, right] = Headlamps::positions(&description.chase);
    let (a, b) = (at(left), at(right));
    let forward = chase * Vector3::x();
    let up = chase * Vector3::y();
    let peak = lamp.peak_cd / Headlamps::LUX_PER_UNIT * brightness;
    [
        [a.x as f32, a.y as f32, a.z as f32, peak as f32],
        [b.x as f32, b.y as f32, b.z as f32, 0.0],
        [
            forward.x as f32,
            forward.y as f32,
            forward.z as f32,
            (1.0 / lamp.sigma_h_deg.to_radians()) as f32,
        ],
        [
            up.x as f32,
            up.y as f32,
            up.z as f32,
            (1.0 / lamp.sigma_v_deg.to_radians()) as f32,
        ],
        [
            lamp.aim_deg.to_radians() as f32,
            lamp.cut_off_deg.unwrap_or(90.0).to_radians() as f32,
            lamp.stray as f32,
            (1.0 / Headlamps::CUT_OFF_RAMP_DEG.to_radians()) as f32,
        ],
    ]
}

/// The tail lamps' radiance in [`Globals`], per object slot (slot `s` at `[s / 4][s % 4]`):
/// a lit lamp's lens's [`TailLamps::radiance`] (its brake lamp's too for a vehicle of
/// `braking`) times the sensor's `brightness`, over the lens's albedo (the shader adds it
/// to the light the lens's albedo multiplies). Zeros for slots without lamps, and all zeros
/// in a scene without them, whose pipelines never read them.
fn glow_params(
    description: &SceneDescription,
    brightness: f64,
    braking: Braking,
) -> [[f32; 4]; GLOW_VEC4S] {
    let mut glow = [[0.0; 4]; GLOW_VEC4S];
    let mut set = |slot: u32, braking: bool| {
        let value = TailLamps::radiance(braking) * brightness / TailLamps::LENS_ALBEDO;
        glow[slot as usize / 4][slot as usize % 4] = value as f32;
    };
    if description.lead.tail_lamps && !description.without_lead {
        set(ObjectSlot::LEAD, braking.lead());
    }
    for (k, actor) in description.actors.iter().enumerate() {
        if actor.tail_lamps {
            set(ObjectSlot::FIRST_ACTOR + k as u32, braking.actor(k));
        }
    }
    glow
}

/// The street lights' parameters in [`Globals`], from the lit lamps' `sources` (world; none
/// by day or without street lights, whose pipelines never read them): the
/// [`StreetLights::LIT_MAX`] nearest the camera's `view` (ties to the earlier on the route),
/// each its source relative to the camera and 1 in w (0: no lamp); then the cone's
/// half-angle (radians), the reciprocal of the cut-off's width (per radian), the lens's glow
/// ([`StreetLights::lens_radiance`] over [`StreetLights::LENS_ALBEDO`]) and the peak
/// intensity in the scene's units (candela over [`Headlamps::LUX_PER_UNIT`]), both times
/// the sensor's `brightness`.
fn street_params(
    sources: &[[f64; 3]],
    view: &CameraView,
    brightness: f64,
) -> [[f32; 4]; STREET_VEC4S] {
    let mut street = [[0.0; 4]; STREET_VEC4S];
    if sources.is_empty() {
        return street;
    }
    let eye = view.eye;
    let relative = |p: &[f64; 3]| Vector3::new(p[0], p[1], p[2]) - eye;
    let mut nearest: Vec<(f64, usize)> = sources
        .iter()
        .enumerate()
        .map(|(k, p)| (relative(p).norm_squared(), k))
        .collect();
    nearest.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
    for (slot, &(_, k)) in street
        .iter_mut()
        .zip(nearest.iter().take(StreetLights::LIT_MAX))
    {
        let r = relative(&sources[k]);
        *slot = [r.x as f32, r.y as f32, r.z as f32, 1.0];
    }
    street[StreetLights::LIT_MAX] = [
        StreetLights::CONE_HALF_DEG.to_radians() as f32,
        (1.0 / StreetLights::CUT_OFF_RAMP_DEG.to_radians()) as f32,
        (StreetLights::lens_radiance() * brightness / StreetLights::LENS_ALBEDO) as f32,
        (StreetLights::PEAK_CD / Headlamps::LUX_PER_UNIT * brightness) as f32,
    ];
    street
}

/// The grass's parameters in [`Globals`]: lattice frequency, albedo range, hash key (the
/// scene's, see [`crate::scene::Scene::grass_key`]).
pub(super) fn ground_params(grass_key: u32) -> [f32; 4] {
    [
        (1.0 / GROUND_CELL_M) as f32,
        GRASS_ALBEDO_RANGE[0] as f32,
        (GRASS_ALBEDO_RANGE[1] - GRASS_ALBEDO_RANGE[0]) as f32,
        grass_key as f32,
    ]
}

/// Column-major f32 copy of a matrix, as WGSL's `mat4x4<f32>` expects.
pub(super) fn to_f32(m: &Matrix4<f64>) -> [[f32; 4]; 4] {
    let mut out = [[0f32; 4]; 4];
    for (c, column) in out.iter_mut().enumerate() {
        for (r, value) in column.iter_mut().enumerate() {
            *value = m[(r, c)] as f32;
        }
    }
    out
}

/// Every object slot's transform (see `Objects` in `scene.wgsl`).
pub(super) type ObjectTransforms = [[[f32; 4]; 4]; ObjectSlot::COUNT as usize];

/// Bytes of [`Globals`].
const GLOBALS_BYTES: u64 = std::mem::size_of::<Globals>() as u64;
/// Bytes of the object transforms, one 4 × 4 matrix of `f32` per slot.
const OBJECTS_BYTES: u64 = 64 * ObjectSlot::COUNT as u64;

/// A pass's uniforms, the globals and the object transforms, in one buffer (the objects at
/// the first offset a binding may start at after the globals), so that a frame writes them
/// in one `write_buffer`: each write costs a staging buffer of its own.
pub(super) struct Uniforms {
    buffer: wgpu::Buffer,
    objects_offset: u64,
}

impl Uniforms {
    /// One entry, `size` bytes or, with `None`, just what it needs.
    fn with_size(device: &wgpu::Device, label: &str, size: Option<u64>) -> Uniforms {
        let objects_offset = Self::align(device, GLOBALS_BYTES);
        Uniforms {
            buffer: device.create_buffer(&wgpu::BufferDescriptor {
                label: Some(label),
                size: size.unwrap_or(objects_offset + OBJECTS_BYTES),
                usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
                mapped_at_creation: false,
            }),
            objects_offset,
        }
    }

    pub fn new(device: &wgpu::Device, label: &str) -> Uniforms {
        Self::with_size(device, label, None)
    }

    /// `bytes` rounded up to where a binding may start.
    fn align(device: &wgpu::Device, bytes: u64) -> u64 {
        let align = u64::from(device.limits().min_uniform_buffer_offset_alignment);
        bytes.div_ceil(align) * align
    }

    /// The globals' binding (`@binding(0)`).
    pub fn globals(&self) -> wgpu::BindingResource<'_> {
        wgpu::BindingResource::Buffer(wgpu::BufferBinding {
            buffer: &self.buffer,
            offset: 0,
            size: wgpu::BufferSize::new(GLOBALS_BYTES),
        })
    }

    /// The object transforms' binding (`@binding(1)`).
    pub fn objects(&self) -> wgpu::BindingResource<'_> {
        wgpu::BindingResource::Buffer(wgpu::BufferBinding {
            buffer: &self.buffer,
            offset: self.objects_offset,
            size: wgpu::BufferSize::new(OBJECTS_BYTES),
        })
    }

    pub fn write(&self, queue: &wgpu::Queue, globals: &Globals, objects: &ObjectTransforms) {
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

/// Draws into the slots' texture a frame may make: every slot's tile drawn whole or set
/// back, and the moving objects' texels (cut in up to four where the texture wraps).
const SLOT_ENTRIES: usize =
    shadow_tiles::WINDOW * shadow_tiles::WINDOW + 4 * ObjectSlot::COUNT as usize;

/// The uniforms of the draws into the slots' texture: [`Uniforms`]' layout once a draw,
/// `stride` bytes apart, each bound at its dynamic offset. All a frame's are written in
/// one `write_buffer`.
pub(super) struct SlotUniforms {
    entries: Uniforms,
    stride: u64,
}

impl SlotUniforms {
    pub fn new(device: &wgpu::Device) -> SlotUniforms {
        let stride = Uniforms::align(
            device,
            Uniforms::align(device, GLOBALS_BYTES) + OBJECTS_BYTES,
        );
        SlotUniforms {
            entries: Uniforms::with_size(
                device,
                "slot uniforms",
                Some(stride * SLOT_ENTRIES as u64),
            ),
            stride,
        }
    }

    /// The bindings of the first entry, which the dynamic offsets move.
    pub fn first(&self) -> &Uniforms {
        &self.entries
    }

    /// Writes the entries `entries`, from the first.
    pub fn write(&self, queue: &wgpu::Queue, entries: &[(Globals, ObjectTransforms)]) {
        if entries.is_empty() {
            return;
        }
        assert!(entries.len() <= SLOT_ENTRIES, "a window's draws at most");
        let stride = self.stride as usize;
        let size = wgpu::BufferSize::new((stride * entries.len()) as u64).expect("entries");
        let mut bytes = queue
            .write_buffer_with(&self.entries.buffer, 0, size)
            .expect("the write lies within the buffer");
        let offset = self.entries.objects_offset as usize;
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
    pub fn offsets(&self, k: usize) -> [u32; 2] {
        let at = (k as u64 * self.stride) as u32;
        [at, at]
    }
}

/// The moving objects as a field places them.
pub(super) struct Placed {
    /// Every object slot's transform, relative to the camera (the zero matrix for what is
    /// off the route).
    pub world_from_object: ObjectTransforms,
    /// The target board's centre, world frame (`None` without a lead).
    pub board_centre: Option<Point3<f64>>,
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The shader's array of object transforms has a matrix for every slot, the actors'
    /// included.
    #[test]
    fn the_shaders_object_array_holds_every_slot() {
        let shader = include_str!("../scene.wgsl");
        let array = format!(
            "world_from_object: array<mat4x4<f32>, {}>",
            ObjectSlot::COUNT
        );
        assert!(shader.contains(&array), "scene.wgsl lacks `{array}`");
        assert_eq!(OBJECTS_BYTES, 64 * 32);
    }
}
