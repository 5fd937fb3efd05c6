//! The tracker's settings. The paper's own values are the defaults; where the paper gives
//! none, the default and its reason are stated beside the field.

use thiserror::Error;

/// Which tracker runs: the paper's, or the robust mode that goes beyond it.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum TrackerMode {
    /// The paper's tracker, stages 1–8 as written (the default).
    #[default]
    Paper,
    /// The paper's stages with the improvements of [`crate::robust`]: an edge threshold
    /// that follows the image noise, M-estimation in stages 3 and 4, a second, faster
    /// motion model chosen by its prediction error, innovation-gated forgetting, ego-motion
    /// aided prediction, and a chamfer search that recovers the target (or finds it at the
    /// start) when the measurement fails its own checks.
    Robust,
}

impl TrackerMode {
    /// Lower-case name, as written in scenario files and tables.
    pub fn as_str(self) -> &'static str {
        match self {
            TrackerMode::Paper => "paper",
            TrackerMode::Robust => "robust",
        }
    }

    /// Parses `paper` or `robust`.
    pub fn parse(text: &str) -> Option<TrackerMode> {
        match text {
            "paper" => Some(TrackerMode::Paper),
            "robust" => Some(TrackerMode::Robust),
            _ => None,
        }
    }
}

/// Every setting of the tracker. `TrackerConfig::default()` is the paper's tracker.
#[derive(Clone, Debug, PartialEq)]
pub struct TrackerConfig {
    /// Edge magnitude threshold on eq. 4's mag = |∇f|, grey levels (of 0–255) per pixel
    /// (2.3: "a threshold value of 8 in a grey level range of 0 to 255 proved to be
    /// effective"). ∇f is the 3×3 Sobel response over 8, the derivative it estimates, so a
    /// step edge of h grey levels has |∇f| = h/2: the default 8 passes steps of 16 grey levels
    /// or more. (Read as a step's height instead, 8 lets about 40 % of the pixels of noise
    /// σ = 7 through before suppression, against 3 %, and the paper's scale runs away on dim,
    /// noisy frames: `tracker/tests/dim_weave.rs`.) Robust mode goes below it in clean frames
    /// ([`crate::robust::adaptive_threshold`]).
    pub edge_threshold: f64,
    /// δ of eq. 7, degrees: how far an edge's direction may be from horizontal or vertical
    /// (section 3: "within a 15 degree threshold about either the horizontal and vertical").
    pub delta_deg: f64,
    /// ζ of 2.4, pixels: an edge point is associated with its nearest feature only if nearer
    /// than this. Not given by the paper. Default 4 px: half the 8 px between the shipped
    /// target's nearest parallel features at its 10 m nominal range, so that a point is never
    /// taken by a feature when it lies nearer the middle of the gap than the feature itself,
    /// and about three times the prediction error seen when tracking at 15 Hz.
    pub zeta_px: f64,
    /// A feature needs at least this fraction of its predicted length in associated points,
    /// or its confidence is zero (2.5: 0.3).
    pub min_support_fraction: f64,
    /// σ² floor of eq. 14, pixels²: below it the confidence is capped at 1/√0.1 (2.5: 0.1).
    pub sigma2_floor: f64,
    /// λ of eq. 18, the motion model's forgetting factor (0 < λ < 1, as eq. 18 requires). Not
    /// given by the paper.
    /// Default 0.8: an effective memory of 1/(1 − λ) = 5 frames (a third of a second at
    /// 15 Hz), enough to average the measurement noise of a three-coefficient model while
    /// following a hard brake within a few frames. Section 4's trade-off: smaller λ follows
    /// abrupt motion, larger λ is more robust to shadows and clutter.
    pub lambda: f64,
    /// The seven window-of-interest sizes of 2.3, as multiples of the target's extent at
    /// scale 1. The smallest size not below the predicted scale is used. Not given by the
    /// paper. Default: √2 steps from 0.5 to 4 (ranges from twice to an eighth of the nominal
    /// range), so the window is never more than √2 times larger than it needs to be.
    pub window_scales: [f64; 7],
    /// Margin of the window beyond the target's extent, as a fraction of that extent, to
    /// hold the target when the prediction is off. Default 0.25: the prediction is rarely off
    /// by more than a quarter of the target's size between two frames 1/15 s apart.
    pub window_margin: f64,
    /// Camera frame rate, Hz: one motion-model cycle (t = 1) lasts 1/rate_hz seconds.
    /// Default 15 Hz (the paper's update rate).
    pub rate_hz: f64,
    /// How long (seconds) the tracker goes without a trusted measurement (one that passes
    /// the coverage check) before it reports `Lost`. Not given by the paper, which has no
    /// loss state (a teleoperator watched). Default 1 s (15 frames): at 35 km/h the lead
    /// moves about 10 m in that time; a quadratic extrapolation over longer is a guess, not
    /// a track, and so is a fit that has stayed off the target's edges that long. In the
    /// paper's mode `Lost` is a status only: the tracker goes on measuring, its estimates are
    /// the same whatever the status, and it reports `tracking` again as soon as the features
    /// return.
    pub lost_after_s: f64,
    /// Floor on J_l (eq. 15) for a fit with no degrees of freedom: with exactly three
    /// features the fit is exact, J_l = 0, and eq. 17, which divides by J_l, has no value.
    /// Not in the paper. Default 1: the expected residual of one degree of freedom when each
    /// feature's error matches its stated σ. A fit with four or more features uses eq. 17 as
    /// written, down to [`crate::object_location::MIN_RESIDUAL_PER_DOF`] of its weights per
    /// degree of freedom.
    pub min_fit_residual: f64,
    /// Improvement over the paper (off by default, so the default is the paper's tracker):
    /// locate each edge point to a fraction of a pixel across the edge by fitting a parabola
    /// to the gradient magnitude of the point and its two neighbours across the edge.
    pub subpixel_edges: bool,
    /// The paper's tracker or the robust mode (default: the paper's).
    pub mode: TrackerMode,
}

impl Default for TrackerConfig {
    fn default() -> Self {
        TrackerConfig {
            edge_threshold: 8.0,
            delta_deg: 15.0,
            zeta_px: 4.0,
            min_support_fraction: 0.3,
            sigma2_floor: 0.1,
            lambda: 0.8,
            window_scales: [0.5, 0.71, 1.0, 1.41, 2.0, 2.83, 4.0],
            window_margin: 0.25,
            rate_hz: 15.0,
            lost_after_s: 1.0,
            min_fit_residual: 1.0,
            subpixel_edges: false,
            mode: TrackerMode::Paper,
        }
    }
}

/// A setting out of its allowed range.
#[derive(Clone, Debug, Error, PartialEq)]
#[error("tracker setting `{field}` = {value}: {allowed}")]
pub struct ConfigError {
    /// The field's name.
    pub field: &'static str,
    /// The refused value.
    pub value: String,
    /// What is allowed.
    pub allowed: &'static str,
}

impl TrackerConfig {
    /// Checks every field's range.
    pub fn validate(&self) -> Result<(), ConfigError> {
        fn check(
            ok: bool,
            field: &'static str,
            value: f64,
            allowed: &'static str,
        ) -> Result<(), ConfigError> {
            if ok {
                Ok(())
            } else {
                Err(ConfigError {
                    field,
                    value: value.to_string(),
                    allowed,
                })
            }
        }
        let c = self;
        check(
            c.edge_threshold.is_finite() && c.edge_threshold >= 0.0,
            "edge_threshold",
            c.edge_threshold,
            "must be ≥ 0 grey levels",
        )?;
        check(
            c.delta_deg > 0.0 && c.delta_deg < 45.0,
            "delta_deg",
            c.delta_deg,
            "must be in (0, 45) degrees",
        )?;
        check(
            c.zeta_px.is_finite() && c.zeta_px > 0.0,
            "zeta_px",
            c.zeta_px,
            "must be > 0 pixels",
        )?;
        check(
            (0.0..=2.0).contains(&c.min_support_fraction),
            "min_support_fraction",
            c.min_support_fraction,
            "must be in [0, 2]",
        )?;
        check(
            c.sigma2_floor.is_finite() && c.sigma2_floor > 0.0,
            "sigma2_floor",
            c.sigma2_floor,
            "must be > 0 pixels²",
        )?;
        check(
            c.lambda > 0.0 && c.lambda < 1.0,
            "lambda",
            c.lambda,
            "must be in (0, 1) (eq. 18: 0 < λ < 1)",
        )?;
        for pair in c.window_scales.windows(2) {
            check(
                pair[0] > 0.0 && pair[1] > pair[0],
                "window_scales",
                pair[1],
                "must be positive and increasing",
            )?;
        }
        check(
            c.window_margin.is_finite() && c.window_margin >= 0.0,
            "window_margin",
            c.window_margin,
            "must be ≥ 0",
        )?;
        check(
            c.rate_hz.is_finite() && c.rate_hz > 0.0,
            "rate_hz",
            c.rate_hz,
            "must be > 0 Hz",
        )?;
        check(
            c.lost_after_s.is_finite() && c.lost_after_s >= 0.0,
            "lost_after_s",
            c.lost_after_s,
            "must be ≥ 0 seconds",
        )?;
        check(
            c.min_fit_residual.is_finite() && c.min_fit_residual > 0.0,
            "min_fit_residual",
            c.min_fit_residual,
            "must be > 0",
        )?;
        Ok(())
    }
}
