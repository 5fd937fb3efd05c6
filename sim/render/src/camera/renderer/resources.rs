//! Resources: the depth maps from the sun, the frame's targets, the ground's textures and
//! the samplers that read them.

use super::device::Gpu;
use super::light::BOARD_SHADOW_SIZE;
use super::RenderOptions;
use crate::camera::rig::CameraRig;
use crate::camera::shadow_tiles;
use crate::camera::texture_cache::ground_texels;
use crate::camera::textures::{LAYERS, TEXTURE_SIZE};
use crate::scene::SceneDescription;

/// Depth format of both passes.
pub(super) const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;
/// Colour format: 8-bit grey, what the frame grabber delivers.
pub(super) const COLOR_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::R8Unorm;

/// A 2D texture of one mip level.
fn texture(
    device: &wgpu::Device,
    label: &str,
    (width, height): (u32, u32),
    format: wgpu::TextureFormat,
    samples: u32,
    usage: wgpu::TextureUsages,
) -> wgpu::Texture {
    device.create_texture(&wgpu::TextureDescriptor {
        label: Some(label),
        size: wgpu::Extent3d {
            width,
            height,
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: samples,
        dimension: wgpu::TextureDimension::D2,
        format,
        usage,
        view_formats: &[],
    })
}

/// A square depth map `side` texels wide that a pass from the sun draws and the main pass
/// samples.
fn depth_map(device: &wgpu::Device, label: &str, side: u32) -> wgpu::TextureView {
    texture(
        device,
        label,
        (side, side),
        DEPTH_FORMAT,
        1,
        wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::TEXTURE_BINDING,
    )
    .create_view(&wgpu::TextureViewDescriptor::default())
}

/// The depth maps from the sun.
pub(super) struct ShadowMaps {
    /// The frame's own map, `RenderOptions::shadow_map_size` a side.
    pub own: wgpu::TextureView,
    /// The board's fine map.
    pub board: wgpu::TextureView,
    /// The static shadow tiles' slots (a small stand-in when the cache is off: the layout
    /// binds a texture either way).
    pub slots: wgpu::TextureView,
}

impl ShadowMaps {
    pub fn new(device: &wgpu::Device, options: &RenderOptions) -> ShadowMaps {
        let slots_side = if options.cached_shadows {
            shadow_tiles::SLOTS_TEXELS
        } else {
            1
        };
        ShadowMaps {
            own: depth_map(device, "shadow map", options.shadow_map_size),
            board: depth_map(device, "board shadow map", BOARD_SHADOW_SIZE),
            slots: depth_map(device, "shadow tiles", slots_side),
        }
    }
}

/// The main pass's targets: the grey frame (and its multisampled twin), and depth.
pub(super) struct Targets {
    /// The frame, which the readback copies from.
    pub color: wgpu::Texture,
    pub color_view: wgpu::TextureView,
    /// With MSAA, what the pass draws into, resolved into `color`.
    pub msaa_view: Option<wgpu::TextureView>,
    pub depth_view: wgpu::TextureView,
}

impl Targets {
    pub fn new(device: &wgpu::Device, rig: &CameraRig, samples: u32) -> Targets {
        let frame_size = (rig.width, rig.height);
        let color = texture(
            device,
            "frame",
            frame_size,
            COLOR_FORMAT,
            1,
            wgpu::TextureUsages::RENDER_ATTACHMENT | wgpu::TextureUsages::COPY_SRC,
        );
        let color_view = color.create_view(&wgpu::TextureViewDescriptor::default());
        let msaa_view = (samples > 1).then(|| {
            texture(
                device,
                "frame msaa",
                frame_size,
                COLOR_FORMAT,
                samples,
                wgpu::TextureUsages::RENDER_ATTACHMENT,
            )
            .create_view(&wgpu::TextureViewDescriptor::default())
        });
        let depth_view = texture(
            device,
            "depth",
            frame_size,
            DEPTH_FORMAT,
            samples,
            wgpu::TextureUsages::RENDER_ATTACHMENT,
        )
        .create_view(&wgpu::TextureViewDescriptor::default());
        Targets {
            color,
            color_view,
            msaa_view,
            depth_view,
        }
    }
}

/// The ground's textures, which the main pass samples trilinearly on the road's surfaces and
/// the grass.
pub(super) struct SurfaceTextures {
    pub view: wgpu::TextureView,
    pub sampler: wgpu::Sampler,
}

impl SurfaceTextures {
    /// Generated from the scene's seed (or read from the cache of an earlier run), every mip
    /// level uploaded (a 1×1 stand-in when they are off: the layout binds a texture either
    /// way).
    pub fn upload(gpu: &Gpu, description: &SceneDescription) -> SurfaceTextures {
        let generated = description
            .textures
            .enabled
            .then(|| ground_texels(description.seed));
        let (side, levels) = match &generated {
            Some(g) => (TEXTURE_SIZE as u32, g.len() as u32),
            None => (1, 1),
        };
        let ground_texture = gpu.device.create_texture(&wgpu::TextureDescriptor {
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
            gpu.queue.write_texture(
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
        let view = ground_texture.create_view(&wgpu::TextureViewDescriptor {
            dimension: Some(wgpu::TextureViewDimension::D2Array),
            ..Default::default()
        });
        // Trilinear, tiling.
        let sampler = gpu.device.create_sampler(&wgpu::SamplerDescriptor {
            label: Some("ground textures"),
            address_mode_u: wgpu::AddressMode::Repeat,
            address_mode_v: wgpu::AddressMode::Repeat,
            mag_filter: wgpu::FilterMode::Linear,
            min_filter: wgpu::FilterMode::Linear,
            mipmap_filter: wgpu::MipmapFilterMode::Linear,
            ..Default::default()
        });
        SurfaceTextures { view, sampler }
    }
}

/// The shadow lookups' samplers: bilinear comparison samplers (a 2 × 2-texel
/// percentage-closer filter).
pub(super) struct ShadowSamplers {
    /// The frame's own map and the board's: clamped at their edges.
    pub clamped: wgpu::Sampler,
    /// The slots' texture, which wraps around (see `shadow_tiles`).
    pub repeating: wgpu::Sampler,
}

impl ShadowSamplers {
    pub fn new(device: &wgpu::Device) -> ShadowSamplers {
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
        ShadowSamplers {
            clamped: comparison_sampler("shadow", wgpu::AddressMode::ClampToEdge),
            repeating: comparison_sampler("shadow tiles", wgpu::AddressMode::Repeat),
        }
    }
}
