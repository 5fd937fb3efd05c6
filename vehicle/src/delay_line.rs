//! The delay line: what the tracker computes from a frame captured at step t reaches the
//! controller at t + latency, quantised to the physics step; optionally with seeded jitter
//! and dropped frames for fault studies.

use crate::clock::{ms_from_steps, steps_from_ms, Step};
use crate::error::{check_range, VehicleError};
use crate::rng_stream::named_stream;
use rand::Rng;
use rand_chacha::ChaCha8Rng;
use serde::{Deserialize, Serialize};
use std::collections::VecDeque;

/// The delay line's configuration.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields, default)]
pub struct DelayLineConfig {
    /// Latency from capture to the controller, ms (default 128 ms, the paper's worst case;
    /// it becomes 15 steps = 125 ms at 120 Hz).
    pub latency_ms: f64,
    /// Jitter: each item's latency varies uniformly by up to this much either way, ms
    /// (default 0). Items still arrive in order.
    pub jitter_ms: f64,
    /// Probability that an item is dropped and never arrives (default 0).
    pub drop_probability: f64,
    /// Seed of the jitter and drops (named stream `"delay_line"`).
    pub seed: u64,
}

impl Default for DelayLineConfig {
    fn default() -> Self {
        DelayLineConfig {
            latency_ms: 128.0,
            jitter_ms: 0.0,
            drop_probability: 0.0,
            seed: 0,
        }
    }
}

/// A first-in, first-out queue that releases each item a fixed number of physics steps
/// after its capture.
#[derive(Clone, Debug)]
pub struct DelayLine<T> {
    latency_steps: u64,
    jitter_steps: u64,
    drop_probability: f64,
    rng: ChaCha8Rng,
    queue: VecDeque<(Step, T)>,
    last_due: Step,
    dropped: u64,
}

impl<T> DelayLine<T> {
    /// A delay line for `config`.
    pub fn new(config: &DelayLineConfig) -> Result<DelayLine<T>, VehicleError> {
        check_range("latency_ms", config.latency_ms, 0.0, 10_000.0)?;
        check_range("jitter_ms", config.jitter_ms, 0.0, config.latency_ms)?;
        check_range("drop_probability", config.drop_probability, 0.0, 1.0)?;
        Ok(DelayLine {
            latency_steps: steps_from_ms(config.latency_ms),
            jitter_steps: steps_from_ms(config.jitter_ms),
            drop_probability: config.drop_probability,
            rng: named_stream(config.seed, "delay_line"),
            queue: VecDeque::new(),
            last_due: Step::ZERO,
            dropped: 0,
        })
    }

    /// The nominal latency in physics steps.
    pub fn latency_steps(&self) -> u64 {
        self.latency_steps
    }

    /// The shortest latency any item can have, physics steps: the nominal latency less the
    /// jitter. An item pushed at step t never pops before t + this, so a caller may run that
    /// many steps of physics while the item is still being computed.
    pub fn min_latency_steps(&self) -> u64 {
        self.latency_steps.saturating_sub(self.jitter_steps)
    }

    /// The nominal latency as applied, ms (a whole number of steps).
    pub fn latency_ms(&self) -> f64 {
        ms_from_steps(self.latency_steps)
    }

    /// Items dropped so far.
    pub fn dropped(&self) -> u64 {
        self.dropped
    }

    /// Items waiting.
    pub fn len(&self) -> usize {
        self.queue.len()
    }

    /// Whether nothing is waiting.
    pub fn is_empty(&self) -> bool {
        self.queue.is_empty()
    }

    /// Queues `item`, computed from a frame captured at `captured`. Returns the step it will
    /// arrive at, or `None` if it is dropped.
    pub fn push(&mut self, captured: Step, item: T) -> Option<Step> {
        // Both draws happen for every item, so the stream does not shift with the settings.
        let drop_draw: f64 = self.rng.random();
        let jitter_draw = self.rng.random_range(0..=2 * self.jitter_steps);
        if drop_draw < self.drop_probability {
            self.dropped += 1;
            return None;
        }
        let delay = (self.latency_steps + jitter_draw).saturating_sub(self.jitter_steps);
        let due = captured.plus(delay).max(self.last_due);
        self.last_due = due;
        self.queue.push_back((due, item));
        Some(due)
    }

    /// Takes every item due at or before `now`, in order.
    pub fn pop_due(&mut self, now: Step) -> Vec<T> {
        let mut out = Vec::new();
        while self.queue.front().is_some_and(|(due, _)| *due <= now) {
            if let Some((_, item)) = self.queue.pop_front() {
                out.push(item);
            }
        }
        out
    }
}
