//! The tracker's resolution (`Tracker::resolution_px`): a target whose parallel features lie
//! closer in the image than ζ is beyond what association (2.4) can tell apart. Both modes
//! say so (an `unresolved` event, and no `tracking`), and trust the track again only when
//! it is well resolved: its features 1.5 ζ apart.

use tracker::robust::{alias_spacing, RESOLVED_AGAIN_FACTOR};
use tracker::synth::{draw, nist_ten_segment, SynthScene};
use tracker::{
    Camera, GrayView, Location, Status, TrackEvent, TrackOutput, Tracker, TrackerConfig,
    TrackerMode,
};

/// A scene the tracker holds at every scale of these tests when resolved: the flat
/// default, a little blur and noise.
fn scene() -> SynthScene {
    SynthScene {
        noise_sigma: 2.0,
        blur_sigma: 0.6,
        ..SynthScene::default()
    }
}

/// Runs a tracker in `mode` from `truth[0]` over `truth`.
fn run(mode: TrackerMode, truth: &[Location]) -> (Tracker, Vec<TrackOutput>) {
    let model = nist_ten_segment();
    let camera = Camera::default();
    let config = TrackerConfig {
        mode,
        ..TrackerConfig::default()
    };
    let mut tracker = Tracker::new(model.clone(), camera, config, truth[0]).unwrap();
    let s = scene();
    let outs = truth
        .iter()
        .enumerate()
        .map(|(k, at)| {
            let px = draw(&model, &camera, *at, &s, 77 + k as u64);
            tracker.step(
                GrayView::new(s.width, s.height, &px).unwrap(),
                k as f64 / 15.0,
            )
        })
        .collect();
    (tracker, outs)
}

/// The scale at which the model's closest parallel features are `px` apart.
fn scale_for_spacing(tracker: &Tracker, px: f64) -> f64 {
    let [x, y] = alias_spacing(tracker.features());
    px / x.min(y)
}

#[test]
fn a_target_beyond_resolution_is_never_reported_tracking_and_is_taken_back_when_near() {
    for mode in [TrackerMode::Paper, TrackerMode::Robust] {
        // Find the scales from a tracker of the same model and camera.
        let probe = run(mode, &[Location::new(128.0, 120.0, 1.0)]).0;
        let limit = probe.resolution_px();
        let far = scale_for_spacing(&probe, 0.85 * limit);
        let again = scale_for_spacing(&probe, RESOLVED_AGAIN_FACTOR * limit);
        // Held far for 2 s, then the gap closing to 10 m over 8 s, and held there for 2 s.
        let truth: Vec<Location> = (0..180)
            .map(|k| {
                let f = ((k as f64 - 30.0) / 120.0).clamp(0.0, 1.0);
                Location::new(128.0, 120.0, far + (1.0 - far) * f)
            })
            .collect();
        let (tracker, outs) = run(mode, &truth);
        let name = mode.as_str();
        assert_eq!(
            outs[0].event,
            Some(TrackEvent::Unresolved),
            "{name}: no `unresolved` event at a spacing of 0.85 ζ"
        );
        let events = outs
            .iter()
            .filter(|o| o.event == Some(TrackEvent::Unresolved))
            .count();
        assert_eq!(events, 1, "{name}: {events} `unresolved` events");
        for (k, o) in outs.iter().enumerate() {
            if o.status == Status::Tracking {
                assert!(
                    (o.estimate.scale / truth[k].scale - 1.0).abs() < 0.05,
                    "{name}: tracking at frame {k} with the scale {:.3} against {:.3}",
                    o.estimate.scale,
                    truth[k].scale
                );
                assert!(
                    o.estimate.scale >= 0.95 * again,
                    "{name}: tracking at frame {k}, scale {:.3} (truth {:.3}); resolved again \
                     from {again:.3}",
                    o.estimate.scale,
                    truth[k].scale
                );
            }
            // Both hold the approach, and say `tracking` once the target is well resolved.
            // (The paper's mode lost it near scale 0.9 before eq. 17's residual floor: an
            // exact fit's confidence of 6·10⁹ froze its motion models for 100 frames.)
            if truth[k].scale >= 1.05 * again {
                assert_eq!(
                    o.status,
                    Status::Tracking,
                    "{name}: not tracking at frame {k}, scale {:.3}",
                    truth[k].scale
                );
            }
        }
        let released = (0..outs.len())
            .filter(|&k| truth[k].scale >= 1.05 * again && outs[k].status == Status::Tracking)
            .count();
        assert!(
            released >= 20,
            "{name}: tracking in only {released} frames once resolved again"
        );
        assert!(tracker.resolution_px() >= 3.0);
    }
}

#[test]
fn the_resolution_is_zeta_and_never_below_the_gradient_operators_width() {
    let model = nist_ten_segment();
    let at = Location::new(128.0, 120.0, 1.0);
    let with_zeta = |zeta_px: f64| {
        let config = TrackerConfig {
            zeta_px,
            ..TrackerConfig::default()
        };
        Tracker::new(model.clone(), Camera::default(), config, at)
            .unwrap()
            .resolution_px()
    };
    assert_eq!(with_zeta(4.0), 4.0);
    assert_eq!(with_zeta(6.5), 6.5);
    assert_eq!(with_zeta(2.0), 3.0);
}
