//! The target model of a vehicle's back (paper 2.1.1: "a 2-D model of the back of the lead
//! vehicle composed of line segments corresponding to features that give rise to strong
//! edges"), for each [`VehicleKind`], made from the numbers its shape is drawn from (`car`'s
//! [`CarBack`], `truck`'s constants), so the model and the drawn back cannot drift apart.
//!
//! The model's frame is a target's (`tracker::model`): metres from the model's centre, x
//! right and y up as the chase camera sees the back. Its centre is the middle of the
//! outline's bounding box on the body's back face ([`back_model_centre_m`]); its x is the
//! vehicle's z. It keeps the edges that are resolved where a whole-image search looks
//! ([`MIN_FEATURE_SPACING_M`]): of two parallel edges closer than that, the longer; a car's
//! cabin and window sides, which lean, are left out. The model paints with step edges, as
//! the paper's target does, where every segment kept still bounds a closed region of the
//! back, and with stripes otherwise.
//!
//! It is a plane's model of a back that is not quite plane: on a car the bumper stands
//! 0.15 m behind the body's back face and the cabin leans forward of it (a sedan's rear
//! window by up to 1.3 m), and the cabin's sides and window narrow towards the roof (the
//! model's vertical lines are at their mean). At 12 m the parallax moves those edges by a
//! pixel or two; a van's and the truck's backs are flat.

use super::car::{CarBack, CarBody};
use super::truck::{
    BOX_BACK_X_M, BOX_FLOOR_M, DOOR_HALF_WIDTH_M, DOOR_Y_M, REAR_BUMPER_HALF_M, REAR_BUMPER_Y_M,
    TAIL_LAMP_Y_M, TAIL_LAMP_Z_M, TRUCK_HALF_WIDTH_M, TRUCK_HEIGHT_M,
};
use super::vehicle_kind::VehicleKind;
use nalgebra::{Isometry3, Matrix3, Rotation3, Translation3, UnitQuaternion};
use tracker::TargetModel;

/// The models' nominal range, metres: the range at which their image scale is 1, the
/// shipped board target's.
pub const BACK_MODEL_NOMINAL_RANGE_M: f64 = 10.0;

/// The least spacing of two parallel features of a back's model whose extents meet, metres.
/// Two edges closer than `tracker::resolvability::EDGE_SEPARATION_PX` (3 px) merge in stage
/// 1, and a model with such a pair is unresolved (2.3, 2.4): its measurements are never
/// trusted and a search never acquires it. 0.25 m is 3.2 px at 25 m through an 8 mm lens
/// (the library's widest), where the whole-image search's smallest scale (0.4) puts a model
/// of [`BACK_MODEL_NOMINAL_RANGE_M`]. Of two features closer than this, the longer is kept.
pub const MIN_FEATURE_SPACING_M: f64 = 0.25;

/// A segment from one point to another of the back: (lateral, height) each, metres in the
/// vehicle's frame (z right, y up from the ground).
type Edge = [[f64; 2]; 2];

/// The target model of the back of a vehicle of `kind`: its strong horizontal and vertical
/// edges (see the module notes), named `"{kind}-back"`, at
/// [`BACK_MODEL_NOMINAL_RANGE_M`], painted with step edges where every segment bounds a
/// region and with stripes otherwise. Its corners are rounded to the
/// micrometre, so that they read as the numbers they are in a target file.
pub fn vehicle_back_model(kind: VehicleKind) -> TargetModel {
    let edges = edges(kind);
    let [_, centre_y, _] = back_model_centre_m(kind);
    let micrometres = |v: f64| (v * 1e6).round() / 1e6;
    let mut corners: Vec<[f64; 2]> = Vec::new();
    let mut corner = |[z, y]: [f64; 2]| {
        let p = [micrometres(z), micrometres(y - centre_y)];
        match corners.iter().position(|&c| c == p) {
            Some(k) => k,
            None => {
                corners.push(p);
                corners.len() - 1
            }
        }
    };
    let segments: Vec<[usize; 2]> = edges.iter().map(|&[a, b]| [corner(a), corner(b)]).collect();
    let model = TargetModel::new(
        format!("{}-back", kind.as_str()),
        BACK_MODEL_NOMINAL_RANGE_M,
        corners,
        segments,
    )
    .expect("every kind's back is a valid model (`back_model`'s tests)");
    // Painted with steps where every segment still bounds a region, else as stripes (the
    // paint is what a board of this model would carry; the renderer draws the vehicle).
    if tracker::paint::layout(&model).is_ok() {
        model
    } else {
        model.with_paint(tracker::paint::Paint::Stripes)
    }
}

/// Whether two axis-aligned edges are parallel, meet along their direction (touching ends
/// count: association compares a point with every feature whose extent spans it, eq. 8,
/// 10), and lie closer than [`MIN_FEATURE_SPACING_M`].
fn too_close(a: &Edge, b: &Edge) -> bool {
    let horizontal = |e: &Edge| e[0][1] == e[1][1];
    if horizontal(a) != horizontal(b) {
        return false;
    }
    let (along, across) = if horizontal(a) { (0, 1) } else { (1, 0) };
    let span = |e: &Edge| {
        let (p, q) = (e[0][along], e[1][along]);
        (p.min(q), p.max(q))
    };
    let ((a0, a1), (b0, b1)) = (span(a), span(b));
    a0.max(b0) <= a1.min(b1) && (a[0][across] - b[0][across]).abs() < MIN_FEATURE_SPACING_M
}

/// The edges a model can resolve: longest first, each kept unless it is [`too_close`] to
/// one kept before it; in their first order.
fn resolvable(edges: Vec<Edge>) -> Vec<Edge> {
    let length = |e: &Edge| (e[1][0] - e[0][0]).hypot(e[1][1] - e[0][1]);
    let mut order: Vec<usize> = (0..edges.len()).collect();
    // A stable sort: edges of one length keep their first order.
    order.sort_by(|&a, &b| length(&edges[b]).total_cmp(&length(&edges[a])));
    let mut kept = vec![false; edges.len()];
    for i in order {
        kept[i] = !(0..edges.len()).any(|j| kept[j] && too_close(&edges[i], &edges[j]));
    }
    edges
        .into_iter()
        .zip(kept)
        .filter_map(|(e, k)| k.then_some(e))
        .collect()
}

/// The centre of [`vehicle_back_model`]`(kind)` in the vehicle's body frame (x forward, y
/// up, z right, origin on the ground under the body's centre), metres: on the body's back
/// face (a car's inside its bumper, the truck's box's), at the middle height of the
/// outline, on the centre line.
pub fn back_model_centre_m(kind: VehicleKind) -> [f64; 3] {
    let (face_x, bottom, top) = match kind.car_body() {
        Some(body) => {
            let back = CarBack::of(body);
            (back.face_x, back.bumper_y[1], back.roof)
        }
        None => (BOX_BACK_X_M, REAR_BUMPER_Y_M[0], TRUCK_HEIGHT_M),
    };
    [face_x, 0.5 * (bottom + top), 0.0]
}

/// The frame of [`vehicle_back_model`]`(kind)` in the vehicle's body frame, as
/// `lead_from_target_of` places the board's: origin at [`back_model_centre_m`], x the
/// vehicle's right (+z), y up, z backwards (−x, towards a chase behind).
pub fn body_from_back_model(kind: VehicleKind) -> Isometry3<f64> {
    // Columns: model x = body +z, model y = body +y, model z = body −x.
    let rotation = Rotation3::from_matrix_unchecked(Matrix3::new(
        0.0, 0.0, -1.0, //
        0.0, 1.0, 0.0, //
        1.0, 0.0, 0.0,
    ));
    let [x, y, z] = back_model_centre_m(kind);
    Isometry3::from_parts(
        Translation3::new(x, y, z),
        UnitQuaternion::from_rotation_matrix(&rotation),
    )
}

/// The back's edges of `kind` that a model can resolve ([`resolvable`]).
fn edges(kind: VehicleKind) -> Vec<Edge> {
    resolvable(match kind.car_body() {
        Some(body) => car_edges(body),
        None => truck_edges(),
    })
}

/// The four sides of the rectangle from lateral `z0` to `z1` and height `y0` to `y1`.
fn rectangle([z0, z1]: [f64; 2], [y0, y1]: [f64; 2]) -> [Edge; 4] {
    [
        [[z0, y0], [z1, y0]],
        [[z1, y0], [z1, y1]],
        [[z1, y1], [z0, y1]],
        [[z0, y1], [z0, y0]],
    ]
}

/// A car's back: the roof line, the belt line (none on a van, whose cabin stands on its
/// back face), the rear window's glass (its top and bottom), the body's sides down to the
/// bumper's top, the bumper's top, and the two tail lamps.
/// The cabin's and the window's sides lean in towards the roof (`car`'s insets), so they
/// are no vertical features and are left out.
fn car_edges(body: CarBody) -> Vec<Edge> {
    let b = CarBack::of(body);
    let s = b.side;
    // The bumper's bottom and sides border the shade under the car and its tyres, as dark
    // as the bumper: no edge there. Its top, on the lighter body, is one.
    let bumper_top = b.bumper_y[1];
    let [glass_bottom, glass_top] = b.glass_y;
    let mut edges = vec![[[-b.cabin[1], b.roof], [b.cabin[1], b.roof]]];
    // A cabin standing on the back face (a van's) shows no belt line: it must not push out
    // the glass's bottom, the edge that is there.
    if !b.cabin_on_face {
        edges.push([[-s, b.belt], [s, b.belt]]);
    }
    edges.extend([
        [
            [-b.glass_half[0], glass_bottom],
            [b.glass_half[0], glass_bottom],
        ],
        [[-b.glass_half[1], glass_top], [b.glass_half[1], glass_top]],
    ]);
    edges.extend([
        [[-s, bumper_top], [-s, b.belt]],
        [[s, bumper_top], [s, b.belt]],
        [[-s, bumper_top], [s, bumper_top]],
    ]);
    let [inner, outer] = b.lamp_z;
    edges.extend(rectangle([-outer, -inner], b.lamp_y));
    edges.extend(rectangle([inner, outer], b.lamp_y));
    edges
}

/// The truck's back: the box's outline, the roll-up door, the rear bumper and the two tail
/// lamps on it.
fn truck_edges() -> Vec<Edge> {
    let w = TRUCK_HALF_WIDTH_M;
    let [inner, outer] = TAIL_LAMP_Z_M;
    let mut edges = Vec::new();
    edges.extend(rectangle([-w, w], [BOX_FLOOR_M, TRUCK_HEIGHT_M]));
    edges.extend(rectangle([-DOOR_HALF_WIDTH_M, DOOR_HALF_WIDTH_M], DOOR_Y_M));
    edges.extend(rectangle(
        [-REAR_BUMPER_HALF_M, REAR_BUMPER_HALF_M],
        REAR_BUMPER_Y_M,
    ));
    edges.extend(rectangle([-outer, -inner], TAIL_LAMP_Y_M));
    edges.extend(rectangle([inner, outer], TAIL_LAMP_Y_M));
    edges
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Point3;
    use tracker::paint::{layout, Paint};
    use tracker::Orientation;

    #[test]
    fn every_kinds_back_is_a_paintable_model_on_the_back_face() {
        for kind in VehicleKind::ALL {
            let model = vehicle_back_model(kind);
            assert_eq!(model.name(), format!("{}-back", kind.as_str()));
            // Steps where every segment bounds a region, else stripes.
            assert_eq!(
                model.paint() == Paint::Steps,
                layout(&model.clone().with_paint(Paint::Steps)).is_ok(),
                "{kind:?}"
            );
            let horizontal = model
                .orientations()
                .filter(|&o| o == Orientation::Horizontal)
                .count();
            assert!(horizontal >= 3 && model.segments().len() - horizontal >= 2);
            // Resolved where the whole-image search looks: no two parallel features whose
            // extents meet closer than 3 px at scale 0.4 through an 8 mm lens.
            let spacing_px = MIN_FEATURE_SPACING_M * 320.0 * 0.4 / BACK_MODEL_NOMINAL_RANGE_M;
            assert!(spacing_px >= tracker::resolvability::EDGE_SEPARATION_PX);
            let edges = edges(kind);
            for (i, a) in edges.iter().enumerate() {
                for b in &edges[i + 1..] {
                    assert!(!too_close(a, b), "{kind:?}: {a:?} and {b:?}");
                }
            }
            // The model spans the back: as wide as the body, from the bumper to the top.
            let (_, width, height) = kind.dimensions();
            let [w, h] = model.size_m();
            assert!(
                w <= width + 1e-9 && w > 0.9 * width,
                "{kind:?}: {w} of {width}"
            );
            let [face_x, centre_y, _] = back_model_centre_m(kind);
            assert!((centre_y + 0.5 * h - height).abs() < 1e-9, "{kind:?}: top");
            let (length, _, _) = kind.dimensions();
            assert!(face_x < 0.0 && face_x > -0.5 * length, "{kind:?}: {face_x}");
            // The model's frame: its x to the vehicle's right, z back towards a chase.
            let frame = body_from_back_model(kind);
            let right = frame * Point3::new(1.0, 0.0, 0.0);
            let back = frame * Point3::new(0.0, 0.0, 1.0);
            assert!((right.z - 1.0).abs() < 1e-12 && (back.x - face_x + 1.0).abs() < 1e-12);
        }
    }
}
