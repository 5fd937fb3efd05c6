//! Ground truth's occlusion test: whether scenery stands between the camera and the target
//! board, so that a loss can be put down to `occluded` rather than to the tracker.
//!
//! Rays go from the camera's centre to a 3 × 3 grid of points over the board (its corners,
//! edge middles and centre, 5 % inside the outline). A ray is blocked when it crosses a
//! triangle of the scene's standing clutter (trees, poles, houses, buildings, parked
//! vehicles), of an oncoming vehicle or of an actor before it reaches the board. Wires are too thin to
//! hide a board and the ground is flat, so neither counts; the lead's own body is behind
//! its board, and the chase's hood below the view. The board is occluded when more than half
//! of the rays are blocked.

use crate::scene::{Layer, MeshPiece, Motion, Scene};
use nalgebra::{Isometry3, Point3, Vector3};

/// Points per side of the grid of rays over the board.
const GRID: usize = 3;
/// How far inside the board's outline the outer rays aim, as a share of its size.
const INSET: f64 = 0.05;

/// Whether more than half of the rays from the camera to the board are blocked by
/// scenery (see the module notes), for the camera at `world_from_camera`, the lead at
/// `world_from_lead`, the actors at `world_from_actors` (as
/// [`FrameInput::world_from_actors`](crate::FrameInput::world_from_actors); an actor
/// without a pose is nowhere) and oncoming traffic at `time_s`. Never, in a scene without
/// a lead.
pub fn target_occluded(
    scene: &Scene,
    world_from_chase: &Isometry3<f64>,
    world_from_lead: &Isometry3<f64>,
    world_from_actors: &[Isometry3<f64>],
    world_from_camera: &Isometry3<f64>,
    time_s: f64,
) -> bool {
    if scene.description().without_lead {
        // No board to hide.
        return false;
    }
    let poses = Poses {
        world_from_chase,
        world_from_lead,
        world_from_actors,
        time_s,
    };
    let target = &scene.description().target;
    let [(x0, x1), (y0, y1)] = {
        let corners = target.corners_m();
        let xs = corners.iter().map(|c| c[0]);
        let ys = corners.iter().map(|c| c[1]);
        let (lo_x, hi_x) = xs.fold((f64::MAX, f64::MIN), |(l, h), v| (l.min(v), h.max(v)));
        let (lo_y, hi_y) = ys.fold((f64::MAX, f64::MIN), |(l, h), v| (l.min(v), h.max(v)));
        [(lo_x, hi_x), (lo_y, hi_y)]
    };
    let world_from_target = world_from_lead * scene.lead_from_target();
    let eye = Point3::from(world_from_camera.translation.vector);
    let at = |i: usize, lo: f64, hi: f64| {
        let t = INSET + (1.0 - 2.0 * INSET) * i as f64 / (GRID - 1) as f64;
        lo + t * (hi - lo)
    };
    let mut blocked = 0;
    for i in 0..GRID {
        for j in 0..GRID {
            let p = world_from_target * Point3::new(at(i, x0, x1), at(j, y0, y1), 0.0);
            if ray_blocked(scene, &poses, eye, p) {
                blocked += 1;
            }
        }
    }
    2 * blocked > GRID * GRID
}

/// Where the moving objects are: the poses a frame gives.
struct Poses<'a> {
    world_from_chase: &'a Isometry3<f64>,
    world_from_lead: &'a Isometry3<f64>,
    world_from_actors: &'a [Isometry3<f64>],
    time_s: f64,
}

/// Whether the segment from `from` to `to` (world) crosses standing clutter, an oncoming
/// vehicle or an actor.
fn ray_blocked(scene: &Scene, poses: &Poses<'_>, from: Point3<f64>, to: Point3<f64>) -> bool {
    let hits = |piece: MeshPiece<'_>, object_from_world: &Isometry3<f64>| {
        let a = object_from_world * from;
        let b = object_from_world * to;
        piece.indices.chunks_exact(3).any(|tri| {
            let v = |k: usize| {
                let p = piece.vertices[(tri[k] - piece.base) as usize].position;
                Point3::new(f64::from(p[0]), f64::from(p[1]), f64::from(p[2]))
            };
            segment_hits_triangle(a, b, [v(0), v(1), v(2)])
        })
    };
    let world = Isometry3::identity();
    let near = (scene.chunks().iter().enumerate())
        .filter(|(_, c)| {
            matches!(c.layer, Layer::Clutter | Layer::Foliage)
                && segment_near_sphere(from, to, Point3::from(c.centre), c.radius)
        })
        .map(|(k, _)| k);
    let mut blocked = false;
    scene.visit_chunks(near, |_, piece| blocked = blocked || hits(piece, &world));
    if blocked {
        return true;
    }
    let objects = scene.objects_geometry();
    let first = scene.objects_indices().start;
    for object in scene.objects() {
        if !matches!(object.motion, Motion::Oncoming { .. } | Motion::Actor(_)) {
            continue;
        }
        let Some(world_from_object) = scene.world_from_object(
            object,
            poses.world_from_chase,
            poses.world_from_lead,
            poses.world_from_actors,
            poses.time_s,
        ) else {
            continue;
        };
        let centre = world_from_object * Point3::from(object.centre);
        let indices =
            (object.indices.start - first) as usize..(object.indices.end - first) as usize;
        let piece = MeshPiece {
            indices: &objects.indices[indices],
            ..objects
        };
        if segment_near_sphere(from, to, centre, object.radius)
            && hits(piece, &world_from_object.inverse())
        {
            return true;
        }
    }
    false
}

/// Whether the segment from `a` to `b` passes within `radius` of `centre`.
fn segment_near_sphere(a: Point3<f64>, b: Point3<f64>, centre: Point3<f64>, radius: f64) -> bool {
    let ab = b - a;
    let len2 = ab.norm_squared();
    let t = if len2 > 0.0 {
        ((centre - a).dot(&ab) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (a + ab * t - centre).norm() <= radius
}

/// Möller–Trumbore: whether the segment from `a` to `b` crosses the triangle strictly
/// between its ends (a hit at either end, the board itself, does not count).
fn segment_hits_triangle(a: Point3<f64>, b: Point3<f64>, tri: [Point3<f64>; 3]) -> bool {
    const EPS: f64 = 1e-12;
    let dir: Vector3<f64> = b - a;
    let e1 = tri[1] - tri[0];
    let e2 = tri[2] - tri[0];
    let p = dir.cross(&e2);
    let det = e1.dot(&p);
    if det.abs() < EPS {
        return false;
    }
    let inv = 1.0 / det;
    let s = a - tri[0];
    let u = s.dot(&p) * inv;
    if !(0.0..=1.0).contains(&u) {
        return false;
    }
    let q = s.cross(&e1);
    let v = dir.dot(&q) * inv;
    if v < 0.0 || u + v > 1.0 {
        return false;
    }
    let t = e2.dot(&q) * inv;
    t > 1e-6 && t < 1.0 - 1e-6
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_segment_through_a_triangle_hits_it_and_one_short_of_it_does_not() {
        let tri = [
            Point3::new(0.0, -1.0, -1.0),
            Point3::new(0.0, 1.0, -1.0),
            Point3::new(0.0, 0.0, 1.0),
        ];
        let a = Point3::new(-1.0, 0.0, 0.0);
        assert!(segment_hits_triangle(a, Point3::new(1.0, 0.0, 0.0), tri));
        assert!(!segment_hits_triangle(a, Point3::new(-0.1, 0.0, 0.0), tri));
        // Beside the triangle.
        assert!(!segment_hits_triangle(
            Point3::new(-1.0, 0.0, 2.0),
            Point3::new(1.0, 0.0, 2.0),
            tri
        ));
        assert!(segment_near_sphere(
            a,
            Point3::new(1.0, 0.0, 0.0),
            Point3::new(0.0, 0.5, 0.0),
            0.6
        ));
        assert!(!segment_near_sphere(
            a,
            Point3::new(1.0, 0.0, 0.0),
            Point3::new(0.0, 0.7, 0.0),
            0.6
        ));
    }
}
