//! The target board on the lead's back door: where it is in the lead's frame, and the
//! paint on it, by the paint rule the tracker's synthetic frames share.

use super::description::LeadVehicle;
use super::mesh::Mesh;
use super::object_slot::ObjectSlot;
use nalgebra::{Isometry3, Matrix3, Point3, Rotation3, Translation3, UnitQuaternion};
use tracker::TargetModel;

/// How far the board stands proud of the lead's back door, metres.
const BOARD_STANDOFF_M: f64 = 0.01;
/// How far the paint on the board stands proud of it, metres (depth-safe at 50 m).
const STRIPE_STANDOFF_M: f64 = 0.003;
/// The paint rule, shared with the tracker's synthetic frames.
pub use tracker::paint::{BOARD_MARGIN_M, STRIPE_EXTENSION_M as STRIPE_OVERRUN_M, STRIPE_WIDTH_M};
/// Albedo of the board's light paint.
pub const BOARD_ALBEDO: f64 = 0.85;
/// Albedo of the board's darkest paint (tone 0 of `tracker::paint::PaintRect`); other
/// tones lie between it and [`BOARD_ALBEDO`].
pub const STRIPE_ALBEDO: f64 = 0.06;

/// The target board's frame in the lead's scene frame (body centre), for a lead body: on its
/// back door, facing backwards.
pub fn lead_from_target_of(lead: &LeadVehicle) -> Isometry3<f64> {
    // Columns: target x = lead +z (the chase's right), target y = lead +y, target z = lead −x.
    let rotation = Rotation3::from_matrix_unchecked(Matrix3::new(
        0.0, 0.0, -1.0, //
        0.0, 1.0, 0.0, //
        1.0, 0.0, 0.0,
    ));
    Isometry3::from_parts(
        Translation3::new(
            -0.5 * lead.length_m - BOARD_STANDOFF_M,
            lead.board_centre_height_m,
            0.0,
        ),
        UnitQuaternion::from_rotation_matrix(&rotation),
    )
}

/// The point (`x`, `y`, `z`) of the target's frame (on the board, or `z` out of it) in the
/// lead's frame, the board's frame there being `lead_from_target`.
pub(super) fn on_lead(lead_from_target: &Isometry3<f64>, x: f64, y: f64, z: f64) -> [f64; 3] {
    let p = lead_from_target * Point3::new(x, y, z);
    [p.x, p.y, p.z]
}

/// A rectangle `[x0, y0, x1, y1]` of the target's frame, `z` out of the board, facing the
/// chase, in the lead's slot.
pub(super) fn board_rect(
    mesh: &mut Mesh,
    lead_from_target: &Isometry3<f64>,
    [x0, y0, x1, y1]: [f64; 4],
    z: f64,
    albedo: f64,
) {
    let put = |x: f64, y: f64| on_lead(lead_from_target, x, y, z);
    mesh.quad_with_normal(
        [put(x0, y0), put(x1, y0), put(x1, y1), put(x0, y1)],
        [-1.0, 0.0, 0.0],
        albedo,
        ObjectSlot::LEAD,
    );
}

/// The board and its paint by the paint rule, in the target frame mapped into the lead
/// frame by `lead_from_target`.
pub(super) fn paint(mesh: &mut Mesh, lead_from_target: &Isometry3<f64>, target: &TargetModel) {
    // Validated with the target file; a model that cannot be painted with steps (only a
    // library caller could build one) is painted with stripes.
    let rects = tracker::paint::layout(target).unwrap_or_else(|_| tracker::paint::stripes(target));
    for (k, r) in rects.iter().enumerate() {
        // The board lies on the door; what is painted on it stands just proud of it.
        let z = if k == 0 { 0.0 } else { STRIPE_STANDOFF_M };
        let albedo = STRIPE_ALBEDO + r.tone * (BOARD_ALBEDO - STRIPE_ALBEDO);
        board_rect(mesh, lead_from_target, r.bounds_m, z, albedo);
    }
}
