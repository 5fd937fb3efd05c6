//! A short history of one vehicle's pose and odometry, keyed by physics step.
//!
//! The chase controller looks up where the chase vehicle was when a camera frame was
//! captured, to place the (delayed) estimate of the lead in the world frame, and how far it
//! had driven and how fast, to turn the range into the lead's own motion.

use crate::clock::Step;
use rapier3d::math::Pose;
use std::collections::VecDeque;

/// `world_from_vehicle` and the odometry at each recent physics step, oldest first.
#[derive(Clone, Debug)]
pub struct PoseHistory {
    entries: VecDeque<(Step, Pose, OwnMotion)>,
    capacity_steps: usize,
}

/// How far the vehicle had driven, and how fast it went, at one step.
#[derive(Copy, Clone, Debug, Default, PartialEq)]
pub struct OwnMotion {
    /// Distance driven since the start, m.
    pub travel_m: f32,
    /// Forward speed, m/s.
    pub speed_mps: f32,
}

impl PoseHistory {
    /// A history keeping the last `capacity_steps` steps (at least 1).
    pub fn new(capacity_steps: usize) -> PoseHistory {
        PoseHistory {
            entries: VecDeque::with_capacity(capacity_steps.max(1)),
            capacity_steps: capacity_steps.max(1),
        }
    }

    /// Records `world_from_vehicle` and `motion` at `step`. Steps must not go backwards: a
    /// step at or before the newest replaces everything from it on.
    pub fn push(&mut self, step: Step, world_from_vehicle: Pose, motion: OwnMotion) {
        while self.entries.back().is_some_and(|(s, _, _)| *s >= step) {
            self.entries.pop_back();
        }
        self.entries.push_back((step, world_from_vehicle, motion));
        while self.entries.len() > self.capacity_steps {
            self.entries.pop_front();
        }
    }

    /// `world_from_vehicle` at `step`, or at the newest recorded step before it; `None` if
    /// `step` is older than the history.
    pub fn world_from_vehicle_at(&self, step: Step) -> Option<Pose> {
        self.at(step).map(|(pose, _)| pose)
    }

    /// The pose and odometry at `step`, or at the newest recorded step before it; `None`
    /// if `step` is older than the history.
    pub fn at(&self, step: Step) -> Option<(Pose, OwnMotion)> {
        let idx = self.entries.partition_point(|(s, _, _)| *s <= step);
        if idx == 0 {
            None
        } else {
            let (_, pose, motion) = self.entries[idx - 1];
            Some((pose, motion))
        }
    }

    /// The newest entry.
    pub fn latest(&self) -> Option<(Step, Pose, OwnMotion)> {
        self.entries.back().copied()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rapier3d::math::Vector;

    #[test]
    fn looks_up_by_step_and_forgets_old_steps() {
        let mut h = PoseHistory::new(3);
        for i in 0..5u64 {
            h.push(
                Step(i),
                Pose::from_translation(Vector::new(i as f32, 0.0, 0.0)),
                OwnMotion {
                    travel_m: 2.0 * i as f32,
                    speed_mps: 1.0,
                },
            );
        }
        assert!(h.world_from_vehicle_at(Step(1)).is_none());
        assert_eq!(h.world_from_vehicle_at(Step(3)).unwrap().translation.x, 3.0);
        assert_eq!(h.world_from_vehicle_at(Step(9)).unwrap().translation.x, 4.0);
        assert_eq!(h.at(Step(3)).unwrap().1.travel_m, 6.0);
    }
}
