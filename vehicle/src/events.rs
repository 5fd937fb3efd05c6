//! The event engine: one vehicle's scripted events ([`EventScript`]) run against the
//! traffic at every physics step, giving the speed and the lateral offset its driver is to
//! follow, and which events started and ended.
//!
//! At each step, in this order:
//! 1. every event waiting for its trigger whose condition holds now (on level) is armed to
//!    start `delay_s` later;
//! 2. every event whose start has come starts its action: a speed action replaces the
//!    running speed action (which ends there), a lane change the running lane change;
//! 3. every action that has reached its end ends; an event with `repeat` waits for its
//!    trigger again from the next step, the others are done.
//!
//! An `after` trigger sees the actions ended at earlier steps. All times are whole steps
//! (`docs/src/conventions.md`, "One clock"): a duration or delay is rounded to the step.

use crate::clock::{Step, PHYSICS_HZ};
use crate::error::{check_range, VehicleError};
use crate::event_spec::{Action, Checked, Condition, EventScript, Shape, Timing};
use crate::lead_driver::SpeedOverride;

/// Below this speed a vehicle stands still, m/s (for standstill triggers): a physics
/// vehicle held by its brakes creeps at millimetres per second as its tyres settle, and
/// 5 cm/s (0.18 km/h) is below what wheel-speed sensors resolve, about 0.1 m/s.
pub const STANDSTILL_MPS: f64 = 0.05;

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
    /// The vehicle a gap trigger measures to.
    to: Option<usize>,
    /// The vehicle a speed or standstill trigger watches (`None`: this one).
    of: Option<usize>,
    /// The step from which the watched vehicle has stood still (standstill triggers).
    still_since: Option<Step>,
    phase: Phase,
    /// Whether its action has ended at least once.
    ended: bool,
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
    lanes: Lanes,
    /// The vehicle's station at the first step, m (distance triggers count from it).
    start_station_m: Option<f64>,
    speed: Option<Motion>,
    lateral: Option<Motion>,
    /// The speed and lateral offset the last update asked for.
    speed_now: Option<SpeedOverride>,
    lateral_now_m: f64,
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
            let to = match &event.trigger.condition {
                Condition::Gap(_, to)
                | Condition::TimeGap(_, to)
                | Condition::Ttc(_, to)
                | Condition::RelativeSpeed(_, to) => {
                    Some(vehicles.iter().position(|v| v == to).ok_or_else(|| {
                        VehicleError::InvalidEvent {
                            field: format!("events[{i}].trigger.to"),
                            reason: format!("no vehicle is named \"{to}\""),
                        }
                    })?)
                }
                _ => None,
            };
            let of = match &event.trigger.condition {
                Condition::Speed(_, of)
                | Condition::Standstill(_, of)
                | Condition::Reach(_, of)
                    if !of.is_empty() =>
                {
                    Some(vehicles.iter().position(|v| v == of).ok_or_else(|| {
                        VehicleError::InvalidEvent {
                            field: format!("events[{i}].trigger.of"),
                            reason: format!("no vehicle is named \"{of}\""),
                        }
                    })?)
                }
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
            if let Condition::Reach(r, _) = &event.trigger.condition {
                if r.lane > lanes.count {
                    return Err(VehicleError::InvalidEvent {
                        field: format!("events[{i}].trigger.reach.lane"),
                        reason: format!("= {}: the road has {} lanes", r.lane, lanes.count),
                    });
                }
            }
            events.push(EventState {
                event,
                to,
                of,
                still_since: None,
                phase: Phase::Armed,
                ended: false,
            });
        }
        Ok(Events {
            events,
            lanes,
            start_station_m: None,
            speed: None,
            lateral: None,
            speed_now: None,
            lateral_now_m: 0.0,
        })
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

    /// The lateral offset from the route the last update asked for, m (positive left; 0
    /// until a lane change has started).
    pub fn lateral_offset_m(&self) -> f64 {
        self.lateral_now_m
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
        for e in &mut self.events {
            if let Condition::Standstill(..) = e.event.trigger.condition {
                let watched = e.of.map_or(Some(mine), |j| view.get(j));
                let still = watched.is_some_and(|v| v.speed_mps.abs() < STANDSTILL_MPS);
                e.still_since = if still {
                    e.still_since.or(Some(now))
                } else {
                    None
                };
            }
        }
        for i in 0..self.events.len() {
            if self.events[i].phase == Phase::Armed
                && self.holds(i, now, view, mine, start_station_m)
            {
                let delay = steps_of(self.events[i].event.trigger.delay_s);
                self.events[i].phase = Phase::Pending(now.plus(delay));
            }
        }
        for i in 0..self.events.len() {
            if matches!(self.events[i].phase, Phase::Pending(at) if at <= now) {
                self.start(i, now, mine, &mut fired);
            }
        }
        for motion in [&mut self.speed, &mut self.lateral].into_iter().flatten() {
            if motion.running && now.since(motion.start) >= motion.steps {
                motion.running = false;
                let event = motion.event;
                Self::end(&mut self.events, event, now, &mut fired);
            }
        }
        self.speed_now = self.speed.map(|m| {
            let (speed, accel) = m.at(now);
            SpeedOverride {
                speed_mps: speed as f32,
                accel_mps2: accel as f32,
            }
        });
        self.lateral_now_m = self.lateral.map_or(0.0, |m| m.at(now).0);
        fired
    }

    /// Whether event `i`'s condition holds now.
    fn holds(
        &self,
        i: usize,
        now: Step,
        view: &TrafficView,
        mine: &VehicleView,
        start_station_m: f64,
    ) -> bool {
        let e = &self.events[i];
        let rule = e.event.trigger.rule;
        let compare = |value: f64, threshold: f64| rule.holds(value, threshold);
        let other = e.to.and_then(|j| view.get(j));
        match (&e.event.trigger.condition, other) {
            (Condition::Time(t), _) => compare(now.seconds(), *t),
            (Condition::Distance(d), _) => compare(mine.station_m - start_station_m, *d),
            (Condition::After(j), _) => self.events[*j].ended,
            (Condition::Speed(v, _), _) => {
                e.of.map_or(Some(mine), |j| view.get(j))
                    .is_some_and(|w| compare(w.speed_mps, *v))
            }
            (Condition::Standstill(d, _), _) => e
                .still_since
                .is_some_and(|since| now.since(since) >= steps_of(*d)),
            (Condition::Reach(r, _), _) => {
                e.of.map_or(Some(mine), |j| view.get(j)).is_some_and(|w| {
                    let along = w.station_m - r.station_m;
                    // The view's offsets are from lane 1's centre.
                    let from_lane_1 = Lanes {
                        route_lane: 1,
                        ..self.lanes
                    };
                    let across = w.left_offset_m - (from_lane_1.offset_m(r.lane) + r.offset_m);
                    along.hypot(across) <= r.tolerance_m
                })
            }
            (Condition::RelativeSpeed(v, _), Some(o)) => compare(mine.speed_mps - o.speed_mps, *v),
            (Condition::Gap(g, _), Some(o)) => compare(Between::new(mine, o).gap_m, *g),
            (Condition::TimeGap(t, _), Some(o)) => {
                let b = Between::new(mine, o);
                let time_gap = if b.behind_speed_mps > 0.0 {
                    b.gap_m / b.behind_speed_mps
                } else {
                    f64::INFINITY
                };
                compare(time_gap, *t)
            }
            (Condition::Ttc(t, _), Some(o)) => {
                let b = Between::new(mine, o);
                b.closing_mps > 0.0 && compare(b.gap_m / b.closing_mps, *t)
            }
            (_, None) => false,
        }
    }

    /// Starts event `i`'s action at `now`.
    fn start(&mut self, i: usize, now: Step, mine: &VehicleView, fired: &mut Vec<Fired>) {
        let (slot, from, to, timing, shape) = match self.events[i].event.action {
            Action::Speed {
                speed_mps,
                timing,
                shape,
            } => (
                &mut self.speed,
                mine.speed_mps.max(0.0),
                speed_mps,
                timing,
                shape,
            ),
            Action::Lane {
                lane,
                timing,
                shape,
            } => {
                let from = self.lateral.map_or(0.0, |m| m.at(now).0);
                (
                    &mut self.lateral,
                    from,
                    self.lanes.offset_m(lane),
                    timing,
                    shape,
                )
            }
        };
        if let Some(old) = slot.as_mut().filter(|m| m.running) {
            old.running = false;
            let event = old.event;
            Self::end(&mut self.events, event, now, fired);
        }
        let steps = match timing {
            Timing::Duration(d) => steps_of(d),
            Timing::Rate(r) => steps_of((to - from).abs() / r),
        };
        *slot = Some(Motion {
            event: i,
            start: now,
            steps,
            from,
            to,
            shape,
            running: true,
        });
        self.events[i].phase = Phase::Running;
        fired.push(Fired {
            step: now,
            event: i,
            name: self.events[i].event.name.clone(),
            kind: FiredKind::Started,
        });
    }

    /// Ends event `i`'s action at `now`: waiting again if it repeats, done if not.
    fn end(events: &mut [EventState], i: usize, now: Step, fired: &mut Vec<Fired>) {
        let e = &mut events[i];
        e.ended = true;
        e.phase = if e.event.repeat {
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
            behind_speed_mps: behind.speed_mps,
            closing_mps: behind.speed_mps - ahead.speed_mps,
        }
    }
}
