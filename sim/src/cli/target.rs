//! `carfollow target`: check a target file, list its features, and draw it.

use super::exit::incomplete;
use super::paths::png_path;
use anyhow::Context;
use clap::Args;
use std::path::PathBuf;
use tracker::synth::{draw, SynthScene};
use tracker::{Camera, Location};

/// Arguments of `carfollow target`.
#[derive(Args, Debug)]
#[command(
    about = "Check a target model file, list its features, and draw it as painted (PNG)",
    after_help = super::exit::TOOL_HELP
)]
pub struct TargetArgs {
    /// Target model file (TOML).
    pub target: PathBuf,
    /// Draw the painted target to this PNG.
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Width of the drawing, pixels.
    #[arg(long, default_value_t = 480)]
    pub width: u32,
}

/// Runs the subcommand.
pub fn run_target(args: TargetArgs) -> anyhow::Result<()> {
    // Arguments first: bad input is refused before anything is said.
    if args.out.is_some() && !(64..=4096).contains(&args.width) {
        anyhow::bail!(
            "--width must be between 64 and 4096 pixels, got {}",
            args.width
        );
    }
    if let Some(out) = &args.out {
        png_path("--out", out)?;
    }
    let model = sim_core::load_target(&args.target)?;
    let [w_m, h_m] = model.size_m();
    say!(
        "{}: `{}`, {:.2} m × {:.2} m, nominal range {} m, {} segments",
        args.target.display(),
        model.name(),
        w_m,
        h_m,
        model.nominal_range_m(),
        model.segments().len()
    );
    let camera = Camera::default();
    for (f, [a, b]) in model.features_px(&camera).iter().zip(model.segments()) {
        say!(
            "  segment {}: corners {a}-{b}, {}, offset {:+.3} m",
            f.segment,
            f.orientation.as_str(),
            f.offset_px * model.nominal_range_m() / camera.focal_px()[0]
                * if f.orientation == tracker::Orientation::Horizontal {
                    -1.0
                } else {
                    1.0
                }
        );
    }
    if let Some(out) = &args.out {
        let width = args.width as usize;
        // Scale the drawing so the board (with its margin) fills 90 % of the width.
        let board_w = w_m + 2.0 * tracker::paint::BOARD_MARGIN_M;
        let board_h = h_m + 2.0 * tracker::paint::BOARD_MARGIN_M;
        let px_per_m = 0.9 * width as f64 / board_w;
        let height = ((board_h * px_per_m) / 0.9).ceil() as usize;
        let scale = px_per_m * model.nominal_range_m() / camera.focal_px()[0];
        let scene = SynthScene {
            width,
            height,
            background: 90.0,
            ..SynthScene::default()
        };
        let at = Location::new(
            (width as f64 - 1.0) / 2.0,
            (height as f64 - 1.0) / 2.0,
            scale,
        );
        let pixels = draw(&model, &camera, at, &scene, 0);
        image::GrayImage::from_raw(width as u32, height as u32, pixels)
            .expect("buffer matches its size")
            .save(out)
            .with_context(|| format!("{}: cannot write", out.display()))
            .map_err(incomplete)?;
        say!("drew {}", out.display());
    }
    Ok(())
}
