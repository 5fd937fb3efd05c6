//! `carfollow synth`: a synthetic frame sequence of a target, with its ground truth, for
//! trying `carfollow track` without a recording.

use super::exit::incomplete;
use anyhow::Context;
use clap::Args;
use std::io::Write;
use std::path::PathBuf;
use tracker::synth::{draw, sequence, sequence_with_truth, wander, SequenceKind, SynthScene};
use tracker::{Camera, Location};

/// Arguments of `carfollow synth`.
#[derive(Args, Debug)]
#[command(
    after_help = super::exit::TOOL_HELP,
    about = "Write a synthetic 256×242 frame sequence of a target (PNG) and its truth.csv",
    long_about = "Draws the target, moving smoothly in position and scale, into OUT_DIR as \
                  frame_0000.png, frame_0001.png, ... with truth.csv (frame,cx,cy,scale). \
                  --kind clutter (or --clutter): sensor noise, a pole and a wire near the \
                  target, and a shadow band sweeping across it; --kind swerve, shake or dim: \
                  abrupt sideways swerves, a shaking camera, or a dim noisy scene. Seeded: the \
                  same seed gives the same frames."
)]
pub struct SynthArgs {
    /// Folder to write into (created if missing).
    pub out_dir: PathBuf,
    /// Target model file (TOML). Default: the built-in NIST target, written beside the
    /// frames as target.toml for `track`.
    #[arg(long)]
    pub target: Option<PathBuf>,
    /// Number of frames.
    #[arg(long, default_value_t = 90)]
    pub frames: usize,
    /// First frame's location CX,CY,SCALE.
    #[arg(long, default_value = "128,110,1.0", allow_hyphen_values = true)]
    pub start: String,
    /// Largest motion per frame, pixels: 0–50.
    #[arg(long, default_value_t = 1.5, allow_hyphen_values = true)]
    pub px_per_frame: f64,
    /// Add noise, a pole, a wire and a moving shadow (the same as --kind clutter).
    #[arg(long)]
    pub clutter: bool,
    /// What the sequence shows: plain (a smooth wander), clutter, swerve (24 px sideways in 4
    /// frames, every 40 frames), shake (±5 px at 2.3 Hz, a rough road) or dim (30 grey levels
    /// of contrast, noise σ = 7).
    #[arg(long, value_parser = ["plain", "clutter", "swerve", "shake", "dim"])]
    pub kind: Option<String>,
    /// Seed for the motion and the noise.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
}

/// Runs the subcommand.
pub fn run_synth(args: SynthArgs) -> anyhow::Result<()> {
    let builtin_path = args.out_dir.join("target.toml");
    let model = match &args.target {
        Some(path) => sim_core::load_target(path)?,
        None => sim_core::parse_target(sim_core::BUILTIN_TARGET_TEXT, &builtin_path)?,
    };
    let start: Location = sim::parse_location(&args.start).context("--start")?;
    if args.frames == 0 || args.frames > 100_000 {
        anyhow::bail!("--frames must be between 1 and 100000, got {}", args.frames);
    }
    if !(args.px_per_frame.is_finite() && (0.0..=50.0).contains(&args.px_per_frame)) {
        anyhow::bail!(
            "--px-per-frame must be 0–50 pixels, got {}",
            args.px_per_frame
        );
    }
    // Every argument is checked before the folder is made or anything written.
    let camera = Camera::default();
    let kind = match (args.kind.as_deref(), args.clutter) {
        (Some(k), _) => SequenceKind::parse(k).expect("clap allows only known kinds"),
        (None, true) => SequenceKind::Clutter,
        (None, false) => SequenceKind::Plain,
    };
    if args.clutter && kind != SequenceKind::Clutter {
        anyhow::bail!(
            "--clutter is --kind clutter; it cannot be combined with --kind {}",
            kind.as_str()
        );
    }
    let half = model
        .size_m()
        .map(|m| 0.5 * m * camera.focal_px()[0] / model.nominal_range_m());
    // A sequence whose target starts outside the frame, or wider than it, shows nothing
    // to track.
    let (width, height) = {
        let frame = SynthScene::default();
        (frame.width as u32, frame.height as u32)
    };
    let inside = |at: f64, size: u32| (0.0..f64::from(size)).contains(&at);
    if !(inside(start.c_x, width) && inside(start.c_y, height)) {
        anyhow::bail!(
            "--start {}: the target's centre must start within the {width} × {height} frame",
            args.start
        );
    }
    if 2.0 * half[0] * start.scale > f64::from(width) {
        anyhow::bail!(
            "--start {}: at scale {} the target is {:.0} px wide, wider than the {width} px frame",
            args.start,
            start.scale,
            2.0 * half[0] * start.scale
        );
    }
    // `track` reads every frame of a folder: old frames left beside new ones would join them.
    if sim::frame_files(&args.out_dir).is_ok() {
        anyhow::bail!(
            "{}: already holds frames (PNG or PGM); synth into a new or empty folder",
            args.out_dir.display()
        );
    }
    std::fs::create_dir_all(&args.out_dir)
        .with_context(|| format!("{}: cannot create", args.out_dir.display()))
        .map_err(incomplete)?;
    let target = match &args.target {
        Some(path) => path.clone(),
        None => {
            std::fs::write(&builtin_path, sim_core::BUILTIN_TARGET_TEXT)
                .with_context(|| format!("{}: cannot write", builtin_path.display()))
                .map_err(incomplete)?;
            builtin_path
        }
    };
    let seq = match kind {
        // The plain and cluttered wanders keep their --px-per-frame.
        SequenceKind::Plain | SequenceKind::Clutter => {
            let truth = wander(start, args.frames, args.px_per_frame, 0.01, args.seed);
            sequence_with_truth(kind, truth, half)
        }
        _ => sequence(kind, start, args.frames, half, args.seed),
    };
    let truth_path = args.out_dir.join("truth.csv");
    let mut csv = std::fs::File::create(&truth_path)
        .with_context(|| format!("{}: cannot create", truth_path.display()))
        .map_err(incomplete)?;
    writeln!(csv, "frame,cx,cy,scale")?;
    for (k, (at, scene)) in seq.truth.iter().zip(&seq.scenes).enumerate() {
        let pixels = draw(
            &model,
            &camera,
            *at,
            scene,
            args.seed.wrapping_mul(1_000_003) + k as u64,
        );
        let path = args.out_dir.join(format!("frame_{k:04}.png"));
        image::GrayImage::from_raw(width, height, pixels)
            .expect("buffer matches its size")
            .save(&path)
            .with_context(|| format!("{}: cannot write", path.display()))
            .map_err(incomplete)?;
        writeln!(csv, "{k},{:.4},{:.4},{:.6}", at.c_x, at.c_y, at.scale)?;
    }
    say!(
        "{}: {} {} frames; track them with: carfollow track {} --target {} --focal-px {} --init {},{},{} \
         (or --mode robust, with or without --init)",
        args.out_dir.display(),
        args.frames,
        kind.as_str(),
        args.out_dir.display(),
        target.display(),
        camera.focal_px()[0],
        start.c_x,
        start.c_y,
        start.scale
    );
    Ok(())
}
