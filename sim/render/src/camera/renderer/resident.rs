//! The scene's geometry on the device: the moving objects, and the static chunks a frame
//! draws or soon may. A frame's passes name what they draw by ranges of the scene's index
//! space ([`Chunk::indices`](crate::scene::Chunk::indices), as if all of its geometry lay in
//! one buffer); before they are encoded, [`Resident::hold`] makes every chunk those ranges
//! reach resident (with those near the camera), and [`Resident::draw`] draws a range where
//! its pieces lie. So a route's length does not set the device's memory (nor the driver's
//! copies of it), and a frame draws the same triangles in the same order as it would from
//! the whole geometry in one buffer: the same pixels.

use super::device::Gpu;
use crate::scene::{Mesh, MeshPiece, Scene};
use nalgebra::Vector3;
use std::ops::Range;

/// The resident geometry: two buffers, and where each block of the scene's index space
/// (each static chunk, then the moving objects) lies in them.
pub(super) struct Resident {
    vertices: wgpu::Buffer,
    indices: wgpu::Buffer,
    /// Where each block starts in the scene's index space, then where the last ends.
    starts: Vec<u32>,
    /// Where each block's indices start in `indices`, when it is resident.
    placed: Vec<Option<u32>>,
    /// The blocks this frame's draws reach (kept to avoid allocating every frame).
    wanted: Vec<bool>,
    /// How many times the resident set was made.
    loads: u32,
    /// How near the camera a chunk comes to be made resident with a frame's draws, metres
    /// ([`RenderOptions::resident_m`](super::RenderOptions::resident_m)).
    reach_m: f64,
}

impl Resident {
    /// Nothing resident yet: the first frame's [`Resident::hold`] uploads what it draws.
    pub fn new(gpu: &Gpu, scene: &Scene, reach_m: f64) -> Resident {
        let mut starts: Vec<u32> = scene.chunks().iter().map(|c| c.indices.start).collect();
        let objects = scene.objects_indices();
        starts.extend([objects.start, objects.end]);
        let blocks = starts.len() - 1;
        Resident {
            vertices: buffer(gpu, "vertices", 0, wgpu::BufferUsages::VERTEX),
            indices: buffer(gpu, "indices", 0, wgpu::BufferUsages::INDEX),
            starts,
            placed: vec![None; blocks],
            wanted: vec![false; blocks],
            loads: 0,
            reach_m,
        }
    }

    /// How many times the resident set has been made.
    pub fn loads(&self) -> u32 {
        self.loads
    }

    /// The block holding index `at` of the scene's index space (the last of equal starts:
    /// blocks are never empty, but a scene may have no chunks).
    fn block_of(&self, at: u32) -> usize {
        self.starts.partition_point(|&s| s <= at) - 1
    }

    /// Notes that this frame draws `range` (of the scene's index space).
    pub fn want(&mut self, range: &Range<u32>) {
        if range.is_empty() {
            return;
        }
        let (first, last) = (self.block_of(range.start), self.block_of(range.end - 1));
        self.wanted[first..=last].fill(true);
    }

    /// Makes every block [`Resident::want`] noted since the last call resident: when one is
    /// not, the resident set is made again, of those blocks, the moving objects and every
    /// chunk within the reach of the camera at `eye` (world frame).
    pub fn hold(&mut self, gpu: &Gpu, scene: &Scene, eye: &Vector3<f64>) {
        let objects = self.placed.len() - 1;
        self.wanted[objects] = true;
        let missing = (self.wanted.iter().zip(&self.placed)).any(|(w, p)| *w && p.is_none());
        if missing {
            for (k, chunk) in scene.chunks().iter().enumerate() {
                let reach = (Vector3::from(chunk.centre) - eye).norm() - chunk.radius;
                self.wanted[k] |= reach <= self.reach_m;
            }
            self.load(gpu, scene);
        }
        self.wanted.fill(false);
    }

    /// Uploads the blocks wanted, in the order of the scene's index space.
    fn load(&mut self, gpu: &Gpu, scene: &Scene) {
        let mut mesh = Mesh::default();
        self.placed.fill(None);
        let mut put = |placed: &mut Option<u32>, piece: MeshPiece<'_>| {
            *placed = Some(mesh.indices.len() as u32);
            mesh.append_piece(piece);
        };
        let wanted = &self.wanted;
        let chunks = (0..wanted.len() - 1).filter(|&k| wanted[k]);
        let placed = &mut self.placed;
        scene.visit_chunks(chunks, |k, piece| put(&mut placed[k], piece));
        let objects = placed.len() - 1;
        put(&mut placed[objects], scene.objects_geometry());
        let (vertices, indices) = (&mesh.vertices, &mesh.indices);
        write(
            gpu,
            &mut self.vertices,
            "vertices",
            bytemuck::cast_slice(vertices),
        );
        write(
            gpu,
            &mut self.indices,
            "indices",
            bytemuck::cast_slice(indices),
        );
        self.loads += 1;
    }

    /// Sets the buffers as `pass`'s vertex and index buffers.
    pub fn bind(&self, pass: &mut wgpu::RenderPass) {
        pass.set_vertex_buffer(0, self.vertices.slice(..));
        pass.set_index_buffer(self.indices.slice(..), wgpu::IndexFormat::Uint32);
    }

    /// Draws `range` of the scene's index space, every block of which is resident (see
    /// [`Resident::hold`]): one draw for each run of it that lies together.
    pub fn draw(&self, pass: &mut wgpu::RenderPass, range: Range<u32>) {
        let mut run: Option<Range<u32>> = None;
        let mut at = range.start;
        let mut k = self.block_of(at);
        while at < range.end {
            let (start, end) = (self.starts[k], self.starts[k + 1].min(range.end));
            let base = self.placed[k].expect("every block a frame draws is held resident");
            let piece = base + (at - start)..base + (end - start);
            match &mut run {
                Some(run) if run.end == piece.start => run.end = piece.end,
                _ => {
                    if let Some(done) = run.replace(piece) {
                        pass.draw_indexed(done, 0, 0..1);
                    }
                }
            }
            (at, k) = (end, k + 1);
        }
        if let Some(done) = run {
            pass.draw_indexed(done, 0, 0..1);
        }
    }
}

/// A buffer of `bytes` bytes (at least 4) for `usage`, written by copies.
fn buffer(gpu: &Gpu, label: &str, bytes: u64, usage: wgpu::BufferUsages) -> wgpu::Buffer {
    gpu.device.create_buffer(&wgpu::BufferDescriptor {
        label: Some(label),
        size: bytes.max(4).next_multiple_of(wgpu::COPY_BUFFER_ALIGNMENT),
        usage: usage | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    })
}

/// Writes `bytes` at the start of `buffer`, first made anew (a quarter larger) when they do
/// not fit.
fn write(gpu: &Gpu, buffer: &mut wgpu::Buffer, label: &str, bytes: &[u8]) {
    let size = (bytes.len() as u64).next_multiple_of(wgpu::COPY_BUFFER_ALIGNMENT);
    if size > buffer.size() {
        *buffer = self::buffer(gpu, label, size + size / 4, buffer.usage());
    }
    // A copy's size is a multiple of 4: vertices and indices always are.
    gpu.queue.write_buffer(buffer, 0, bytes);
}
