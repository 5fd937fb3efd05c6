//! The shadow pass: the casters drawn depth only from the sun into a map of the frame's
//! own, and the board's fine map (with soft shadows on the target).

use super::culling::CasterDraws;
use super::light::Sunlight;
use super::pipelines::{Builder, CasterPipelines, Pass, SunMap};
use super::resident::Resident;
use super::Renderer;
use std::ops::Range;
use tracker::PixelRect;

impl Renderer {
    /// Encodes the passes from the sun: with the `sun`'s window of cached tiles, the slots
    /// pass (its draws prepared), else every caster into the frame's own map; then the
    /// board's pass, only with soft shadows: without them nothing samples its map.
    pub(super) fn encode_sun_passes(&mut self, encoder: &mut wgpu::CommandEncoder, sun: &Sunlight) {
        let geometry = &self.geometry;
        if sun.window.is_some() {
            let queue = &self.gpu.queue;
            self.stats.shadow_triangles = self.slots.encode(encoder, queue, geometry);
        } else {
            self.shadow.encode(encoder, geometry, Some(sun.seen));
        }
        if sun.board.is_some() {
            self.board_shadow.encode(encoder, geometry, None);
        }
    }
}

/// A pass from the sun into a map of its own: its pipelines, with the frame's bind group,
/// its target, and what it draws this frame.
pub(super) struct ShadowPass {
    label: &'static str,
    pass: Pass<CasterPipelines, ()>,
    view: wgpu::TextureView,
    /// The casters it draws, culled for the frame. With the static shadows cached, those of
    /// the frame's own map are the vehicles alone, drawn into the slots instead.
    pub draws: CasterDraws,
}

impl ShadowPass {
    /// The pass into `map`, whose target is `view`, drawing with the frame's group 0.
    pub fn new(
        builder: &Builder,
        frame_group: wgpu::BindGroup,
        map: SunMap,
        view: wgpu::TextureView,
    ) -> ShadowPass {
        ShadowPass {
            label: match map {
                SunMap::Own => "shadow",
                SunMap::Board => "board shadow",
            },
            pass: builder.sun_pass(frame_group, map),
            view,
            draws: CasterDraws::default(),
        }
    }

    /// Encodes the pass: the map cleared, and its casters drawn, scissored to `texels` when
    /// given (nothing drawn when they are empty).
    pub fn encode(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        geometry: &Resident,
        texels: Option<PixelRect>,
    ) {
        let mut pass = depth_pass(encoder, self.label, &self.view, wgpu::LoadOp::Clear(1.0));
        pass.set_bind_group(0, &self.pass.bind_group, &[]);
        geometry.bind(&mut pass);
        if let Some(texels) = texels {
            if texels.is_empty() {
                return;
            }
            pass.set_scissor_rect(
                texels.x0 as u32,
                texels.y0 as u32,
                texels.width() as u32,
                texels.height() as u32,
            );
        }
        draw_casters(
            &mut pass,
            geometry,
            &self.pass.pipelines,
            self.draws.lists(),
        );
    }
}

/// A depth-only render pass into `view`, loading (or clearing) it as `load` says and
/// storing it: the passes from the sun.
pub(super) fn depth_pass<'e>(
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

/// Draws the solid casters and the canopies of `draws` from `geometry`, each list with its
/// pipeline of `pipelines` (an empty list sets none).
pub(super) fn draw_casters(
    pass: &mut wgpu::RenderPass,
    geometry: &Resident,
    pipelines: &[wgpu::RenderPipeline],
    draws: [&[Range<u32>]; 2],
) {
    for (pipeline, list) in pipelines.iter().zip(draws) {
        if !list.is_empty() {
            pass.set_pipeline(pipeline);
            for range in list {
                geometry.draw(pass, range.clone());
            }
        }
    }
}
