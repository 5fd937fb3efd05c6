//! Light fitting: the sun's orthographic frusta ([`Light`]) fitted to what the camera sees,
//! and the frame's choice among them ([`Sunlight`]): the frame's own map, the window of
//! cached tiles under it, the board's fine map.

use super::view::CameraView;
use super::{RenderOptions, Renderer};
use crate::camera::rig::{CameraRig, FAR_M, NEAR_M};
use crate::camera::shadow_tiles::{self, TileFrame, Window};
use crate::scene::{Sun, Terrain};
use nalgebra::{Isometry3, Matrix4, Point3, Vector3};
use tracker::PixelRect;

/// How far (metres) along the sun's direction casters may stand beyond the receivers the
/// camera sees: taller than any building (20 m) at the lowest sensible sun (15°).
const CASTER_REACH_M: f64 = 80.0;
/// Height range of receivers, metres: nothing stands below the ground or above 25 m.
const RECEIVER_TOP_M: f64 = 25.0;
/// Shadow lookups start this many texels off the surface along its normal, which removes
/// acne without detaching shadows from their casters.
pub(super) const NORMAL_OFFSET_TEXELS: f64 = 1.5;
/// The board's own shadow map: a second, fine map around the target board, so that shadow
/// edges on the target are as crisp as real ones. Side, texels.
pub(super) const BOARD_SHADOW_SIZE: u32 = 256;
/// Half the side of the square it covers around the board's centre, metres: 4 m over 256
/// texels is 1.6 cm a texel (half a pixel at 5 m), and holds the 2.3 × 1.7 m board at any
/// sun angle.
const BOARD_SHADOW_HALF_M: f64 = 2.0;
/// How far towards the sun its casters may stand from the board, metres: a building's
/// height at a low sun.
const BOARD_CASTER_REACH_M: f64 = 40.0;
/// How far beyond the board's receivers' box (`BOARD_SHADOW_HALF_M` about its centre) a
/// draw's bounding sphere must stay to be drawn without the board's fine map: the normal
/// offset of its lookup (1.5 of its 1.6 cm texels) and f32 rounding, with room to spare.
const BOARD_RECEIVER_MARGIN_M: f64 = 0.1;
/// The sun's angular diameter, degrees. A shadow's penumbra, seen across its edge, is as
/// wide as the sun's disc seen from the receiver across the distance to the occluder:
/// 2 tan(0.265°) ≈ 0.93 cm for every metre.
const SUN_DIAMETER_DEG: f64 = 0.53;

impl Renderer {
    /// The frame's maps from the sun, fitted to the camera's `view` through the pixels
    /// `part` of the frame, with the target board's centre at `board_centre`.
    pub(super) fn fit_sun(
        &self,
        view: &CameraView,
        board_centre: Option<Point3<f64>>,
        part: PixelRect,
    ) -> Sunlight {
        let sun = &self.scene.description().sun.lighting();
        let tiles = &self.slots.tiles;
        Sunlight::fit(
            &self.rig,
            view,
            sun,
            &self.options,
            tiles,
            board_centre,
            part,
            receiver_band(self.scene.terrain()),
        )
    }
}

/// A frame's maps from the sun, fitted to the part of the frame drawn.
pub(super) struct Sunlight {
    /// The sun's frustum, fitted to the part of the camera's frustum within the shadow
    /// distance.
    pub fitted: Light,
    /// Static shadows from the cached tiles under the fitted map, and the vehicles drawn
    /// into them (see `shadow_tiles`): the window of tiles, and its square of tiles as one
    /// map. `None` when the cache is off or the fitted map is wider than a window: every
    /// caster is then drawn into the frame's own map.
    pub window: Option<(Window, Light)>,
    /// Only the texels the part of the frame asked for can sample: of the map the lookups
    /// read (the window's square of tiles, else the frame's own map)...
    pub seen: PixelRect,
    /// ...whose side is this many texels.
    pub size: u32,
    /// With soft shadows on the target: the board's receivers, what can lie within its fine
    /// map (see [`Sunlight::in_board_map`]).
    board_receivers: Option<Light>,
    /// The board's shadow map: a fine one around the target board, with its casters.
    pub board: Option<Light>,
}

impl Sunlight {
    /// Fits the frame's maps: to the camera's `view` (the pixels `part` of the frame, of
    /// `rig`), for the `sun`, the options' shadow distance, map size and cache, the static
    /// tiles' frame `tiles`, the board's centre (`None` without a lead in the scene), and
    /// the heights receivers lie between (`band`, metres: [`receiver_band`]).
    #[allow(clippy::too_many_arguments)]
    pub fn fit(
        rig: &CameraRig,
        view: &CameraView,
        sun: &Sun,
        options: &RenderOptions,
        tiles: &TileFrame,
        board_centre: Option<Point3<f64>>,
        part: PixelRect,
        band: [f64; 2],
    ) -> Sunlight {
        let fitted = Light::fit(
            rig,
            &view.world_from_camera,
            sun.direction(),
            options.shadow_distance_m,
            options.shadow_map_size,
            band,
        );
        let window = if options.cached_shadows {
            shadow_tiles::window(
                [fitted.min[0], fitted.min[1]],
                [fitted.max[0], fitted.max[1]],
            )
        } else {
            None
        }
        .map(|w| {
            let (min, max) = tiles.window_box(w.corner);
            let light = Light::of_box(tiles.axes, min, max, shadow_tiles::SLOTS_TEXELS);
            (w, light)
        });
        let (lookup, size) = match &window {
            Some((_, l)) => (l, shadow_tiles::SLOTS_TEXELS),
            None => (&fitted, options.shadow_map_size),
        };
        let seen = if part == PixelRect::whole(rig.width as usize, rig.height as usize) {
            PixelRect::whole(size as usize, size as usize)
        } else {
            lookup.texels_seen(rig, &view.world_from_camera, part, size, band)
        };
        let board_centre = board_centre.filter(|_| sun.soft_shadows);
        let around_board = |reach_m| {
            board_centre.map(|c| {
                Light::around(
                    c.coords,
                    sun.direction(),
                    BOARD_SHADOW_HALF_M,
                    reach_m,
                    BOARD_SHADOW_SIZE,
                )
            })
        };
        Sunlight {
            fitted,
            window,
            seen,
            size,
            board_receivers: around_board(BOARD_SHADOW_HALF_M),
            board: around_board(BOARD_CASTER_REACH_M),
        }
    }

    /// The map the frame's lookups read: the window's square of tiles, or the frame's own.
    pub fn lookup(&self) -> &Light {
        match &self.window {
            Some((_, l)) => l,
            None => &self.fitted,
        }
    }

    /// Whether a bounding sphere can lie within the board's fine map. With soft shadows on
    /// the target, only what can takes the soft-shadow pipelines: the rest would run the
    /// board's lookups for nothing (llvmpipe runs both sides of a branch).
    pub fn in_board_map(&self, centre: [f64; 3], radius: f64) -> bool {
        self.board_receivers
            .as_ref()
            .is_some_and(|l| l.holds(centre, radius + BOARD_RECEIVER_MARGIN_M))
    }

    /// The board's map's parameters in the frame's `Globals`: its depth range, the
    /// penumbra's width a metre from the occluder, its texel, and from which depth receivers
    /// use it.
    pub fn board_params(board: Option<&Light>) -> [f32; 4] {
        match board {
            Some(l) => {
                let depth_m = l.max[2] - l.min[2];
                [
                    depth_m as f32,
                    (2.0 * (0.5 * SUN_DIAMETER_DEG).to_radians().tan()) as f32,
                    l.texel_m as f32,
                    // Receivers from 2 m in front of the board's centre (towards the
                    // sun) use this map; the rest, the main one.
                    ((BOARD_CASTER_REACH_M - BOARD_SHADOW_HALF_M) / depth_m) as f32,
                ]
            }
            // No lead in the scene: no receiver uses the board's map.
            None => [1.0, 0.0, 1.0, 2.0],
        }
    }
}

/// The sun's orthographic frustum, fitted to the receivers the camera can see.
pub(super) struct Light {
    /// World → the shadow map's clip space (x, y in −1..1, depth 0 nearest the sun).
    pub clip_from_world: Matrix4<f64>,
    /// The light frame's axes (rows: x, y, towards the sun) and fitted box.
    axes: [Vector3<f64>; 3],
    min: [f64; 3],
    max: [f64; 3],
    /// Size of one shadow texel on the ground, metres (the larger side).
    pub texel_m: f64,
}

impl Light {
    /// The light frame's axes: x and y across the sun's rays, and the direction towards it.
    pub fn axes(towards_sun: [f64; 3]) -> [Vector3<f64>; 3] {
        let d = Vector3::from(towards_sun).normalize();
        let hint = if d.y.abs() > 0.99 {
            Vector3::x()
        } else {
            Vector3::y()
        };
        let x = hint.cross(&d).normalize();
        let y = d.cross(&x);
        [x, y, d]
    }

    /// The orthographic projection onto the box `min..max` (light coordinates) of a map
    /// `size` texels square.
    pub fn of_box(axes: [Vector3<f64>; 3], min: [f64; 3], max: [f64; 3], size: u32) -> Light {
        let [x, y, d] = axes;
        let (sx, sy, depth) = (max[0] - min[0], max[1] - min[1], max[2] - min[2]);
        let row = |axis: &Vector3<f64>, scale: f64, offset: f64| {
            [axis.x * scale, axis.y * scale, axis.z * scale, offset]
        };
        let r0 = row(&x, 2.0 / sx, -2.0 * min[0] / sx - 1.0);
        let r1 = row(&y, 2.0 / sy, -2.0 * min[1] / sy - 1.0);
        let r2 = row(&d, -1.0 / depth, max[2] / depth);
        let clip_from_world = Matrix4::new(
            r0[0], r0[1], r0[2], r0[3], //
            r1[0], r1[1], r1[2], r1[3], //
            r2[0], r2[1], r2[2], r2[3], //
            0.0, 0.0, 0.0, 1.0,
        );
        Light {
            clip_from_world,
            axes,
            min,
            max,
            texel_m: sx.max(sy) / f64::from(size),
        }
    }

    /// A map around `centre` (world): `half_m` either side across the rays and along them,
    /// and casters up to `reach_m` towards the sun.
    fn around(
        centre: Vector3<f64>,
        towards_sun: [f64; 3],
        half_m: f64,
        reach_m: f64,
        size: u32,
    ) -> Light {
        let axes = Self::axes(towards_sun);
        let c = axes.map(|a| a.dot(&centre));
        Self::of_box(
            axes,
            [c[0] - half_m, c[1] - half_m, c[2] - half_m],
            [c[0] + half_m, c[1] + half_m, c[2] + reach_m],
            size,
        )
    }

    /// The map of the receivers the camera can see within `distance_m`, `size` texels a
    /// side, with casters up to `CASTER_REACH_M` beyond them towards the sun.
    fn fit(
        rig: &CameraRig,
        world_from_camera: &Isometry3<f64>,
        towards_sun: [f64; 3],
        distance_m: f64,
        size: u32,
        band: [f64; 2],
    ) -> Light {
        let axes = Self::axes(towards_sun);
        // Corners of the camera's frustum from near to the shadow distance, clamped to the
        // height band receivers live in, in light coordinates.
        let [fx, fy] = rig.intrinsics.focal_px();
        let [cx, cy] = rig.intrinsics.image_center_px;
        let (mut min, mut max) = ([f64::MAX; 3], [f64::MIN; 3]);
        for z in [NEAR_M, distance_m] {
            for (u, v) in [
                (-0.5, -0.5),
                (f64::from(rig.width) - 0.5, -0.5),
                (-0.5, f64::from(rig.height) - 0.5),
                (f64::from(rig.width) - 0.5, f64::from(rig.height) - 0.5),
            ] {
                let p_cam = Point3::new((u - cx) / fx * z, (v - cy) / fy * z, z);
                let mut p = world_from_camera * p_cam;
                p.y = p.y.clamp(band[0], band[1]);
                for k in 0..3 {
                    let value = axes[k].dot(&p.coords);
                    min[k] = min[k].min(value);
                    max[k] = max[k].max(value);
                }
            }
        }
        max[2] += CASTER_REACH_M;
        Self::of_box(axes, min, max, size)
    }

    /// The texels of this map (`size` a side) that shading the camera's pixels `part` can
    /// sample: every receiver seen through `part` lies in the camera's frustum cut to
    /// `part`, from the near to the far plane, and within the receivers' height band; that
    /// region's corners all lie on its edges clipped to the band, and the map is an
    /// orthographic projection, so their bounding box in the map holds it. Grown by the
    /// normal offset of the lookups and the bilinear comparison's texel.
    fn texels_seen(
        &self,
        rig: &CameraRig,
        world_from_camera: &Isometry3<f64>,
        part: PixelRect,
        size: u32,
        band: [f64; 2],
    ) -> PixelRect {
        let [fx, fy] = rig.intrinsics.focal_px();
        let [cx, cy] = rig.intrinsics.image_center_px;
        let (u0, u1) = (part.x0 as f64 - 0.5, part.x1 as f64 - 0.5);
        let (v0, v1) = (part.y0 as f64 - 0.5, part.y1 as f64 - 0.5);
        let corner = |u: f64, v: f64, z: f64| {
            world_from_camera * Point3::new((u - cx) / fx * z, (v - cy) / fy * z, z)
        };
        let rect = [(u0, v0), (u1, v0), (u1, v1), (u0, v1)];
        let mut edges = Vec::with_capacity(12);
        for k in 0..4 {
            let (a, b) = (rect[k], rect[(k + 1) % 4]);
            edges.push((corner(a.0, a.1, NEAR_M), corner(a.0, a.1, FAR_M)));
            edges.push((corner(a.0, a.1, NEAR_M), corner(b.0, b.1, NEAR_M)));
            edges.push((corner(a.0, a.1, FAR_M), corner(b.0, b.1, FAR_M)));
        }
        let (mut lo, mut hi) = ([f64::MAX; 2], [f64::MIN; 2]);
        for (a, b) in edges {
            let Some((t0, t1)) = within_receivers(a.y, b.y, band) else {
                continue;
            };
            for t in [t0, t1] {
                let p = a.coords + (b.coords - a.coords) * t;
                for k in 0..2 {
                    let v = self.axes[k].dot(&p);
                    lo[k] = lo[k].min(v);
                    hi[k] = hi[k].max(v);
                }
            }
        }
        if lo[0] > hi[0] {
            return PixelRect::whole(0, 0);
        }
        // Map texels: x from min[0], y from max[1] downwards (the clip y is flipped).
        let n = f64::from(size);
        let (sx, sy) = (self.max[0] - self.min[0], self.max[1] - self.min[1]);
        let margin = NORMAL_OFFSET_TEXELS + 2.0;
        let tx = |v: f64| (v - self.min[0]) / sx * n;
        let ty = |v: f64| (self.max[1] - v) / sy * n;
        let clip = |t: f64| t.clamp(0.0, n) as usize;
        PixelRect {
            x0: clip((tx(lo[0]) - margin).floor()),
            x1: clip((tx(hi[0]) + margin).ceil()),
            y0: clip((ty(hi[1]) - margin).floor()),
            y1: clip((ty(lo[1]) + margin).ceil()),
        }
    }

    /// The texels of this map (`size` a side) that a bounding sphere can cover, grown by two
    /// texels (the rasteriser's rounding, with room to spare).
    pub fn caster_texels(&self, centre: [f64; 3], radius: f64, size: u32) -> PixelRect {
        let n = f64::from(size);
        let (sx, sy) = (self.max[0] - self.min[0], self.max[1] - self.min[1]);
        let clip = |t: f64| t.clamp(0.0, n) as usize;
        let c = Vector3::from(centre);
        let tx = (self.axes[0].dot(&c) - self.min[0]) / sx * n;
        let ty = (self.max[1] - self.axes[1].dot(&c)) / sy * n;
        let (rx, ry) = (radius / sx * n + 2.0, radius / sy * n + 2.0);
        PixelRect {
            x0: clip((tx - rx).floor()),
            x1: clip((tx + rx).ceil()),
            y0: clip((ty - ry).floor()),
            y1: clip((ty + ry).ceil()),
        }
    }

    /// Whether a sphere can cover any of the texels `texels` of this map (`size` a side).
    pub fn reaches(&self, texels: PixelRect, size: u32, centre: [f64; 3], radius: f64) -> bool {
        let n = f64::from(size);
        let (sx, sy) = (self.max[0] - self.min[0], self.max[1] - self.min[1]);
        let c = Vector3::from(centre);
        let (x, y) = (self.axes[0].dot(&c), self.axes[1].dot(&c));
        // The texels' extent in the light frame (texel rows run down from max[1]).
        let x0 = self.min[0] + texels.x0 as f64 / n * sx;
        let x1 = self.min[0] + texels.x1 as f64 / n * sx;
        let y0 = self.max[1] - texels.y1 as f64 / n * sy;
        let y1 = self.max[1] - texels.y0 as f64 / n * sy;
        !texels.is_empty()
            && x + radius >= x0
            && x - radius <= x1
            && y + radius >= y0
            && y - radius <= y1
    }

    /// Whether a sphere can lie within the map's box.
    pub fn holds(&self, centre: [f64; 3], radius: f64) -> bool {
        let c = Vector3::from(centre);
        (0..3).all(|k| {
            let v = self.axes[k].dot(&c);
            v >= self.min[k] - radius && v <= self.max[k] + radius
        })
    }
}

/// The heights receivers of shadows lie between, metres: the ground (y = 0, or the lowest
/// of a road's profile) up to [`RECEIVER_TOP_M`] above it (above the highest of the
/// profile). On flat or bumpy ground, exactly `[0, RECEIVER_TOP_M]`.
pub(super) fn receiver_band(terrain: Option<&Terrain>) -> [f64; 2] {
    match terrain.filter(|t| t.follows_profile()) {
        Some(t) => {
            let [lo, hi] = t.height_range_m();
            [lo.min(0.0), hi.max(0.0) + RECEIVER_TOP_M]
        }
        None => [0.0, RECEIVER_TOP_M],
    }
}

/// The part (`t0..t1`, from 0 at `a` to 1 at `b`) of an edge from height `a_y` to `b_y`
/// within the receivers' height band `band`, if any.
fn within_receivers(a_y: f64, b_y: f64, band: [f64; 2]) -> Option<(f64, f64)> {
    let (mut t0, mut t1) = (0.0f64, 1.0f64);
    let dy = b_y - a_y;
    for (bound, below) in [(band[0], true), (band[1], false)] {
        if dy.abs() < 1e-12 {
            if (below && a_y < bound) || (!below && a_y > bound) {
                t1 = -1.0;
            }
            continue;
        }
        let t = (bound - a_y) / dy;
        // Inside is y >= the floor (below it is out) and y <= the top.
        let entering = if below { dy > 0.0 } else { dy < 0.0 };
        if entering {
            t0 = t0.max(t);
        } else {
            t1 = t1.min(t);
        }
    }
    (t0 <= t1).then_some((t0, t1))
}
