//! Cached static shadows, and the one map every fragment looks its sunlight up in.
//!
//! The sun does not move, so the static scenery's depth map from the sun is drawn once per
//! tile and kept. The tiles live in one frame fixed for the whole scene: the light frame's
//! axes x and y across the sun's rays (see `Light::axes`), cut into squares of
//! [`TILE_SIDE_M`] anchored at x = y = 0, and one depth mapping along the rays for every
//! tile, from the scene's static geometry. A tile's texels therefore depend only on which
//! tile it is: never on the frame that first needed it, the renderer that drew it, or what
//! else its texture held.
//!
//! The tiles share one square texture of [`WINDOW`] × [`WINDOW`] slots, addressed with
//! wrap-around: tile (i, j) lives in slot (i mod 4, −(j + 1) mod 4), so any window of up to
//! 4 × 4 neighbouring tiles lies in it whole and seamless, and the sampler's repeat mode
//! carries a bilinear tap across a slot's edge into the neighbouring tile. Each frame also
//! draws the moving vehicles into the slots under them (their texels sit on the same 10 cm
//! grid), and the next frame sets those texels back (the depth cleared and the static
//! casters there drawn again, the same draws as the tile's, so the same texels). A fragment
//! therefore takes its sunlight from one lookup of one plain texture ([`Slots`]).
//!
//! A frame reads a window of at most [`WINDOW`] × [`WINDOW`] tiles: the tiles under the part
//! of the light frame its fitted map covers (see [`window`]). A frame whose fitted map is
//! wider than that (it never is at the default 60 m shadow distance: at most about 65 m
//! across) draws every caster into its own map instead.

use nalgebra::{Matrix4, Vector3};

/// Side of a tile, texels.
pub(super) const TILE_TEXELS: u32 = 256;
/// A tile texel on the light frame's plane, metres: a little finer than the per-frame map's
/// (11–13 cm over the fitted ~55–65 m).
pub(super) const TEXEL_M: f64 = 0.1;
/// Side of a tile, metres.
pub(super) const TILE_SIDE_M: f64 = TILE_TEXELS as f64 * TEXEL_M;
/// Tiles a side of the window a frame reads, and slots a side of the texture: 4 × 25.6 m
/// holds any fitted map up to 76.8 m across wherever it falls on the grid.
pub(super) const WINDOW: usize = 4;
/// Side of the slots' texture, texels (4 MB of depth).
pub(super) const SLOTS_TEXELS: u32 = WINDOW as u32 * TILE_TEXELS;
/// How far beyond the fitted map's box the window must reach, metres: the lookups' normal
/// offset and the bilinear comparison's texel, with room to spare.
const WINDOW_MARGIN_M: f64 = 1.0;
/// The depth range's margin beyond the static geometry, metres: the moving vehicles are
/// drawn into the same depth mapping, and may stand above what is static.
const DEPTH_MARGIN_M: f64 = 5.0;
/// Window edges a lookup keeps off, texels: the bilinear comparison's second texel would
/// otherwise read a slot outside the window (a tile the window does not hold, whatever the
/// slot held last).
const EDGE_TEXELS: f64 = 1.0;
/// How far beyond a texel rectangle a caster's bounding sphere may reach and still be
/// drawn when the rectangle is set back, texels: the rasteriser's rounding, with room to
/// spare.
const RECT_MARGIN_TEXELS: f64 = 2.0;

/// A tile: its column and row on the light frame's grid.
pub(super) type Cell = (i64, i64);

/// The tiles' frame: the sun's axes and the one depth mapping of every tile.
#[derive(Clone, Debug)]
pub(super) struct TileFrame {
    /// Rows x, y (across the sun's rays) and the direction towards the sun.
    pub axes: [Vector3<f64>; 3],
    /// The depth range along the rays, towards the sun: every static vertex, with
    /// `DEPTH_MARGIN_M` to spare for the moving vehicles.
    pub depth: [f64; 2],
}

impl TileFrame {
    /// The frame for the sun's axes `axes` and static geometry inside the bounding spheres
    /// `spheres` (centre, radius).
    pub fn new(axes: [Vector3<f64>; 3], spheres: impl Iterator<Item = ([f64; 3], f64)>) -> Self {
        let (mut lo, mut hi) = (f64::MAX, f64::MIN);
        for (centre, radius) in spheres {
            let t = axes[2].dot(&Vector3::from(centre));
            lo = lo.min(t - radius);
            hi = hi.max(t + radius);
        }
        if lo > hi {
            (lo, hi) = (0.0, 0.0);
        }
        TileFrame {
            axes,
            depth: [lo - DEPTH_MARGIN_M, hi + DEPTH_MARGIN_M],
        }
    }

    /// The box (light coordinates) a tile covers.
    pub fn tile_box(&self, (i, j): Cell) -> ([f64; 3], [f64; 3]) {
        let (x0, y0) = (i as f64 * TILE_SIDE_M, j as f64 * TILE_SIDE_M);
        (
            [x0, y0, self.depth[0]],
            [x0 + TILE_SIDE_M, y0 + TILE_SIDE_M, self.depth[1]],
        )
    }

    /// A world point near a tile's static geometry: its square's centre across the rays, on
    /// the plane y = 0 (the ground). Its casters' vertices reach the GPU relative to it.
    pub fn tile_origin(&self, (i, j): Cell) -> Vector3<f64> {
        let [x, y, d] = self.axes;
        let (u, v) = (
            (i as f64 + 0.5) * TILE_SIDE_M,
            (j as f64 + 0.5) * TILE_SIDE_M,
        );
        // d.y > 0: the sun is above the horizon.
        let t = -(u * x.y + v * y.y) / d.y;
        x * u + y * v + d * t
    }

    /// Whether a bounding sphere reaches the texels `rect` (grown by `RECT_MARGIN_TEXELS`).
    pub fn reaches(&self, rect: TexelRect, centre: [f64; 3], radius: f64) -> bool {
        let c = Vector3::from(centre);
        let (x, y) = (self.axes[0].dot(&c), self.axes[1].dot(&c));
        let reach = radius + RECT_MARGIN_TEXELS * TEXEL_M;
        // Texel column X spans x from X to X + 1 texels; row R spans y from −R − 1 to −R.
        !rect.is_empty()
            && x + reach >= rect.x0 as f64 * TEXEL_M
            && x - reach <= rect.x1 as f64 * TEXEL_M
            && y + reach >= -(rect.r1 as f64) * TEXEL_M
            && y - reach <= -(rect.r0 as f64) * TEXEL_M
    }

    /// The box (light coordinates) of the texels `rect`, the whole depth range.
    pub fn texels_box(&self, rect: TexelRect) -> ([f64; 3], [f64; 3]) {
        (
            [
                rect.x0 as f64 * TEXEL_M,
                -(rect.r1 as f64) * TEXEL_M,
                self.depth[0],
            ],
            [
                rect.x1 as f64 * TEXEL_M,
                -(rect.r0 as f64) * TEXEL_M,
                self.depth[1],
            ],
        )
    }

    /// The sun's projection a window of `corner` reads through: the map of the light
    /// frame's square of [`WINDOW`] × [`WINDOW`] tiles from `corner` (which holds the
    /// window, whatever its extent), [`SLOTS_TEXELS`] a side, so that its texels are the
    /// tiles' (its rows run down from the square's greatest y). As `Light::of_box` takes
    /// it: (min, max) in light coordinates.
    pub fn window_box(&self, corner: Cell) -> ([f64; 3], [f64; 3]) {
        let (min, _) = self.tile_box(corner);
        let side = WINDOW as f64 * TILE_SIDE_M;
        (min, [min[0] + side, min[1] + side, self.depth[1]])
    }

    /// The lookup of a window with corner tile `corner`: camera-relative world (the camera
    /// at `eye`) to (x, y) in tiles from the window's corner and the tiles' depth (0 nearest
    /// the sun), computed in f64 so that only small numbers reach f32.
    pub fn lookup(&self, corner: Cell, eye: &Vector3<f64>) -> Matrix4<f64> {
        let [x, y, d] = self.axes;
        let depth = self.depth[1] - self.depth[0];
        let row = |axis: &Vector3<f64>, scale: f64, offset: f64| {
            [axis.x * scale, axis.y * scale, axis.z * scale, offset]
        };
        let g = TILE_SIDE_M;
        let r0 = row(&x, 1.0 / g, (x.dot(eye) - corner.0 as f64 * g) / g);
        let r1 = row(&y, 1.0 / g, (y.dot(eye) - corner.1 as f64 * g) / g);
        let r2 = row(&d, -1.0 / depth, (self.depth[1] - d.dot(eye)) / depth);
        Matrix4::new(
            r0[0], r0[1], r0[2], r0[3], //
            r1[0], r1[1], r1[2], r1[3], //
            r2[0], r2[1], r2[2], r2[3], //
            0.0, 0.0, 0.0, 1.0,
        )
    }
}

/// The window of tiles a frame reads.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) struct Window {
    /// The tile at the window's corner (least x and y).
    pub corner: Cell,
    /// Tiles used along x and y from the corner (1 to [`WINDOW`]).
    pub extent: (usize, usize),
}

impl Window {
    /// The tiles the window uses, row by row.
    pub fn cells(&self) -> impl Iterator<Item = Cell> + '_ {
        let (i0, j0) = self.corner;
        (0..self.extent.1)
            .flat_map(move |b| (0..self.extent.0).map(move |a| (i0 + a as i64, j0 + b as i64)))
    }

    /// The texels of the window's tiles.
    pub fn texels(&self) -> TexelRect {
        let (i0, j0) = self.corner;
        let (nx, ny) = (self.extent.0 as i64, self.extent.1 as i64);
        let n = i64::from(TILE_TEXELS);
        TexelRect {
            x0: i0 * n,
            x1: (i0 + nx) * n,
            r0: -(j0 + ny) * n,
            r1: -j0 * n,
        }
    }

    /// The lookup of the frame's fragments, from the tiles' lookup `lookup` (camera-relative
    /// world to x, y in tiles from the corner and the depth; see [`TileFrame::lookup`]):
    /// camera-relative world to the slots' texture coordinates (u, v, from 0 to 2: the
    /// sampler repeats) and depth; and the bounds (u0, v0, u1, v1) of what the window's
    /// tiles answer, [`EDGE_TEXELS`] inside its edges.
    pub fn slots_lookup(&self, lookup: &Matrix4<f64>) -> (Matrix4<f64>, [f64; 4]) {
        let w = WINDOW as f64;
        // u = (x + i0 mod 4) / 4; v = (m − y) / 4, m = −j0 mod 4 + 4, so that row −(j + f)
        // of the texture (mod 4 tiles) holds y = j + f.
        let ox = self.corner.0.rem_euclid(WINDOW as i64) as f64;
        let m = (-self.corner.1).rem_euclid(WINDOW as i64) as f64 + w;
        let to_uv = Matrix4::new(
            1.0 / w,
            0.0,
            0.0,
            ox / w, //
            0.0,
            -1.0 / w,
            0.0,
            m / w, //
            0.0,
            0.0,
            1.0,
            0.0, //
            0.0,
            0.0,
            0.0,
            1.0,
        );
        let h = EDGE_TEXELS / f64::from(TILE_TEXELS);
        let (ex, ey) = (self.extent.0 as f64, self.extent.1 as f64);
        (
            to_uv * lookup,
            [
                (ox + h) / w,
                (m - ey + h) / w,
                (ox + ex - h) / w,
                (m - h) / w,
            ],
        )
    }
}

/// The window under the box `min..max` (x and y in light coordinates) of a frame's fitted
/// map, grown by a margin: a function of the box alone. `None` when it needs more than
/// [`WINDOW`] tiles a side.
pub(super) fn window(min: [f64; 2], max: [f64; 2]) -> Option<Window> {
    let cell = |v: f64| (v / TILE_SIDE_M).floor() as i64;
    let (i0, j0) = (
        cell(min[0] - WINDOW_MARGIN_M),
        cell(min[1] - WINDOW_MARGIN_M),
    );
    let (i1, j1) = (
        cell(max[0] + WINDOW_MARGIN_M),
        cell(max[1] + WINDOW_MARGIN_M),
    );
    let (nx, ny) = ((i1 - i0 + 1) as usize, (j1 - j0 + 1) as usize);
    (nx <= WINDOW && ny <= WINDOW).then_some(Window {
        corner: (i0, j0),
        extent: (nx, ny),
    })
}

/// Texels of the tiles' grid, half open: columns `x0..x1` (column X spans x from X to X + 1
/// texels) and rows `r0..r1` (row R spans y from −R − 1 to −R texels: rows run down, as
/// the texture's do).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) struct TexelRect {
    pub x0: i64,
    pub x1: i64,
    pub r0: i64,
    pub r1: i64,
}

impl TexelRect {
    /// A tile's texels.
    pub fn of_cell((i, j): Cell) -> TexelRect {
        let n = i64::from(TILE_TEXELS);
        TexelRect {
            x0: i * n,
            x1: (i + 1) * n,
            r0: -(j + 1) * n,
            r1: -j * n,
        }
    }

    /// The texels of `rect` of the map of [`TileFrame::window_box`] of `corner` (columns
    /// from the square's least x, rows down from its greatest y).
    pub fn of_window_texels(corner: Cell, rect: tracker::PixelRect) -> TexelRect {
        let n = i64::from(TILE_TEXELS);
        let (x, r) = (corner.0 * n, -(corner.1 + WINDOW as i64) * n);
        TexelRect {
            x0: x + rect.x0 as i64,
            x1: x + rect.x1 as i64,
            r0: r + rect.y0 as i64,
            r1: r + rect.y1 as i64,
        }
    }

    /// Whether it holds no texel.
    pub fn is_empty(&self) -> bool {
        self.x0 >= self.x1 || self.r0 >= self.r1
    }

    /// The texels in both.
    pub fn intersection(&self, other: &TexelRect) -> TexelRect {
        TexelRect {
            x0: self.x0.max(other.x0),
            x1: self.x1.min(other.x1),
            r0: self.r0.max(other.r0),
            r1: self.r1.min(other.r1),
        }
    }

    /// The tiles it touches.
    pub fn cells(&self) -> impl Iterator<Item = Cell> {
        let n = i64::from(TILE_TEXELS);
        let (i0, i1) = (self.x0.div_euclid(n), (self.x1 - 1).div_euclid(n));
        // Row R lies in tile j = −R div n − 1... as −(R + 1) div n.
        let (j0, j1) = (
            (-(self.r1 - 1) - 1).div_euclid(n),
            (-self.r0 - 1).div_euclid(n),
        );
        let empty = self.is_empty();
        (j0..=j1)
            .flat_map(move |j| (i0..=i1).map(move |i| (i, j)))
            .filter(move |_| !empty)
    }

    /// Where it lies in the slots' texture, as a scissor rectangle (x, y, width, height):
    /// it must lie within one turn of the wrap-around.
    pub fn in_slots(&self) -> [u32; 4] {
        let n = i64::from(SLOTS_TEXELS);
        [
            self.x0.rem_euclid(n) as u32,
            self.r0.rem_euclid(n) as u32,
            (self.x1 - self.x0) as u32,
            (self.r1 - self.r0) as u32,
        ]
    }
}

/// The slots' texture on the CPU side: which tile each slot holds, and the texels the last
/// frames drew the moving vehicles into (to set back before the next frame reads them).
#[derive(Clone, Debug, Default)]
pub(super) struct Slots {
    cells: [[Option<Cell>; WINDOW]; WINDOW],
    dirty: Vec<TexelRect>,
}

/// What a frame draws into the slots' texture before it reads it.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub(super) struct SlotWork {
    /// Tiles drawn whole: their slot held another tile (or none).
    pub tiles: Vec<Cell>,
    /// Texels set back to the static scenery's (each within one tile, which its slot still
    /// holds): where earlier frames drew the vehicles.
    pub restore: Vec<(Cell, TexelRect)>,
    /// Texels the vehicles are drawn into, none overlapping another, each within the
    /// window and within one turn of the slots' wrap-around (so whole in the texture).
    pub vehicles: Vec<TexelRect>,
}

/// The slot a tile lives in: its column and row of tiles in the texture.
pub(super) fn slot((i, j): Cell) -> (usize, usize) {
    let w = WINDOW as i64;
    (i.rem_euclid(w) as usize, (-(j + 1)).rem_euclid(w) as usize)
}

impl Slots {
    /// What a frame of window `window` must draw, the vehicles covering `vehicles` (texels,
    /// clipped to the window by this): and the slots' record of it.
    pub fn frame(&mut self, window: &Window, vehicles: &[TexelRect]) -> SlotWork {
        let mut work = SlotWork::default();
        for cell in window.cells() {
            let (a, b) = slot(cell);
            if self.cells[b][a] != Some(cell) {
                self.cells[b][a] = Some(cell);
                work.tiles.push(cell);
            }
        }
        for rect in std::mem::take(&mut self.dirty) {
            for cell in rect.cells() {
                let (a, b) = slot(cell);
                if self.cells[b][a] == Some(cell) && !work.tiles.contains(&cell) {
                    let part = rect.intersection(&TexelRect::of_cell(cell));
                    // Rectangles set back in the same tile are joined: one draw a tile.
                    match work.restore.iter_mut().find(|(c, _)| *c == cell) {
                        Some((_, r)) => *r = r.union(&part),
                        None => work.restore.push((cell, part)),
                    }
                }
            }
        }
        let area = window.texels();
        let mut drawn: Vec<TexelRect> = vehicles
            .iter()
            .map(|r| r.intersection(&area))
            .filter(|r| !r.is_empty())
            .collect();
        // Overlapping rectangles joined, until none overlap.
        'join: loop {
            for a in 0..drawn.len() {
                for b in a + 1..drawn.len() {
                    if !drawn[a].intersection(&drawn[b]).is_empty() {
                        let r = drawn.swap_remove(b);
                        drawn[a] = drawn[a].union(&r);
                        continue 'join;
                    }
                }
            }
            break;
        }
        let n = i64::from(SLOTS_TEXELS);
        for rect in drawn {
            // Cut where the texture wraps around.
            for x in rect.x0.div_euclid(n)..=(rect.x1 - 1).div_euclid(n) {
                for r in rect.r0.div_euclid(n)..=(rect.r1 - 1).div_euclid(n) {
                    work.vehicles.push(rect.intersection(&TexelRect {
                        x0: x * n,
                        x1: (x + 1) * n,
                        r0: r * n,
                        r1: (r + 1) * n,
                    }));
                }
            }
            self.dirty.push(rect);
        }
        work
    }
}

impl TexelRect {
    /// The least rectangle holding both.
    pub fn union(&self, other: &TexelRect) -> TexelRect {
        TexelRect {
            x0: self.x0.min(other.x0),
            x1: self.x1.max(other.x1),
            r0: self.r0.min(other.r0),
            r1: self.r1.max(other.r1),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn windows_hold_their_box_and_are_at_most_four_tiles_a_side() {
        for &(x, y, w, h) in &[
            (0.3, -7.0, 60.0, 55.0),
            (-1000.0, 3000.7, 73.0, 10.0),
            (25.1, 25.1, 1.0, 1.0),
        ] {
            let w = window([x, y], [x + w, y + h]).expect("fits");
            let (i0, j0) = w.corner;
            assert!(i0 as f64 * TILE_SIDE_M <= x - WINDOW_MARGIN_M);
            assert!(j0 as f64 * TILE_SIDE_M <= y - WINDOW_MARGIN_M);
            assert!((i0 + w.extent.0 as i64) as f64 * TILE_SIDE_M > x + 1.0);
            assert!(w.extent.0 <= WINDOW && w.extent.1 <= WINDOW);
        }
        assert_eq!(window([0.5, 0.0], [80.0, 10.0]), None);
    }

    #[test]
    fn slots_keep_their_tiles_and_set_back_where_the_vehicles_were() {
        let mut slots = Slots::default();
        let w = Window {
            corner: (-1, 2),
            extent: (3, 3),
        };
        let n = i64::from(TILE_TEXELS);
        // Over the corner of tiles (0, 2), (1, 2), (0, 3) and (1, 3); a second car
        // overlapping it, and a third apart.
        let car = TexelRect {
            x0: n - 10,
            x1: n + 20,
            r0: -3 * n - 5,
            r1: -3 * n + 7,
        };
        let beside = TexelRect {
            x0: n + 15,
            x1: n + 40,
            r0: -3 * n,
            r1: -3 * n + 3,
        };
        let apart = TexelRect {
            x0: 0,
            x1: 10,
            r0: -4 * n + 1,
            r1: -4 * n + 9,
        };
        let first = slots.frame(&w, &[car, beside, apart]);
        assert_eq!(first.tiles.len(), 9);
        assert!(first.restore.is_empty());
        // The overlapping two are joined; none of the drawn rectangles overlap.
        assert_eq!(first.vehicles, vec![car.union(&beside), apart]);
        // The window moves one tile along x: one column of tiles is drawn anew, in the
        // slots of the column left behind, and the cars' old texels are set back, a
        // rectangle a tile.
        let w2 = Window {
            corner: (0, 2),
            extent: (3, 3),
        };
        let second = slots.frame(&w2, &[]);
        assert_eq!(second.tiles, vec![(2, 2), (2, 3), (2, 4)]);
        let mut restored: Vec<Cell> = second.restore.iter().map(|(c, _)| *c).collect();
        restored.sort_unstable();
        assert_eq!(restored, vec![(0, 2), (0, 3), (1, 2), (1, 3)]);
        for (cell, r) in &second.restore {
            assert_eq!(r.intersection(&TexelRect::of_cell(*cell)), *r);
        }
        assert!(second.vehicles.is_empty());
        // Nothing is left to set back, and a window of four tiles evicts the column that
        // shares its slots.
        let third = slots.frame(
            &Window {
                corner: (0, 2),
                extent: (4, 3),
            },
            &[],
        );
        assert_eq!(third.tiles, vec![(3, 2), (3, 3), (3, 4)]);
        assert!(third.restore.is_empty());
        // Slots: four tiles apart share one.
        assert_eq!(slot((3, 2)), slot((-1, 2)));
        assert_ne!(slot((3, 2)), slot((3, 3)));
        // A rectangle across the texture's wrap-around is cut there.
        let across = TexelRect {
            x0: 4 * n - 5,
            x1: 4 * n + 5,
            r0: -3 * n,
            r1: -3 * n + 4,
        };
        let w3 = Window {
            corner: (2, 2),
            extent: (3, 3),
        };
        let pieces = slots.frame(&w3, &[across]).vehicles;
        assert_eq!(pieces.len(), 2);
        for p in &pieces {
            let [x, _, w, _] = p.in_slots();
            assert!(x + w <= SLOTS_TEXELS, "{p:?}");
        }
    }

    #[test]
    fn texel_rects_map_to_their_tiles_and_slots() {
        let n = i64::from(TILE_TEXELS);
        for cell in [(0, 0), (-1, -1), (5, -7), (-9, 3)] {
            let r = TexelRect::of_cell(cell);
            assert_eq!(r.cells().collect::<Vec<_>>(), vec![cell]);
            let (a, b) = slot(cell);
            let [x, y, w, h] = r.in_slots();
            assert_eq!(
                [x, y, w, h],
                [
                    a as u32 * TILE_TEXELS,
                    b as u32 * TILE_TEXELS,
                    TILE_TEXELS,
                    TILE_TEXELS
                ]
            );
        }
        // A tile's texel on the light frame: column X spans x from X to X + 1 texels, row
        // R spans y from −R − 1 to −R.
        let axes = [Vector3::x(), Vector3::z(), -Vector3::y()];
        let frame = TileFrame::new(axes, std::iter::empty());
        let r = TexelRect {
            x0: n,
            x1: n + 1,
            r0: -n,
            r1: -n + 1,
        };
        let margin = (RECT_MARGIN_TEXELS + 0.5) * TEXEL_M;
        let x = (n as f64 + 0.5) * TEXEL_M;
        let y = (n as f64 - 0.5) * TEXEL_M;
        assert!(frame.reaches(r, [x, 0.0, y], 0.01));
        assert!(!frame.reaches(r, [x + margin + 0.02, 0.0, y], 0.01));
        assert!(!frame.reaches(r, [x, 0.0, y + margin + 0.02], 0.01));
    }

    #[test]
    fn the_lookup_puts_tile_corners_on_whole_numbers_and_depth_in_range() {
        let axes = {
            let d = Vector3::new(0.3, 0.8, -0.5).normalize();
            let x = Vector3::y().cross(&d).normalize();
            [x, d.cross(&x), d]
        };
        let frame = TileFrame::new(axes, [([0.0, 0.0, 0.0], 500.0)].into_iter());
        let eye = Vector3::new(123.4, 2.0, -56.7);
        let corner = (3, -2);
        let m = frame.lookup(corner, &eye);
        // The world point at the light coordinates of cell (4, -1)'s corner, on the ground.
        let (u, v) = (4.0 * TILE_SIDE_M, -TILE_SIDE_M);
        let t = -(u * axes[0].y + v * axes[1].y) / axes[2].y;
        let p = axes[0] * u + axes[1] * v + axes[2] * t - eye;
        let q = m * p.push(1.0);
        assert!(
            (q.x - 1.0).abs() < 1e-9 && (q.y - 1.0).abs() < 1e-9,
            "{q:?}"
        );
        assert!(q.z > 0.0 && q.z < 1.0);
        // The tile's origin lies in its square, on the ground.
        let o = frame.tile_origin((4, -1));
        let q = m * (o - eye).push(1.0);
        assert!((q.x - 1.5).abs() < 1e-9 && (q.y - 1.5).abs() < 1e-9 && o.y.abs() < 1e-9);
    }
}
