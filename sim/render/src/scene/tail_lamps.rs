//! Tail and brake lamps: red lamps at the rear corners of the lead and of the actors that
//! glow on their own, whatever lights the scene ([`TailLamps`]), brighter while the
//! vehicle brakes ([`Braking`]).

use super::description::LeadVehicle;
use super::mesh::Mesh;
use super::vehicle_kind::VehicleKind;
use tracker::TargetModel;

/// The tail and brake lamps' photometry and placement.
pub struct TailLamps;

impl TailLamps {
    /// A tail lamp's luminous intensity, candela: SAE J585 asks 2 cd at least and 18 cd at
    /// most on the axis; a typical lamp gives about 5.
    pub const TAIL_CD: f64 = 5.0;
    /// A brake (stop) lamp's, candela, added to the tail lamp's while braking: SAE J586
    /// asks 80–300 cd on the axis; the least, 80.
    pub const BRAKE_CD: f64 = 80.0;
    /// A lamp's lens: width and height, metres (0.024 m², a small car's tail lamp).
    pub const LENS_M: [f64; 2] = [0.2, 0.12];
    /// How far in from the body's side a lens's outer edge sits, metres.
    pub const INSET_M: f64 = 0.05;
    /// How far the lens stands proud of the back, metres.
    pub const PROUD_M: f64 = 0.01;
    /// The lens's own albedo, for the light that falls on it (dark red glass, in grey).
    pub const LENS_ALBEDO: f64 = 0.1;
    /// The albedo a lamp's vertices carry in place of the lens's: the shader takes any
    /// albedo at least [`TailLamps::MARK_MIN`] for a lamp, of albedo
    /// [`TailLamps::LENS_ALBEDO`], that glows by its slot's radiance.
    pub const MARK: f64 = 8.0;
    /// The least albedo the shader reads as a lamp's mark.
    pub const MARK_MIN: f64 = 4.0;
    /// The brake actuator's reading (0–1) above which the brake lamps are lit: real brake
    /// lamps are switched by the pedal, not by the deceleration; 5 % is past the pedal's
    /// free play.
    pub const BRAKE_SWITCH: f64 = 0.05;

    /// The luminance (cd/m²) of a lamp's lens, its intensity spread over the lens: about
    /// 210 cd/m² for the tail lamp alone and 3 500 cd/m² braking.
    pub fn luminance_cd_m2(braking: bool) -> f64 {
        let cd = Self::TAIL_CD + if braking { Self::BRAKE_CD } else { 0.0 };
        cd / (Self::LENS_M[0] * Self::LENS_M[1])
    }

    /// A lens's radiance in the scene's units (before the sensor's brightness): a white,
    /// matte surface under one unit of irradiance (`LUX_PER_UNIT` lux) has a luminance of
    /// `LUX_PER_UNIT / π` cd/m², so a luminance `L` is `π L / LUX_PER_UNIT` units: 0.41
    /// for the tail lamp, 6.7 braking (the board's white paint in full sun is about 0.8).
    pub fn radiance(braking: bool) -> f64 {
        std::f64::consts::PI * Self::luminance_cd_m2(braking) / super::Headlamps::LUX_PER_UNIT
    }

    /// Appends the two lamps of a body whose back is the plane `x = back_x` (facing −x),
    /// `half_width` either side of the centre, each lens's bottom at `bottom_m`, in `slot`.
    pub(super) fn add(mesh: &mut Mesh, slot: u32, back_x: f64, half_width: f64, bottom_m: f64) {
        let [w, h] = Self::LENS_M;
        for side in [-1.0, 1.0] {
            let outer = side * (half_width - Self::INSET_M);
            let inner = side * (half_width - Self::INSET_M - w);
            mesh.aabb(
                [back_x - Self::PROUD_M, bottom_m, outer.min(inner)],
                [back_x, bottom_m + h, outer.max(inner)],
                Self::MARK,
                slot,
            );
        }
    }

    /// Appends the lead's lamps: at its back's corners, low, and below the target board
    /// wherever the board reaches as far out as a lamp (the lamps are never drawn over it).
    pub(super) fn add_to_lead(
        mesh: &mut Mesh,
        slot: u32,
        lead: &LeadVehicle,
        target: &TargetModel,
    ) {
        Self::add(
            mesh,
            slot,
            -0.5 * lead.length_m,
            0.5 * lead.width_m,
            Self::lead_bottom_m(lead, target),
        );
    }

    /// The bottom of the lead's lenses, metres up: [`LEAD_LAMP_BOTTOM_M`], lower where the
    /// board reaches as far out as a lamp, never below the box's floor.
    fn lead_bottom_m(lead: &LeadVehicle, target: &TargetModel) -> f64 {
        let [bx0, by0, bx1, _] = tracker::paint::board_m(target);
        let half_width = 0.5 * lead.width_m;
        let board_bottom = lead.board_centre_height_m + by0;
        let reaches = bx0.abs().max(bx1.abs()) > half_width - Self::INSET_M - Self::LENS_M[0];
        // The box's floor is 0.55 m up; a lamp sits 0.1 m above it, below the board.
        let mut bottom = LEAD_LAMP_BOTTOM_M;
        if reaches {
            bottom = bottom.min(board_bottom - 0.05 - Self::LENS_M[1]);
        }
        bottom.max(LEAD_FLOOR_M)
    }

    /// The centres of the two lenses of a body whose back is the plane `x = back_x`, in its
    /// frame (x forward, y up, z right), as [`TailLamps::add`] draws them.
    fn centres(back_x: f64, half_width: f64, bottom_m: f64) -> [[f64; 3]; 2] {
        let [w, h] = Self::LENS_M;
        let z = half_width - Self::INSET_M - 0.5 * w;
        [-1.0, 1.0].map(|side| [back_x - Self::PROUD_M, bottom_m + 0.5 * h, side * z])
    }

    /// The centres of the lead's lenses in its frame (see [`TailLamps::centres`]).
    pub fn lead_centres(lead: &LeadVehicle, target: &TargetModel) -> [[f64; 3]; 2] {
        Self::centres(
            -0.5 * lead.length_m,
            0.5 * lead.width_m,
            Self::lead_bottom_m(lead, target),
        )
    }

    /// The centres of the lenses of an actor of `kind` in its frame.
    pub fn kind_centres(kind: VehicleKind) -> [[f64; 3]; 2] {
        let (length, width, _) = kind.dimensions();
        Self::centres(-0.5 * length, 0.5 * width, KIND_LAMP_BOTTOM_M)
    }

    /// A lamp's intensity, candela (towards the back, within its beam): the tail lamp's,
    /// and the brake lamp's too when `braking`.
    pub fn intensity_cd(braking: bool) -> f64 {
        Self::TAIL_CD + if braking { Self::BRAKE_CD } else { 0.0 }
    }

    /// Appends the lamps of an actor of `kind`: at its back's corners, their bottom
    /// [`KIND_LAMP_BOTTOM_M`] up (a car's and a truck's tail lamps sit 0.7–1 m up).
    pub(super) fn add_to_kind(mesh: &mut Mesh, slot: u32, kind: VehicleKind) {
        let (length, width, _) = kind.dimensions();
        Self::add(mesh, slot, -0.5 * length, 0.5 * width, KIND_LAMP_BOTTOM_M);
    }
}

/// The lead's box floor, metres above the ground: its lamps sit on it at the lowest.
const LEAD_FLOOR_M: f64 = 0.55;
/// A lead lamp's bottom, metres above the ground, when the board leaves room.
const LEAD_LAMP_BOTTOM_M: f64 = 0.65;
/// An actor's lamps' bottom, metres above the ground.
const KIND_LAMP_BOTTOM_M: f64 = 0.75;

/// Which vehicles brake in a frame, so that their brake lamps are lit: bit 0 the lead,
/// bit `1 + k` actor `k` (0: none brakes).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Braking(pub u64);

impl Braking {
    /// Whether the lead brakes.
    pub fn lead(self) -> bool {
        self.0 & 1 != 0
    }

    /// Whether actor `k` brakes.
    pub fn actor(self, k: usize) -> bool {
        k < 63 && self.0 & (1 << (k + 1)) != 0
    }

    /// From the lead's and each actor's brake actuator (0–1): braking above
    /// [`TailLamps::BRAKE_SWITCH`].
    pub fn of(lead_brake: f64, actor_brakes: impl IntoIterator<Item = f64>) -> Braking {
        let on = |b: f64| b > TailLamps::BRAKE_SWITCH;
        let mut bits = u64::from(on(lead_brake));
        for (k, b) in actor_brakes.into_iter().enumerate().take(63) {
            bits |= u64::from(on(b)) << (k + 1);
        }
        Braking(bits)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The lead's lamps stay off the board: below its bottom or beside it.
    #[test]
    fn the_leads_lamps_are_not_over_the_board() {
        let d = crate::scene::builtin_description(crate::scene::builtin_target(), 1);
        let mut mesh = Mesh::default();
        TailLamps::add_to_lead(&mut mesh, 2, &d.lead, &d.target);
        let [bx0, by0, bx1, by1] = tracker::paint::board_m(&d.target);
        let c = d.lead.board_centre_height_m;
        assert_eq!(mesh.vertices.len(), 48);
        for v in &mesh.vertices {
            let (y, z) = (f64::from(v.position[1]), f64::from(v.position[2]));
            let over = (bx0..=bx1).contains(&z) && (c + by0..=c + by1).contains(&y);
            assert!(!over, "({y}, {z}) on the board");
            assert!(y >= LEAD_FLOOR_M - 1e-6);
        }
    }

    #[test]
    fn braking_bits_name_their_vehicles() {
        let b = Braking::of(0.2, [0.0, 0.3, 0.04]);
        assert!(b.lead() && !b.actor(0) && b.actor(1) && !b.actor(2));
        assert!(TailLamps::radiance(true) > 10.0 * TailLamps::radiance(false));
    }
}
