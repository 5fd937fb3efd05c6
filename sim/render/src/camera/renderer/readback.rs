//! Readback: the frame's rows copied into a staging buffer (rows padded to wgpu's 256-byte
//! copy alignment), mapped and read; the two fields of an interlaced frame woven; then the
//! sensor.

use super::{RenderError, Renderer};
use crate::camera::backend::Backend;
use crate::camera::rig::CameraRig;
use crate::camera::sensor::apply_sensor_to_rows;
use image::GrayImage;
use std::ops::Range;

/// The staging buffer the frame is read back through.
pub(super) struct Readback {
    staging: wgpu::Buffer,
    /// Bytes of a row in it: the frame's width padded to wgpu's 256-byte copy alignment.
    padded_row: u32,
    width: u32,
    height: u32,
}

impl Readback {
    /// A staging buffer for `rig`'s frames.
    pub fn new(device: &wgpu::Device, rig: &CameraRig) -> Readback {
        let padded_row = rig.width.div_ceil(wgpu::COPY_BYTES_PER_ROW_ALIGNMENT)
            * wgpu::COPY_BYTES_PER_ROW_ALIGNMENT;
        let staging = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("staging"),
            size: u64::from(padded_row) * u64::from(rig.height),
            usage: wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::MAP_READ,
            mapped_at_creation: false,
        });
        Readback {
            staging,
            padded_row,
            width: rig.width,
            height: rig.height,
        }
    }

    /// Encodes the copy of the rows `rows` of `frame` into the staging buffer (nothing when
    /// there are none).
    pub fn copy(
        &self,
        encoder: &mut wgpu::CommandEncoder,
        frame: &wgpu::Texture,
        rows: Range<u32>,
    ) {
        if rows.is_empty() {
            return;
        }
        encoder.copy_texture_to_buffer(
            wgpu::TexelCopyTextureInfo {
                texture: frame,
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
                width: self.width,
                height: rows.len() as u32,
                depth_or_array_layers: 1,
            },
        );
    }

    /// Maps the staging buffer once the submitted copy of `rows` is done, and reads them,
    /// dropping the row padding: the frame with those rows (the others zero).
    pub fn read(
        &self,
        device: &wgpu::Device,
        backend: Backend,
        rows: Range<u32>,
    ) -> Result<GrayImage, RenderError> {
        let readback = |reason: String| RenderError::Readback { backend, reason };
        let width = self.width as usize;
        let mut pixels = vec![0; width * self.height as usize];
        if rows.is_empty() {
            return Ok(GrayImage::from_raw(self.width, self.height, pixels)
                .expect("buffer holds width × height bytes"));
        }
        let bytes = u64::from(self.padded_row) * rows.len() as u64;
        let (sender, receiver) = std::sync::mpsc::channel();
        self.staging
            .map_async(wgpu::MapMode::Read, ..bytes, move |result| {
                let _ = sender.send(result);
            });
        device
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
            if self.padded_row as usize == width {
                // No padding (a width of a multiple of 256): one copy.
                drawn.copy_from_slice(&data);
            } else {
                for (row, out) in data
                    .chunks_exact(self.padded_row as usize)
                    .zip(drawn.chunks_exact_mut(width))
                {
                    out.copy_from_slice(&row[..width]);
                }
            }
        }
        self.staging.unmap();
        Ok(GrayImage::from_raw(self.width, self.height, pixels)
            .expect("buffer holds width × height bytes"))
    }
}

impl Renderer {
    /// The sensor: blur and noise, seeded per frame (`frame_index`), the read noise only on
    /// the rows drawn, `rows` (the only ones read back); with the sensor's read noise in
    /// electrons, its noise counted at the frame's gain (times the automatic gain,
    /// `auto_gain`).
    pub(super) fn apply_sensor(
        &self,
        image: &mut GrayImage,
        frame_index: u64,
        auto_gain: f64,
        rows: Range<usize>,
    ) {
        let description = self.scene.description();
        let mut sensor = std::borrow::Cow::Borrowed(&description.sensor);
        if sensor.read_noise_e.is_some() {
            sensor.to_mut().gain *= auto_gain;
        }
        apply_sensor_to_rows(
            image,
            &sensor,
            &self.rig.intrinsics,
            description.seed,
            frame_index,
            rows,
        );
    }
}

/// Replaces the odd rows of `frame` with those of `other`: the two fields of an interlaced
/// frame.
pub(super) fn interlace(frame: &mut GrayImage, other: &GrayImage) {
    let width = frame.width() as usize;
    for (row, out) in frame
        .as_mut()
        .chunks_exact_mut(width)
        .zip(other.as_raw().chunks_exact(width))
        .skip(1)
        .step_by(2)
    {
        row.copy_from_slice(out);
    }
}
