//! A scenario's pass/fail criteria (`[expect]`), which the reports judge a run by.

use serde::{Deserialize, Serialize};

/// The pass/fail criteria of a scenario (`[expect]`). A criterion left out is not checked.
/// Every limit must be finite and at least 0; a gap band's minimum below its maximum.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Expect {
    /// The following distance must stay within this band, metres `[min, max]`, except for
    /// at most `max_time_outside_gap_band_s`.
    #[serde(default, deserialize_with = "super::file::exact::optional")]
    pub gap_band_m: Option<[f64; 2]>,
    /// Time allowed outside the gap band, seconds (default 0 when a band is given).
    pub max_time_outside_gap_band_s: Option<f64>,
    /// Longest total time the tracker may be lost by the ground-truth judgement, seconds.
    pub max_lost_s: Option<f64>,
    /// Largest lateral deviation from the lead's path, metres.
    pub max_lateral_deviation_m: Option<f64>,
    /// The vehicles must never touch.
    #[serde(default)]
    pub no_collision: bool,
    /// The chase vehicle must drive at least this far, metres.
    pub min_distance_m: Option<f64>,
    /// Largest 95th percentile of the range estimate's absolute error over the tracked
    /// frames, metres.
    pub max_range_error_p95_m: Option<f64>,
    /// Most ground-truth tracking-loss events (maximal runs of lost frames) allowed.
    pub max_loss_events: Option<u64>,
    /// Longest total time the tracker may raise a false alarm, seconds: not say `tracking`
    /// while its estimate is within the ground truth's tolerance of a target wholly in view,
    /// not hidden and not too faint for the paper's edge threshold (the dual of a silent
    /// loss).
    pub max_false_alarm_s: Option<f64>,
    // The traffic's criteria (below) are written only when given, so that a scenario
    // without them resolves as it did before they existed.
    /// Largest speed of the chase towards what it hit at its first contact with another
    /// vehicle, km/h; 0 allows no contact at all.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max_impact_speed_kph: Option<f64>,
    /// Smallest time to collision with the vehicle in the chase's path, seconds.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub min_ttc_s: Option<f64>,
    /// Longest total time the tracker may hold a vehicle that is not the one in the chase's
    /// path, seconds.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max_wrong_vehicle_s: Option<f64>,
    /// The chase's hardest deceleration, m/s² (from its speed frame to frame).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max_decel_mps2: Option<f64>,
    /// The chase's largest jerk, m/s³ (from its accelerations frame to frame).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max_jerk_mps3: Option<f64>,
    /// A tracker that starts with nothing placed (`tracker.start = "search"`) must first
    /// hold its target (in traffic, the vehicle in the chase's path) at least this far off,
    /// metres (the true range then); one that never holds it fails, one held from the start
    /// passes. (Written only when given.)
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub min_acquisition_range_m: Option<f64>,
}
