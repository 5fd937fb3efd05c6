//! One episode of `carfollow/Follow-v0`, without the interpreter: the agent's controller
//! with its delay line, the closed loop it drives, and what one step of the agent gives
//! (reward, termination). The single environment (`gym::GymCore`) and the vector one
//! (`vec_gym::VecCore`) both run episodes so, the vector one on several threads at once.

use crate::plugins::PyTracker;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use sim_core::{
    BuiltinController, ClosedLoop, Command, ControlInput, Controller, ControllerChoice, Delivered,
    FrameOutput, LoopOptions, Plan, PluginError, TrackerChoice,
};
use sim_render::Backend;
use std::collections::VecDeque;
use std::sync::{Arc, Mutex};
use vehicle::{DelayLine, Step, VehicleParams, STEPS_PER_FRAME};

/// Actions still in flight that the estimate observation carries (the latency is under two
/// frames in every shipped scenario: 128 ms is 1.92 frames).
pub(crate) const IN_FLIGHT: usize = 2;

/// What the agent commands.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum ActionKind {
    /// Steering (full lock at ±1) and the longitudinal (throttle above 0, brake below).
    Drive,
    /// The longitudinal only; the built-in controller steers (and aims the pan head).
    Longitudinal,
}

impl ActionKind {
    /// The kind named `name` ("drive" or "longitudinal").
    pub(crate) fn parse(name: &str) -> PyResult<ActionKind> {
        match name {
            "drive" => Ok(ActionKind::Drive),
            "longitudinal" => Ok(ActionKind::Longitudinal),
            other => Err(PyValueError::new_err(format!(
                "action = {other:?}: must be \"drive\" or \"longitudinal\""
            ))),
        }
    }
}

/// How an episode is run: the same for every episode of an environment.
#[derive(Clone, Copy, Debug)]
pub(crate) struct EpisodeOptions {
    /// What the agent commands.
    pub(crate) kind: ActionKind,
    /// Every frame rendered whole (camera observations), not only the tracker's part.
    pub(crate) whole_frames: bool,
    /// The graphics backend.
    pub(crate) backend: Backend,
}

/// The controller in the loop: the agent's actions through their delay line.
struct Agent {
    /// Actions queued at their observation's capture step: `[steer, longitudinal]`.
    actions: Arc<Mutex<DelayLine<[f64; 2]>>>,
    /// The action applied now (nothing until the first is due).
    now: [f64; 2],
    max_steer_rad: f64,
    /// The built-in controller, steering, in `Longitudinal`.
    steering: Option<BuiltinController>,
    /// The latest input, for the estimate observation.
    seen: Arc<Mutex<Option<ControlInput>>>,
}

impl Controller for Agent {
    /// The built-in steering hears every estimate delivered, as in the loop.
    fn receive(&mut self, delivered: &Delivered) {
        if let Some(builtin) = &mut self.steering {
            builtin.receive(delivered);
        }
    }

    fn name(&self) -> String {
        match self.steering {
            Some(_) => "gymnasium agent (longitudinal; built-in steering)".into(),
            None => "gymnasium agent".into(),
        }
    }

    fn control(&mut self, input: &ControlInput) -> Result<Command, PluginError> {
        let due = self
            .actions
            .lock()
            .unwrap_or_else(|p| p.into_inner())
            .pop_due(Step::from_seconds(input.t_s));
        if let Some(&latest) = due.last() {
            self.now = latest;
        }
        *self.seen.lock().unwrap_or_else(|p| p.into_inner()) = Some(*input);
        let [steer, longitudinal] = self.now;
        let (steering_rad, pan_rate_rad_s) = match &mut self.steering {
            Some(builtin) => {
                let c = builtin.control(input)?;
                (c.steering_rad, c.pan_rate_rad_s)
            }
            None => (steer * self.max_steer_rad, 0.0),
        };
        Ok(Command {
            steering_rad,
            throttle: longitudinal.max(0.0),
            brake: (-longitudinal).max(0.0),
            pan_rate_rad_s,
        })
    }
}

/// What one step of the agent gave.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct Outcome {
    pub(crate) reward: f64,
    pub(crate) terminated: bool,
    pub(crate) truncated: bool,
}

/// One episode.
pub(crate) struct Episode {
    pub(crate) looped: ClosedLoop,
    actions: Arc<Mutex<DelayLine<[f64; 2]>>>,
    pub(crate) seen: Arc<Mutex<Option<ControlInput>>>,
    pub(crate) last: FrameOutput,
    /// The actions taken, newest last (for the observation and the smoothness reward).
    pub(crate) taken: VecDeque<[f64; 2]>,
    gap_band_m: [f64; 2],
    /// The lead's path further than this beside the chase: off the road, metres.
    off_road_m: f64,
}

/// Everything an episode needs that only the interpreter can give: the plan (planning reads
/// the scenario's Python value) and the tracker plug-in, if any.
pub(crate) struct Planned {
    pub(crate) plan: Plan,
    pub(crate) tracker: Option<PyTracker>,
}

impl Episode {
    /// Starts the episode of `planned` and renders its first frame (then starts rendering
    /// the next). With `software_device`, its frames render on Mesa's software EGL device
    /// where there is one (see `ClosedLoop::render_on_software_device`; the same frames).
    /// Runs without the interpreter.
    pub(crate) fn start(
        planned: Planned,
        options: EpisodeOptions,
        software_device: bool,
    ) -> Result<Episode, sim::RunError> {
        let Planned { plan, tracker } = planned;
        let s = plan.scenario().clone();
        if !s.has_lead {
            // Its reward is the gap to the lead's target, and its end a chase off the lead's
            // path: neither exists.
            return Err(sim::RunError::Other(format!(
                "scenario `{}` has no lead ([lead]), and `Follow-v0` rewards the gap kept to \
                 one: give it a scenario with a lead",
                s.name
            )));
        }
        let line = DelayLine::new(&s.delay).map_err(|e| sim::RunError::Other(e.to_string()))?;
        let actions = Arc::new(Mutex::new(line));
        let seen = Arc::new(Mutex::new(None));
        let steering = match options.kind {
            ActionKind::Drive => None,
            ActionKind::Longitudinal => Some(
                BuiltinController::new(s.chase.clone(), s.chase_initial_speed_mps)
                    .map_err(|e| sim::RunError::Other(e.to_string()))?,
            ),
        };
        let agent = Agent {
            actions: actions.clone(),
            now: [0.0; 2],
            max_steer_rad: f64::from(VehicleParams::hmmwv_m998().max_steer_rad),
            steering,
            seen: seen.clone(),
        };
        let loop_options = LoopOptions {
            // One renderer: two in flight run the physics a frame ahead, which would need
            // the agent's next action before it is taken.
            renderers: 1,
            whole_frames: options.whole_frames,
            tracker: match tracker {
                Some(t) => TrackerChoice::Plugin(Box::new(t)),
                None => TrackerChoice::Builtin,
            },
            controller: ControllerChoice::Plugin(Box::new(agent)),
            ..LoopOptions::new(options.backend)
        };
        let mut looped = ClosedLoop::start(plan, loop_options)?;
        if software_device {
            // Where there is no such device, the loop's own renderer serves: only slower.
            let _ = looped.render_on_software_device(options.backend);
        }
        let last = looped.step()?.expect("a scenario has at least one frame");
        looped.prefetch()?;
        Ok(Episode {
            looped,
            actions,
            seen,
            last,
            taken: VecDeque::new(),
            gap_band_m: s.expect.gap_band_m.unwrap_or([5.0, 15.0]),
            off_road_m: 1.5 * s.route.lane_width_of(s.lead_lane),
        })
    }

    /// Takes `action` (finite, clamped to [-1, 1]) on the last observation and runs to the
    /// next frame (then starts rendering the one after). Runs without the interpreter.
    pub(crate) fn advance(&mut self, action: [f64; 2]) -> Result<Outcome, sim::RunError> {
        let captured = Step(self.last.record.frame * u64::from(STEPS_PER_FRAME));
        self.actions
            .lock()
            .unwrap_or_else(|p| p.into_inner())
            .push(captured, action);
        let previous = self.taken.back().copied().unwrap_or(action);
        self.taken.push_back(action);
        while self.taken.len() > IN_FLIGHT {
            self.taken.pop_front();
        }
        let Some(out) = self.looped.step()? else {
            return Ok(Outcome {
                truncated: true,
                ..Outcome::default()
            });
        };
        self.looped.prefetch()?;
        self.last = out;
        let r = &self.last.record;
        let smooth = (action[0] - previous[0]).abs() + (action[1] - previous[1]).abs();
        let terminated = r.collision || r.lateral_deviation_m > self.off_road_m;
        Ok(Outcome {
            reward: reward(r, self.gap_band_m, smooth),
            terminated,
            // The scenario's end, by its duration or by an event's `end_run`.
            truncated: !terminated
                && (self.looped.frame() >= self.looped.frames()
                    || self.looped.run_ended().is_some()),
        })
    }
}

/// An action as the episode takes it: finite, each value clamped to [-1, 1].
pub(crate) fn clamped(steer: f64, longitudinal: f64) -> PyResult<[f64; 2]> {
    if !(steer.is_finite() && longitudinal.is_finite()) {
        return Err(PyValueError::new_err("the action must be finite"));
    }
    Ok([steer.clamp(-1.0, 1.0), longitudinal.clamp(-1.0, 1.0)])
}

/// An action must be applied after the frame it answers: the latency less the jitter at
/// least one frame.
pub(crate) fn latency_ok(d: &vehicle::DelayLineConfig) -> PyResult<()> {
    let frame_ms = 1000.0 / f64::from(vehicle::CAMERA_HZ);
    if d.latency_ms - d.jitter_ms < frame_ms {
        return Err(PyValueError::new_err(format!(
            "`loop.latency_ms` − `loop.jitter_ms` = {} ms: the environment needs at least one \
             frame ({frame_ms:.1} ms), so that an action takes effect after the frame it answers",
            d.latency_ms - d.jitter_ms
        )));
    }
    Ok(())
}

/// The default reward of one frame (documented in `carfollow.env.FollowEnv`): +1 inside the
/// gap band, less the distance outside it over 5 m (down to −1); −1 when the target is out of
/// the camera's view; −10 on a collision; −0.1 times the action's change since the last.
fn reward(r: &sim_core::FrameRecord, band: [f64; 2], change: f64) -> f64 {
    let [lo, hi] = band;
    let outside = (lo - r.gap_m).max(r.gap_m - hi).max(0.0);
    let gap = if outside == 0.0 {
        1.0
    } else {
        -(outside / 5.0).min(1.0)
    };
    let view = if r.target_in_view { 0.0 } else { -1.0 };
    let collision = if r.collision { -10.0 } else { 0.0 };
    gap + view + collision - 0.1 * change
}
