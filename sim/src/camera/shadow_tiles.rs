//! Cached static shadows: the sun's depth map of the static scenery, rendered once per tile
//! and kept, so that each frame redraws only the moving vehicles into its own map.
//!
//! The sun does not move, so the tiles live in one frame fixed for the whole scene: the
//! light frame's axes x and y across the sun's rays (see `Light::axes`), cut into squares
//! of [`TILE_SIDE_M`] anchored at x = y = 0, and one depth mapping along the rays for every
//! tile, from the scene's static geometry. A tile's texels therefore depend only on which
//! tile it is: never on the frame that first needed it, the renderer that drew it, or what
//! else its cache held. That keeps frames bit for bit the same whatever order they are
//! rendered in, by either of a run's two renderers, partly or whole.
//!
//! A frame reads a window of [`WINDOW`] × [`WINDOW`] tiles: the tiles under the part of the
//! light frame its fitted map covers (see [`window`]). A frame whose fitted map is wider
//! than that (it never is at the default 60 m shadow distance: at most about 65 m across)
//! draws its static casters into its own map as before.

use nalgebra::{Matrix4, Vector3};

/// Side of a tile's texture, texels.
pub(super) const TILE_TEXELS: u32 = 256;
/// Texels on each side of a tile that repeat its neighbours', so that the bilinear
/// comparison at a tile's edge reads what lies beyond it.
pub(super) const GUARD_TEXELS: u32 = 2;
/// Texels across a tile's own square.
pub(super) const INNER_TEXELS: u32 = TILE_TEXELS - 2 * GUARD_TEXELS;
/// A tile texel on the light frame's plane, metres: a little finer than the per-frame map's
/// (11–13 cm over the fitted ~55–65 m).
pub(super) const TEXEL_M: f64 = 0.1;
/// Side of a tile's own square, metres.
pub(super) const TILE_SIDE_M: f64 = INNER_TEXELS as f64 * TEXEL_M;
/// Tiles a side of the window a frame reads: 4 × 25.2 m holds any fitted map up to 75.6 m
/// across wherever it falls on the grid.
pub(super) const WINDOW: usize = 4;
/// Tiles a renderer keeps: what the widest window needs (4 MB). A window of 3 × 3, the
/// usual one, leaves the last window's other tiles cached.
pub(super) const LAYERS: u32 = (WINDOW * WINDOW) as u32;
/// A window cell with no tile: its receivers are lit as far as static casters go.
pub(super) const NO_TILE: u32 = u32::MAX;
/// How far beyond the fitted map's box the window must reach, metres: the lookups' normal
/// offset and the bilinear comparison's texel, with room to spare.
const WINDOW_MARGIN_M: f64 = 1.0;

/// A tile: its column and row on the light frame's grid.
pub(super) type Cell = (i64, i64);

/// The tiles' frame: the sun's axes and the one depth mapping of every tile.
#[derive(Clone, Debug)]
pub(super) struct TileFrame {
    /// Rows x, y (across the sun's rays) and the direction towards the sun.
    pub axes: [Vector3<f64>; 3],
    /// The depth range along the rays, towards the sun: every static vertex, with a metre
    /// to spare.
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
            depth: [lo - 1.0, hi + 1.0],
        }
    }

    /// The box (light coordinates) a tile's texture covers, guard texels included.
    pub fn tile_box(&self, (i, j): Cell) -> ([f64; 3], [f64; 3]) {
        let guard = f64::from(GUARD_TEXELS) * TEXEL_M;
        let (x0, y0) = (i as f64 * TILE_SIDE_M, j as f64 * TILE_SIDE_M);
        (
            [x0 - guard, y0 - guard, self.depth[0]],
            [
                x0 + TILE_SIDE_M + guard,
                y0 + TILE_SIDE_M + guard,
                self.depth[1],
            ],
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

    /// Whether a bounding sphere reaches a tile's texture.
    pub fn touches(&self, cell: Cell, centre: [f64; 3], radius: f64) -> bool {
        let (min, max) = self.tile_box(cell);
        let c = Vector3::from(centre);
        (0..2).all(|k| {
            let v = self.axes[k].dot(&c);
            v + radius >= min[k] && v - radius <= max[k]
        })
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
    /// The tiles the window uses, row by row, with their place in it.
    pub fn cells(&self) -> impl Iterator<Item = (usize, usize, Cell)> + '_ {
        let (i0, j0) = self.corner;
        (0..self.extent.1).flat_map(move |b| {
            (0..self.extent.0).map(move |a| (a, b, (i0 + a as i64, j0 + b as i64)))
        })
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

/// Which tile each layer of the renderer's tile texture holds, least recently used first
/// out.
#[derive(Clone, Debug)]
pub(super) struct TileCache {
    cells: Vec<Option<Cell>>,
    used: Vec<u64>,
    frame: u64,
}

impl TileCache {
    /// An empty cache of `layers` tiles.
    pub fn new(layers: u32) -> Self {
        TileCache {
            cells: vec![None; layers as usize],
            used: vec![0; layers as usize],
            frame: 0,
        }
    }

    /// Starts a frame: the tiles it asks for are kept until the next.
    pub fn begin_frame(&mut self) {
        self.frame += 1;
    }

    /// The layer holding `cell`, and whether it must be drawn first (it was not held: it
    /// takes the layer least recently used, never one this frame asked for).
    pub fn layer(&mut self, cell: Cell) -> (u32, bool) {
        let frame = self.frame;
        let (k, fresh) = match self.cells.iter().position(|c| *c == Some(cell)) {
            Some(k) => (k, false),
            None => {
                let k = (0..self.cells.len())
                    .filter(|&k| self.used[k] != frame)
                    .min_by_key(|&k| (self.cells[k].is_some(), self.used[k]))
                    .expect("as many layers as a window has tiles");
                self.cells[k] = Some(cell);
                (k, true)
            }
        };
        self.used[k] = frame;
        (k as u32, fresh)
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
    fn the_cache_keeps_what_a_frame_uses_and_evicts_the_oldest() {
        let mut cache = TileCache::new(3);
        cache.begin_frame();
        assert_eq!(cache.layer((0, 0)), (0, true));
        assert_eq!(cache.layer((1, 0)), (1, true));
        cache.begin_frame();
        assert_eq!(cache.layer((1, 0)), (1, false));
        assert_eq!(cache.layer((2, 0)), (2, true));
        // (0, 0) is the oldest and this frame has not asked for it.
        assert_eq!(cache.layer((3, 0)), (0, true));
        // Every layer was last used by the last frame: the first goes.
        cache.begin_frame();
        assert_eq!(cache.layer((0, 0)), (0, true));
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
