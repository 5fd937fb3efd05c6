//! Pipelines: the shader, the bind group layouts, and every pass's pipelines and bind
//! groups, built into [`Pass`] values as in wgpu's shadow example: depth only from the sun,
//! shaded grey from the camera.

use super::resources::{ShadowMaps, ShadowSamplers, SurfaceTextures, COLOR_FORMAT, DEPTH_FORMAT};
use super::uniforms::{SlotUniforms, Uniforms};
use crate::scene::Vertex;

/// A pass as wgpu's shadow example has it: its pipelines, the bind group they draw with
/// (group 0), and the uniforms behind that group where the pass owns them (the passes from
/// the sun bind the frame's, which the main pass owns: `U` is then `()`).
pub(super) struct Pass<P, U> {
    pub pipelines: P,
    pub bind_group: wgpu::BindGroup,
    pub uniforms: U,
}

/// A pass from the sun's pipelines: the solid casters' (depth only) and the canopies' (with
/// a fragment stage that discards their holes).
pub(super) type CasterPipelines = [wgpu::RenderPipeline; 2];

/// Which pipeline of the main pass draws a piece of geometry.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Shading {
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

/// How a pipeline of the main pass is compiled (see [`Builder::shaded`]).
#[derive(Clone, Copy)]
struct Shaded {
    /// Whether it draws grass faces (the `grass_faces` override).
    grass: bool,
    /// Whether it takes soft shadows on the target from the board's fine map and the
    /// sun's disc (the fragment shader's `_soft` entry).
    soft: bool,
    /// Whether it veils what lies behind the vehicles' spray (the `spray_on` override;
    /// only in rain with spray).
    spray: bool,
}

/// The main pass's pipelines, one for each [`Shading`] the scene uses.
pub(super) struct ShadedPipelines {
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

/// Every pipeline of the main pass.
pub(super) struct MainPipelines {
    /// With the frame's shadow map and tiles alone.
    shaded: ShadedPipelines,
    /// With soft shadows on the target: the same with the board's fine map too, for what
    /// can lie within it (see `Sunlight::in_board_map`).
    soft: Option<ShadedPipelines>,
    /// In rain with spray, the same two compiled without it (`spray_on` off), for the
    /// frames in which no vehicle throws any (all below the spray's onset): they draw the
    /// same pixels bit for bit (the march through no plume keeps a surface's grey as it
    /// is), and on llvmpipe the spray's pipelines cost a frame with no plume half as much
    /// again as these (`examples/weather/cost.py`).
    unsprayed: Option<(ShadedPipelines, Option<ShadedPipelines>)>,
    /// Sets the main pass's depth back to the cleared depth under the scissor of a part of
    /// a frame, its colour left alone (`vs_far`, `fs_far`): instead of clearing the whole
    /// depth target (a whole frame's is cleared).
    pub far: wgpu::RenderPipeline,
}

impl MainPipelines {
    /// The pipeline that draws `shading`, with soft shadows on the target (`soft`) when the
    /// scene has them, in a frame in which some vehicle throws spray (`sprayed`) or none.
    pub fn of(&self, shading: Shading, soft: bool, sprayed: bool) -> &wgpu::RenderPipeline {
        let (shaded, soft_pipelines) = match &self.unsprayed {
            Some((shaded, soft_pipelines)) if !sprayed => (shaded, soft_pipelines),
            _ => (&self.shaded, &self.soft),
        };
        match soft_pipelines {
            Some(soft_pipelines) if soft => soft_pipelines.of(shading),
            _ => shaded.of(shading),
        }
    }

    /// Whether the ground's surfaces are textured (they have pipelines of their own).
    pub fn textured(&self) -> bool {
        self.shaded.ground.is_some()
    }
}

/// The main pass's group 1, its shadow lookups and the ground's textures: one a map its
/// shadow lookups may read.
pub(super) struct Lookups {
    /// Reading the slots' texture of the static tiles and the vehicles (`shadow_tiles`)...
    pub tiles: wgpu::BindGroup,
    /// ...or the frame's own map, which then holds every caster.
    pub own_map: wgpu::BindGroup,
}

/// The attributes of [`Vertex`]: position, normal, albedo, object.
const VERTEX_ATTRIBUTES: [wgpu::VertexAttribute; 4] =
    wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x3, 2 => Float32, 3 => Uint32];

/// The one vertex buffer every pipeline that draws the scene reads.
const VERTEX_BUFFERS: [Option<wgpu::VertexBufferLayout<'static>>; 1] =
    [Some(wgpu::VertexBufferLayout {
        array_stride: std::mem::size_of::<Vertex>() as u64,
        step_mode: wgpu::VertexStepMode::Vertex,
        attributes: &VERTEX_ATTRIBUTES,
    })];

/// What the pipelines and bind groups are made of: the shader, the bind group layouts and
/// the pipeline layouts over them.
pub(super) struct Builder<'d> {
    device: &'d wgpu::Device,
    shader: wgpu::ShaderModule,
    /// The main pass's samples (MSAA).
    samples: u32,
    /// Whether the main pass's pipelines fog what they shade (the `fog_on` override): only a
    /// scene in fog pays for it, and a scene without draws what it drew before fog existed.
    fog: bool,
    /// Whether the main pass's pipelines add the chase's headlamps' light (the
    /// `headlamps_on` override): off, a scene is drawn as before headlamps existed.
    headlamps: bool,
    /// Whether the main pass's pipelines wet the road (the `rain_on` override): off, a
    /// scene is drawn as before rain existed.
    rain: bool,
    /// Whether the main pass's pipelines let tail lamps glow (the `tail_lamps_on`
    /// override): off, a scene is drawn as before tail lamps existed.
    tail_lamps: bool,
    /// Whether the main pass's pipelines add the street lights' light and let their lenses
    /// glow (the `street_lights_on` override, at night with street lights): off, a scene is
    /// drawn as before street lights existed.
    street_lights: bool,
    /// Whether the main pass's pipelines veil what lies behind the vehicles' spray (the
    /// `spray_on` override, in rain with spray): off, a scene is drawn as before spray
    /// existed.
    spray: bool,
    /// Whether the main pass's pipelines let the wet road mirror the lit lamps (the
    /// `mirror_on` override): off, a scene is drawn as before mirrored lamps existed.
    mirror: bool,
    /// Group 0 of the frame's passes: the globals and the object transforms.
    frame_layout: wgpu::BindGroupLayout,
    /// Group 1 of the main pass: the shadow lookups and the ground's textures.
    lookup_layout: wgpu::BindGroupLayout,
    /// Group 0 of the draws into the slots: the same as the frame's, at dynamic offsets.
    slot_layout: wgpu::BindGroupLayout,
    shadow_pipeline_layout: wgpu::PipelineLayout,
    slot_pipeline_layout: wgpu::PipelineLayout,
    main_pipeline_layout: wgpu::PipelineLayout,
}

impl<'d> Builder<'d> {
    /// The shader and the layouts, for a main pass of `samples` samples, in `fog` (any
    /// extinction of the air: fog's or rain's) or not, with the `headlamps` on or not,
    /// `rain` wetting the road or not, `tail_lamps` or not, `street_lights` lit or not, the
    /// vehicles' `spray` or not and the lamps mirrored on the wet road (`mirror`) or not.
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        device: &'d wgpu::Device,
        samples: u32,
        fog: bool,
        headlamps: bool,
        rain: bool,
        tail_lamps: bool,
        street_lights: bool,
        spray: bool,
        mirror: bool,
    ) -> Builder<'d> {
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
        let uniforms_layout = |label, has_dynamic_offset| {
            device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
                label: Some(label),
                entries: &[
                    uniform_entry(0, has_dynamic_offset),
                    uniform_entry(1, has_dynamic_offset),
                ],
            })
        };
        let frame_layout = uniforms_layout("frame", false);
        let slot_layout = uniforms_layout("slot", true);
        let lookup_layout = lookup_layout(device);
        let pipeline_layout = |label, groups: &[Option<&wgpu::BindGroupLayout>]| {
            device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
                label: Some(label),
                bind_group_layouts: groups,
                immediate_size: 0,
            })
        };
        let shadow_pipeline_layout = pipeline_layout("shadow", &[Some(&frame_layout)]);
        let slot_pipeline_layout = pipeline_layout("slot", &[Some(&slot_layout)]);
        let main_pipeline_layout =
            pipeline_layout("main", &[Some(&frame_layout), Some(&lookup_layout)]);
        let shader = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("scene.wgsl"),
            source: wgpu::ShaderSource::Wgsl(include_str!("../scene.wgsl").into()),
        });
        Builder {
            device,
            shader,
            samples,
            fog,
            headlamps,
            rain,
            tail_lamps,
            street_lights,
            spray,
            mirror,
            frame_layout,
            lookup_layout,
            slot_layout,
            shadow_pipeline_layout,
            slot_pipeline_layout,
            main_pipeline_layout,
        }
    }

    /// The frame's group 0 over its uniforms: bound by the passes from the sun and the main
    /// pass.
    pub fn frame_bind_group(&self, uniforms: &Uniforms) -> wgpu::BindGroup {
        self.uniforms_group("frame", &self.frame_layout, uniforms)
    }

    /// A group 0 of the globals and the object transforms in `uniforms`.
    fn uniforms_group(
        &self,
        label: &str,
        layout: &wgpu::BindGroupLayout,
        uniforms: &Uniforms,
    ) -> wgpu::BindGroup {
        self.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some(label),
            layout,
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
    }

    /// The main pass's group 1 for each map its lookups may read, with the board's fine map
    /// and the ground's textures.
    pub fn lookups(
        &self,
        maps: &ShadowMaps,
        surfaces: &SurfaceTextures,
        samplers: &ShadowSamplers,
    ) -> Lookups {
        // Bindings 0 to 5, in the order of `lookup_layout`.
        let lookup_group = |label, view, sampler| {
            let entries: Vec<wgpu::BindGroupEntry> = [
                wgpu::BindingResource::TextureView(view),
                wgpu::BindingResource::Sampler(sampler),
                wgpu::BindingResource::TextureView(&maps.board),
                wgpu::BindingResource::TextureView(&surfaces.view),
                wgpu::BindingResource::Sampler(&surfaces.sampler),
                wgpu::BindingResource::Sampler(&samplers.clamped),
            ]
            .into_iter()
            .zip(0..)
            .map(|(resource, binding)| wgpu::BindGroupEntry { binding, resource })
            .collect();
            self.device.create_bind_group(&wgpu::BindGroupDescriptor {
                label: Some(label),
                layout: &self.lookup_layout,
                entries: &entries,
            })
        };
        Lookups {
            tiles: lookup_group("shadow tiles", &maps.slots, &samplers.repeating),
            own_map: lookup_group("shadow map", &maps.own, &samplers.clamped),
        }
    }

    /// A pass from the sun into `map`, drawing with the frame's group 0 `frame_group`.
    pub fn sun_pass(&self, frame_group: wgpu::BindGroup, map: SunMap) -> Pass<CasterPipelines, ()> {
        let layout = &self.shadow_pipeline_layout;
        let fragment = Some("fs_foliage_shadow");
        let pipelines = if map == SunMap::Board {
            [
                self.depth_only("board shadow", layout, "vs_board_shadow", None),
                self.depth_only(
                    "foliage board shadow",
                    layout,
                    "vs_foliage_board_shadow",
                    fragment,
                ),
            ]
        } else {
            [
                self.depth_only("shadow", layout, "vs_shadow", None),
                self.depth_only("foliage shadow", layout, "vs_foliage_shadow", fragment),
            ]
        };
        Pass {
            pipelines,
            bind_group: frame_group,
            uniforms: (),
        }
    }

    /// The draws into the static shadow tiles' slots: `vs_far` (writes the cleared depth
    /// wherever it is scissored to), the casters and the canopies, over `uniforms`.
    pub fn slots_pass(
        &self,
        uniforms: SlotUniforms,
    ) -> Pass<[wgpu::RenderPipeline; 3], SlotUniforms> {
        let layout = &self.slot_pipeline_layout;
        let pipelines = [
            self.far("far", layout, wgpu::MultisampleState::default(), None),
            self.depth_only("tile shadow", layout, "vs_shadow", None),
            self.depth_only(
                "tile foliage shadow",
                layout,
                "vs_foliage_shadow",
                Some("fs_foliage_shadow"),
            ),
        ];
        let bind_group = self.uniforms_group("slot", &self.slot_layout, uniforms.first());
        Pass {
            pipelines,
            bind_group,
            uniforms,
        }
    }

    /// The main pass, over the frame's `uniforms` (its group 0 `frame_group`): the ground's
    /// textured pipelines when `textured`, the soft-shadow ones too when `soft` (soft
    /// shadows on the target: the board's fine map and the sun's disc).
    pub fn main_pass(
        &self,
        uniforms: Uniforms,
        frame_group: wgpu::BindGroup,
        textured: bool,
        soft: bool,
    ) -> Pass<MainPipelines, Uniforms> {
        let far = self.far(
            "main far",
            &self.main_pipeline_layout,
            wgpu::MultisampleState {
                count: self.samples,
                ..Default::default()
            },
            Some(wgpu::FragmentState {
                module: &self.shader,
                entry_point: Some("fs_far"),
                compilation_options: Default::default(),
                targets: &[Some(wgpu::ColorTargetState {
                    format: COLOR_FORMAT,
                    blend: None,
                    write_mask: wgpu::ColorWrites::empty(),
                })],
            }),
        );
        Pass {
            pipelines: MainPipelines {
                shaded: self.shaded_pipelines(textured, false, self.spray),
                soft: soft.then(|| self.shaded_pipelines(textured, true, self.spray)),
                unsprayed: self.spray.then(|| {
                    (
                        self.shaded_pipelines(textured, false, false),
                        soft.then(|| self.shaded_pipelines(textured, true, false)),
                    )
                }),
                far,
            },
            bind_group: frame_group,
            uniforms,
        }
    }

    /// One of each pipeline of the main pass the scene uses (see [`Builder::shaded`]), with
    /// the vehicles' spray (`spray`) or without.
    fn shaded_pipelines(&self, textured: bool, soft: bool, spray: bool) -> ShadedPipelines {
        let back = Some(wgpu::Face::Back);
        let with = |grass, soft| Shaded { grass, soft, spray };
        ShadedPipelines {
            main: self.shaded("main", "vs_main", "fs_main", back, with(false, soft)),
            grass: (!textured)
                .then(|| self.shaded("grass", "vs_main", "fs_main", back, with(true, soft))),
            ground: textured.then(|| {
                [false, true].map(|grass| {
                    self.shaded("ground", "vs_ground", "fs_ground", back, with(grass, soft))
                })
            }),
            foliage: self.shaded(
                "foliage",
                "vs_foliage",
                "fs_foliage",
                None,
                with(false, soft),
            ),
        }
    }

    /// Depth only, from the sun: the main shadow map (`vs_shadow`) and the board's
    /// (`vs_board_shadow`); canopies with a fragment stage that discards their holes.
    fn depth_only(
        &self,
        label: &str,
        layout: &wgpu::PipelineLayout,
        entry: &str,
        fragment: Option<&str>,
    ) -> wgpu::RenderPipeline {
        self.device
            .create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                label: Some(label),
                layout: Some(layout),
                vertex: self.vertex_state(entry),
                // Every closed mesh is wound counter-clockwise seen from outside
                // (`Mesh::orient_faces`), open ones are two-sided: back faces never show.
                // A canopy's clumps cast from their sunlit side alone (as the outer leaves
                // of a real clump do most of its shading).
                primitive: wgpu::PrimitiveState {
                    cull_mode: Some(wgpu::Face::Back),
                    ..Default::default()
                },
                depth_stencil: depth_state(
                    wgpu::CompareFunction::LessEqual,
                    // A little slope-scaled bias on top of the normal offset, for grazing light.
                    wgpu::DepthBiasState {
                        constant: 2,
                        slope_scale: 1.5,
                        clamp: 0.0,
                    },
                ),
                multisample: wgpu::MultisampleState::default(),
                fragment: fragment.map(|entry| wgpu::FragmentState {
                    module: &self.shader,
                    entry_point: Some(entry),
                    compilation_options: Default::default(),
                    targets: &[],
                }),
                multiview_mask: None,
                cache: None,
            })
    }

    /// Writes the cleared depth (1) wherever it is scissored to, whatever was there (the
    /// main pass's depth set back under the scissor, a slot's vehicles' texels set back).
    fn far(
        &self,
        label: &str,
        layout: &wgpu::PipelineLayout,
        multisample: wgpu::MultisampleState,
        fragment: Option<wgpu::FragmentState>,
    ) -> wgpu::RenderPipeline {
        self.device
            .create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                label: Some(label),
                layout: Some(layout),
                vertex: wgpu::VertexState {
                    module: &self.shader,
                    entry_point: Some("vs_far"),
                    compilation_options: Default::default(),
                    buffers: &[],
                },
                primitive: wgpu::PrimitiveState::default(),
                depth_stencil: depth_state(
                    wgpu::CompareFunction::Always,
                    wgpu::DepthBiasState::default(),
                ),
                multisample,
                fragment,
                multiview_mask: None,
                cache: None,
            })
    }

    /// A pipeline of the main pass, compiled as `options` says.
    fn shaded(
        &self,
        label: &str,
        vertex: &str,
        fragment: &str,
        cull: Option<wgpu::Face>,
        options: Shaded,
    ) -> wgpu::RenderPipeline {
        let Shaded { grass, soft, spray } = options;
        let mut constants = vec![
            ("grass_faces", f64::from(u8::from(grass))),
            ("fog_on", f64::from(u8::from(self.fog))),
            ("headlamps_on", f64::from(u8::from(self.headlamps))),
            ("rain_on", f64::from(u8::from(self.rain))),
        ];
        // The tail lamps are the vertex stage's (a lamp's vertices carry its mark), the street
        // lights both stages' (their light, and their lenses' marks); without them each
        // stage is compiled as before they existed.
        let mut lamp_constants = Vec::new();
        if self.tail_lamps {
            lamp_constants.push(("tail_lamps_on", 1.0));
        }
        if self.street_lights {
            lamp_constants.push(("street_lights_on", 1.0));
            constants.push(("street_lights_on", 1.0));
        }
        // Rain's options are the fragment stage's; without them it is compiled as before.
        if spray {
            constants.push(("spray_on", 1.0));
        }
        if self.mirror {
            constants.push(("mirror_on", 1.0));
        }
        let mut vertex_state = self.vertex_state(vertex);
        if !lamp_constants.is_empty() {
            vertex_state.compilation_options.constants = &lamp_constants;
        }
        self.device
            .create_render_pipeline(&wgpu::RenderPipelineDescriptor {
                label: Some(label),
                layout: Some(&self.main_pipeline_layout),
                vertex: vertex_state,
                // Every closed mesh is wound counter-clockwise seen from outside
                // (`Mesh::orient_faces`), open ones are two-sided: back faces never show
                // (canopies' do, through their holes).
                primitive: wgpu::PrimitiveState {
                    cull_mode: cull,
                    ..Default::default()
                },
                depth_stencil: depth_state(
                    wgpu::CompareFunction::Less,
                    wgpu::DepthBiasState::default(),
                ),
                multisample: wgpu::MultisampleState {
                    count: self.samples,
                    ..Default::default()
                },
                fragment: Some(wgpu::FragmentState {
                    module: &self.shader,
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
    }

    /// The vertex stage `entry`, reading [`Vertex`]es.
    fn vertex_state<'a>(&'a self, entry: &'a str) -> wgpu::VertexState<'a> {
        wgpu::VertexState {
            module: &self.shader,
            entry_point: Some(entry),
            compilation_options: Default::default(),
            buffers: &VERTEX_BUFFERS,
        }
    }
}

/// A depth test of `compare` that writes depth, with `bias`.
fn depth_state(
    compare: wgpu::CompareFunction,
    bias: wgpu::DepthBiasState,
) -> Option<wgpu::DepthStencilState> {
    Some(wgpu::DepthStencilState {
        format: DEPTH_FORMAT,
        depth_write_enabled: Some(true),
        depth_compare: Some(compare),
        stencil: wgpu::StencilState::default(),
        bias,
    })
}

/// The layout of the main pass's group 1: the shadow lookups' map (0) and its comparison
/// sampler (1), the board's fine map (2), the ground's textures (3) and their sampler (4),
/// and the board's map's comparison sampler (5).
fn lookup_layout(device: &wgpu::Device) -> wgpu::BindGroupLayout {
    let fragment = |binding, ty| wgpu::BindGroupLayoutEntry {
        binding,
        visibility: wgpu::ShaderStages::FRAGMENT,
        ty,
        count: None,
    };
    let depth_map = wgpu::BindingType::Texture {
        sample_type: wgpu::TextureSampleType::Depth,
        view_dimension: wgpu::TextureViewDimension::D2,
        multisampled: false,
    };
    let comparison = wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Comparison);
    device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
        label: Some("shadow"),
        entries: &[
            fragment(0, depth_map),
            fragment(1, comparison),
            fragment(2, depth_map),
            fragment(
                3,
                wgpu::BindingType::Texture {
                    sample_type: wgpu::TextureSampleType::Float { filterable: true },
                    view_dimension: wgpu::TextureViewDimension::D2Array,
                    multisampled: false,
                },
            ),
            fragment(
                4,
                wgpu::BindingType::Sampler(wgpu::SamplerBindingType::Filtering),
            ),
            fragment(5, comparison),
        ],
    })
}

/// Which map a pass from the sun draws.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum SunMap {
    /// The frame's own map (`vs_shadow`).
    Own,
    /// The board's fine map (`vs_board_shadow`).
    Board,
}
