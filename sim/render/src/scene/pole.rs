//! The telephone pole: a post with a cross-arm and insulators, and what else it may carry
//! (a lower cross-arm, a transformer).

use super::footing::Footing;
use super::mesh::Mesh;
use super::object_slot::ObjectSlot;

/// Height of a telephone pole's top, metres.
pub(super) const POLE_TOP_M: f64 = 9.0;
/// Height of a pole's cross-arm, metres.
const ARM_Y_M: f64 = 8.4;
/// Height of a pole's lower cross-arm, metres.
const LOWER_ARM_Y_M: f64 = 7.6;
/// Albedo of a telephone pole.
pub(super) const POLE_ALBEDO: f64 = 0.30;
/// Albedo of insulators (glazed porcelain).
const INSULATOR_ALBEDO: f64 = 0.78;

/// What a telephone pole carries besides its cross-arm and insulators.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum PoleFittings {
    /// Nothing more.
    Plain,
    /// A second, shorter cross-arm below the first, with its own insulators.
    LowerArm,
    /// A transformer can hung on the side away from the road.
    Transformer,
}

impl PoleFittings {
    /// The fittings for a draw of a uniform number in [0, 1): half the poles are plain.
    pub(super) fn pick(u: f64) -> PoleFittings {
        if u < 0.5 {
            PoleFittings::Plain
        } else if u < 0.75 {
            PoleFittings::LowerArm
        } else {
            PoleFittings::Transformer
        }
    }
}

/// A telephone pole on flat ground at `at`, its cross-arm across `heading` (along its
/// right), with an insulator near each end of the arm and its fittings. Returns the tops
/// of the two outer insulators, where the wires hang from.
pub(super) fn pole(
    mesh: &mut Mesh,
    at: [f64; 2],
    heading: f64,
    fittings: PoleFittings,
) -> [[f64; 3]; 2] {
    let f = Footing::new(at, heading);
    mesh.upright_box(
        at[0],
        at[1],
        heading,
        0.13,
        0.13,
        0.0,
        POLE_TOP_M,
        POLE_ALBEDO,
    );
    let arm = |mesh: &mut Mesh, y: f64, reach: f64, insulators: &[f64]| {
        mesh.beam(f.p(0.0, y, -reach), f.p(0.0, y, reach), 0.06, 0.28);
        for &b in insulators {
            mesh.standing_box(
                f.p(0.0, y + 0.06 + 0.1, b),
                f.axes(),
                [0.045, 0.1, 0.045],
                INSULATOR_ALBEDO,
                ObjectSlot::WORLD,
            );
        }
    };
    arm(mesh, ARM_Y_M, 1.0, &[-0.9, -0.35, 0.9]);
    match fittings {
        PoleFittings::Plain => {}
        PoleFittings::LowerArm => arm(mesh, LOWER_ARM_Y_M, 0.7, &[-0.6, 0.6]),
        PoleFittings::Transformer => {
            // A can on a bracket, on the pole's side away from the road.
            mesh.beam(f.p(0.0, 6.9, 0.0), f.p(0.0, 6.9, 0.45), 0.04, POLE_ALBEDO);
            mesh.oriented_box(
                f.p(0.0, 6.4, 0.45),
                f.axes(),
                [0.27, 0.45, 0.27],
                0.42,
                ObjectSlot::WORLD,
            );
        }
    }
    let top = ARM_Y_M + 0.06 + 0.2;
    [f.p(0.0, top, -0.9), f.p(0.0, top, 0.9)]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::test_support::triangles;

    #[test]
    fn poles_carry_insulators_and_their_fittings() {
        let count = |fittings| {
            let mut mesh = Mesh::default();
            let ends = pole(&mut mesh, [0.0, 0.0], 0.0, fittings);
            for end in ends {
                // The wires hang from the insulators' tops.
                assert!(mesh.vertices.iter().any(|v| f64::from(v.albedo)
                    == f64::from(INSULATOR_ALBEDO as f32)
                    && (f64::from(v.position[1]) - end[1]).abs() < 1e-4
                    && (f64::from(v.position[2]) - end[2]).abs() < 0.05));
            }
            let insulators = mesh
                .vertices
                .iter()
                .filter(|v| f64::from(v.albedo) == f64::from(INSULATOR_ALBEDO as f32))
                .count()
                / 20;
            (insulators, triangles(&mesh))
        };
        let (plain, plain_triangles) = count(PoleFittings::Plain);
        eprintln!("plain pole: {plain_triangles} triangles");
        assert_eq!(plain, 3);
        assert_eq!(count(PoleFittings::LowerArm).0, 5);
        let (with_can, can_triangles) = count(PoleFittings::Transformer);
        assert_eq!(with_can, 3);
        assert_eq!(can_triangles, plain_triangles + 8 + 12, "bracket and can");
    }
}
