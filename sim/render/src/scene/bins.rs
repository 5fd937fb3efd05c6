//! Static geometry binned by ground cell and by layer, and the chunks the bins become.

use super::chunk::{Chunk, ChunkPart};
use super::layer::Layer;
use super::mesh::Mesh;
use super::terrain::Terrain;
use std::collections::BTreeMap;

/// Side of the square ground cells static geometry is binned into, metres. 50 m keeps the
/// number of draw calls small (about 30 cells are in view) while culling most of a
/// kilometre-long route.
pub const BIN_M: f64 = 50.0;

/// Side of the square cells whose geometry a [`Chunk`] can cull one by one ([`ChunkPart`]),
/// metres: a frame rendered only in part (the tracker's window) then draws less of it; a
/// 50 m cell's clutter was 70 % of the triangles such a part drew.
pub const PART_M: f64 = 10.0;

/// Static geometry binned by ground cell and by layer. Within a bin, each run of geometry
/// added in one [`PART_M`] cell is a part of its own (see [`ChunkPart`]).
#[derive(Default)]
pub(super) struct Bins {
    bins: BTreeMap<(i64, i64, Layer), Bin>,
}

/// One bin's geometry, and where each of its parts starts: the index and the part's cell.
#[derive(Default)]
pub(super) struct Bin {
    mesh: Mesh,
    parts: Vec<(usize, (i64, i64))>,
}

impl Bins {
    /// The mesh of the bin of ground point (`x`, `z`) and layer `layer`, for geometry there
    /// to be added to it.
    pub(super) fn at(&mut self, x: f64, z: f64, layer: Layer) -> &mut Mesh {
        let cell = |m: f64| ((x / m).floor() as i64, (z / m).floor() as i64);
        let (cx, cz) = cell(BIN_M);
        let bin = self.bins.entry((cx, cz, layer)).or_default();
        let part = cell(PART_M);
        if bin.parts.last().is_none_or(|&(_, last)| last != part) {
            bin.parts.push((bin.mesh.indices.len(), part));
        }
        &mut bin.mesh
    }

    /// Lays every bin of `layer` on the terrain (see [`Terrain::drape_marked`]), cutting no
    /// edge longer than `max_edge_m` and keeping its parts: each starts where its first
    /// triangle's pieces do.
    pub(super) fn drape(&mut self, layer: Layer, terrain: &Terrain, max_edge_m: f64) {
        for (&(_, _, bin_layer), bin) in self.bins.iter_mut() {
            if bin_layer == layer {
                let mut marks: Vec<usize> = bin.parts.iter().map(|&(at, _)| at).collect();
                bin.mesh = terrain.drape_marked(&bin.mesh, max_edge_m, &mut marks);
                for (part, at) in bin.parts.iter_mut().zip(marks) {
                    part.0 = at;
                }
            }
        }
    }

    /// Concatenates the bins into one mesh, recording each as a chunk (in the bins' order:
    /// by cell, then layer), each of its parts a [`ChunkPart`].
    pub(super) fn into_chunks(self) -> (Mesh, Vec<Chunk>) {
        let mut mesh = Mesh::default();
        let mut chunks = Vec::new();
        for (&(_, _, layer), Bin { mesh: bin, parts }) in &self.bins {
            if bin.indices.is_empty() {
                continue;
            }
            let (centre, radius) = bin.bounding_sphere();
            let start = mesh.indices.len() as u32;
            mesh.append(bin);
            // Each part runs to where the next starts (a part may have added nothing).
            let ends = parts
                .iter()
                .skip(1)
                .map(|&(at, _)| at)
                .chain([bin.indices.len()]);
            let parts = parts
                .iter()
                .zip(ends)
                .filter(|((at, _), end)| end > at)
                .map(|(&(at, _), end)| {
                    let (centre, radius) = bin.bounding_sphere_of(at..end);
                    ChunkPart {
                        indices: start + at as u32..start + end as u32,
                        centre,
                        radius,
                    }
                })
                .collect();
            chunks.push(Chunk {
                indices: start..mesh.indices.len() as u32,
                centre,
                radius,
                casts_shadow: matches!(layer, Layer::Clutter | Layer::Foliage),
                layer,
                parts,
            });
        }
        (mesh, chunks)
    }
}
