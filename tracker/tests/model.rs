//! The target model's validation (2.1.1) and the camera's stage 8 (eq. 36).
//! Run with `cargo test -p tracker --test model`.

use tracker::{Camera, Orientation, TargetError, TargetModel};

fn rect() -> (Vec<[f64; 2]>, Vec<[usize; 2]>) {
    (
        vec![[-0.8, 0.5], [0.8, 0.5], [0.8, -0.5], [-0.8, -0.5]],
        vec![[0, 1], [1, 2], [2, 3], [3, 0]],
    )
}

#[test]
fn a_rectangle_is_a_valid_model() {
    let (c, s) = rect();
    let m = TargetModel::new("r", 10.0, c, s).unwrap();
    let o: Vec<_> = m.orientations().collect();
    assert_eq!(
        o,
        [
            Orientation::Horizontal,
            Orientation::Vertical,
            Orientation::Horizontal,
            Orientation::Vertical
        ]
    );
    assert_eq!(m.size_m(), [1.6, 1.0]);
    // Features at scale 1 with f = 320 px at 10 m: 32 px per metre; image y is down.
    let f = m.features_px(&Camera::default());
    assert!(
        (f[0].offset_px + 16.0).abs() < 1e-9,
        "top edge is above the centre"
    );
    assert!((f[1].offset_px - 25.6).abs() < 1e-9);
    assert!((f[0].length_px() - 51.2).abs() < 1e-9);
}

#[test]
fn refusals_name_the_segment() {
    let (c, _) = rect();
    let e =
        TargetModel::new("r", 10.0, c.clone(), vec![[0, 1], [1, 2], [2, 3], [0, 2]]).unwrap_err();
    assert!(
        matches!(e, TargetError::NotAxisAligned { segment: 3, .. }),
        "{e}"
    );
    assert!(e.to_string().contains("segment 3"));
    let e = TargetModel::new("r", 10.0, c.clone(), vec![[0, 1], [1, 7]]).unwrap_err();
    assert!(
        matches!(
            e,
            TargetError::IndexOutOfRange {
                segment: 1,
                corner: 7,
                ..
            }
        ),
        "{e}"
    );
    let e = TargetModel::new(
        "r",
        10.0,
        c.clone(),
        vec![[0, 1], [1, 2], [2, 3], [3, 0], [1, 0]],
    )
    .unwrap_err();
    assert!(
        matches!(
            e,
            TargetError::Duplicate {
                segment: 4,
                first: 0,
                ..
            }
        ),
        "{e}"
    );
    // Only horizontal segments.
    let e = TargetModel::new("r", 10.0, c.clone(), vec![[0, 1], [2, 3]]).unwrap_err();
    assert!(
        matches!(
            e,
            TargetError::Underdetermined {
                horizontal: 2,
                vertical: 0,
                ..
            }
        ),
        "{e}"
    );
    // One of each, so the scale cannot be measured.
    let e = TargetModel::new("r", 10.0, c.clone(), vec![[0, 1], [1, 2]]).unwrap_err();
    assert!(matches!(e, TargetError::Underdetermined { .. }), "{e}");
    let e = TargetModel::new("r", -1.0, c, vec![[0, 1]]).unwrap_err();
    assert!(matches!(e, TargetError::BadNominalRange(_)));
}

#[test]
fn stage8_inverts_the_pinhole_projection() {
    let cam = Camera::default();
    let p = [1.2, -0.4, 12.5];
    let [u, v] = cam.project(p).unwrap();
    // A 1.6 m target at 12.5 m spans 1.6 × 320 / 12.5 px.
    let size_px = 1.6 * cam.focal_px()[0] / p[2];
    let q = cam.position_3d(u, v, size_px, 1.6);
    for k in 0..3 {
        assert!((p[k] - q[k]).abs() < 1e-9, "axis {k}: {} vs {}", p[k], q[k]);
    }
}

#[test]
fn segments_along_one_another_are_refused_and_meeting_at_a_corner_is_not() {
    let c = vec![
        [-1.0, 0.5],
        [1.0, 0.5],
        [1.0, -0.5],
        [-1.0, -0.5],
        [0.0, -0.5],
        [2.0, -0.5],
    ];
    // Segment 4 (corner 4 to corner 2) lies on the bottom edge, segment 2.
    let e = TargetModel::new(
        "r",
        10.0,
        c.clone(),
        vec![[0, 1], [1, 2], [2, 3], [3, 0], [4, 2]],
    )
    .unwrap_err();
    assert!(
        matches!(
            e,
            TargetError::Overlap {
                segment: 4,
                first: 2,
                orientation: "horizontal",
                ..
            }
        ),
        "{e}"
    );
    // Corner 2 to corner 5 continues the bottom edge beyond corner 2: allowed.
    TargetModel::new("r", 10.0, c, vec![[0, 1], [1, 2], [2, 3], [3, 0], [2, 5]]).unwrap();
}
