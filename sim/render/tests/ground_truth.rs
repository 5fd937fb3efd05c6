//! Ground truth's view of the target: wholly in view, partly out of view, or out of it.

use nalgebra::{Isometry3, Translation3, UnitQuaternion};
use sim_render::{ground_truth_of, CameraRig, GroundTruth};

/// The truth for the target `dx` metres to the right of the camera's axis and `z` ahead of
/// it, facing the camera.
fn truth_at(dx: f64, z: f64) -> GroundTruth {
    let rig = CameraRig::default();
    let target = tracker::synth::nist_ten_segment();
    let chase = Isometry3::identity();
    let camera = rig.world_from_camera_panned(&chase, 0.0);
    let lead =
        camera * Isometry3::from_parts(Translation3::new(dx, 0.0, z), UnitQuaternion::identity());
    ground_truth_of(&rig, &Isometry3::identity(), &target, &chase, &lead, 0.0)
}

#[derive(Clone, Copy, Debug, PartialEq)]
enum View {
    Whole,
    Partly,
    Out,
}

fn view(t: &GroundTruth) -> View {
    assert!(!(t.in_view && t.partly_in_view), "{t:?}");
    match (t.in_view, t.partly_in_view) {
        (true, _) => View::Whole,
        (false, true) => View::Partly,
        (false, false) => View::Out,
    }
}

#[test]
fn a_target_sliding_out_sideways_is_whole_then_partly_then_out_of_view() {
    // 1 cm steps from the axis to 15 m aside at 10 m: the classes come in order, each seen.
    let views: Vec<View> = (0..1500)
        .map(|i| view(&truth_at(i as f64 * 0.01, 10.0)))
        .collect();
    let mut runs = views.clone();
    runs.dedup();
    assert_eq!(runs, [View::Whole, View::Partly, View::Out]);
    // Partly in view while the centre crosses the image's edge: the target's half width
    // either side of it (the board is about 1 m wide, so at 10 m some tens of centimetres).
    let partly = views.iter().filter(|&&v| v == View::Partly).count();
    assert!((20..200).contains(&partly), "{partly} steps partly in view");
    let edge = truth_at(
        0.01 * views.iter().position(|&v| v == View::Partly).unwrap() as f64,
        10.0,
    );
    assert!(
        edge.c_x < 255.5,
        "the centre is still inside at the first partial frame"
    );
}

#[test]
fn a_target_behind_the_camera_is_out_of_view() {
    let t = truth_at(0.0, -10.0);
    assert_eq!(view(&t), View::Out);
}
