//! The outputs of a run, end to end through `RunOutputs`: a synthetic 60 s run (the lead on a
//! curving road, the chase 10 m behind, a loss between 20 and 24 s, a gap excursion) writes
//! `frames.csv`, `summary.json`, five PNG plots, a GIF and stills, all of which must decode;
//! and the same records written twice give byte-identical files.
//!
//! Run with `cargo test -p sim --release --test report_outputs`. To look at the files, set
//! `CARFOLLOW_REPORT_DEMO_DIR=/some/dir`: they are then written there as well.

use std::path::Path;

use image::{GenericImageView, Rgb, RgbImage};
use sim::{write_junit, JunitScenario, OutputOptions, RunOutputs, PLOT_FILES, VIDEO_OUTPUTS};
use sim_core::{Expect, FrameRecord, TrackerStatus};

const FRAMES: u64 = 900;

fn record(i: u64) -> FrameRecord {
    let t = i as f64 / 15.0;
    // The lead drives along a gentle S: z = 20 sin(x / 40), at 8 m/s.
    let path = |s: f64| [s, 20.0 * (s / 40.0).sin()];
    let gap = if (30.0..34.0).contains(&t) {
        17.0
    } else {
        10.0 + (t / 5.0).sin()
    };
    let lead_s = 8.0 * t + 10.0;
    let lost = (20.0..24.0).contains(&t);
    let status = if lost {
        if t < 21.0 {
            TrackerStatus::Coasting
        } else {
            TrackerStatus::Lost
        }
    } else {
        TrackerStatus::Tracking
    };
    let deviation = 0.3 * (t / 3.0).sin() + if lost { 0.6 } else { 0.0 };
    let chase = path(lead_s - gap);
    FrameRecord {
        frame: i,
        t_s: t,
        true_cx: 160.0 + 20.0 * (t / 4.0).sin(),
        true_cy: 120.0,
        true_scale: 10.0 / gap,
        true_range_m: gap,
        true_lateral_m: 0.5 * (t / 4.0).sin(),
        target_in_view: !(22.0..23.0).contains(&t),
        target_partly_out_of_view: false,
        est_cx: 161.0,
        est_cy: 121.0,
        est_scale: 10.0 / gap,
        est_range_m: if lost {
            gap + 6.0
        } else {
            gap + 0.2 * (t * 3.0).sin()
        },
        est_lateral_m: 0.0,
        confidence: if lost { [0.0; 3] } else { [0.9, 0.9, 0.8] },
        status,
        lost_truth: lost,
        gap_m: gap,
        chase_speed_mps: 8.0,
        lead_speed_mps: 8.0,
        steering_rad: 0.05 * (t / 5.0).cos(),
        throttle: 0.3,
        brake: 0.0,
        lateral_deviation_m: deviation.abs(),
        chase_distance_m: 8.0 * t,
        chase_xz: [chase[0], chase[1] + deviation],
        lead_xz: path(lead_s),
        collision: false,
        chase_mode: "following".into(),
        coverage: [0.95, 0.9],
        coverage_gain: 0.0,
        tracker_event: String::new(),
        fit_residual: 0.8,
        feature_sigma2: vec![0.1; 10],
        loss_cause: sim_core::LossCause::None,
        camera_pan_deg: 0.0,
        desired_gap_m: 10.0,
        false_alarm: false,
        traffic: None,
    }
}

/// A camera frame with a bright box where the target is, and the overlay's colours.
fn image(i: u64) -> RgbImage {
    let r = record(i);
    let mut img = RgbImage::from_fn(320, 240, |x, y| {
        let g = (60 + (y / 2) + (x + i as u32) % 40) as u8;
        Rgb([g, g, g])
    });
    let (cx, cy) = (r.true_cx as i64, r.true_cy as i64);
    for dx in -20..=20 {
        for dy in -15..=15 {
            img.put_pixel((cx + dx) as u32, (cy + dy) as u32, Rgb([220, 220, 220]));
        }
    }
    let line = |img: &mut RgbImage, c: Rgb<u8>, y: i64| {
        for dx in -25..=25 {
            img.put_pixel((cx + dx) as u32, y as u32, c);
        }
    };
    line(&mut img, sim::OverlayColour::WINDOW, cy - 25);
    line(&mut img, sim::OverlayColour::WINDOW, cy + 25);
    line(&mut img, sim::OverlayColour::PREDICTED, cy - 15);
    img
}

fn expect() -> Expect {
    Expect {
        gap_band_m: Some([5.0, 15.0]),
        max_time_outside_gap_band_s: Some(1.0),
        max_lost_s: Some(2.0),
        max_lateral_deviation_m: Some(1.5),
        no_collision: true,
        min_distance_m: Some(400.0),
        max_range_error_p95_m: None,
        max_loss_events: None,
        max_false_alarm_s: None,
        ..Expect::default()
    }
}

fn run(dir: &Path) -> sim::Summary {
    let options = OutputOptions {
        video: true,
        video_stride: 3,
        expected_frames: Some(FRAMES),
        plots: true,
        features: 10,
        traffic: false,
    };
    let mut out = RunOutputs::create(dir, options, &expect()).unwrap();
    for i in 0..FRAMES {
        // Image before record on even frames, after on odd ones: both orders must work.
        if i % 2 == 0 {
            out.frame_image(i, &image(i)).unwrap();
            out.record(&record(i)).unwrap();
        } else {
            out.record(&record(i)).unwrap();
            out.frame_image(i, &image(i)).unwrap();
        }
    }
    out.finish("synthetic-s-curve", 42, 2.5, None).unwrap()
}

/// Every file a run with video writes besides the plots.
fn files() -> impl Iterator<Item = &'static str> {
    ["frames.csv", "summary.json"]
        .into_iter()
        .chain(VIDEO_OUTPUTS)
}

#[test]
fn a_run_writes_every_output_and_they_decode() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = match std::env::var_os("CARFOLLOW_REPORT_DEMO_DIR") {
        Some(d) => d.into(),
        None => tmp.path().join("synthetic"),
    };
    let s = run(&dir);

    assert_eq!(s.frames, FRAMES);
    assert!((s.duration_s - 60.0).abs() < 1e-9);
    assert!(
        (s.tracking_lost_s - 4.0).abs() < 1e-6,
        "{}",
        s.tracking_lost_s
    );
    assert_eq!(s.tracking_loss_events, 1);
    assert!((s.time_outside_gap_band_s - 4.0).abs() < 1e-6);
    assert_eq!(s.realtime_factor, Some(24.0));
    assert!(!s.passed);
    assert_eq!(s.failures.len(), 2, "{:?}", s.failures);
    assert!(s.failures[0].starts_with("gap left the band [5, 15] m for 4.00 s (allowed 1.00 s"));
    assert!(s.failures[1].starts_with("tracking lost (ground truth) for 4.00 s in 1 event(s)"));

    let csv = std::fs::read_to_string(dir.join("frames.csv")).unwrap();
    assert_eq!(csv.lines().count() as u64, FRAMES + 1);
    let json: serde_json::Value =
        serde_json::from_slice(&std::fs::read(dir.join("summary.json")).unwrap()).unwrap();
    assert_eq!(json["scenario"], "synthetic-s-curve");
    assert_eq!(json["tracking_loss_events"], 1);

    for file in PLOT_FILES {
        let img = image::open(dir.join(file)).unwrap_or_else(|e| panic!("{file}: {e}"));
        assert!(img.width() >= 800, "{file}");
        // Not blank: some dark (text, axes) and some coloured pixels.
        let rgb = img.to_rgb8();
        assert!(
            rgb.pixels().any(|p| p.0.iter().all(|&c| c < 60)),
            "{file} has no text"
        );
        assert!(
            rgb.pixels().any(|p| p.0[0] != p.0[2]),
            "{file} has no colour"
        );
    }
    for file in files().filter(|f| f.ends_with(".png")) {
        let img = image::open(dir.join(file)).unwrap_or_else(|e| panic!("{file}: {e}"));
        assert_eq!(img.dimensions(), (320, 240));
    }
    // The first lost frame is frame 300 (t = 20 s); its image has the target box there.
    let lost = image::open(dir.join("still_first_lost.png"))
        .unwrap()
        .to_rgb8();
    assert_eq!(lost, image(300));

    let gif = std::io::BufReader::new(std::fs::File::open(dir.join("video.gif")).unwrap());
    let decoder = image::codecs::gif::GifDecoder::new(gif).unwrap();
    use image::AnimationDecoder;
    let frames = decoder.into_frames().collect_frames().unwrap();
    assert_eq!(frames.len() as u64, FRAMES / 3);
    let (n, d) = frames[0].delay().numer_denom_ms();
    assert_eq!(n / d, 200, "stride 3 at 15 fps: 20 cs a frame");

    let junit = write_junit(&dir, &[JunitScenario::Ran(&s)]).unwrap();
    let xml = std::fs::read_to_string(junit).unwrap();
    assert!(xml.contains("<testsuite name=\"synthetic-s-curve\""));
    // One testcase per criterion and one for the run, two of them failed.
    assert_eq!(xml.matches("<testcase ").count(), 6, "{xml}");
    assert_eq!(
        xml.matches("<failure message=\"measured ").count(),
        2,
        "{xml}"
    );
}

#[test]
fn identical_records_give_byte_identical_outputs() {
    let tmp = tempfile::tempdir().unwrap();
    let (a, b) = (tmp.path().join("a"), tmp.path().join("b"));
    let (sa, sb) = (run(&a), run(&b));
    assert_eq!(sa, sb);
    for file in files().chain(PLOT_FILES) {
        let fa = std::fs::read(a.join(file)).unwrap();
        let fb = std::fs::read(b.join(file)).unwrap();
        assert!(fa == fb, "{file} differs between two identical runs");
    }
}

/// A run without video in a folder where an earlier run wrote one leaves no video or stills
/// that could pass for its own.
#[test]
fn an_earlier_runs_video_and_stills_are_removed() {
    let tmp = tempfile::tempdir().unwrap();
    for name in VIDEO_OUTPUTS {
        std::fs::write(tmp.path().join(name), b"old").unwrap();
    }
    std::fs::write(tmp.path().join("notes.txt"), b"mine").unwrap();
    let out = RunOutputs::create(tmp.path(), OutputOptions::default(), &expect()).unwrap();
    out.finish("x", 1, 0.0, None).unwrap();
    for name in VIDEO_OUTPUTS {
        assert!(!tmp.path().join(name).exists(), "{name}");
    }
    assert!(tmp.path().join("notes.txt").exists());
}

#[test]
fn empty_and_one_frame_runs_still_write_their_outputs() {
    let tmp = tempfile::tempdir().unwrap();
    // No frame at all: the summary fails with a reason, the plots are empty but drawn.
    let dir = tmp.path().join("empty");
    let out = RunOutputs::create(&dir, OutputOptions::default(), &expect()).unwrap();
    let s = out.finish("empty", 1, 0.0, None).unwrap();
    assert!(!s.passed);
    assert_eq!(
        s.failures[0],
        "the run recorded no frames (at least 1 needed)"
    );
    assert_eq!(s.realtime_factor, None);
    for file in PLOT_FILES {
        image::open(dir.join(file)).unwrap_or_else(|e| panic!("{file}: {e}"));
    }
    let json = std::fs::read_to_string(dir.join("summary.json")).unwrap();
    assert!(json.contains("\"mean_abs\": null"), "{json}");

    // One frame, with video on: every still is that frame; no NaN anywhere.
    let dir = tmp.path().join("one");
    let options = OutputOptions {
        video: true,
        expected_frames: Some(1),
        ..OutputOptions::default()
    };
    let mut out = RunOutputs::create(&dir, options, &Expect::default()).unwrap();
    out.record(&record(0)).unwrap();
    out.frame_image(0, &image(0)).unwrap();
    let s = out.finish("one", 1, 0.1, None).unwrap();
    assert!(s.passed, "{:?}", s.failures);
    assert!((s.duration_s - 1.0 / 15.0).abs() < 1e-12);
    for file in files().filter(|f| *f != "still_first_lost.png") {
        assert!(dir.join(file).is_file(), "{file}");
    }
    assert!(!std::fs::read_to_string(dir.join("summary.json"))
        .unwrap()
        .contains("NaN"));
}
