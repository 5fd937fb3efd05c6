//! Static geometry binned by ground cell and by layer, and the chunks the bins become.
//!
//! A scene is built a district at a time ([`DISTRICT_BINS`] bins a side; see `districts`):
//! the builders run whole each time, and [`Bins`] keeps what they lay in the districts
//! asked for, dropping the rest. What a bin holds does not depend on which others are kept,
//! so a chunk built with its district is the chunk built with the whole scene.

use super::chunk::{Chunk, ChunkPart};
use super::layer::Layer;
use super::mesh::Mesh;
use super::terrain::Terrain;
use std::collections::{BTreeMap, BTreeSet};

/// Side of the square ground cells static geometry is binned into, metres. 50 m keeps the
/// number of draw calls small (about 30 cells are in view) while culling most of a
/// kilometre-long route.
pub const BIN_M: f64 = 50.0;

/// Side of the square cells whose geometry a [`Chunk`] can cull one by one ([`ChunkPart`]),
/// metres: a frame rendered only in part (the tracker's window) then draws less of it; a
/// 50 m cell's clutter was 70 % of the triangles such a part drew.
pub const PART_M: f64 = 10.0;

/// Side of a district, in bins: 500 m.
pub(super) const DISTRICT_BINS: i64 = 10;

/// A bin's cell, by `BIN_M` cells: (x, z).
pub(super) type Cell = (i64, i64);

/// The district a cell lies in.
pub(super) fn district_of((cx, cz): Cell) -> Cell {
    (cx.div_euclid(DISTRICT_BINS), cz.div_euclid(DISTRICT_BINS))
}

/// Which bins a [`Bins`] keeps.
pub(super) enum Keep {
    /// The bins of these districts.
    Districts(BTreeSet<Cell>),
    /// None: it only notes, for each district, how many indices were laid there (before
    /// draping), in the order the districts were first laid in.
    Survey(Survey),
}

/// What a survey notes: each district laid in, in the order first laid in, with the
/// indices laid there; and where each is in that list.
#[derive(Default)]
pub(super) struct Survey {
    laid: Vec<(Cell, usize)>,
    position: BTreeMap<Cell, usize>,
}

/// Static geometry binned by ground cell and by layer. Within a bin, each run of geometry
/// added in one [`PART_M`] cell is a part of its own (see [`ChunkPart`]).
pub(super) struct Bins {
    bins: BTreeMap<(i64, i64, Layer), Bin>,
    keep: Keep,
    /// Where what is not kept is laid, and the district it was laid in (surveying).
    dropped: Mesh,
    dropped_in: Option<Cell>,
}

/// One bin's geometry, and where each of its parts starts: the index and the part's cell.
#[derive(Default)]
pub(super) struct Bin {
    mesh: Mesh,
    parts: Vec<(usize, (i64, i64))>,
}

impl Bins {
    /// Bins keeping what `keep` says.
    pub(super) fn new(keep: Keep) -> Bins {
        Bins {
            bins: BTreeMap::new(),
            keep,
            dropped: Mesh::default(),
            dropped_in: None,
        }
    }

    /// The mesh of the bin of ground point (`x`, `z`) and layer `layer`, for geometry there
    /// to be added to it.
    pub(super) fn at(&mut self, x: f64, z: f64, layer: Layer) -> &mut Mesh {
        let cell = |m: f64| ((x / m).floor() as i64, (z / m).floor() as i64);
        let (cx, cz) = cell(BIN_M);
        let district = district_of((cx, cz));
        let kept = match &self.keep {
            Keep::Districts(kept) => kept.contains(&district),
            Keep::Survey(_) => false,
        };
        if !kept {
            self.note_dropped();
            self.dropped_in = Some(district);
            return &mut self.dropped;
        }
        let bin = self.bins.entry((cx, cz, layer)).or_default();
        let part = cell(PART_M);
        if bin.parts.last().is_none_or(|&(_, last)| last != part) {
            bin.parts.push((bin.mesh.indices.len(), part));
        }
        &mut bin.mesh
    }

    /// Surveying, notes the indices last laid where nothing is kept; drops them.
    fn note_dropped(&mut self) {
        if let (Keep::Survey(survey), Some(district)) = (&mut self.keep, self.dropped_in.take()) {
            let Survey { laid, position } = survey;
            let at = *position.entry(district).or_insert_with(|| {
                laid.push((district, 0));
                laid.len() - 1
            });
            laid[at].1 += self.dropped.indices.len();
        }
        self.dropped.vertices.clear();
        self.dropped.indices.clear();
    }

    /// What a survey found: each district laid in, in the order first laid in, with the
    /// indices laid there (empty unless surveying).
    pub(super) fn into_survey(mut self) -> Vec<(Cell, usize)> {
        self.note_dropped();
        match self.keep {
            Keep::Survey(survey) => survey.laid,
            _ => Vec::new(),
        }
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
    /// by cell, then layer), each of its parts a [`ChunkPart`], with the cell and layer
    /// of each.
    pub(super) fn into_chunks(self) -> (Mesh, Vec<Chunk>, Vec<(Cell, Layer)>) {
        let mut mesh = Mesh::default();
        let mut chunks = Vec::new();
        let mut keys = Vec::new();
        // Each bin is let go once appended: the bins and the mesh are never both whole.
        for ((cx, cz, layer), Bin { mesh: bin, parts }) in self.bins {
            if bin.indices.is_empty() {
                continue;
            }
            let (centre, radius) = bin.bounding_sphere();
            let start = mesh.indices.len() as u32;
            let first_vertex = mesh.vertices.len() as u32;
            mesh.append(&bin);
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
                vertices: first_vertex..mesh.vertices.len() as u32,
                centre,
                radius,
                casts_shadow: matches!(layer, Layer::Clutter | Layer::Foliage),
                layer,
                parts,
            });
            keys.push(((cx, cz), layer));
        }
        (mesh, chunks, keys)
    }
}
