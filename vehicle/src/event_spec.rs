//! Scripted events as a scenario file writes them: a trigger and an action, as esmini and
//! OpenSCENARIO script their traffic, checked into the typed form the engine
//! ([`crate::Events`]) runs.
//!
//! A vehicle's events are a list of tables:
//!
//! ```toml
//! [[actors.events]]            # also [[lead.events]]
//! name = "cut-in"
//! trigger = { time_s = 8.0 }
//! action = { lane = 1, duration_s = 2.5, shape = "cubic" }
//!
//! [[actors.events]]
//! name = "brake"
//! trigger = { after = "cut-in", delay_s = 0.5 }
//! action = { speed_mps = 8.0, rate_mps2 = 2.0 }
//! ```
//!
//! Each table is read with unknown fields refused; what each may hold together (exactly one
//! kind of trigger, the timing an action needs) is checked by [`EventScript::validate`],
//! whose errors name the field as a dotted path (`events[1].trigger.after`).

use crate::error::VehicleError;
use serde::{Deserialize, Serialize};

mod action;
mod trigger;
use action::action;

/// The most lanes a road may have on one side of its centre line.
pub const MAX_LANES: u32 = 16;
/// Largest time or distance threshold, delay or duration, s or m.
const MAX_KEY: f64 = 1e7;
/// Largest gap threshold either way, m.
const MAX_GAP_M: f64 = 1e4;
/// Largest time-gap and time-to-collision threshold, s.
const MAX_TIME_S: f64 = 1e3;
/// Largest standstill duration a trigger may wait for, s: as the largest time gap, far
/// beyond any run.
const MAX_STANDSTILL_S: f64 = 1e3;
/// Largest rate of change of speed (or deceleration) an action may ask, m/s².
const MAX_RATE_MPS2: f64 = 20.0;
/// Largest lateral speed of a lane change, m/s.
const MAX_LATERAL_SPEED_MPS: f64 = 10.0;
/// Largest peak lateral acceleration of an offset, m/s²: beyond what tyres hold.
const MAX_LATERAL_ACCEL_MPS2: f64 = 20.0;
/// Largest lateral offset of a position from its lane's centre, m: as a lane's widest
/// (`Lanes`' 20 m), past which the point is on another lane.
pub(crate) const MAX_POSITION_OFFSET_M: f64 = 20.0;
/// The deepest a trigger's `all` and `any` may nest (OpenSCENARIO's trigger, any of
/// groups of all of conditions, each of them any or all of its entities, is three deep).
pub const MAX_TRIGGER_DEPTH: usize = 4;
/// The most condition groups a trigger may come to when written as OpenSCENARIO writes
/// one, any of groups each all of conditions (an `all` of `any`s multiplies out): as
/// many as a file may sensibly hold.
pub const MAX_TRIGGER_GROUPS: usize = 64;
/// How close two reals must be for `equal` to hold (and `not_equal` not to), in the
/// compared value's unit (s, m, m/s): a millionth of it. Simulation time moves in whole
/// 1/120 s steps, whose sums in f64 are exact to far below this, so `time_s` equal to a
/// multiple of 1/120 s holds at exactly that step; a measured speed or gap passes
/// through a value between two steps and is rarely within a millionth of it, as the
/// standard's equality on reals means.
pub const EQUAL_TOLERANCE: f64 = 1e-6;

/// One vehicle's scripted events, in the order written (a scenario's `[[lead.events]]` or
/// an actor's `events`): a TOML array of [`EventSpec`] tables.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(transparent)]
pub struct EventScript(pub Vec<EventSpec>);

/// One event: when its trigger holds, its action runs once (or again each time it holds
/// after the action ended, with `repeat`, up to `max_runs` runs in all).
///
/// ```toml
/// name = "slow-down"
/// trigger = { gap_m = 12.0, to = "chase", rule = "less" }
/// action = { speed_mps = 8.0, duration_s = 3.0, shape = "cubic" }
/// repeat = false
/// ```
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct EventSpec {
    /// The event's name, unique among the vehicle's events (for `after` and the log).
    pub name: String,
    /// When the action starts.
    pub trigger: TriggerSpec,
    /// What the vehicle does.
    pub action: ActionSpec,
    /// Fire again each time the trigger holds after the action ended (default: once).
    #[serde(default, skip_serializing_if = "is_false")]
    pub repeat: bool,
    /// With `repeat`, how many times the action runs at most, in all (at least 2; default:
    /// no limit): OpenSCENARIO's `maximumExecutionCount`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schemars(range(min = 2))]
    pub max_runs: Option<u32>,
}

/// For `skip_serializing_if`: a flag written only when on.
pub(crate) fn is_false(b: &bool) -> bool {
    !*b
}

/// Which side of its threshold a trigger's value must be on.
#[derive(Copy, Clone, Debug, PartialEq, Eq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum Rule {
    /// At most the threshold (the default for gaps, time gaps and times to collision).
    Less,
    /// At least the threshold (the default for time and distance).
    Greater,
    /// Within [`EQUAL_TOLERANCE`] of the threshold (in the value's unit).
    Equal,
    /// Farther than [`EQUAL_TOLERANCE`] from the threshold.
    NotEqual,
}

impl Rule {
    /// Whether `value` meets this rule against `threshold`.
    pub fn holds(self, value: f64, threshold: f64) -> bool {
        match self {
            Rule::Less => value <= threshold,
            Rule::Greater => value >= threshold,
            Rule::Equal => (value - threshold).abs() <= EQUAL_TOLERANCE,
            Rule::NotEqual => (value - threshold).abs() > EQUAL_TOLERANCE,
        }
    }
}

/// A point on the road a vehicle is to reach: on lane `lane`'s centre line, `offset_m` to
/// its left, at station `station_m` along the route (OpenSCENARIO's
/// `ReachPositionCondition`).
///
/// ```toml
/// trigger = { reach = { station_m = 150.0, lane = 1, tolerance_m = 2.0 } }
/// ```
///
/// The distance to it is measured in the road's frame, √(Δstation² + Δlateral²) between
/// the point and the vehicle's reference point (its rear axle): on a straight road the
/// distance on the ground, on a curve the distance along and across the lanes.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ReachSpec {
    /// The point's station along the route, m.
    #[schemars(extend("minimum" = 0.0, "maximum" = 1e7))]
    pub station_m: f64,
    /// The lane whose centre line the point is on (1 = the lane next to the centre line).
    #[schemars(extend("minimum" = 1, "maximum" = 16))]
    pub lane: u32,
    /// The point's offset to the left of the lane's centre, m (default 0).
    #[serde(default, skip_serializing_if = "is_zero")]
    #[schemars(extend("minimum" = -20.0, "maximum" = 20.0))]
    pub offset_m: f64,
    /// How near the vehicle must come to the point, m.
    #[schemars(extend("exclusiveMinimum" = 0.0, "maximum" = 1e4))]
    pub tolerance_m: f64,
}

/// For `skip_serializing_if`: a value written only when not 0.
fn is_zero(v: &f64) -> bool {
    *v == 0.0
}

/// When an event's action starts: exactly one of `time_s`, `distance_m`, `gap_m`,
/// `spacing_m`, `time_gap_s`, `ttc_s`, `speed_mps`, `relative_speed_mps`, `standstill_s`,
/// `road_end_s`, `reach`, `after`, `started`, `contact`, `all` and `any`, evaluated at every physics step on level (it fires at the
/// first step its condition holds, not only when it becomes true), or with `rising` or
/// `falling` on its edges.
///
/// ```toml
/// trigger = { time_s = 8.0 }                   # simulation time ≥ 8 s
/// trigger = { distance_m = 120.0 }             # this vehicle has travelled ≥ 120 m
/// trigger = { gap_m = 12.0, to = "chase" }     # gap to `chase` ≤ 12 m
/// trigger = { spacing_m = 30.0, to = "chase" }  # rear axle to rear axle ≤ 30 m
/// trigger = { time_gap_s = 1.5, to = "lead" }  # gap ÷ speed of the one behind ≤ 1.5 s
/// trigger = { ttc_s = 3.0, to = "stopped" }    # gap ÷ closing speed ≤ 3 s, while closing
/// trigger = { time_gap_s = 1.5, to = "lead", between_axles = true }  # spacing ÷ speed ≤ 1.5 s
/// trigger = { speed_mps = 5.0, of = "lead" }   # the lead's speed ≤ 5 m/s
/// trigger = { speed_mps = 20.0, rule = "greater" }  # this vehicle's speed ≥ 20 m/s
/// trigger = { standstill_s = 2.0, of = "van" }  # `van` has stood still for ≥ 2 s
/// trigger = { road_end_s = 2.5, of = "lead" }  # the lead has been at the road's end ≥ 2.5 s
/// trigger = { relative_speed_mps = 3.0, to = "lead", rule = "greater" }  # ≥ 3 m/s faster
/// trigger = { reach = { station_m = 150.0, lane = 1, tolerance_m = 2.0 } }  # within 2 m
/// trigger = { time_s = 5.0, rule = "equal" }   # exactly at 5 s (see `EQUAL_TOLERANCE`)
/// trigger = { after = "cut-in", delay_s = 0.5 }  # 0.5 s after `cut-in`'s action ended
/// trigger = { started = "cut-in", delay_s = 1.0 }  # 1 s after `cut-in`'s action started
/// trigger = { contact = true, to = "chase" }    # while this vehicle touches `chase`
/// trigger = { all = [{ time_s = 5.0 }, { gap_m = 20.0, to = "chase" }] }  # both at once
/// trigger = { any = [{ time_s = 20.0 }, { ttc_s = 2.0, to = "chase" }] }  # either
/// trigger = { all = [{ gap_m = 30.0, to = "chase", latched = true }, { time_gap_s = 1.0, to = "chase" }] }
///                                              # a time gap ≤ 1 s, once the gap was ≤ 30 m
/// ```
///
/// The gap to the vehicle `to` is measured along the road, whatever the lanes, from the
/// rear bumper of whichever is ahead to the front bumper of the other; the spacing, along
/// the road too, between the two vehicles' reference points (the middles of their rear
/// axles). A time gap or a time to collision is measured on the gap, or with
/// `between_axles` on the spacing (OpenSCENARIO's `freespace="false"`).
///
/// `all` and `any` are OpenSCENARIO's condition groups: a list of triggers (members),
/// each written as a trigger is, that holds at a step when every one of them (`all`) or
/// at least one (`any`) holds at it. They nest up to [`MAX_TRIGGER_DEPTH`] deep and take no
/// `to`, `of`, `rule` or `delay_s` of their own. A member's `delay_s` is OpenSCENARIO's
/// condition delay: the member holds at a step when its condition held `delay_s` earlier
/// (for the trigger of a whole event, which fires once it holds, that is the same as the
/// action starting `delay_s` after it first holds). A member with `latched` holds from the
/// first step it holds to the run's end: OpenSCENARIO's act start trigger, which starts an
/// act once, whose events wait for their own triggers from then on.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct TriggerSpec {
    /// Simulation time, s.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schemars(extend("minimum" = 0.0, "maximum" = 1e7))]
    pub time_s: Option<f64>,
    /// Distance this vehicle has travelled along the road since the start, m.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schemars(extend("minimum" = 0.0, "maximum" = 1e7))]
    pub distance_m: Option<f64>,
    /// Bumper-to-bumper gap along the road to the vehicle `to`, m.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schemars(extend("minimum" = -1e4, "maximum" = 1e4))]
    pub gap_m: Option<f64>,
    /// Distance along the road between this vehicle's reference point (the middle of its
    /// rear axle) and that of the vehicle `to`, whichever is ahead, m (OpenSCENARIO's
    /// relative distance with `freespace="false"`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schemars(extend("minimum" = 0.0, "maximum" = 1e4))]
    pub spacing_m: Option<f64>,
    /// Time gap to `to`: the gap over the speed of whichever of the two is behind, s
    /// (endless while that one stands still).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schemars(extend("minimum" = 0.0, "maximum" = 1e3))]
    pub time_gap_s: Option<f64>,
    /// Time to collision with `to`: the gap over the speed at which it closes, s. The
    /// condition holds only while the gap is closing, whatever the rule.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schemars(extend("minimum" = 0.0, "maximum" = 1e3))]
    pub ttc_s: Option<f64>,
    /// Speed along the road of the vehicle `of` (default: this vehicle), m/s.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schemars(extend("minimum" = 0.0, "maximum" = 40.0))]
    pub speed_mps: Option<f64>,
    /// This vehicle's speed less the speed of the vehicle `to`, both along the road, m/s
    /// (positive while this one is the faster).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schemars(extend("minimum" = -40.0, "maximum" = 40.0))]
    pub relative_speed_mps: Option<f64>,
    /// A point the vehicle `of` (default: this vehicle) reaches: holds while it is within
    /// the point's `tolerance_m`. Takes no `rule`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub reach: Option<ReachSpec>,
    /// How long the vehicle `of` (default: this vehicle) has stood still without a break,
    /// s: holds once its speed has stayed below 0.05 m/s this long (a duration of 0 holds at
    /// the first step it stands). Takes no `rule`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schemars(extend("minimum" = 0.0, "maximum" = 1e3))]
    pub standstill_s: Option<f64>,
    /// How long the vehicle `of` (default: this vehicle) has been at the road's end without
    /// a break, s: holds once its reference point has stayed within [`ROAD_END_M`] of the
    /// end this long (a driver stops 2 m before it; a duration of 0 holds at the first
    /// step there). OpenSCENARIO's `EndOfRoadCondition`. Takes no `rule`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schemars(extend("minimum" = 0.0, "maximum" = 1e3))]
    pub road_end_s: Option<f64>,
    /// The name of another of this vehicle's events: holds once that event's action has
    /// ended.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub after: Option<String>,
    /// The name of another of this vehicle's events: holds once that event's action has
    /// started (OpenSCENARIO's wait for an event's `startTransition`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub started: Option<String>,
    /// Holds while this vehicle's body touches the vehicle `to`'s (OpenSCENARIO's
    /// `CollisionCondition`). Takes no `rule`.
    #[serde(default, skip_serializing_if = "is_false")]
    pub contact: bool,
    /// Holds when every one of these triggers holds (OpenSCENARIO's `ConditionGroup`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub all: Option<Vec<TriggerSpec>>,
    /// Holds when at least one of these triggers holds (OpenSCENARIO's several condition
    /// groups).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub any: Option<Vec<TriggerSpec>>,
    /// The vehicle a gap, time gap, time to collision or relative speed is measured to (a
    /// name the scenario gives).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub to: Option<String>,
    /// The vehicle whose speed, standstill or position is watched (a name the scenario
    /// gives; default: this vehicle). Only for `speed_mps`, `standstill_s`, `road_end_s`
    /// and `reach`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub of: Option<String>,
    /// Which side of the threshold holds: `less` (at most; the default for gaps and
    /// times) or `greater` (at least; the default for `time_s` and `distance_m`), or
    /// `equal` / `not_equal` (within / farther than [`EQUAL_TOLERANCE`] of it, in its
    /// unit). Not for `after`, `standstill_s`, `road_end_s` nor `reach`; `less` is the
    /// default for `speed_mps` and `relative_speed_mps`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rule: Option<Rule>,
    /// The action starts this long after the condition first holds, s (default 0).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schemars(extend("minimum" = 0.0, "maximum" = 1e7))]
    pub delay_s: Option<f64>,
    /// Holds only at the step its condition (after its `delay_s`) starts to hold, not at
    /// the step before (at the first step: if it holds): OpenSCENARIO's
    /// `conditionEdge="rising"`. So an event with `repeat` fires again only once the
    /// condition has stopped holding and holds again. On `all` and `any`: the edge of the
    /// group's value.
    #[serde(default, skip_serializing_if = "is_false")]
    pub rising: bool,
    /// Holds only at the step its condition (after its `delay_s`) stops holding, having
    /// held at the step before (never at the first step): OpenSCENARIO's
    /// `conditionEdge="falling"`; with `rising` too, at either edge (`risingOrFalling`).
    #[serde(default, skip_serializing_if = "is_false")]
    pub falling: bool,
    /// Once it holds (after its `delay_s` and edges), holds at every step after: a latch,
    /// for a member of `all` or `any` only (an event's own trigger fires once it holds).
    /// OpenSCENARIO's act start trigger: an act, once started, stays started, and its
    /// events wait for their own triggers from then on (`all = [{ ..., latched = true },
    /// the event's own trigger]`).
    #[serde(default, skip_serializing_if = "is_false")]
    pub latched: bool,
    /// With `time_gap_s` or `ttc_s`: measured on the spacing between the two vehicles'
    /// reference points (the middles of their rear axles), not on the gap between their
    /// bumpers (OpenSCENARIO's `freespace="false"`; default false).
    #[serde(default, skip_serializing_if = "is_false")]
    pub between_axles: bool,
    /// With `time_gap_s`: the side of `to` this vehicle must be on for the condition to
    /// hold, `behind` (`to` ahead, the time gap over this vehicle's speed) or `ahead` (over
    /// `to`'s); `either`, the default, takes whichever is behind. OpenSCENARIO's headway
    /// is measured only towards a vehicle ahead of the one that measures it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub side: Option<KeepSide>,
}

impl TriggerSpec {
    /// Calls `visit` with this trigger and each member of its `all` or `any`, at any depth,
    /// each with its field (`path`, `path.all[0]`, `path.all[0].any[1]`, ...), this first.
    pub fn walk<'a>(&'a self, path: &str, visit: &mut impl FnMut(&str, &'a TriggerSpec)) {
        visit(path, self);
        for (kind, members) in [("all", &self.all), ("any", &self.any)] {
            for (k, m) in members.iter().flatten().enumerate() {
                m.walk(&format!("{path}.{kind}[{k}]"), visit);
            }
        }
    }
}

/// How an action moves between its start and its end.
#[derive(Copy, Clone, Debug, PartialEq, Eq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum Shape {
    /// At a constant rate (speed actions; the default for them).
    Linear,
    /// Smoothstep 3u² − 2u³: no jump in rate at either end (the default for lane changes).
    Cubic,
    /// (1 − cos πu) / 2 (lane changes).
    Sinusoidal,
    /// At once (speed actions; no duration).
    Step,
}

/// What an event does: exactly one of `lane`, `offset_m`, `speed_mps`, `profile`, `stop`,
/// `keep` and `end_run`, with its timing.
///
/// ```toml
/// action = { lane = 2, duration_s = 3.0 }                   # shape cubic (default) or sinusoidal
/// action = { lane = 1, lateral_speed_mps = 1.0, shape = "sinusoidal" }
/// action = { speed_mps = 8.0, rate_mps2 = 2.0 }             # linear at 2 m/s²
/// action = { speed_mps = 8.0, duration_s = 3.0, shape = "cubic" }  # linear (default) or cubic
/// action = { speed_mps = 0.0, shape = "step" }              # at once: the hardest braking
/// action = { stop = true, decel_mps2 = 4.0 }                # to a standstill at 4 m/s², held
/// action = { offset_m = 0.8, lateral_accel_mps2 = 0.5 }     # 0.8 m left of the lane's centre
/// action = { offset_m = -0.5, lateral_accel_mps2 = 1.0, shape = "sinusoidal" }
/// action = { profile = [{ speed_mps = 15.0, duration_s = 2.0 }, { speed_mps = 5.0, rate_mps2 = 2.0 }] }
/// action = { keep = { time_gap_s = 1.5, to = "lead" } }     # 1.5 s behind the lead, kept
/// action = { end_run = true }                               # the run ends here
/// ```
///
/// Lanes are numbered 1, 2, … from the road's centre line outward, lane k centred
/// (k − 0.5) lane widths to the right of it. A lane change moves the vehicle from where it
/// is asked to be to the centre of lane `lane`, over `duration_s` or at an average
/// `lateral_speed_mps`. A speed action changes the speed from the vehicle's speed when it
/// starts to `speed_mps`, and the vehicle keeps that speed afterwards: the profile no longer
/// applies. A stop is a speed action to 0 at `decel_mps2`. An action ends when its
/// reference reaches its end (a stop's, when the speed asked reaches 0), which is what an
/// `after` trigger waits for. An offset moves the vehicle across its lane (the lane it
/// started in, or the last lane change's), to `offset_m` left of the lane's centre
/// (OpenSCENARIO's `LaneOffsetAction`), its shape `cubic` or `sinusoidal` taking the time
/// that makes its peak lateral acceleration `lateral_accel_mps2` (the standard's
/// `maxLateralAcc`); it holds until another lateral action, and a lane change ends on its
/// lane's centre. A profile is speed changes one after another, each linear to its
/// `speed_mps` over its `duration_s` (0: at once) or at its `rate_mps2`, the first from the
/// vehicle's speed when it starts, each next from the speed the one before reached
/// (OpenSCENARIO's `SpeedProfileAction`, `followingMode="position"`); it ends when its last
/// change does.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ActionSpec {
    /// Change to this lane (1 = the lane next to the centre line).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schemars(extend("minimum" = 1, "maximum" = 16))]
    pub lane: Option<u32>,
    /// Move to this offset from the lane's centre, m (positive left).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schemars(extend("minimum" = -20.0, "maximum" = 20.0))]
    pub offset_m: Option<f64>,
    /// Change speed to this, m/s; with `speed_of`, to that vehicle's speed plus this (which
    /// may then be negative).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schemars(extend("minimum" = 0.0, "maximum" = 40.0))]
    pub speed_mps: Option<f64>,
    /// Change speed to that of the vehicle named (a name the scenario gives), plus
    /// `speed_mps` or times `speed_factor`, as it is when the change starts (OpenSCENARIO's
    /// `RelativeTargetSpeed`); with `continuous`, kept to it after.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub speed_of: Option<String>,
    /// With `speed_of`, instead of `speed_mps`: change speed to this times that vehicle's
    /// speed (0–10).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schemars(extend("minimum" = 0.0, "maximum" = 10.0))]
    pub speed_factor: Option<f64>,
    /// With `speed_of`: once changed, keep to the relative speed as that vehicle's speed
    /// changes, until another speed action starts (OpenSCENARIO's `continuous="true"`;
    /// default false: the change ends at the speed it reached).
    #[serde(default, skip_serializing_if = "is_false")]
    pub continuous: bool,
    /// Change speed along these changes, one after another.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub profile: Option<Vec<ProfileEntry>>,
    /// Stop (must be `true`), at `decel_mps2`, and stand still.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub stop: Option<bool>,
    /// End the run (must be `true`): the scenario's end when its trigger holds, before
    /// `duration_s` (OpenSCENARIO's `StopTrigger`). The frame whose physics step it starts
    /// at is the run's last; the outputs cover the run up to there, and `summary.json`'s
    /// `ended_by` names the event.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub end_run: Option<bool>,
    /// How long a lane change or speed change takes, s.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schemars(extend("exclusiveMinimum" = 0.0, "maximum" = 1e7))]
    pub duration_s: Option<f64>,
    /// A lane change's average lateral speed, m/s (instead of `duration_s`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schemars(extend("exclusiveMinimum" = 0.0, "maximum" = 10.0))]
    pub lateral_speed_mps: Option<f64>,
    /// An offset's peak lateral acceleration, m/s² (what sets its pace).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schemars(extend("exclusiveMinimum" = 0.0, "maximum" = 20.0))]
    pub lateral_accel_mps2: Option<f64>,
    /// A speed change's constant rate, m/s² (instead of `duration_s`; linear).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schemars(extend("exclusiveMinimum" = 0.0, "maximum" = 20.0))]
    pub rate_mps2: Option<f64>,
    /// A stop's deceleration, m/s².
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schemars(extend("exclusiveMinimum" = 0.0, "maximum" = 20.0))]
    pub decel_mps2: Option<f64>,
    /// How the change is made: `cubic` or `sinusoidal` for lane changes, `linear`,
    /// `cubic` or `step` for speed changes.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub shape: Option<Shape>,
    /// Keep a gap to another vehicle (OpenSCENARIO's `LongitudinalDistanceAction`): a speed
    /// action that steers this vehicle's speed to hold the gap, within its limits.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub keep: Option<KeepSpec>,
}

/// A gap kept to another vehicle, as a speed action: exactly one of `gap_m` and
/// `time_gap_s`, to the vehicle `to`.
///
/// ```toml
/// action = { keep = { gap_m = 20.0, to = "lead" } }   # 20 m behind the lead, kept
/// action = { keep = { time_gap_s = 1.5, to = "chase", side = "ahead", continuous = false } }
/// ```
///
/// The speed asked is the other vehicle's speed plus [`KEEP_GAIN_PER_S`] times the gap's
/// error (less, ahead of it), reached through a lag of [`KEEP_LAG_S`] within the
/// acceleration, deceleration, jerk and speed limits: the gap settles without overshoot
/// (the two make the loop critically damped) unless a limit binds. The standard leaves
/// these dynamics to the simulator. With `continuous = false` the action ends once the gap
/// is within [`KEEP_REACHED_M`] and the speeds within [`KEEP_REACHED_MPS`] of each other,
/// and the vehicle keeps the speed it has; with `true` (the default) it keeps the gap until
/// another speed action starts.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct KeepSpec {
    /// The vehicle the gap is kept to (a name the scenario gives).
    pub to: String,
    /// The gap, m: bumper to bumper along the road, or with `between_axles` between the two
    /// reference points.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schemars(extend("minimum" = 0.0, "maximum" = 1e4))]
    pub gap_m: Option<f64>,
    /// The time gap, s: the gap over the speed of whichever of the two is behind.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schemars(extend("minimum" = 0.0, "maximum" = 1e3))]
    pub time_gap_s: Option<f64>,
    /// Measure between the reference points (OpenSCENARIO's `freespace="false"`).
    #[serde(default, skip_serializing_if = "is_false")]
    pub between_axles: bool,
    /// Which side of `to` this vehicle keeps the gap on: `behind` (the default; the
    /// standard's `trailingReferencedEntity`), `ahead` (`leadingReferencedEntity`) or
    /// `either` (`any`: the side it is on when the action starts).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub side: Option<KeepSide>,
    /// Keep the gap until another speed action starts (default true), or end once reached.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub continuous: Option<bool>,
    /// The largest acceleration, m/s² (default [`KEEP_MAX_ACCEL_MPS2`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schemars(extend("exclusiveMinimum" = 0.0, "maximum" = 20.0))]
    pub max_accel_mps2: Option<f64>,
    /// The largest deceleration, m/s² (default [`KEEP_MAX_DECEL_MPS2`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schemars(extend("exclusiveMinimum" = 0.0, "maximum" = 20.0))]
    pub max_decel_mps2: Option<f64>,
    /// The largest rate of change of the acceleration, m/s³ (default: none).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schemars(extend("exclusiveMinimum" = 0.0, "maximum" = 1e3))]
    pub max_jerk_mps3: Option<f64>,
    /// The highest speed, m/s (default 40, the most any speed may be).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schemars(extend("exclusiveMinimum" = 0.0, "maximum" = 40.0))]
    pub max_speed_mps: Option<f64>,
}

/// Which side of the other vehicle a kept gap is on, or a time-gap trigger holds on.
#[derive(Copy, Clone, Debug, PartialEq, Eq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum KeepSide {
    /// Behind it.
    Behind,
    /// Ahead of it.
    Ahead,
    /// Either: a kept gap on the side it is on when the action starts, a trigger on
    /// whichever side it is.
    Either,
}

/// How strongly a kept gap's error sets the speed asked, per second (see [`KeepSpec`]).
pub const KEEP_GAIN_PER_S: f64 = 0.5;
/// The lag through which the speed asked is reached, s: with [`KEEP_GAIN_PER_S`], `4 · lag ·
/// gain = 1`, critically damped.
pub const KEEP_LAG_S: f64 = 0.5;
/// A kept gap's default largest acceleration, m/s².
pub const KEEP_MAX_ACCEL_MPS2: f64 = 4.0;
/// A kept gap's default largest deceleration, m/s².
pub const KEEP_MAX_DECEL_MPS2: f64 = 8.0;
/// How near the gap counts as reached, m (a time gap too: its gap at the speed behind).
pub const KEEP_REACHED_M: f64 = 0.25;
/// How near the speeds count as matched, m/s.
pub const KEEP_REACHED_MPS: f64 = 0.25;

/// One change of a speed profile action: linear to `speed_mps`, over `duration_s` or at
/// `rate_mps2` (exactly one).
///
/// ```toml
/// { speed_mps = 15.0, duration_s = 2.0 }
/// ```
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ProfileEntry {
    /// The speed this change reaches, m/s.
    #[schemars(extend("minimum" = 0.0, "maximum" = 40.0))]
    pub speed_mps: f64,
    /// How long it takes, s (0: at once).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schemars(extend("minimum" = 0.0, "maximum" = 1e7))]
    pub duration_s: Option<f64>,
    /// Its constant rate, m/s².
    #[serde(default, skip_serializing_if = "Option::is_none")]
    #[schemars(extend("exclusiveMinimum" = 0.0, "maximum" = 20.0))]
    pub rate_mps2: Option<f64>,
}

/// The most changes a speed profile action holds.
pub const MAX_PROFILE_ENTRIES: usize = 256;

impl Shape {
    /// The shape's name as a scenario file writes it.
    pub fn name(self) -> &'static str {
        match self {
            Shape::Linear => "linear",
            Shape::Cubic => "cubic",
            Shape::Sinusoidal => "sinusoidal",
            Shape::Step => "step",
        }
    }

    /// How long this shape takes to make a change of `change` (> 0) whose second
    /// derivative peaks at `peak` (> 0), s: cubic 6 change / T², sinusoidal
    /// π² change / (2 T²); the others, which have no finite peak, at once.
    pub(crate) fn time_at_peak_accel(self, change: f64, peak: f64) -> f64 {
        match self {
            Shape::Cubic => (6.0 * change / peak).sqrt(),
            Shape::Sinusoidal => std::f64::consts::PI * (change / (2.0 * peak)).sqrt(),
            Shape::Linear | Shape::Step => 0.0,
        }
    }

    /// How far along the change is at `u` in [0, 1] (0 at the start, 1 at the end), and
    /// its derivative by `u`.
    pub(crate) fn at(self, u: f64) -> (f64, f64) {
        match self {
            Shape::Linear => (u, 1.0),
            Shape::Cubic => (u * u * (3.0 - 2.0 * u), 6.0 * u * (1.0 - u)),
            Shape::Sinusoidal => {
                let pi = std::f64::consts::PI;
                (0.5 * (1.0 - (pi * u).cos()), 0.5 * pi * (pi * u).sin())
            }
            Shape::Step => (1.0, 0.0),
        }
    }
}

/// What a checked trigger measures.
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum Condition {
    /// Simulation time, s.
    Time(f64),
    /// Distance travelled, m.
    Distance(f64),
    /// Gap to a vehicle, m.
    Gap(f64, String),
    /// Distance between this vehicle's reference point and a vehicle's, m.
    Spacing(f64, String),
    /// Time gap to a vehicle, s, on the gap or (`true`) the spacing, with this vehicle on
    /// the side of it given (`Either`: any).
    TimeGap(f64, String, bool, KeepSide),
    /// Time to collision with a vehicle, s, on the gap or (`true`) the spacing.
    Ttc(f64, String, bool),
    /// The speed of a vehicle (empty: this one), m/s.
    Speed(f64, String),
    /// How long a vehicle (empty: this one) has stood still, s.
    Standstill(f64, String),
    /// How long a vehicle (empty: this one) has been at the road's end, s.
    RoadEnd(f64, String),
    /// This vehicle's speed less a vehicle's, m/s.
    RelativeSpeed(f64, String),
    /// A vehicle (empty: this one) within reach of a point.
    Reach(ReachSpec, String),
    /// Another event (its index) has ended.
    After(usize),
    /// Another event (its index) has started.
    Started(usize),
    /// This vehicle touches a vehicle.
    Contact(String),
    /// Every member holds.
    All(Vec<Trigger>),
    /// At least one member holds.
    Any(Vec<Trigger>),
}

/// A checked trigger.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Trigger {
    pub(crate) condition: Condition,
    /// The comparison (`Greater`, unused, for `after`, `all` and `any`).
    pub(crate) rule: Rule,
    /// For an event's trigger, how long after it first holds its action starts; for a
    /// member of `all` or `any`, how long ago its condition must have held, s.
    pub(crate) delay_s: f64,
    /// Holds only at the step its condition starts to hold.
    pub(crate) rising: bool,
    /// Holds only at the step its condition stops holding (with `rising`: at either).
    pub(crate) falling: bool,
    /// Once it holds, holds at every step after (members only).
    pub(crate) latched: bool,
}

/// How long a change takes.
#[derive(Copy, Clone, Debug, PartialEq)]
pub(crate) enum Timing {
    /// Over this many seconds.
    Duration(f64),
    /// At this average rate (m/s for lane changes, m/s² for speed), whatever the change.
    Rate(f64),
    /// With this peak rate of the rate of change, m/s² (an offset's lateral
    /// acceleration): the time the shape takes to make the change with that peak.
    PeakAccel(f64),
}

/// A checked action.
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum Action {
    /// To the centre of this lane.
    Lane {
        lane: u32,
        timing: Timing,
        shape: Shape,
    },
    /// To this offset left of the lane's centre, m.
    Offset {
        offset_m: f64,
        timing: Timing,
        shape: Shape,
    },
    /// To this speed, m/s (a stop is one to 0 at its deceleration); with `relative`, to a
    /// vehicle's speed plus this, or times it.
    Speed {
        speed_mps: f64,
        timing: Timing,
        shape: Shape,
        relative: Option<RelativeSpeed>,
    },
    /// Linear to each speed in turn, m/s, each with its timing.
    Profile(Vec<(f64, Timing)>),
    /// A gap kept to a vehicle.
    Keep(Keep),
    /// The run's end: starts and ends at once, moving nothing.
    EndRun,
}

/// A checked kept gap ([`KeepSpec`]).
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Keep {
    pub(crate) to: String,
    /// The gap, m, or (`time`) the time gap, s.
    pub(crate) value: f64,
    pub(crate) time: bool,
    pub(crate) axles: bool,
    pub(crate) side: KeepSide,
    pub(crate) continuous: bool,
    pub(crate) max_accel_mps2: f64,
    pub(crate) max_decel_mps2: f64,
    pub(crate) max_jerk_mps3: Option<f64>,
    pub(crate) max_speed_mps: f64,
}

/// A speed change's target relative to another vehicle's speed.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct RelativeSpeed {
    /// The vehicle's name.
    pub(crate) of: String,
    /// Whether the change's value is a factor (else a difference, m/s).
    pub(crate) factor: bool,
    /// Whether the speed is kept relative after the change.
    pub(crate) continuous: bool,
}

/// A checked event.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Checked {
    pub(crate) name: String,
    pub(crate) trigger: Trigger,
    pub(crate) action: Action,
    /// How many times the action may run: `Some(1)` once, `None` with no limit.
    pub(crate) max_runs: Option<u32>,
}

/// An [`VehicleError::InvalidEvent`] for `events[i].<path>`.
fn invalid(i: usize, path: &str, reason: String) -> VehicleError {
    VehicleError::InvalidEvent {
        field: format!("events[{i}].{path}"),
        reason,
    }
}

/// Checks that `value` is finite and within `[min, max]` (above `min` when `open`).
fn check(
    i: usize,
    path: &str,
    value: f64,
    min: f64,
    max: f64,
    open: bool,
) -> Result<f64, VehicleError> {
    let above = if open { value > min } else { value >= min };
    if value.is_finite() && above && value <= max {
        Ok(value)
    } else {
        let low = if open { "above" } else { "at least" };
        Err(invalid(
            i,
            path,
            format!("= {value}: must be finite, {low} {min} and at most {max}"),
        ))
    }
}

impl EventScript {
    /// Checks every event: names unique and not empty; each trigger exactly one condition,
    /// `to` given for (and only for) gaps, time gaps and times to collision, `after` naming
    /// another of these events, values finite and in range; each action exactly one of
    /// `lane`, `speed_mps` and `stop` with the timing and shape it takes. The names of
    /// vehicles (`to`) and the lanes are checked by the caller, who knows the scenario:
    /// see [`EventScript::vehicles_named`] and [`EventScript::lanes_named`].
    pub fn validate(&self) -> Result<(), VehicleError> {
        self.checked().map(|_| ())
    }

    /// Whether there are no events.
    pub fn is_empty(&self) -> bool {
        self.0.is_empty()
    }

    /// The vehicles the triggers measure to or watch, each with its field
    /// (`events[2].trigger.to`, `events[3].trigger.all[1].of`), in the order written, for
    /// the caller to check against the scenario's vehicles.
    pub fn vehicles_named(&self) -> impl Iterator<Item = (String, &str)> {
        let mut out = Vec::new();
        for (i, e) in self.0.iter().enumerate() {
            e.trigger
                .walk(&format!("events[{i}].trigger"), &mut |path, t| {
                    let to = t.to.as_deref().map(|to| (format!("{path}.to"), to));
                    let of = t.of.as_deref().map(|of| (format!("{path}.of"), of));
                    out.extend(to.into_iter().chain(of));
                });
        }
        out.into_iter()
    }

    /// The lanes the reach points are on and the lane changes go to, each with its field
    /// (`events[0].trigger.reach.lane`, `events[1].action.lane`), in
    /// the order written, for the caller to check against the road's lanes.
    pub fn lanes_named(&self) -> impl Iterator<Item = (String, u32)> + '_ {
        let mut out = Vec::new();
        for (i, e) in self.0.iter().enumerate() {
            e.trigger
                .walk(&format!("events[{i}].trigger"), &mut |path, t| {
                    if let Some(r) = &t.reach {
                        out.push((format!("{path}.reach.lane"), r.lane));
                    }
                });
            if let Some(lane) = e.action.lane {
                out.push((format!("events[{i}].action.lane"), lane));
            }
        }
        out.into_iter()
    }

    /// The events checked into the engine's form.
    pub(crate) fn checked(&self) -> Result<Vec<Checked>, VehicleError> {
        for (i, e) in self.0.iter().enumerate() {
            if e.name.trim().is_empty() {
                return Err(invalid(i, "name", "must not be empty".into()));
            }
            if let Some(j) = self.0[..i].iter().position(|o| o.name == e.name) {
                return Err(invalid(
                    i,
                    "name",
                    format!("\"{}\" is already the name of events[{j}]", e.name),
                ));
            }
        }
        self.0
            .iter()
            .enumerate()
            .map(|(i, e)| {
                let max_runs = match (e.repeat, e.max_runs) {
                    (false, None) => Some(1),
                    (true, None) => None,
                    (true, Some(n)) if n >= 2 => Some(n),
                    (true, Some(n)) => {
                        return Err(invalid(i, "max_runs", format!("= {n}: must be at least 2")))
                    }
                    (false, Some(_)) => {
                        return Err(invalid(i, "max_runs", "needs `repeat = true`".into()))
                    }
                };
                Ok(Checked {
                    name: e.name.clone(),
                    trigger: self.trigger(i, "trigger", &e.trigger, 0)?,
                    action: action(i, &e.action)?,
                    max_runs,
                })
            })
            .collect()
    }
}
