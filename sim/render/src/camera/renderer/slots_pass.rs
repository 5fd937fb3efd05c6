//! The slots pass: the draws into the static shadow tiles' slots (`shadow_tiles`). The tiles
//! a frame's window needs and its slots do not hold are drawn whole; the texels the last
//! frame's vehicles wrote are set back; then this frame's vehicles are drawn over them.

use super::culling::{push_merged, sort_merged, triangles, CasterDraws, DrawItem};
use super::light::{Light, Sunlight};
use super::pipelines::{Builder, Pass, Shading};
use super::resident::Resident;
use super::shadow_pass::{depth_pass, draw_casters};
use super::uniforms::{to_f32, Globals, ObjectTransforms, SlotUniforms};
use crate::camera::shadow_tiles::{self, Cell, SlotWork, Slots, TexelRect, TileFrame};
use crate::scene::{Chunk, Layer, ObjectSlot};
use nalgebra::{Translation3, Vector3};
use std::ops::Range;

/// The static shadow tiles' texture of slots, and its draws.
pub(super) struct SlotsPass {
    /// The static shadow tiles' frame: the light's axes and the grid the tiles are
    /// anchored to, with one depth mapping for the whole scene.
    pub tiles: TileFrame,
    /// Which tile each slot of their texture holds and where the vehicles were drawn.
    slots: Slots,
    /// The texture as a render target.
    view: wgpu::TextureView,
    /// Its pipelines (`vs_far`, which writes the cleared depth wherever it is scissored to,
    /// the casters and the canopies), and the uniforms of its draws (one entry a tile or
    /// the vehicles over a tile, picked by dynamic offset).
    pass: Pass<[wgpu::RenderPipeline; 3], SlotUniforms>,
    /// The grass's parameters, in every draw's globals.
    ground: [f32; 4],
    /// The frame's draws, and their uniforms' entries ([`SlotsPass::prepare`]).
    entries: Vec<(Globals, ObjectTransforms)>,
    draws: Vec<SlotDraw>,
}

/// The frame's vehicles, as the slots pass draws them.
pub(super) struct Vehicles<'a> {
    /// The frame's draw items.
    pub items: &'a [DrawItem],
    /// The moving casters the frame draws from the sun, solid and canopies: those of its
    /// items it draws.
    pub draws: &'a CasterDraws,
    /// Every object slot's transform, relative to the camera at `eye`.
    pub world_from_object: &'a ObjectTransforms,
    pub eye: &'a Vector3<f64>,
}

/// A draw into the slots' texture.
struct SlotDraw {
    /// Its viewport: x, y, width, height in the texture.
    viewport: [u32; 4],
    /// Its scissor, likewise.
    scissor: [u32; 4],
    /// Whether it clears its scissor first (a static tile's draw: the cleared depth).
    clear: bool,
    /// Its casters: solid, and canopies.
    casters: [Vec<Range<u32>>; 2],
}

impl SlotsPass {
    /// The pass into the slots' texture `view`, of the tiles of `tiles`.
    pub fn new(
        builder: &Builder,
        uniforms: SlotUniforms,
        tiles: TileFrame,
        view: wgpu::TextureView,
        ground: [f32; 4],
    ) -> SlotsPass {
        SlotsPass {
            tiles,
            slots: Slots::default(),
            view,
            pass: builder.slots_pass(uniforms),
            ground,
            entries: Vec::new(),
            draws: Vec::new(),
        }
    }

    /// The frame's work in the slots, with the `sun`'s window of tiles: none without one.
    pub fn plan(&mut self, items: &[DrawItem], sun: &Sunlight) -> SlotWork {
        let Some((window, light)) = &sun.window else {
            return SlotWork::default();
        };
        // Each moving caster's texels, as far as the fitted map reaches (the static
        // tiles reach further; the vehicles' shadows, as far as they always did).
        let rects: Vec<TexelRect> = items
            .iter()
            .filter(|d| {
                d.moving_caster()
                    && sun.fitted.holds(d.centre, d.radius)
                    && light.holds(d.centre, d.radius)
            })
            .map(|d| {
                let one = light
                    .caster_texels(d.centre, d.radius, sun.size)
                    .intersection(&sun.seen);
                TexelRect::of_window_texels(window.corner, one)
            })
            .filter(|r| !r.is_empty())
            .collect();
        self.slots.frame(window, &rects)
    }

    /// Makes the frame's draws into the slots' texture (`work`): the tiles drawn whole, the
    /// texels set back (the cleared depth, and the static casters there drawn again: the
    /// same draws as the tile's, so the same texels), then the `vehicles`.
    pub fn prepare(&mut self, chunks: &[Chunk], work: &SlotWork, vehicles: &Vehicles) {
        (self.entries, self.draws) = self.draws(chunks, work, vehicles);
    }

    /// The index ranges the frame's draws ([`SlotsPass::prepare`]) draw.
    pub fn ranges(&self) -> impl Iterator<Item = &Range<u32>> {
        self.draws.iter().flat_map(|d| d.casters.iter().flatten())
    }

    /// Encodes the frame's draws ([`SlotsPass::prepare`]). Returns the vehicles' triangles
    /// drawn.
    pub fn encode(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        queue: &wgpu::Queue,
        geometry: &Resident,
    ) -> u32 {
        let (entries, draws) = (&self.entries, &self.draws);
        if draws.is_empty() {
            return 0;
        }
        self.pass.uniforms.write(queue, entries);
        let [far, casters @ ..] = &self.pass.pipelines;
        let mut pass = depth_pass(encoder, "shadow tiles", &self.view, wgpu::LoadOp::Load);
        geometry.bind(&mut pass);
        let mut vehicle_triangles = 0;
        for (k, draw) in draws.iter().enumerate() {
            let offsets = self.pass.uniforms.offsets(k);
            pass.set_bind_group(0, &self.pass.bind_group, &offsets);
            let [vx, vy, vw, vh] = draw.viewport.map(|v| v as f32);
            pass.set_viewport(vx, vy, vw, vh, 0.0, 1.0);
            let [x, y, w, h] = draw.scissor;
            pass.set_scissor_rect(x, y, w, h);
            let [solid, leafy] = &draw.casters;
            if draw.clear {
                pass.set_pipeline(far);
                pass.draw(0..3, 0..1);
            } else {
                vehicle_triangles += triangles(solid) + triangles(leafy);
            }
            draw_casters(&mut pass, geometry, casters, [solid, leafy]);
        }
        vehicle_triangles
    }

    /// Every draw of `work`, and its uniforms' entry.
    fn draws(
        &self,
        chunks: &[Chunk],
        work: &SlotWork,
        vehicles: &Vehicles,
    ) -> (Vec<(Globals, ObjectTransforms)>, Vec<SlotDraw>) {
        let side = shadow_tiles::TILE_TEXELS;
        let in_tile = |cell: Cell, rect: TexelRect, casters| {
            let (a, b) = shadow_tiles::slot(cell);
            SlotDraw {
                viewport: [a as u32 * side, b as u32 * side, side, side],
                scissor: rect.in_slots(),
                clear: true,
                casters,
            }
        };
        let mut entries = Vec::new();
        let mut draws = Vec::new();
        for &cell in &work.tiles {
            entries.push(self.tile_entry(cell));
            let rect = TexelRect::of_cell(cell);
            draws.push(in_tile(cell, rect, self.static_casters(chunks, rect, true)));
        }
        for &(cell, rect) in &work.restore {
            entries.push(self.tile_entry(cell));
            draws.push(in_tile(
                cell,
                rect,
                self.static_casters(chunks, rect, false),
            ));
        }
        for &rect in &work.vehicles {
            entries.push(self.vehicle_entry(rect, vehicles));
            let texels = rect.in_slots();
            draws.push(SlotDraw {
                viewport: texels,
                scissor: texels,
                clear: false,
                casters: self.vehicle_casters(rect, vehicles),
            });
        }
        (entries, draws)
    }

    /// A tile's static casters within `rect` (all of them when `whole`), solid and
    /// canopies: whole chunks for a whole tile, else the chunks' parts that reach it.
    fn static_casters(
        &self,
        chunks: &[Chunk],
        rect: TexelRect,
        whole: bool,
    ) -> [Vec<Range<u32>>; 2] {
        let frame = &self.tiles;
        let (mut solid, mut leafy) = (Vec::new(), Vec::new());
        for chunk in chunks.iter().filter(|c| c.casts_shadow) {
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
    }

    /// A tile's uniforms: the sun's projection onto its square, its vertices relative to a
    /// point of the tile (as the frame's are to the camera), the same every time.
    fn tile_entry(&self, cell: Cell) -> (Globals, ObjectTransforms) {
        let frame = &self.tiles;
        let (min, max) = frame.tile_box(cell);
        let light = Light::of_box(frame.axes, min, max, shadow_tiles::TILE_TEXELS);
        let origin = frame.tile_origin(cell);
        let mut objects = [[[0f32; 4]; 4]; ObjectSlot::COUNT as usize];
        objects[ObjectSlot::WORLD as usize] = to_f32(&Translation3::from(-origin).to_homogeneous());
        (Globals::of_slot_draw(&light, &origin, self.ground), objects)
    }

    /// The vehicles' uniforms over texels `rect`: the sun's projection onto just those
    /// texels, the frame's transforms.
    fn vehicle_entry(&self, rect: TexelRect, vehicles: &Vehicles) -> (Globals, ObjectTransforms) {
        let frame = &self.tiles;
        let (min, max) = frame.texels_box(rect);
        let size = (rect.x1 - rect.x0).max(rect.r1 - rect.r0) as u32;
        let light = Light::of_box(frame.axes, min, max, size);
        (
            Globals::of_slot_draw(&light, vehicles.eye, self.ground),
            *vehicles.world_from_object,
        )
    }

    /// The moving casters that reach texels `rect`, of those the frame draws, solid and
    /// canopies.
    fn vehicle_casters(&self, rect: TexelRect, vehicles: &Vehicles) -> [Vec<Range<u32>>; 2] {
        let mut casters = [Vec::new(), Vec::new()];
        let drawn = vehicles.draws.lists();
        for item in vehicles
            .items
            .iter()
            .filter(|d| d.moving_caster() && self.tiles.reaches(rect, d.centre, d.radius))
        {
            let foliage = usize::from(item.shading == Shading::Foliage);
            if drawn[foliage]
                .iter()
                .any(|r| r.start <= item.indices.start && item.indices.end <= r.end)
            {
                casters[foliage].push(item.indices.clone());
            }
        }
        casters.map(|mut ranges| {
            let mut list = Vec::new();
            sort_merged(&mut list, &mut ranges);
            list
        })
    }
}
