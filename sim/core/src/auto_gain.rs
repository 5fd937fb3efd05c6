//! The camera's automatic gain control, run by the closed loop.
//!
//! After each frame the control meters the mean grey of the frame's metering window
//! ([`AutoGain::metering_window`], which the renderer renders exactly even when it renders
//! only part of a frame, so the gain is the same with and without whole frames) and moves
//! the logarithm of its gain towards the gain that would have brought that mean to the
//! target, by the fraction `1 − exp(−T/τ)` of a frame period `T`: a first-order lag with
//! time constant τ. Frame k is exposed with the gain after metering frame k − 2, because
//! with two frames in flight frame k is submitted before frame k − 1 has come back; every
//! mode of the loop uses that same lag, so the gains never depend on the mode. No
//! randomness: the same frames give the same gains.
//!
//! With highlight protection (`AutoGain::max_clipped_share`), the gain it moves towards is
//! also held under the one that would bring the window's brightest pixels, beyond that
//! share, to [`CLIP_AIM_GREY`]: a camera that meters a dark frame with a bright target in
//! it (a car's back in its own high beams) lowers its gain until the target is no longer
//! white, where a mean alone would keep it clipped.

use image::GrayImage;
use sim_render::AutoGain;
use tracker::PixelRect;

/// Frames between the one metered and the first exposed with the result.
const LAG_FRAMES: u64 = 2;

/// The grey that highlight protection brings the window's brightest pixels (beyond the
/// share it lets clip) to: a little under white, so that sensor noise on them seldom
/// clips.
const CLIP_AIM_GREY: f64 = 250.0;

/// Highlight protection's step when more than the share is already white, where how far
/// above white the light lies cannot be read: half the gain, reached over the control's
/// time constant.
const CLIPPED_BACKOFF: f64 = 0.5;

/// The control's state.
#[derive(Clone, Debug)]
pub(crate) struct AutoGainControl {
    config: Option<AutoGain>,
    window: PixelRect,
    /// The fraction of the way to the metered gain moved per frame.
    alpha: f64,
    /// The natural logarithm of the gain after metering each of the last frames:
    /// `(frame index, ln gain)`, oldest first.
    history: Vec<(u64, f64)>,
}

impl AutoGainControl {
    /// The control of `config` (`None`: off, the gain always 1) for frames
    /// `width × height` at `frame_hz` frames a second.
    pub(crate) fn new(
        config: Option<AutoGain>,
        width: u32,
        height: u32,
        frame_hz: f64,
    ) -> AutoGainControl {
        let alpha = config.map_or(0.0, |c| 1.0 - (-1.0 / (frame_hz * c.time_constant_s)).exp());
        AutoGainControl {
            config,
            window: AutoGain::metering_window(width as usize, height as usize),
            alpha,
            history: Vec::with_capacity(4),
        }
    }

    /// The gain to expose frame `frame_index` with.
    pub(crate) fn gain_for(&self, frame_index: u64) -> f64 {
        if self.config.is_none() || frame_index < LAG_FRAMES {
            return 1.0;
        }
        let metered = frame_index - LAG_FRAMES;
        self.history
            .iter()
            .rev()
            .find(|(k, _)| *k <= metered)
            .map_or(1.0, |&(_, ln_gain)| ln_gain.exp())
    }

    /// Meters frame `frame_index`, exposed with gain `gain` (frames come in order).
    pub(crate) fn observe(&mut self, frame_index: u64, gain: f64, image: &GrayImage) {
        let Some(config) = self.config else {
            return;
        };
        let w = &self.window;
        let width = image.width() as usize;
        let pixels = image.as_raw();
        let sum: u64 = (w.y0..w.y1.min(image.height() as usize))
            .flat_map(|y| pixels[y * width + w.x0..y * width + w.x1.min(width)].iter())
            .map(|&p| u64::from(p))
            .sum();
        let count = (w.width() * w.height()).max(1) as f64;
        // Half a grey level at least: a black frame asks for the most gain, not infinity.
        let mean = (sum as f64 / count).max(0.5);
        let mut wanted = gain.ln() + (config.target_grey / mean).ln();
        if let Some(share) = config.max_clipped_share {
            wanted = wanted.min(gain.ln() + self.highlight_ratio(image, share).ln());
        }
        let last = self.history.last().map_or(0.0, |&(_, g)| g);
        let limit = config.max_gain.ln();
        let next = (last + self.alpha * (wanted - last)).clamp(-limit, limit);
        if self.history.len() == LAG_FRAMES as usize + 1 {
            self.history.remove(0);
        }
        self.history.push((frame_index, next));
    }

    /// The factor on the gain that brings the metering window's brightest pixels, beyond
    /// the `share` of it allowed to clip, to [`CLIP_AIM_GREY`]: the grey below which all
    /// but that share lie, up to [`CLIP_AIM_GREY`]; [`CLIPPED_BACKOFF`] when it is white.
    fn highlight_ratio(&self, image: &GrayImage, share: f64) -> f64 {
        let w = &self.window;
        let width = image.width() as usize;
        let pixels = image.as_raw();
        let mut counts = [0u64; 256];
        for y in w.y0..w.y1.min(image.height() as usize) {
            for &p in &pixels[y * width + w.x0..y * width + w.x1.min(width)] {
                counts[usize::from(p)] += 1;
            }
        }
        let total: u64 = counts.iter().sum();
        let allowed = (share * total as f64).floor() as u64;
        // The least grey with at most `allowed` pixels above it.
        let mut above = 0;
        let mut level = 255;
        while level > 0 && above + counts[level] <= allowed {
            above += counts[level];
            level -= 1;
        }
        if level == 255 {
            CLIPPED_BACKOFF
        } else {
            CLIP_AIM_GREY / (level.max(1) as f64)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A scene of uniform reflectance `level` seen with gain `gain`.
    fn frame(level: f64, gain: f64) -> GrayImage {
        let v = (level * gain).round().clamp(0.0, 255.0) as u8;
        GrayImage::from_pixel(256, 242, image::Luma([v]))
    }

    #[test]
    fn the_gain_brings_a_dark_scene_towards_the_target_with_its_lag() {
        let config = AutoGain::default();
        let mut c = AutoGainControl::new(Some(config), 256, 242, 15.0);
        let mut means = Vec::new();
        for k in 0..60 {
            let g = c.gain_for(k);
            if k < 2 {
                assert_eq!(g, 1.0);
            }
            let image = frame(30.0, g);
            means.push(f64::from(image.as_raw()[0]));
            c.observe(k, g, &image);
        }
        // Up from 30 over the frames, never past the target, and close to it after 4 s.
        assert!(means.windows(2).all(|m| m[1] >= m[0]), "{means:?}");
        assert!(means.iter().all(|&m| m <= config.target_grey + 1.0));
        assert!((means[59] - config.target_grey).abs() <= 2.0, "{means:?}");
        // After one time constant (7.5 frames, plus the lag) about 63 % of the way in
        // the logarithm of the gain.
        let ln_reached = (means[10] / 30.0).ln() / (config.target_grey / 30.0).ln();
        assert!((0.55..0.75).contains(&ln_reached), "{ln_reached}");
    }

    /// A dark scene (reflectance `dark`) with a bright patch (`bright`, may exceed white)
    /// covering `patch` of the metering window's pixels, seen with gain `gain`.
    fn frame_with_patch(dark: f64, bright: f64, patch: usize, gain: f64) -> GrayImage {
        let window = AutoGain::metering_window(256, 242);
        let mut image = frame(dark, gain);
        let v = (bright * gain).round().clamp(0.0, 255.0) as u8;
        let mut left = patch;
        'rows: for y in window.y0..window.y1 {
            for x in window.x0..window.x1 {
                if left == 0 {
                    break 'rows;
                }
                image.put_pixel(x as u32, y as u32, image::Luma([v]));
                left -= 1;
            }
        }
        image
    }

    /// The gains and frames of `frames` frames of a dark scene with a bright patch.
    fn settle(config: AutoGain, patch: usize, frames: u64) -> (f64, GrayImage) {
        let mut c = AutoGainControl::new(Some(config), 256, 242, 15.0);
        let mut last = (1.0, frame(0.0, 1.0));
        for k in 0..frames {
            let g = c.gain_for(k);
            let image = frame_with_patch(5.0, 400.0, patch, g);
            c.observe(k, g, &image);
            last = (g, image);
        }
        last
    }

    #[test]
    fn highlight_protection_keeps_a_bright_patch_off_white_in_a_dark_frame() {
        let window = AutoGain::metering_window(256, 242);
        let pixels = window.width() * window.height();
        // A patch 4 % of the window, 80 times the background and above white at gain 1.
        let patch = pixels / 25;
        let white = |image: &GrayImage| image.as_raw().iter().filter(|&&p| p == 255).count();
        let plain = AutoGain {
            max_gain: 64.0,
            ..AutoGain::default()
        };
        // Metering the mean, the gain rises and the patch stays white.
        let (g, image) = settle(plain, patch, 150);
        assert!(g > 4.0, "{g}");
        assert_eq!(white(&image), patch);
        // With at most 1 % allowed to clip, the gain falls until the patch is near 250.
        let protected = AutoGain {
            max_clipped_share: Some(0.01),
            ..plain
        };
        let (g, image) = settle(protected, patch, 150);
        assert!(
            (250.0 / 400.0 * 0.9..=250.0 / 400.0 * 1.05).contains(&g),
            "{g}"
        );
        assert_eq!(white(&image), 0);
        // A patch within the share leaves the gain to the mean, as without protection.
        let small = pixels / 200;
        let (a, _) = settle(plain, small, 150);
        let (b, _) = settle(protected, small, 150);
        assert_eq!(a, b);
    }

    #[test]
    fn off_it_is_always_one_and_the_gain_is_bounded() {
        let mut off = AutoGainControl::new(None, 256, 242, 15.0);
        off.observe(0, 1.0, &frame(0.0, 1.0));
        assert_eq!(off.gain_for(5), 1.0);
        let mut c = AutoGainControl::new(Some(AutoGain::default()), 256, 242, 15.0);
        for k in 0..200 {
            let g = c.gain_for(k);
            c.observe(k, g, &frame(0.0, g));
        }
        assert!((c.gain_for(200) - AutoGain::default().max_gain).abs() < 1e-9);
    }
}
