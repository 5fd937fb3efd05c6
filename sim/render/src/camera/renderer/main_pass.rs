//! The main pass: what the camera's frustum holds, shaded grey front to back into the
//! frame, its shadow lookups in the slots' texture or the frame's own map; and the rows the
//! chase vehicle's hood covers, which it scissors away.

use super::culling::{DrawItem, Frustum, HOOD_CLASS};
use super::light::Sunlight;
use super::pipelines::{Lookups, MainPipelines, Pass, Shading};
use super::resident::Resident;
use super::resources::Targets;
use super::uniforms::{Globals, ObjectTransforms, Uniforms};
use crate::camera::rig::{CameraRig, NEAR_M};
use crate::scene::{ChaseVehicle, Chunk};
use nalgebra::{Point3, Vector3};
use std::ops::Range;
use tracker::PixelRect;

/// The main pass: its pipelines, the frame's bind group and uniforms (which the passes from
/// the sun bind too), its shadow lookups, its targets, and what it draws this frame.
pub(super) struct MainPass {
    pass: Pass<MainPipelines, Uniforms>,
    lookups: Lookups,
    pub targets: Targets,
    /// The whole frame's pixels.
    whole: PixelRect,
    /// The rows the hood covers.
    pub hood: Hood,
    /// The indices of the items the frustum holds (kept to avoid allocating every frame).
    in_view: Vec<usize>,
    /// The frame's draws, in order.
    draws: Vec<MainDraw>,
    /// How many of them draw the hood: drawn first, unscissored.
    hood_draws: usize,
}

/// A draw of the main pass: an index range, its pipeline, and whether it may lie within
/// the board's fine shadow map (then the soft-shadow pipelines draw it; see
/// [`Sunlight::in_board_map`]).
struct MainDraw {
    indices: Range<u32>,
    shading: Shading,
    soft: bool,
}

impl MainPass {
    pub fn new(
        pass: Pass<MainPipelines, Uniforms>,
        lookups: Lookups,
        targets: Targets,
        rig: &CameraRig,
        hood: Hood,
    ) -> MainPass {
        MainPass {
            pass,
            lookups,
            targets,
            whole: PixelRect::whole(rig.width as usize, rig.height as usize),
            hood,
            in_view: Vec::new(),
            draws: Vec::new(),
            hood_draws: 0,
        }
    }

    /// Whether the ground's surfaces are textured.
    pub fn textured(&self) -> bool {
        self.pass.pipelines.textured()
    }

    /// Writes the frame's uniforms, which the passes from the sun read too.
    pub fn write_uniforms(
        &self,
        queue: &wgpu::Queue,
        globals: &Globals,
        world_from_object: &ObjectTransforms,
    ) {
        self.pass.uniforms.write(queue, globals, world_from_object);
    }

    /// The frame's draws: what the camera's `frustum` holds of `items` (the static chunks
    /// part by part, of `chunks`), front to back (by class, then by distance), so early
    /// depth testing rejects hidden fragments before shading them; each with the
    /// soft-shadow pipelines where the `sun`'s board map may reach it.
    pub fn cull(
        &mut self,
        items: &[DrawItem],
        frustum: &Frustum,
        chunks: &[Chunk],
        sun: &Sunlight,
    ) {
        let draws = &mut self.draws;
        draws.clear();
        // Only what the frustum holds is sorted (a tenth of the items, typically); the
        // sort is stable, so the order is the whole list's, sorted and then filtered.
        let in_view = &mut self.in_view;
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
        for item in in_view.iter().map(|&i| &items[i]) {
            if item.class == HOOD_CLASS {
                draws.push(MainDraw {
                    indices: item.indices.clone(),
                    shading: item.shading,
                    soft: sun.in_board_map(item.centre, item.radius),
                });
                hood_draws = draws.len();
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
            for (indices, centre, radius) in whole.chain(visible) {
                let draw = MainDraw {
                    indices,
                    shading: item.shading,
                    soft: sun.in_board_map(centre, radius),
                };
                if draws.len() == hood_draws {
                    // Never joined to the hood's draw: what follows is scissored.
                    draws.push(draw);
                    continue;
                }
                // Joined to the last draw when they touch and share a pipeline.
                match draws.last_mut() {
                    Some(last)
                        if last.indices.end == draw.indices.start
                            && (last.shading, last.soft) == (draw.shading, draw.soft) =>
                    {
                        last.indices.end = draw.indices.end
                    }
                    _ => draws.push(draw),
                }
            }
        }
        self.hood_draws = hood_draws;
    }

    /// Triangles the frame's draws hold: all of them, or (`soft_only`) those drawn with
    /// soft shadows on the target.
    pub fn triangles(&self, soft_only: bool) -> u32 {
        self.draws
            .iter()
            .filter(|d| d.soft || !soft_only)
            .map(|d| (d.indices.end - d.indices.start) / 3)
            .sum()
    }

    /// The index ranges the frame's draws draw.
    pub fn ranges(&self) -> impl Iterator<Item = &Range<u32>> {
        self.draws.iter().map(|d| &d.indices)
    }

    /// The frame's draw calls.
    pub fn draw_calls(&self) -> usize {
        self.draws.len()
    }

    /// Encodes the pass: the frame cleared to the `sky`'s grey, and the frame's draws in
    /// the pixels `scissor` of the frame, with the rows from `hood_rows` down left to the
    /// hood; its shadow lookups in the slots' texture (`from_tiles`) or the frame's own map;
    /// with the pipelines that veil what lies behind the spray only when some vehicle
    /// throws any (`sprayed`).
    #[allow(clippy::too_many_arguments)]
    pub fn encode(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        geometry: &Resident,
        sky: f64,
        scissor: PixelRect,
        hood_rows: u32,
        from_tiles: bool,
        sprayed: bool,
    ) {
        let whole = self.whole;
        // A whole frame's depth is cleared with the colour: a clear fills llvmpipe's tiles
        // without shading them, where `far` shades every pixel (the same depth, 1, either way).
        let clear_depth = scissor == whole;
        let mut pass = self.begin(encoder, sky, clear_depth);
        pass.set_bind_group(0, &self.pass.bind_group, &[]);
        let lookups = if from_tiles {
            &self.lookups.tiles
        } else {
            &self.lookups.own_map
        };
        pass.set_bind_group(1, lookups, &[]);
        geometry.bind(&mut pass);
        // Only the part of the frame asked for is shaded.
        if scissor.is_empty() {
            return;
        }
        if scissor != whole {
            set_scissor(&mut pass, scissor);
        }
        let pipelines = &self.pass.pipelines;
        if !clear_depth {
            pass.set_pipeline(&pipelines.far);
            pass.draw(0..3, 0..1);
        }
        let mut current = None;
        for (k, draw) in self.draws.iter().enumerate() {
            if current != Some((draw.shading, draw.soft)) {
                pass.set_pipeline(pipelines.of(draw.shading, draw.soft, sprayed));
                current = Some((draw.shading, draw.soft));
            }
            if k == self.hood_draws && (hood_rows as usize) < whole.y1 {
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
            geometry.draw(&mut pass, draw.indices.clone());
        }
    }

    /// Begins the pass, the colour cleared to `sky`, and the depth too when `clear_depth`
    /// (a whole frame).
    fn begin<'e>(
        &self,
        encoder: &'e mut wgpu::CommandEncoder,
        sky: f64,
        clear_depth: bool,
    ) -> wgpu::RenderPass<'e> {
        let targets = &self.targets;
        let (view, resolve_target) = match &targets.msaa_view {
            Some(msaa) => (msaa, Some(&targets.color_view)),
            None => (&targets.color_view, None),
        };
        // The colour is cleared whole (drawing the sky under the scissor instead shades
        // every pixel of the part, which costs more than the clear saves); the depth of a
        // part is set back under the scissor alone, by the first draw (llvmpipe's
        // whole-target clear is a fill of every 64² tile), and of a whole frame cleared;
        // it is stored, since a discarded target would be cleared whole again before it is
        // next loaded.
        encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
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
                view: &targets.depth_view,
                depth_ops: Some(wgpu::Operations {
                    load: if clear_depth {
                        wgpu::LoadOp::Clear(1.0)
                    } else {
                        wgpu::LoadOp::Load
                    },
                    store: wgpu::StoreOp::Store,
                }),
                stencil_ops: None,
            }),
            timestamp_writes: None,
            occlusion_query_set: None,
            multiview_mask: None,
        })
    }
}

/// Scissors `pass` to the pixels `r`.
fn set_scissor(pass: &mut wgpu::RenderPass, r: PixelRect) {
    pass.set_scissor_rect(
        r.x0 as u32,
        r.y0 as u32,
        r.width() as u32,
        r.height() as u32,
    )
}

/// The rows the chase vehicle's hood covers, which the main pass scissors away.
pub(super) struct Hood {
    /// The first image row from which the hood covers every pixel to the bottom, for the
    /// camera straight ahead (the hood moves with the camera, so this changes only when the
    /// camera pans); later draws are scissored above it.
    straight: u32,
    /// The same for the last panned angle seen, as (angle's bits, row).
    panned: Option<(u64, u32)>,
}

impl Hood {
    pub fn new(rig: &CameraRig, chase: &ChaseVehicle) -> Hood {
        Hood {
            straight: hood_row(rig, chase, 0.0),
            panned: None,
        }
    }

    /// The first row the hood covers from edge to edge, for the camera panned by `pan_rad`.
    pub fn rows(&mut self, rig: &CameraRig, chase: &ChaseVehicle, pan_rad: f64) -> u32 {
        if pan_rad == 0.0 {
            return self.straight;
        }
        match self.panned {
            Some((bits, row)) if bits == pan_rad.to_bits() => row,
            _ => {
                let row = hood_row(rig, chase, pan_rad);
                self.panned = Some((pan_rad.to_bits(), row));
                row
            }
        }
    }
}

/// The first row from which the ray through every pixel centre below hits the hood (one
/// row of margin above that for rasterisation's edge rules); `rig.height` if there is none.
fn hood_row(rig: &CameraRig, chase: &ChaseVehicle, camera_pan_rad: f64) -> u32 {
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
        let (mut near, mut far) = (NEAR_M, f64::MAX);
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
