//! `carfollow synth`: a synthetic frame sequence of a target, with its ground truth, for
//! trying `carfollow track` without a recording.

use super::exit::incomplete;
use anyhow::Context;
use clap::Args;
use std::io::Write;
use std::path::PathBuf;
use tracker::synth::{draw, wander, Rect, SynthScene};
use tracker::{Camera, Location};

/// Arguments of `carfollow synth`.
#[derive(Args, Debug)]
#[command(
    about = "Write a synthetic 256×242 frame sequence of a target (PNG) and its truth.csv",
    long_about = "Draws the target, moving smoothly in position and scale, into OUT_DIR as \
                  frame_0000.png, frame_0001.png, ... with truth.csv (frame,cx,cy,scale). \
                  With --clutter: sensor noise, a pole and a wire near the target, and a \
                  shadow band sweeping across it. Seeded: the same seed gives the same frames."
)]
pub struct SynthArgs {
    /// Folder to write into (created if missing).
    pub out_dir: PathBuf,
    /// Target model file (TOML).
    #[arg(long, default_value = "scenarios/targets/nist-ten-segment.toml")]
    pub target: PathBuf,
    /// Number of frames.
    #[arg(long, default_value_t = 90)]
    pub frames: usize,
    /// First frame's location CX,CY,SCALE.
    #[arg(long, default_value = "128,110,1.0", allow_hyphen_values = true)]
    pub start: String,
    /// Largest motion per frame, pixels.
    #[arg(long, default_value_t = 1.5)]
    pub px_per_frame: f64,
    /// Add noise, a pole, a wire and a moving shadow.
    #[arg(long)]
    pub clutter: bool,
    /// Seed for the motion and the noise.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
}

/// Runs the subcommand.
pub fn run_synth(args: SynthArgs) -> anyhow::Result<()> {
    let model = sim::target::load(&args.target)?;
    let start: Location = sim::track::parse_location(&args.start).context("--start")?;
    if args.frames == 0 || args.frames > 100_000 {
        anyhow::bail!("--frames must be between 1 and 100000, got {}", args.frames);
    }
    std::fs::create_dir_all(&args.out_dir)
        .with_context(|| format!("{}: cannot create", args.out_dir.display()))
        .map_err(incomplete)?;
    let camera = Camera::default();
    let truth = wander(start, args.frames, args.px_per_frame, 0.01, args.seed);
    let truth_path = args.out_dir.join("truth.csv");
    let mut csv = std::fs::File::create(&truth_path)
        .with_context(|| format!("{}: cannot create", truth_path.display()))
        .map_err(incomplete)?;
    writeln!(csv, "frame,cx,cy,scale")?;
    let half = model
        .size_m()
        .map(|m| 0.5 * m * camera.focal_px()[0] / model.nominal_range_m());
    for (k, at) in truth.iter().enumerate() {
        let mut scene = SynthScene::default();
        if args.clutter {
            let (hw, hh) = (half[0] * at.scale, half[1] * at.scale);
            let sweep = at.c_x - 60.0 + (2.0 * k as f64) % 120.0;
            scene.noise_sigma = 4.0;
            scene.distractors = vec![
                Rect {
                    bounds: [at.c_x - hw - 12.0, 0.0, at.c_x - hw - 9.0, 242.0],
                    value: 60.0,
                },
                Rect {
                    bounds: [0.0, at.c_y - hh - 13.0, 256.0, at.c_y - hh - 12.0],
                    value: 70.0,
                },
            ];
            scene.shadows = vec![Rect {
                bounds: [sweep, 0.0, sweep + 14.0, 242.0],
                value: 0.55,
            }];
        }
        let pixels = draw(
            &model,
            &camera,
            *at,
            &scene,
            args.seed.wrapping_mul(1_000_003) + k as u64,
        );
        let path = args.out_dir.join(format!("frame_{k:04}.png"));
        image::GrayImage::from_raw(256, 242, pixels)
            .expect("buffer matches its size")
            .save(&path)
            .with_context(|| format!("{}: cannot write", path.display()))
            .map_err(incomplete)?;
        writeln!(csv, "{k},{:.4},{:.4},{:.6}", at.c_x, at.c_y, at.scale)?;
    }
    println!(
        "{}: {} frames; track them with: carfollow track {} --target {} --focal-px {} --init {},{},{}",
        args.out_dir.display(),
        args.frames,
        args.out_dir.display(),
        args.target.display(),
        camera.focal_px()[0],
        start.c_x,
        start.c_y,
        start.scale
    );
    Ok(())
}
