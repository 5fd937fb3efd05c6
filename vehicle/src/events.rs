//! The event engine: one vehicle's scripted events ([`EventScript`]) run against the
//! traffic at every physics step, giving the speed and the lateral offset its driver is to
//! follow, and which events started and ended.
//!
//! At each step, in this order:
//! 1. every event waiting for its trigger whose condition holds now (on level; with
//!    `rising`, only if it did not at the step before; with `falling`, if it holds no longer
//!    and did at the step before) is armed to start `delay_s` later;
//! 2. every event whose start has come starts its action: a speed action replaces the
//!    running speed action (which ends there), a lane change the running lane change;
//! 3. every action that has reached its end ends; an event with `repeat` waits for its
//!    trigger again from the next step, the others are done.
//!
//! An `after` trigger sees the actions ended at earlier steps, a `started` trigger those
//! started at earlier steps. A trigger of several
//! conditions (`all`, `any`) is evaluated at every step, whatever its event's phase, so that
//! a member with a delay answers from its condition's history that long ago. All times are whole steps
//! (`docs/src/conventions.md`, "One clock"): a duration or delay is rounded to the step.

use crate::clock::{Step, PHYSICS_HZ};
use crate::error::{check_range, VehicleError};
use crate::event_spec::{
    Action, Checked, Condition, EventScript, KeepSide, Shape, Timing, Trigger,
};
use crate::lead_driver::SpeedOverride;
use keep::KeepState;
use std::collections::VecDeque;

mod keep;

/// Below this speed a vehicle stands still, m/s (for standstill triggers): a physics
/// vehicle held by its brakes creeps at millimetres per second as its tyres settle, and
/// 5 cm/s (0.18 km/h) is below what wheel-speed sensors resolve, about 0.1 m/s.
pub const STANDSTILL_MPS: f64 = 0.05;

/// How near the road's end a vehicle's reference point counts as at it, m (for road end
/// triggers): a driver stops 2 m before the end of its route.
pub const ROAD_END_M: f64 = 5.0;

/// One vehicle of the traffic as the triggers see it: positions along the road (the
/// caller's measure of it, the same for every vehicle), metres.
#[derive(Copy, Clone, Debug, Default, PartialEq)]
pub struct VehicleView {
    /// Where the vehicle is along the road (its reference point, e.g. the rear axle), m.
    pub station_m: f64,
    /// Its lateral offset from lane 1's centre, m (positive left).
    pub left_offset_m: f64,
    /// Its speed along the road, m/s.
    pub speed_mps: f64,
    /// Where its front bumper is along the road, m.
    pub front_m: f64,
    /// Where its rear bumper is along the road, m.
    pub rear_m: f64,
    /// The vehicles its body touches, a bit each by their index in the view (bit `j`:
    /// vehicle `j`; none beyond 63), for contact triggers: the caller sets those of the
    /// pairs [`Events::contacts_watched`] asks for, and may leave the others clear.
    pub touching: u64,
}

/// The traffic at one step: every vehicle, by the index the caller gave its name in
/// [`Events::new`].
pub type TrafficView = [VehicleView];

/// The road's lanes as one vehicle's events need them.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct Lanes {
    /// Width of each lane, m.
    pub width_m: f64,
    /// How many lanes the vehicle's side of the road has (lanes 1..=count).
    pub count: u32,
    /// The lane whose centre the vehicle's route runs along: lane k's centre is
    /// `(route_lane − k) × width_m` to the left of the route when the lanes are of one
    /// width.
    pub route_lane: u32,
    /// Each lane's own width, m, lane 1 first (the first `count` read), when they differ;
    /// `None`: every lane is `width_m` wide.
    pub widths_m: Option<[f64; Lanes::MAX]>,
}

impl Lanes {
    /// The most lanes whose own widths [`Lanes::widths_m`] holds.
    pub const MAX: usize = 4;

    /// The left offset from the route of lane `lane`'s centre, m.
    pub fn offset_m(&self, lane: u32) -> f64 {
        match &self.widths_m {
            None => (f64::from(self.route_lane) - f64::from(lane)) * self.width_m,
            Some(w) => {
                // A lane's centre from the inner edge of lane 1: the lanes inside it and
                // half its own.
                let centre = |k: u32| {
                    let k = (k as usize).clamp(1, Lanes::MAX);
                    w[..k - 1].iter().sum::<f64>() + 0.5 * w[k - 1]
                };
                centre(self.route_lane) - centre(lane)
            }
        }
    }
}

/// Whether an event started or ended.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub enum FiredKind {
    /// Its action started.
    Started,
    /// Its action ended: it reached its end, or a newer action of its kind (speed or
    /// lane) replaced it.
    Ended,
}

/// An event that started or ended at a step, for the caller's log.
#[derive(Clone, Debug, PartialEq)]
pub struct Fired {
    /// The step it happened at.
    pub step: Step,
    /// The event's index in the script.
    pub event: usize,
    /// The event's name.
    pub name: String,
    /// Started or ended.
    pub kind: FiredKind,
}

/// Where an event is.
#[derive(Copy, Clone, Debug, PartialEq)]
enum Phase {
    /// Waiting for its trigger.
    Armed,
    /// Triggered; its action starts at this step.
    Pending(Step),
    /// Its action is running.
    Running,
    /// Fired and finished, for good.
    Done,
}

/// One event in the engine.
#[derive(Clone, Debug)]
struct EventState {
    event: Checked,
    /// What its trigger watches, in the shape of the trigger.
    watch: Watch,
    phase: Phase,
    /// How many times its action has run to its end.
    runs: u32,
    /// The vehicle (its index in the view) its speed change is relative to, if any.
    speed_of: Option<usize>,
}

/// The run-time state of one trigger (an event's, or a member of an `all` or `any`), with
/// one `Watch` per member.
#[derive(Clone, Debug, Default)]
struct Watch {
    /// The vehicle a gap trigger measures to.
    to: Option<usize>,
    /// The vehicle a speed or standstill trigger watches (`None`: this one).
    of: Option<usize>,
    /// The step from which the watched vehicle has stood still (standstill triggers), or
    /// has been at the road's end (road end triggers).
    still_since: Option<Step>,
    /// The members' watches, in order (`all` and `any`).
    members: Vec<Watch>,
    /// A delayed member's condition as it changed: the steps at which it turned true or
    /// false, oldest first, those older than its delay dropped but the last.
    turns: VecDeque<(Step, bool)>,
    /// Whether the condition held at the step before (for a rising edge).
    held_before: bool,
    /// Whether a latched member has held (it holds from then on).
    latched_on: bool,
}

/// What a trigger is evaluated against at one step.
struct Now<'a> {
    now: Step,
    view: &'a TrafficView,
    mine: &'a VehicleView,
    start_station_m: f64,
    lanes: Lanes,
    /// Where the road ends, m along it (road end triggers).
    road_end_m: f64,
    /// Whether each of the vehicle's events has ended (for `after`).
    ended: &'a [bool],
    /// Whether each of the vehicle's events has started (for `started`).
    started: &'a [bool],
}

/// The index in `vehicles` of the vehicle `name`, or an error at `field`.
fn vehicle_index(vehicles: &[&str], name: &str, field: String) -> Result<usize, VehicleError> {
    vehicles
        .iter()
        .position(|v| *v == name)
        .ok_or_else(|| VehicleError::InvalidEvent {
            field,
            reason: format!("no vehicle is named \"{name}\""),
        })
}

impl Watch {
    /// The watch of `trigger` at `field` (`events[0].trigger`, ...), with its vehicles
    /// found among `vehicles` and its reach lanes checked against `lanes`.
    fn new(
        trigger: &Trigger,
        field: &str,
        vehicles: &[&str],
        lanes: &Lanes,
    ) -> Result<Watch, VehicleError> {
        let mut watch = Watch::default();
        match &trigger.condition {
            Condition::Gap(_, to)
            | Condition::Spacing(_, to)
            | Condition::TimeGap(_, to, _, _)
            | Condition::Ttc(_, to, _)
            | Condition::RelativeSpeed(_, to)
            | Condition::Contact(to) => {
                watch.to = Some(vehicle_index(vehicles, to, format!("{field}.to"))?);
            }
            Condition::Speed(_, of)
            | Condition::Standstill(_, of)
            | Condition::RoadEnd(_, of)
            | Condition::Reach(_, of)
                if !of.is_empty() =>
            {
                watch.of = Some(vehicle_index(vehicles, of, format!("{field}.of"))?);
            }
            Condition::All(members) | Condition::Any(members) => {
                let kind = match trigger.condition {
                    Condition::All(_) => "all",
                    _ => "any",
                };
                for (k, m) in members.iter().enumerate() {
                    let at = format!("{field}.{kind}[{k}]");
                    watch.members.push(Watch::new(m, &at, vehicles, lanes)?);
                }
            }
            _ => {}
        }
        if let Condition::Reach(r, _) = &trigger.condition {
            if r.lane > lanes.count {
                return Err(VehicleError::InvalidEvent {
                    field: format!("{field}.reach.lane"),
                    reason: format!("= {}: the road has {} lanes", r.lane, lanes.count),
                });
            }
        }
        Ok(watch)
    }

    /// Keeps a standstill trigger's start of standing still at `c`'s step, or a road end
    /// trigger's start at the road's end.
    fn update_still(&mut self, trigger: &Trigger, c: &Now) {
        let watched = || self.of.map_or(Some(c.mine), |j| c.view.get(j));
        let still = match trigger.condition {
            Condition::Standstill(..) => {
                watched().is_some_and(|v| v.speed_mps.abs() < STANDSTILL_MPS)
            }
            Condition::RoadEnd(..) => {
                watched().is_some_and(|v| v.station_m >= c.road_end_m - ROAD_END_M)
            }
            _ => return,
        };
        self.still_since = if still {
            self.still_since.or(Some(c.now))
        } else {
            None
        };
    }

    /// Whether an `all` or `any` trigger holds at `c`'s step, every member evaluated
    /// (so that each delayed member keeps its history and each standstill its start).
    fn group_holds(&mut self, trigger: &Trigger, c: &Now) -> bool {
        let (members, all) = match &trigger.condition {
            Condition::All(m) => (m, true),
            Condition::Any(m) => (m, false),
            _ => return false,
        };
        let mut holds = all;
        for (m, w) in members.iter().zip(&mut self.members) {
            let member = w.member_holds(m, c);
            holds = if all {
                holds && member
            } else {
                holds || member
            };
        }
        holds
    }

    /// Whether the member `trigger` holds at `c`'s step: its condition now, or, with a
    /// delay, `delay_s` ago; with a rising edge, only if it did not at the step before.
    /// A latched member holds from the first step it holds on.
    fn member_holds(&mut self, trigger: &Trigger, c: &Now) -> bool {
        let level = self.member_level(trigger, c);
        let holds = self.edge(trigger, level);
        self.latched_on |= trigger.latched && holds;
        holds || self.latched_on
    }

    /// `level`, the condition of `trigger` at this step, as the trigger holds: with a
    /// rising edge, only if it did not hold at the step before (kept here); with a falling
    /// edge, only if it holds no longer and did at the step before.
    fn edge(&mut self, trigger: &Trigger, level: bool) -> bool {
        if !trigger.rising && !trigger.falling {
            return level;
        }
        let before = std::mem::replace(&mut self.held_before, level);
        (trigger.rising && level && !before) || (trigger.falling && !level && before)
    }

    /// Whether the member `trigger`'s condition holds at `c`'s step: now, or, with a delay,
    /// `delay_s` ago.
    fn member_level(&mut self, trigger: &Trigger, c: &Now) -> bool {
        let now = match &trigger.condition {
            Condition::All(_) | Condition::Any(_) => self.group_holds(trigger, c),
            _ => {
                self.update_still(trigger, c);
                self.holds(trigger, c)
            }
        };
        let delay = steps_of(trigger.delay_s);
        if delay == 0 {
            return now;
        }
        if self.turns.back().map(|t| t.1) != Some(now) {
            self.turns.push_back((c.now, now));
        }
        let Some(then) = c.now.0.checked_sub(delay).map(Step) else {
            return false;
        };
        while self.turns.get(1).is_some_and(|t| t.0 <= then) {
            self.turns.pop_front();
        }
        self.turns
            .front()
            .is_some_and(|&(at, held)| at <= then && held)
    }

    /// Whether the one-condition `trigger` holds now.
    fn holds(&self, trigger: &Trigger, c: &Now) -> bool {
        let rule = trigger.rule;
        let compare = |value: f64, threshold: f64| rule.holds(value, threshold);
        let mine = c.mine;
        let other = self.to.and_then(|j| c.view.get(j));
        match (&trigger.condition, other) {
            (Condition::Time(t), _) => compare(c.now.seconds(), *t),
            (Condition::Distance(d), _) => compare(mine.station_m - c.start_station_m, *d),
            (Condition::After(j), _) => c.ended.get(*j).copied().unwrap_or(false),
            (Condition::Started(j), _) => c.started.get(*j).copied().unwrap_or(false),
            (Condition::Contact(_), _) => self
                .to
                .is_some_and(|j| j < u64::BITS as usize && mine.touching & (1 << j) != 0),
            (Condition::Speed(v, _), _) => self
                .of
                .map_or(Some(mine), |j| c.view.get(j))
                .is_some_and(|w| compare(w.speed_mps, *v)),
            (Condition::Standstill(d, _) | Condition::RoadEnd(d, _), _) => self
                .still_since
                .is_some_and(|since| c.now.since(since) >= steps_of(*d)),
            (Condition::Reach(r, _), _) => {
                self.of
                    .map_or(Some(mine), |j| c.view.get(j))
                    .is_some_and(|w| {
                        let along = w.station_m - r.station_m;
                        // The view's offsets are from lane 1's centre.
                        let from_lane_1 = Lanes {
                            route_lane: 1,
                            ..c.lanes
                        };
                        let across = w.left_offset_m - (from_lane_1.offset_m(r.lane) + r.offset_m);
                        along.hypot(across) <= r.tolerance_m
                    })
            }
            (Condition::All(_) | Condition::Any(_), _) => false,
            (Condition::RelativeSpeed(v, _), Some(o)) => compare(mine.speed_mps - o.speed_mps, *v),
            (Condition::Gap(g, _), Some(o)) => compare(Between::new(mine, o).gap_m, *g),
            (Condition::Spacing(d, _), Some(o)) => {
                compare((mine.station_m - o.station_m).abs(), *d)
            }
            (Condition::TimeGap(t, _, axles, side), Some(o)) => {
                let b = Between::new(mine, o).on_axles(*axles);
                let time_gap = if b.behind_speed_mps > 0.0 {
                    b.gap_m / b.behind_speed_mps
                } else {
                    f64::INFINITY
                };
                let on_side = match side {
                    KeepSide::Behind => mine.station_m < o.station_m,
                    KeepSide::Ahead => mine.station_m > o.station_m,
                    KeepSide::Either => true,
                };
                on_side && compare(time_gap, *t)
            }
            (Condition::Ttc(t, _, axles), Some(o)) => {
                let b = Between::new(mine, o).on_axles(*axles);
                b.closing_mps > 0.0 && compare(b.gap_m / b.closing_mps, *t)
            }
            (_, None) => false,
        }
    }
}

/// A change of one quantity (speed or lateral offset) from `from` to `to` over `steps`.
#[derive(Copy, Clone, Debug, PartialEq)]
struct Motion {
    event: usize,
    start: Step,
    steps: u64,
    from: f64,
    to: f64,
    shape: Shape,
    running: bool,
    /// Which change of a speed profile this is (0 for other actions).
    segment: usize,
    /// A continuous relative speed: its target follows that vehicle's speed, and it runs
    /// until another speed action replaces it.
    follow: Option<Follow>,
}

/// A speed kept relative to another vehicle's ([`Motion::follow`]).
#[derive(Copy, Clone, Debug, PartialEq)]
struct Follow {
    /// The vehicle's index in the view.
    vehicle: usize,
    /// The difference (m/s) or the factor.
    value: f64,
    factor: bool,
}

impl Follow {
    /// The target for the vehicle's speed `v`, m/s.
    fn target(&self, v: f64) -> f64 {
        let t = if self.factor {
            self.value * v
        } else {
            v + self.value
        };
        t.clamp(0.0, f64::from(crate::speed_profile::MAX_SPEED_MPS))
    }
}

/// Whole steps a change from `from` to `to` takes with `timing` and `shape`.
fn steps_for(timing: Timing, from: f64, to: f64, shape: Shape) -> u64 {
    match timing {
        Timing::Duration(d) => steps_of(d),
        Timing::Rate(r) => steps_of((to - from).abs() / r),
        Timing::PeakAccel(a) => steps_of(shape.time_at_peak_accel((to - from).abs(), a)),
    }
}

impl Motion {
    /// Its value at `now` and its rate of change, per second.
    fn at(&self, now: Step) -> (f64, f64) {
        let done = now.since(self.start);
        if done >= self.steps {
            return (self.to, 0.0);
        }
        let u = done as f64 / self.steps as f64;
        let (f, df) = self.shape.at(u);
        let change = self.to - self.from;
        let duration_s = self.steps as f64 / f64::from(PHYSICS_HZ);
        (self.from + change * f, change * df / duration_s)
    }
}

/// One vehicle's events at run time: see the module's doc for what a step does.
#[derive(Clone, Debug)]
pub struct Events {
    events: Vec<EventState>,
    /// Whether each event's action has ended at least once (what `after` waits for).
    ended: Vec<bool>,
    /// Whether each event's action has started at least once (what `started` waits for).
    started: Vec<bool>,
    lanes: Lanes,
    /// The vehicle's station at the first step, m (distance triggers count from it).
    start_station_m: Option<f64>,
    speed: Option<Motion>,
    lateral: Option<Motion>,
    /// The lateral offset from the route before any lateral action, m (positive left).
    base_lateral_m: f64,
    /// The speed and lateral offset the last update asked for.
    speed_now: Option<SpeedOverride>,
    lateral_now_m: f64,
    /// The lane the vehicle is in or changing to (its route's lane until a lane change):
    /// what an offset is from.
    lane_now: u32,
    /// The step at which an `end_run` action first started, and its event.
    run_ended: Option<(Step, usize)>,
    /// The kept gap the speed follows, while one runs: it sets the speed motion's speed
    /// step by step, and runs until reached (not continuous) or until another speed
    /// action replaces it.
    keep: Option<KeepState>,
    /// Where the road ends, m along it (endless until [`Events::with_road_end_m`]).
    road_end_m: f64,
}

/// Whole steps in `seconds`, rounded.
fn steps_of(seconds: f64) -> u64 {
    (seconds * f64::from(PHYSICS_HZ)).round() as u64
}

impl Events {
    /// The engine for `script`, measuring to the vehicles `vehicles` (the names, in the
    /// order of the [`TrafficView`] the updates get) on a road of `lanes`. Checks the
    /// script ([`EventScript::validate`]), that each `to` and `of` names a vehicle and each lane
    /// change a lane of the road.
    pub fn new(
        script: &EventScript,
        vehicles: &[&str],
        lanes: Lanes,
    ) -> Result<Events, VehicleError> {
        check_range("lane_width_m", lanes.width_m, 0.5, 20.0)?;
        if let Some(widths) = &lanes.widths_m {
            check_range("lanes", f64::from(lanes.count), 1.0, Lanes::MAX as f64)?;
            for &w in &widths[..lanes.count as usize] {
                check_range("lane_widths_m", w, 0.5, 20.0)?;
            }
        }
        check_range("lanes", f64::from(lanes.count), 1.0, 16.0)?;
        check_range(
            "route_lane",
            f64::from(lanes.route_lane),
            1.0,
            f64::from(lanes.count),
        )?;
        let checked = script.checked()?;
        let mut events = Vec::with_capacity(checked.len());
        for (i, event) in checked.into_iter().enumerate() {
            let watch = Watch::new(
                &event.trigger,
                &format!("events[{i}].trigger"),
                vehicles,
                &lanes,
            )?;
            let speed_of = match &event.action {
                Action::Speed {
                    relative: Some(r), ..
                } => Some(vehicle_index(
                    vehicles,
                    &r.of,
                    format!("events[{i}].action.speed_of"),
                )?),
                Action::Keep(k) => Some(vehicle_index(
                    vehicles,
                    &k.to,
                    format!("events[{i}].action.keep.to"),
                )?),
                _ => None,
            };
            if let Action::Lane { lane, .. } = event.action {
                if lane > lanes.count {
                    return Err(VehicleError::InvalidEvent {
                        field: format!("events[{i}].action.lane"),
                        reason: format!("= {lane}: the road has {} lanes", lanes.count),
                    });
                }
            }
            events.push(EventState {
                event,
                watch,
                phase: Phase::Armed,
                runs: 0,
                speed_of,
            });
        }
        Ok(Events {
            ended: vec![false; events.len()],
            started: vec![false; events.len()],
            events,
            lanes,
            start_station_m: None,
            speed: None,
            lateral: None,
            base_lateral_m: 0.0,
            speed_now: None,
            lateral_now_m: 0.0,
            lane_now: lanes.route_lane,
            run_ended: None,
            keep: None,
            road_end_m: f64::INFINITY,
        })
    }

    /// The same, for a vehicle that starts `offset_m` to the left of its route's lane
    /// centre (negative: to the right) and keeps that offset until a lateral action moves
    /// it.
    pub fn with_lateral_offset_m(self, offset_m: f64) -> Events {
        Events {
            base_lateral_m: offset_m,
            lateral_now_m: offset_m,
            ..self
        }
    }

    /// The same, on a road that ends `end_m` along it (in the measure of the views the
    /// updates get): where a road end trigger's vehicle must be. Without it the road has
    /// no end, and a road end trigger never holds.
    pub fn with_road_end_m(self, end_m: f64) -> Events {
        Events {
            road_end_m: end_m,
            ..self
        }
    }

    /// How many events there are.
    pub fn len(&self) -> usize {
        self.events.len()
    }

    /// Whether there are none.
    pub fn is_empty(&self) -> bool {
        self.events.is_empty()
    }

    /// Event `index`'s name (empty for an index out of range).
    pub fn name(&self, index: usize) -> &str {
        self.events.get(index).map_or("", |e| e.event.name.as_str())
    }

    /// The speed the last update asked for and its rate of change (`None` until a speed
    /// action has started; then the action's speed, held at its end).
    pub fn speed_override(&self) -> Option<SpeedOverride> {
        self.speed_now
    }

    /// The step at which an event's `end_run` action started, ending the run, and that
    /// event's index (`None` while none has).
    pub fn run_ended(&self) -> Option<(Step, usize)> {
        self.run_ended
    }

    /// The lateral offset from the route the last update asked for, m (positive left; the
    /// start's offset, 0 unless [`Events::with_lateral_offset_m`] gives one, until a
    /// lateral action has started).
    pub fn lateral_offset_m(&self) -> f64 {
        self.lateral_now_m
    }

    /// The vehicles (their indices in the view) whose contact with this one its contact
    /// triggers watch, each once, in order: the pairs whose [`VehicleView::touching`] the
    /// caller is to set.
    pub fn contacts_watched(&self) -> Vec<usize> {
        fn walk(trigger: &Trigger, watch: &Watch, out: &mut Vec<usize>) {
            match &trigger.condition {
                Condition::Contact(_) => out.extend(watch.to),
                Condition::All(members) | Condition::Any(members) => {
                    for (m, w) in members.iter().zip(&watch.members) {
                        walk(m, w, out);
                    }
                }
                _ => {}
            }
        }
        let mut out = Vec::new();
        for e in &self.events {
            walk(&e.event.trigger, &e.watch, &mut out);
        }
        out.sort_unstable();
        out.dedup();
        out
    }

    /// Runs step `now` for the vehicle `me` of `view`: the events that started and ended
    /// at it, in that order. Call it at every physics step from the first: a distance
    /// trigger counts from `me`'s station at the first call. A `me` or `to` missing from
    /// `view` holds no condition.
    pub fn update(&mut self, now: Step, view: &TrafficView, me: usize) -> Vec<Fired> {
        let mut fired = Vec::new();
        let Some(mine) = view.get(me) else {
            return fired;
        };
        let start_station_m = *self.start_station_m.get_or_insert(mine.station_m);
        let c = Now {
            now,
            view,
            mine,
            start_station_m,
            lanes: self.lanes,
            road_end_m: self.road_end_m,
            ended: &self.ended,
            started: &self.started,
        };
        for e in &mut self.events {
            let trigger = &e.event.trigger;
            let holds = match trigger.condition {
                // A group is evaluated at every step, armed or not, so that its delayed
                // members keep their histories.
                Condition::All(_) | Condition::Any(_) => {
                    let level = e.watch.group_holds(trigger, &c);
                    e.watch.edge(trigger, level)
                }
                // Evaluated while armed; an edge at every step, armed or not, so that it
                // knows the step before.
                _ => {
                    e.watch.update_still(trigger, &c);
                    (trigger.rising || trigger.falling || e.phase == Phase::Armed) && {
                        let level = e.watch.holds(trigger, &c);
                        e.watch.edge(trigger, level)
                    }
                }
            };
            if e.phase == Phase::Armed && holds {
                e.phase = Phase::Pending(now.plus(steps_of(trigger.delay_s)));
            }
        }
        for i in 0..self.events.len() {
            if matches!(self.events[i].phase, Phase::Pending(at) if at <= now) {
                self.start(i, now, mine, view, &mut fired);
            }
        }
        // A continuous relative speed's target follows its vehicle's speed now.
        if let Some(m) = self.speed.as_mut().filter(|m| m.running) {
            if let Some((f, other)) = m.follow.and_then(|f| Some((f, view.get(f.vehicle)?))) {
                m.to = f.target(other.speed_mps);
            }
        }
        // A kept gap moves its speed on; reached, and not continuous, it ends there, and
        // the vehicle keeps the speed it has.
        if let (Some(m), Some(k)) = (self.speed.as_mut(), &mut self.keep) {
            let reached = k.step(mine, view.get(k.vehicle));
            m.to = k.speed_mps;
            if reached {
                m.running = false;
                m.steps = 0;
                self.keep = None;
                let event = m.event;
                Self::end(&mut self.events, &mut self.ended, event, now, &mut fired);
            }
        }
        for motion in [&mut self.speed, &mut self.lateral].into_iter().flatten() {
            // A continuous relative speed runs until another speed action replaces it.
            while motion.running
                && motion.follow.is_none()
                && now.since(motion.start) >= motion.steps
            {
                // A speed profile goes on to its next change from the speed this one
                // reached, at this step.
                let next = match &self.events[motion.event].event.action {
                    Action::Profile(changes) => changes.get(motion.segment + 1).copied(),
                    _ => None,
                };
                if let Some((to, timing)) = next {
                    let from = motion.to;
                    *motion = Motion {
                        start: now,
                        steps: steps_for(timing, from, to, Shape::Linear),
                        from,
                        to,
                        segment: motion.segment + 1,
                        ..*motion
                    };
                    continue;
                }
                motion.running = false;
                let event = motion.event;
                Self::end(&mut self.events, &mut self.ended, event, now, &mut fired);
            }
        }
        self.speed_now = self.speed.map(|m| {
            let (speed, accel) = match &self.keep {
                Some(k) => (k.speed_mps, k.accel_mps2),
                None => m.at(now),
            };
            SpeedOverride {
                speed_mps: speed as f32,
                accel_mps2: accel as f32,
            }
        });
        self.lateral_now_m = self.lateral.map_or(self.base_lateral_m, |m| m.at(now).0);
        fired
    }

    /// Starts event `i`'s action at `now`, with the traffic `view` (`mine` in it).
    fn start(
        &mut self,
        i: usize,
        now: Step,
        mine: &VehicleView,
        view: &TrafficView,
        fired: &mut Vec<Fired>,
    ) {
        self.started[i] = true;
        let action = self.events[i].event.action.clone();
        let mut follow = None;
        let mut kept = false;
        let (slot, from, to, timing, shape) = match action {
            Action::EndRun => {
                // The run ends at this step: the action starts and ends at once.
                self.run_ended.get_or_insert((now, i));
                fired.push(Fired {
                    step: now,
                    event: i,
                    name: self.events[i].event.name.clone(),
                    kind: FiredKind::Started,
                });
                Self::end(&mut self.events, &mut self.ended, i, now, fired);
                return;
            }
            Action::Keep(keep) => {
                // Its speed set step by step from this one's, until reached or replaced.
                let j = self.events[i].speed_of.unwrap_or(usize::MAX);
                let state = KeepState::new(keep, j, mine, view.get(j));
                let v = state.speed_mps;
                self.keep = Some(state);
                kept = true;
                (&mut self.speed, v, v, Timing::Duration(0.0), Shape::Linear)
            }
            Action::Profile(changes) => {
                self.keep = None;
                let (to, timing) = changes[0];
                (
                    &mut self.speed,
                    mine.speed_mps.max(0.0),
                    to,
                    timing,
                    Shape::Linear,
                )
            }
            Action::Speed {
                speed_mps,
                timing,
                shape,
                relative,
            } => {
                self.keep = None;
                // Relative: to the other's speed now (this one's, should it be missing).
                let to = match (&relative, self.events[i].speed_of) {
                    (Some(r), Some(j)) => {
                        let f = Follow {
                            vehicle: j,
                            value: speed_mps,
                            factor: r.factor,
                        };
                        if r.continuous {
                            follow = Some(f);
                        }
                        f.target(view.get(j).map_or(mine.speed_mps, |o| o.speed_mps))
                    }
                    _ => speed_mps,
                };
                (&mut self.speed, mine.speed_mps.max(0.0), to, timing, shape)
            }
            Action::Lane {
                lane,
                timing,
                shape,
            } => {
                let from = self.lateral.map_or(self.base_lateral_m, |m| m.at(now).0);
                self.lane_now = lane;
                (
                    &mut self.lateral,
                    from,
                    self.lanes.offset_m(lane),
                    timing,
                    shape,
                )
            }
            Action::Offset {
                offset_m,
                timing,
                shape,
            } => {
                let from = self.lateral.map_or(self.base_lateral_m, |m| m.at(now).0);
                (
                    &mut self.lateral,
                    from,
                    self.lanes.offset_m(self.lane_now) + offset_m,
                    timing,
                    shape,
                )
            }
        };
        if let Some(old) = slot.as_mut().filter(|m| m.running) {
            old.running = false;
            let event = old.event;
            Self::end(&mut self.events, &mut self.ended, event, now, fired);
        }
        *slot = Some(Motion {
            event: i,
            start: now,
            steps: if kept {
                u64::MAX
            } else {
                steps_for(timing, from, to, shape)
            },
            from,
            to,
            shape,
            running: true,
            segment: 0,
            follow,
        });
        self.events[i].phase = Phase::Running;
        fired.push(Fired {
            step: now,
            event: i,
            name: self.events[i].event.name.clone(),
            kind: FiredKind::Started,
        });
    }

    /// Ends event `i`'s action at `now`: waiting again if it repeats and has runs left, done
    /// if not.
    fn end(
        events: &mut [EventState],
        ended: &mut [bool],
        i: usize,
        now: Step,
        fired: &mut Vec<Fired>,
    ) {
        ended[i] = true;
        let e = &mut events[i];
        e.runs += 1;
        e.phase = if e.event.max_runs.is_none_or(|n| e.runs < n) {
            Phase::Armed
        } else {
            Phase::Done
        };
        fired.push(Fired {
            step: now,
            event: i,
            name: e.event.name.clone(),
            kind: FiredKind::Ended,
        });
    }
}

/// Two vehicles along the road: the bumper-to-bumper gap from the one behind to the one
/// ahead, the speed of the one behind and how fast the gap closes.
struct Between {
    gap_m: f64,
    /// Between the two reference points (the middles of the rear axles), m.
    spacing_m: f64,
    behind_speed_mps: f64,
    closing_mps: f64,
}

impl Between {
    fn new(a: &VehicleView, b: &VehicleView) -> Between {
        let (ahead, behind) = if a.station_m >= b.station_m {
            (a, b)
        } else {
            (b, a)
        };
        Between {
            gap_m: ahead.rear_m - behind.front_m,
            spacing_m: ahead.station_m - behind.station_m,
            behind_speed_mps: behind.speed_mps,
            closing_mps: behind.speed_mps - ahead.speed_mps,
        }
    }

    /// The same, its gap the spacing when `axles`.
    fn on_axles(self, axles: bool) -> Between {
        Between {
            gap_m: if axles { self.spacing_m } else { self.gap_m },
            ..self
        }
    }
}
