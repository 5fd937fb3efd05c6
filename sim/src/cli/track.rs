//! `carfollow track`: the tracker alone on a folder of recorded frames.

use super::exit::incomplete;
use super::paths::same_path;
use anyhow::Context;
use clap::Args;
use sim::{parse_location, track, TrackJob};
use sim::{replay, ReplayError, ReplayJob, SettingChange};
use std::path::PathBuf;
use tracker::{TrackerConfig, TrackerMode};

/// Arguments of `carfollow track`.
#[derive(Args, Debug)]
#[command(
    after_help = super::exit::TOOL_HELP,
    about = "Run the tracker on a folder of frames (PNG or PGM), or replay a recording (run.mcap)",
    long_about = "Run the paper's tracker (stages 1-8) over every PNG or PGM in FRAMES_DIR, \
                  sorted by name, converting colour to grey. Writes one CSV row per frame as \
                  it goes: frame,cx,cy,scale,status, then confidences, the prediction, the \
                  3-D position and per-feature counts.\n\n\
                  Given a recording of `carfollow run --mcap` (a .mcap file) instead, replays \
                  its camera frames through the tracker as the run set it up (target, camera, \
                  settings and start, all from the recording); --mode, --lambda, \
                  --subpixel-edges and --set tracker.KEY=VALUE change the settings. Writes \
                  frames.csv's tracker columns (same names, same number format) and whether \
                  each frame's estimate equals the recorded one; with the run's settings, \
                  every frame does."
)]
pub struct TrackArgs {
    /// Folder of frames, or a recording (run.mcap) to replay.
    #[arg(value_name = "FRAMES_DIR|RUN.mcap")]
    pub frames_dir: PathBuf,
    /// Target model file (TOML), e.g. scenarios/targets/nist-ten-segment.toml (frames only:
    /// a recording carries its target).
    #[arg(long)]
    pub target: Option<PathBuf>,
    /// Camera focal length, pixels (frames only: a recording carries its camera).
    #[arg(long)]
    pub focal_px: Option<f64>,
    /// The target's location in the first frame: CX,CY,SCALE (the teleoperator's placement).
    /// Required by the paper's mode; robust mode without it searches the whole image.
    #[arg(long, allow_hyphen_values = true)]
    pub init: Option<String>,
    /// Tracker mode: paper (the paper's tracker, the default for frames; a recording
    /// replays in its run's mode) or robust.
    #[arg(long, value_parser = ["paper", "robust"])]
    pub mode: Option<String>,
    /// Forgetting factor λ of the motion model (0 < λ < 1).
    #[arg(long, allow_hyphen_values = true)]
    pub lambda: Option<f64>,
    /// Frame rate, Hz: frame k is at k / rate seconds (default 15; frames only: a recording
    /// carries its frames' times).
    #[arg(long)]
    pub rate_hz: Option<f64>,
    /// Image centre CX,CY in pixels (default: the middle of the frame).
    #[arg(long, allow_hyphen_values = true)]
    pub center: Option<String>,
    /// Pixel size on the sensor, millimetres (stage 8 needs only focal_px; this keeps the
    /// camera physical).
    #[arg(long, default_value_t = 0.025)]
    pub pixel_size_mm: f64,
    /// Locate edge points to a fraction of a pixel (an improvement over the paper; off by
    /// default).
    #[arg(long)]
    pub subpixel_edges: bool,
    /// Change a tracker setting of a recording's run, as in a scenario file, e.g. --set
    /// tracker.zeta_px=4 (repeatable; recordings only).
    #[arg(long = "set", value_name = "tracker.KEY=VALUE")]
    pub set: Vec<String>,
    /// Where to write the CSV.
    #[arg(long, default_value = "track.csv")]
    pub out: PathBuf,
    /// Write each frame with the overlay (window, predicted model, associated edges) here.
    #[arg(long)]
    pub overlay: Option<PathBuf>,
    /// No progress bar.
    #[arg(long)]
    pub quiet: bool,
}

/// Refuses outputs that would overwrite the input: `--out` on the recording or on a frame,
/// `--overlay` on the frames' folder (its files take the frames' names).
fn check_outputs(args: &TrackArgs) -> anyhow::Result<()> {
    let input = &args.frames_dir;
    let out_is_input = same_path(&args.out, input)
        || (input.is_dir()
            && sim::frame_files(input)
                .is_ok_and(|files| files.iter().any(|f| same_path(f, &args.out))));
    if out_is_input {
        anyhow::bail!(
            "--out {}: that is the input; the CSV would overwrite it",
            args.out.display()
        );
    }
    if let Some(overlay) = &args.overlay {
        if same_path(overlay, input) {
            anyhow::bail!(
                "--overlay {}: that is the frames' folder; the overlays would overwrite the frames",
                overlay.display()
            );
        }
    }
    Ok(())
}

/// Runs the subcommand.
pub fn run_track(args: TrackArgs) -> anyhow::Result<()> {
    check_outputs(&args)?;
    let mcap = args
        .frames_dir
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("mcap"));
    let frame_file = args.frames_dir.is_file()
        && args
            .frames_dir
            .extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("png") || e.eq_ignore_ascii_case("pgm"));
    if frame_file {
        anyhow::bail!(
            "{}: a single frame; give the folder of frames (or a recording, run.mcap)",
            args.frames_dir.display()
        );
    }
    if mcap || args.frames_dir.is_file() {
        return replay_recording(args);
    }
    if !args.set.is_empty() {
        anyhow::bail!(
            "--set changes a recording's settings; for frames, use --mode, --lambda, ..."
        );
    }
    let (Some(target), Some(focal_px)) = (&args.target, args.focal_px) else {
        anyhow::bail!(
            "{}: frames need --target T.toml and --focal-px F (only a recording carries them)",
            args.frames_dir.display()
        );
    };
    let model = sim_core::load_target(target)?;
    let mode = TrackerMode::parse(args.mode.as_deref().unwrap_or("paper"))
        .expect("clap allows only known modes");
    let init = match &args.init {
        Some(text) => Some(parse_location(text).context("--init")?),
        None if mode == TrackerMode::Robust => None,
        None => anyhow::bail!(
            "--init CX,CY,SCALE is required in the paper's mode (the teleoperator's placement, \
             paper 2.2); --mode robust can search for the target instead"
        ),
    };
    if !(focal_px.is_finite() && focal_px > 0.0) {
        anyhow::bail!("--focal-px must be a positive number of pixels, got {focal_px}");
    }
    if !(args.pixel_size_mm.is_finite() && args.pixel_size_mm > 0.0) {
        anyhow::bail!(
            "--pixel-size-mm must be positive, got {}",
            args.pixel_size_mm
        );
    }
    let image_center_px = match &args.center {
        None => None,
        Some(text) => {
            let v: Vec<f64> = text
                .split(',')
                .map(|p| p.trim().parse::<f64>())
                .collect::<Result<_, _>>()
                .ok()
                .filter(|v: &Vec<f64>| v.len() == 2 && v.iter().all(|x| x.is_finite()))
                .with_context(|| format!("--center: expected CX,CY (two numbers), got `{text}`"))?;
            Some([v[0], v[1]])
        }
    };
    let mut config = TrackerConfig {
        rate_hz: args.rate_hz.unwrap_or(15.0),
        subpixel_edges: args.subpixel_edges,
        mode,
        ..TrackerConfig::default()
    };
    if let Some(lambda) = args.lambda {
        config.lambda = lambda;
    }
    // Only the flags above set values here: the error names the flag.
    config.validate().map_err(|e| {
        let flag = match e.field {
            "lambda" => "--lambda",
            "rate_hz" => "--rate-hz",
            other => other,
        };
        anyhow::anyhow!("{flag} {}: {}", e.value, e.allowed)
    })?;
    let job = TrackJob {
        frames_dir: args.frames_dir,
        model,
        focal_px,
        pixel_size_mm: args.pixel_size_mm,
        image_center_px,
        init,
        config,
        out_csv: args.out.clone(),
        overlay_dir: args.overlay,
        progress: !args.quiet,
    };
    // An output that cannot be written leaves the run incomplete (3); the rest is bad input.
    let s = track(&job).map_err(|e| match e.downcast_ref::<sim::TrackOutputError>() {
        Some(_) => incomplete(e),
        None => e,
    })?;
    eprintln!(
        "{}: {} frames: {} tracking, {} coasting, {} lost, {} (re)acquired; median step {:.1} µs",
        args.out.display(),
        s.frames,
        s.tracking,
        s.coasting,
        s.lost,
        s.acquisitions,
        s.median_step_us
    );
    Ok(())
}

/// `carfollow track run.mcap`: the recording's frames through the tracker again, as its run
/// set it up, with the settings the flags change.
fn replay_recording(args: TrackArgs) -> anyhow::Result<()> {
    for (flag, given) in [
        ("--target", args.target.is_some()),
        ("--focal-px", args.focal_px.is_some()),
        ("--init", args.init.is_some()),
        ("--center", args.center.is_some()),
        ("--rate-hz", args.rate_hz.is_some()),
    ] {
        if given {
            anyhow::bail!(
                "{}: {flag} is for folders of frames: a recording carries its target, camera, \
                 start and frame times",
                args.frames_dir.display()
            );
        }
    }
    // Each flag as the setting it changes, and as it was given (errors name the latter).
    let flag = |assignment: String, given_as: String| SettingChange {
        assignment,
        given_as,
    };
    let mut overrides = Vec::new();
    if let Some(mode) = &args.mode {
        overrides.push(flag(
            format!("tracker.mode={mode}"),
            format!("--mode {mode}"),
        ));
    }
    if let Some(lambda) = args.lambda {
        overrides.push(flag(
            format!("tracker.lambda={lambda}"),
            format!("--lambda {lambda}"),
        ));
    }
    if args.subpixel_edges {
        overrides.push(flag(
            "tracker.subpixel_edges=true".to_string(),
            "--subpixel-edges".to_string(),
        ));
    }
    // A flag and a --set of the same setting: one would override the other unseen.
    let key = |a: &str| a.split_once('=').map(|(k, _)| k.trim().to_string());
    for given in &args.set {
        if let Some(flagged) = overrides.iter().find(|o| key(&o.assignment) == key(given)) {
            anyhow::bail!(
                "--set {given} and the flag that sets `{}` change the same setting; give one",
                flagged.assignment
            );
        }
    }
    overrides.extend(args.set.iter().map(|s| SettingChange::set(s)));
    let job = ReplayJob {
        input: args.frames_dir.clone(),
        overrides,
        out_csv: args.out.clone(),
        overlay_dir: args.overlay,
        progress: !args.quiet,
    };
    let s = match replay(&job) {
        Ok(s) => s,
        Err(e @ ReplayError::Output(_)) => return Err(incomplete(e)),
        Err(e) => return Err(e.into()),
    };
    let agreement = match s.first_difference {
        None => "every estimate equals the recorded one".to_string(),
        Some(k) => format!(
            "{} of {} estimates equal the recorded ones, the first difference at frame {k}",
            s.same_as_recorded, s.frames
        ),
    };
    eprintln!(
        "{}: {} of {} frames of {}: {} tracking, {} coasting, {} lost, {} (re)acquired; {agreement}",
        args.out.display(),
        s.frames,
        s.frames_recorded,
        s.scenario,
        s.tracking,
        s.coasting,
        s.lost,
        s.acquisitions,
    );
    Ok(())
}
