//! `carfollow track`: the tracker alone on a folder of recorded frames.

use anyhow::Context;
use clap::Args;
use sim::track::{parse_location, run, TrackJob};
use std::path::PathBuf;
use tracker::{TrackerConfig, TrackerMode};

/// Arguments of `carfollow track`.
#[derive(Args, Debug)]
#[command(
    about = "Run the tracker on a folder of recorded frames (PNG or PGM, sorted by name)",
    long_about = "Run the paper's tracker (stages 1-8) over every PNG or PGM in FRAMES_DIR, \
                  sorted by name, converting colour to grey. Writes one CSV row per frame as \
                  it goes: frame,cx,cy,scale,status, then confidences, the prediction, the \
                  3-D position and per-feature counts."
)]
pub struct TrackArgs {
    /// Folder of frames.
    pub frames_dir: PathBuf,
    /// Target model file (TOML), e.g. scenarios/targets/nist-ten-segment.toml.
    #[arg(long)]
    pub target: PathBuf,
    /// Camera focal length, pixels.
    #[arg(long)]
    pub focal_px: f64,
    /// The target's location in the first frame: CX,CY,SCALE (the teleoperator's placement).
    /// Required by the paper's mode; robust mode without it searches the whole image.
    #[arg(long, allow_hyphen_values = true)]
    pub init: Option<String>,
    /// Tracker mode: paper (the paper's tracker, the default) or robust.
    #[arg(long, default_value = "paper", value_parser = ["paper", "robust"])]
    pub mode: String,
    /// Forgetting factor λ of the motion model (0 < λ ≤ 1).
    #[arg(long)]
    pub lambda: Option<f64>,
    /// Frame rate, Hz: frame k is at k / rate seconds.
    #[arg(long, default_value_t = 15.0)]
    pub rate_hz: f64,
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

/// Runs the subcommand.
pub fn run_track(args: TrackArgs) -> anyhow::Result<()> {
    let model = sim::target::load(&args.target)?;
    let mode = TrackerMode::parse(&args.mode).expect("clap allows only known modes");
    let init = match &args.init {
        Some(text) => Some(parse_location(text).context("--init")?),
        None if mode == TrackerMode::Robust => None,
        None => anyhow::bail!(
            "--init CX,CY,SCALE is required in the paper's mode (the teleoperator's placement, \
             paper 2.2); --mode robust can search for the target instead"
        ),
    };
    if !(args.focal_px.is_finite() && args.focal_px > 0.0) {
        anyhow::bail!(
            "--focal-px must be a positive number of pixels, got {}",
            args.focal_px
        );
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
        rate_hz: args.rate_hz,
        subpixel_edges: args.subpixel_edges,
        mode,
        ..TrackerConfig::default()
    };
    if let Some(lambda) = args.lambda {
        config.lambda = lambda;
    }
    config.validate().context("bad tracker setting")?;
    let job = TrackJob {
        frames_dir: args.frames_dir,
        model,
        focal_px: args.focal_px,
        pixel_size_mm: args.pixel_size_mm,
        image_center_px,
        init,
        config,
        out_csv: args.out.clone(),
        overlay_dir: args.overlay,
        progress: !args.quiet,
    };
    let s = run(&job)?;
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
