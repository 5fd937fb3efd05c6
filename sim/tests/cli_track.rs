//! `carfollow track` and `carfollow synth` end to end through the real binary: a synthetic
//! sequence written as PNG files is tracked to sub-pixel error, and bad input gets a one-line
//! error naming the file and exit status 2, without losing rows already written.
//! Run with `cargo test -p sim --test cli_track`.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn carfollow(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_carfollow"))
        .args(args)
        .current_dir(root())
        .output()
        .expect("run carfollow")
}

fn root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..")
}

const TARGET: &str = "scenarios/targets/nist-ten-segment.toml";

fn stderr(o: &Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

fn synth(dir: &Path, frames: usize, clutter: bool) {
    let frames = frames.to_string();
    let mut args = vec![
        "synth",
        dir.to_str().unwrap(),
        "--target",
        TARGET,
        "--frames",
        &frames,
        "--seed",
        "3",
    ];
    if clutter {
        args.push("--clutter");
    }
    let o = carfollow(&args);
    assert!(o.status.success(), "synth failed: {}", stderr(&o));
}

fn read_csv(path: &Path) -> (Vec<String>, Vec<Vec<String>>) {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    let header = lines.next().unwrap().split(',').map(String::from).collect();
    let rows = lines
        .map(|l| l.split(',').map(String::from).collect())
        .collect();
    (header, rows)
}

#[test]
fn tracks_a_synthetic_sequence_from_files_to_sub_pixel_error() {
    let dir = tempfile::tempdir().unwrap();
    let frames = dir.path().join("frames");
    synth(&frames, 40, true);
    let csv = dir.path().join("track.csv");
    let overlay = dir.path().join("overlay");
    let o = carfollow(&[
        "track",
        frames.to_str().unwrap(),
        "--target",
        TARGET,
        "--focal-px",
        "320",
        "--init",
        "128,110,1.0",
        "--out",
        csv.to_str().unwrap(),
        "--overlay",
        overlay.to_str().unwrap(),
        "--quiet",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let (header, rows) = read_csv(&csv);
    assert_eq!(&header[..5], ["frame", "cx", "cy", "scale", "status"]);
    assert_eq!(rows.len(), 40);
    let (_, truth) = read_csv(&frames.join("truth.csv"));
    for (k, (r, t)) in rows.iter().zip(&truth).enumerate() {
        assert_eq!(r[0], k.to_string());
        assert_eq!(r[4], "tracking", "frame {k}");
        let f = |s: &String| s.parse::<f64>().unwrap();
        let err = (f(&r[1]) - f(&t[1])).hypot(f(&r[2]) - f(&t[2]));
        assert!(err < 1.0, "frame {k}: {err:.3} px off");
        assert!((f(&r[3]) / f(&t[3]) - 1.0).abs() < 0.03, "frame {k}: scale");
    }
    // One overlay per frame, in colour, with red associated points on it.
    let first = image::open(overlay.join("frame_0000.png"))
        .unwrap()
        .into_rgb8();
    assert_eq!(first.dimensions(), (256, 242));
    assert!(first.pixels().filter(|p| p.0 == [255, 40, 40]).count() > 50);
    assert_eq!(std::fs::read_dir(&overlay).unwrap().count(), 40);
}

#[test]
fn colour_frames_are_converted_to_grey() {
    let dir = tempfile::tempdir().unwrap();
    let frames = dir.path().join("frames");
    synth(&frames, 5, false);
    for k in 0..5 {
        let p = frames.join(format!("frame_{k:04}.png"));
        let grey = image::open(&p).unwrap().into_luma8();
        let rgb = image::RgbImage::from_fn(256, 242, |x, y| {
            let g = grey.get_pixel(x, y)[0];
            image::Rgb([g, g, g])
        });
        rgb.save(&p).unwrap();
    }
    let csv = dir.path().join("t.csv");
    let o = carfollow(&[
        "track",
        frames.to_str().unwrap(),
        "--target",
        TARGET,
        "--focal-px",
        "320",
        "--init",
        "128,110,1",
        "--out",
        csv.to_str().unwrap(),
        "--quiet",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let (_, rows) = read_csv(&csv);
    assert!(rows.iter().all(|r| r[4] == "tracking"));
}

fn expect_input_error(o: &Output, needle: &str) {
    assert_eq!(o.status.code(), Some(2), "stderr: {}", stderr(o));
    let e = stderr(o);
    assert_eq!(e.trim_end().lines().count(), 1, "one line expected: {e}");
    assert!(e.contains(needle), "`{needle}` not in: {e}");
    assert!(!e.contains("panicked"), "{e}");
}

#[test]
fn bad_input_is_one_line_naming_the_file_and_exit_2() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let empty = d.join("empty");
    std::fs::create_dir(&empty).unwrap();
    let csv = d.join("t.csv");
    let with = |frames: &Path, target: &str, init: &str, extra: &[&str]| {
        let mut args = vec![
            "track",
            frames.to_str().unwrap(),
            "--target",
            target,
            "--focal-px",
            "320",
            "--init",
            init,
            "--out",
            csv.to_str().unwrap(),
            "--quiet",
        ];
        args.extend(extra);
        carfollow(&args)
    };
    let base = |frames: &Path, target: &str, init: &str| with(frames, target, init, &[]);
    // An empty folder.
    expect_input_error(&base(&empty, TARGET, "128,110,1"), "no PNG or PGM frames");
    // A bad --init.
    let frames = d.join("frames");
    synth(&frames, 6, false);
    expect_input_error(&base(&frames, TARGET, "128,110"), "--init");
    expect_input_error(&base(&frames, TARGET, "128,110,-1"), "SCALE > 0");
    // A bad target file: a diagonal segment, named with its line.
    let bad = d.join("bad.toml");
    let text = std::fs::read_to_string(root().join(TARGET))
        .unwrap()
        .replace("[8, 9], [10, 11]", "[8, 9], [0, 2]");
    std::fs::write(&bad, text).unwrap();
    let o = base(&frames, bad.to_str().unwrap(), "128,110,1");
    expect_input_error(&o, "bad.toml:");
    assert!(
        stderr(&o).contains("segment 9") && stderr(&o).contains("neither horizontal nor vertical")
    );
    // A missing target file.
    expect_input_error(&base(&frames, "nope.toml", "128,110,1"), "nope.toml");
    // A start outside the frame.
    expect_input_error(
        &base(&frames, TARGET, "1000,1000,1"),
        "must lie in the 256×242",
    );
    // A tracker setting out of its range, named by its flag.
    for (flag, value) in [("--lambda", "1.5"), ("--rate-hz", "0")] {
        let o = with(&frames, TARGET, "128,110,1", &[flag, value]);
        expect_input_error(&o, &format!("{flag} {value}: "));
    }
}

/// Outputs never overwrite the input: the CSV on a recording or a frame, the overlays on the
/// frames' folder; synth never mixes new frames with old ones.
#[test]
fn outputs_that_would_overwrite_the_input_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let frames = dir.path().join("frames");
    synth(&frames, 3, false);
    let before = std::fs::read(frames.join("frame_0000.png")).unwrap();
    let track = |out: &Path, overlay: Option<&Path>| {
        let mut args = vec![
            "track",
            frames.to_str().unwrap(),
            "--target",
            TARGET,
            "--focal-px",
            "320",
            "--init",
            "128,110,1",
            "--out",
            out.to_str().unwrap(),
            "--quiet",
        ];
        if let Some(o) = overlay {
            args.extend(["--overlay", o.to_str().unwrap()]);
        }
        carfollow(&args)
    };
    expect_input_error(
        &track(&frames.join("frame_0000.png"), None),
        "that is the input",
    );
    // A single frame for a folder.
    let o = carfollow(&[
        "track",
        frames.join("frame_0000.png").to_str().unwrap(),
        "--target",
        TARGET,
    ]);
    expect_input_error(&o, "a single frame; give the folder");
    let csv = dir.path().join("t.csv");
    expect_input_error(&track(&csv, Some(&frames)), "that is the frames' folder");
    assert_eq!(
        std::fs::read(frames.join("frame_0000.png")).unwrap(),
        before
    );
    assert!(track(&csv, Some(&dir.path().join("overlay")))
        .status
        .success());
    // A recording as its own output.
    let mcap = dir.path().join("run.mcap");
    std::fs::write(&mcap, b"not yet a recording").unwrap();
    let o = carfollow(&[
        "track",
        mcap.to_str().unwrap(),
        "--out",
        mcap.to_str().unwrap(),
    ]);
    expect_input_error(&o, "that is the input");
    assert_eq!(std::fs::read(&mcap).unwrap(), b"not yet a recording");
    // synth into a folder of frames, and a motion that is not a number of pixels.
    let o = carfollow(&["synth", frames.to_str().unwrap(), "--target", TARGET]);
    expect_input_error(&o, "already holds frames");
    for bad in ["NaN", "-1", "inf"] {
        let o = carfollow(&[
            "synth",
            dir.path().join("new").to_str().unwrap(),
            "--px-per-frame",
            bad,
        ]);
        expect_input_error(&o, "--px-per-frame");
    }
}

/// Without --target, synth draws the built-in target and writes it beside the frames, so
/// that it works from any folder.
#[test]
fn synth_without_a_target_writes_the_built_in_one() {
    let dir = tempfile::tempdir().unwrap();
    let frames = dir.path().join("frames");
    let o = Command::new(env!("CARGO_BIN_EXE_carfollow"))
        .args(["synth", frames.to_str().unwrap(), "--frames", "2"])
        .current_dir(dir.path())
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", stderr(&o));
    assert_eq!(
        std::fs::read_to_string(frames.join("target.toml")).unwrap(),
        std::fs::read_to_string(root().join(TARGET)).unwrap()
    );
    assert!(
        stderr(&o).contains("target.toml")
            || String::from_utf8_lossy(&o.stdout).contains("target.toml")
    );
}

/// synth checks every argument before it makes its folder or writes anything: a target
/// that starts outside the frame or wider than it shows nothing to track.
#[test]
fn synth_refuses_bad_arguments_before_writing_anything() {
    let dir = tempfile::tempdir().unwrap();
    let frames = dir.path().join("frames");
    for (args, needle) in [
        (
            &["--start", "1e9,0,1"][..],
            "must start within the 256 × 242 frame",
        ),
        (&["--start", "128,110,6"][..], "wider than the 256 px frame"),
        (&["--clutter", "--kind", "swerve"][..], "cannot be combined"),
    ] {
        let mut all = vec!["synth", frames.to_str().unwrap()];
        all.extend(args);
        let o = carfollow(&all);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {}", stderr(&o));
        assert_eq!(stderr(&o).lines().count(), 1, "{}", stderr(&o));
        assert!(stderr(&o).contains(needle), "{}", stderr(&o));
        assert!(!frames.exists(), "{args:?} made the folder");
    }
}

#[test]
fn a_bad_frame_mid_run_keeps_the_rows_before_it() {
    let dir = tempfile::tempdir().unwrap();
    let frames = dir.path().join("frames");
    synth(&frames, 8, false);
    // Frame 5 is not an image; frame 6 would have another size.
    std::fs::write(frames.join("frame_0005.png"), b"not a png").unwrap();
    let csv = dir.path().join("t.csv");
    let run = || {
        carfollow(&[
            "track",
            frames.to_str().unwrap(),
            "--target",
            TARGET,
            "--focal-px",
            "320",
            "--init",
            "128,110,1",
            "--out",
            csv.to_str().unwrap(),
            "--quiet",
        ])
    };
    let o = run();
    expect_input_error(&o, "frame_0005.png");
    let (_, rows) = read_csv(&csv);
    assert_eq!(rows.len(), 5, "frames 0-4 stay written");

    image::GrayImage::new(100, 100)
        .save(frames.join("frame_0005.png"))
        .unwrap();
    let o = run();
    expect_input_error(&o, "frame_0005.png: frame is 100×100, but the first frame");
    assert_eq!(read_csv(&csv).1.len(), 5);
}

#[test]
fn robust_mode_finds_a_swerving_target_without_a_start_and_the_paper_mode_needs_one() {
    let dir = tempfile::tempdir().unwrap();
    let frames = dir.path().join("swerve");
    let o = carfollow(&[
        "synth",
        frames.to_str().unwrap(),
        "--target",
        TARGET,
        "--frames",
        "70",
        "--kind",
        "swerve",
        "--seed",
        "2",
    ]);
    assert!(o.status.success(), "synth failed: {}", stderr(&o));
    let (_, truth) = read_csv(&frames.join("truth.csv"));

    // Robust mode, no --init: it finds the target in the first frame and holds the swerves.
    let csv = dir.path().join("robust.csv");
    let o = carfollow(&[
        "track",
        frames.to_str().unwrap(),
        "--target",
        TARGET,
        "--focal-px",
        "320",
        "--mode",
        "robust",
        "--out",
        csv.to_str().unwrap(),
        "--quiet",
    ]);
    assert!(o.status.success(), "track failed: {}", stderr(&o));
    let (header, rows) = read_csv(&csv);
    let col = |name: &str| header.iter().position(|c| c == name).unwrap();
    assert_eq!(rows.len(), 70);
    assert_eq!(rows[0][col("event")], "acquired");
    for (row, t) in rows.iter().zip(&truth) {
        let err = (row[col("cx")].parse::<f64>().unwrap() - t[1].parse::<f64>().unwrap()).abs();
        assert!(err < 2.0, "frame {}: {err:.2} px off", row[0]);
        assert_eq!(row[col("status")], "tracking", "frame {}", row[0]);
    }

    // The paper's mode refuses to start without the teleoperator's placement (exit 2).
    let o = carfollow(&[
        "track",
        frames.to_str().unwrap(),
        "--target",
        TARGET,
        "--focal-px",
        "320",
        "--out",
        dir.path().join("paper.csv").to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(2), "{}", stderr(&o));
    assert!(stderr(&o).contains("--init"), "{}", stderr(&o));
    assert_eq!(stderr(&o).trim().lines().count(), 1, "{}", stderr(&o));
}

/// An output that cannot be written (a CSV in a missing folder, on a full disk, an overlay
/// folder that is a file) is a run that could not complete: exit status 3, in one line
/// naming the file; the input was good.
#[test]
fn an_output_that_cannot_be_written_exits_3() {
    let dir = tempfile::tempdir().unwrap();
    let frames = dir.path().join("frames");
    synth(&frames, 3, false);
    let in_the_way = dir.path().join("a-file");
    std::fs::write(&in_the_way, "in the way").unwrap();
    let missing = dir.path().join("no/such/folder/t.csv");
    let csv = dir.path().join("t.csv");
    let cases: Vec<(Vec<&str>, String)> = vec![
        (
            vec!["--out", missing.to_str().unwrap()],
            "cannot create the CSV".into(),
        ),
        (
            vec![
                "--out",
                csv.to_str().unwrap(),
                "--overlay",
                in_the_way.to_str().unwrap(),
            ],
            "cannot create the overlay folder".into(),
        ),
        #[cfg(target_os = "linux")]
        (vec!["--out", "/dev/full"], "/dev/full: cannot write".into()),
    ];
    for (extra, needle) in cases {
        let mut args = vec![
            "track",
            frames.to_str().unwrap(),
            "--target",
            TARGET,
            "--focal-px",
            "320",
            "--init",
            "128,110,1",
            "--quiet",
        ];
        args.extend(extra.iter());
        let o = carfollow(&args);
        let err = stderr(&o);
        assert_eq!(o.status.code(), Some(3), "{extra:?}: {err}");
        assert!(err.contains(&needle), "{extra:?}: {err}");
        assert_eq!(err.trim().lines().count(), 1, "one line: {err}");
    }
}

/// A user's target whose close parallel edges association tells apart: a stripe whose top
/// edge lies 0.12 m under the board's top edge (3.8 px at scale 1 with the 320 px lens,
/// under ζ = 4 px), the two extents overlapping. `synth` draws it and `track` follows it,
/// saying `tracking` in every frame: no false alarm.
#[test]
fn a_target_with_close_parallel_edges_is_tracked_without_a_false_alarm() {
    let dir = tempfile::tempdir().unwrap();
    let target = dir.path().join("stripe.toml");
    std::fs::write(
        &target,
        "name = \"stripe\"\nnominal_range_m = 10.0\ncorners_m = [\n    [-0.8, 0.5], [0.8, 0.5], \
         [0.8, -0.5], [-0.8, -0.5], [-0.8, 0.0], [0.8, 0.0],\n    [-0.3, 0.38], [0.3, 0.38], \
         [0.3, 0.18], [-0.3, 0.18],\n]\nsegments = [\n    [0, 1], [1, 5], [5, 2], [2, 3], [3, 4], \
         [4, 0], [4, 5],\n    [6, 7], [7, 8], [8, 9], [9, 6],\n]\n",
    )
    .unwrap();
    let frames = dir.path().join("frames");
    let o = carfollow(&[
        "synth",
        frames.to_str().unwrap(),
        "--target",
        target.to_str().unwrap(),
        "--frames",
        "60",
        "--start",
        "128,121,1.0",
        "--seed",
        "5",
    ]);
    assert!(o.status.success(), "synth failed: {}", stderr(&o));
    let csv = dir.path().join("track.csv");
    let o = carfollow(&[
        "track",
        frames.to_str().unwrap(),
        "--target",
        target.to_str().unwrap(),
        "--focal-px",
        "320",
        "--init",
        "128,121,1.0",
        "--out",
        csv.to_str().unwrap(),
        "--quiet",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    let (_, rows) = read_csv(&csv);
    let (_, truth) = read_csv(&frames.join("truth.csv"));
    assert_eq!(rows.len(), 60);
    for (k, (r, t)) in rows.iter().zip(&truth).enumerate() {
        assert_eq!(r[4], "tracking", "frame {k}: a false alarm");
        let f = |s: &String| s.parse::<f64>().unwrap();
        let err = (f(&r[1]) - f(&t[1])).hypot(f(&r[2]) - f(&t[2]));
        assert!(err < 1.0, "frame {k}: {err:.3} px off");
    }
}
