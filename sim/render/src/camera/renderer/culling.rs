//! Culling: every piece of geometry a frame may draw ([`DrawItem`], the moving objects
//! placed), the camera's frustum, and the casters a map from the sun draws
//! ([`CasterDraws`]).

use super::light::{Light, Sunlight};
use super::pipelines::Shading;
use super::uniforms::{to_f32, Placed};
use super::view::CameraView;
use super::{DrawStats, Renderer};
use crate::camera::frame::Field;
use crate::camera::rig::{CameraRig, FAR_M, NEAR_M};
use crate::camera::shadow_tiles::SlotWork;
use crate::scene::{Layer, ObjectSlot, Scene};
use nalgebra::{Isometry3, Point3, Vector3};
use std::ops::Range;
use tracker::PixelRect;

/// Draw-order class of the chase vehicle's hood: drawn first, unscissored.
pub(super) const HOOD_CLASS: u8 = 0;
/// Draw-order class of the first static layer: below it, the moving objects.
const FIRST_STATIC_CLASS: u8 = 3;

impl Renderer {
    /// What each pass draws of the frame's items, seen from `view` through the pixels
    /// `part` of the frame, with the `sun`'s maps: the main pass's draws, the casters of
    /// the frame's own map (or, with the static shadows cached, the vehicles alone) and of
    /// the board's, and the work in the static tiles' slots, which it returns. Sets the
    /// frame's [`DrawStats`].
    pub(super) fn cull(&mut self, view: &CameraView, sun: &Sunlight, part: PixelRect) -> SlotWork {
        let frustum = Frustum::of_part(&self.rig, &view.camera_from_world, part);
        let items = &self.items;
        self.main.cull(items, &frustum, self.scene.chunks(), sun);
        let texels = Some((sun.seen, sun.size));
        let with_static = sun.window.is_none();
        self.shadow
            .draws
            .cull(items, sun.lookup(), texels, with_static);
        let slot_work = self.slots.plan(items, sun);
        match &sun.board {
            Some(light) => self.board_shadow.draws.cull(items, light, None, true),
            None => self.board_shadow.draws.clear(),
        }
        // The shadow triangles are those of the frame's own map; with the static shadows
        // cached, the slots pass's encoding replaces them with the vehicles' it drew.
        self.stats = DrawStats {
            main_triangles: self.main.triangles(false),
            soft_triangles: self.main.triangles(true),
            shadow_triangles: self.shadow.draws.triangles(),
            draw_calls: (self.main.draw_calls() + self.shadow.draws.len()) as u32,
            shadow_tiles_drawn: slot_work.tiles.len() as u32,
        };
        slot_work
    }
}

/// A piece of geometry the frame may draw: static chunk or placed moving object.
#[derive(Clone, Debug)]
pub(super) struct DrawItem {
    pub indices: Range<u32>,
    /// Bounding sphere, world frame.
    pub centre: [f64; 3],
    pub radius: f64,
    casts_shadow: bool,
    /// Draw-order class: hood, lead, other vehicles, then the static layers.
    pub class: u8,
    /// From the camera to the bounding sphere's centre, metres.
    pub distance_m: f64,
    /// Which pipeline draws it.
    pub shading: Shading,
    /// The static chunk it is (its index in [`Scene::chunks`]), whose parts the main pass
    /// culls one by one.
    pub chunk: Option<usize>,
}

impl DrawItem {
    /// Whether it is a moving object that casts a shadow: what a frame draws from the sun
    /// on top of the static casters' cached tiles.
    pub fn moving_caster(&self) -> bool {
        self.casts_shadow && self.class < FIRST_STATIC_CLASS
    }
}

/// Into `items`: every moving object, placed as `field` has it, then every static chunk,
/// each with its bounding sphere, its distance from the camera and its pipeline (the
/// textured ones when `textured`).
pub(super) fn gather_items(
    items: &mut Vec<DrawItem>,
    scene: &Scene,
    field: &Field,
    view: &CameraView,
    textured: bool,
) -> Placed {
    let eye = view.eye;
    let mut world_from_object = [[[0f32; 4]; 4]; ObjectSlot::COUNT as usize];
    world_from_object[ObjectSlot::WORLD as usize] = to_f32(&view.relative_from_world);
    items.clear();
    let mut board_centre = None;
    for object in scene.objects() {
        // Off the route: the zero matrix collapses it to nothing.
        if let Some(pose) = scene.world_from_object(
            object,
            &field.world_from_chase,
            &field.world_from_lead,
            &field.world_from_actors,
            field.time_s,
        ) {
            world_from_object[object.slot as usize] =
                to_f32(&(view.relative_from_world * pose.to_homogeneous()));
            if object.slot == ObjectSlot::LEAD {
                board_centre = Some(pose * scene.lead_from_target() * Point3::origin());
            }
            let c = pose * Point3::from(object.centre);
            // The hood hides the bottom of the frame and the lead the middle: drawn
            // first, they let depth testing reject what lies behind them unshaded.
            let class = match object.slot {
                ObjectSlot::CHASE => HOOD_CLASS,
                ObjectSlot::LEAD => 1,
                _ => 2,
            };
            items.push(DrawItem {
                indices: object.indices.clone(),
                centre: [c.x, c.y, c.z],
                radius: object.radius,
                casts_shadow: object.casts_shadow,
                class,
                distance_m: (c.coords - eye).norm(),
                shading: Shading::Plain,
                chunk: None,
            });
        }
    }
    for (index, chunk) in scene.chunks().iter().enumerate() {
        items.push(DrawItem {
            chunk: Some(index),
            indices: chunk.indices.clone(),
            centre: chunk.centre,
            radius: chunk.radius,
            casts_shadow: chunk.casts_shadow,
            class: FIRST_STATIC_CLASS + chunk.layer as u8,
            distance_m: (Vector3::from(chunk.centre) - eye).norm(),
            // Only the ground layer has grass faces (`Scene`'s invariant): the other
            // pipelines leave the grass's hashes out.
            shading: match (chunk.layer, textured) {
                (Layer::Foliage, _) => Shading::Foliage,
                (Layer::Surface, true) => Shading::Ground,
                (Layer::Ground, true) => Shading::GroundGrass,
                (Layer::Ground, false) => Shading::PlainGrass,
                _ => Shading::Plain,
            },
        });
    }
    Placed {
        world_from_object,
        board_centre,
    }
}

/// The camera's view frustum as planes through the optical centre plus near and far, in the
/// camera frame.
pub(super) struct Frustum {
    camera_from_world: Isometry3<f64>,
    sides: [Vector3<f64>; 4],
}

impl Frustum {
    /// The frustum through the pixels `part` of the frame.
    pub fn of_part(
        rig: &CameraRig,
        camera_from_world: &Isometry3<f64>,
        part: PixelRect,
    ) -> Frustum {
        let [fx, fy] = rig.intrinsics.focal_px();
        let [cx, cy] = rig.intrinsics.image_center_px;
        let left = (part.x0 as f64 - 0.5 - cx) / fx;
        let right = (part.x1 as f64 - 0.5 - cx) / fx;
        let top = (part.y0 as f64 - 0.5 - cy) / fy;
        let bottom = (part.y1 as f64 - 0.5 - cy) / fy;
        Frustum {
            camera_from_world: *camera_from_world,
            sides: [
                Vector3::new(1.0, 0.0, -left).normalize(),
                Vector3::new(-1.0, 0.0, right).normalize(),
                Vector3::new(0.0, 1.0, -top).normalize(),
                Vector3::new(0.0, -1.0, bottom).normalize(),
            ],
        }
    }

    /// Whether a bounding sphere (world frame) can reach into the frustum.
    pub fn sees(&self, centre: [f64; 3], radius: f64) -> bool {
        let c = (self.camera_from_world * Point3::from(centre)).coords;
        c.z > NEAR_M - radius
            && c.z < FAR_M + radius
            && self.sides.iter().all(|n| n.dot(&c) >= -radius)
    }
}

/// What a pass from the sun draws: the index ranges of its solid casters and of its
/// canopies (drawn by a pipeline of their own), sorted and joined into as few draws as
/// possible (depth only, so order does not matter). Kept to avoid allocating every frame.
#[derive(Default)]
pub(super) struct CasterDraws {
    pub solid: Vec<Range<u32>>,
    pub foliage: Vec<Range<u32>>,
}

impl CasterDraws {
    /// The items that cast shadows within `light`'s box (and, with `texels`, can cover
    /// those texels of its map, `size` a side), the static ones only `with_static` (else the
    /// moving objects alone).
    pub fn cull(
        &mut self,
        items: &[DrawItem],
        light: &Light,
        texels: Option<(PixelRect, u32)>,
        with_static: bool,
    ) {
        caster_draws(items, light, texels, false, with_static, &mut self.solid);
        caster_draws(items, light, texels, true, with_static, &mut self.foliage);
    }

    pub fn clear(&mut self) {
        self.solid.clear();
        self.foliage.clear();
    }

    /// Both lists, solid casters first.
    pub fn lists(&self) -> [&[Range<u32>]; 2] {
        [&self.solid, &self.foliage]
    }

    /// Triangles in both lists.
    pub fn triangles(&self) -> u32 {
        triangles(&self.solid) + triangles(&self.foliage)
    }

    /// Draw calls in both lists.
    pub fn len(&self) -> usize {
        self.solid.len() + self.foliage.len()
    }
}

/// Triangles in a list of index ranges.
pub(super) fn triangles(draws: &[Range<u32>]) -> u32 {
    draws.iter().map(|r| (r.end - r.start) / 3).sum()
}

/// Into `draws`: the index ranges of the items that cast shadows within `light`'s box,
/// canopies (`foliage`) or the rest, the static ones only `with_static` (else the moving
/// objects alone), sorted and joined into as few draws as possible (depth only, so order
/// does not matter).
fn caster_draws(
    items: &[DrawItem],
    light: &Light,
    texels: Option<(PixelRect, u32)>,
    foliage: bool,
    with_static: bool,
    draws: &mut Vec<Range<u32>>,
) {
    let mut ranges: Vec<Range<u32>> = items
        .iter()
        .filter(|d| {
            d.casts_shadow
                && (with_static || d.moving_caster())
                && (d.shading == Shading::Foliage) == foliage
                && light.holds(d.centre, d.radius)
                && texels.is_none_or(|(t, size)| light.reaches(t, size, d.centre, d.radius))
        })
        .map(|d| d.indices.clone())
        .collect();
    draws.clear();
    sort_merged(draws, &mut ranges);
}

/// Into `draws` (appended): `ranges`, sorted by their starts and joined where they touch
/// ([`push_merged`]).
pub(super) fn sort_merged(draws: &mut Vec<Range<u32>>, ranges: &mut [Range<u32>]) {
    ranges.sort_by_key(|r| r.start);
    for range in ranges {
        push_merged(draws, range.clone());
    }
}

/// Appends an index range to a draw list, joining it to the last one when they touch.
pub(super) fn push_merged(draws: &mut Vec<Range<u32>>, range: Range<u32>) {
    match draws.last_mut() {
        Some(last) if last.end == range.start => last.end = range.end,
        _ => draws.push(range),
    }
}
