//! Breadcrumbs: the lead's path in the world frame, built from delayed estimates.
//!
//! The paper's chase vehicle steers along the path of the lead vehicle (its refs. 1–2). Each
//! estimate, placed in the world through the chase pose at the frame's capture time, drops a
//! crumb; the chase vehicle drives over them and eats the ones it has passed.

use crate::clock::Step;
use rapier3d::math::{Pose, Vector};
use std::collections::VecDeque;

/// One crumb: where the lead's target was, and when.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct Breadcrumb {
    /// The frame's capture step.
    pub capture_step: Step,
    /// The target's position in the world frame, m.
    pub position_world_m: Vector,
}

/// The lead's path ahead of the chase vehicle, oldest crumb first.
#[derive(Clone, Debug)]
pub struct BreadcrumbTrail {
    crumbs: VecDeque<Breadcrumb>,
    min_spacing_m: f32,
    max_crumbs: usize,
}

impl BreadcrumbTrail {
    /// An empty trail keeping crumbs at least `min_spacing_m` apart, at most `max_crumbs`.
    pub fn new(min_spacing_m: f32, max_crumbs: usize) -> BreadcrumbTrail {
        BreadcrumbTrail {
            crumbs: VecDeque::new(),
            min_spacing_m,
            max_crumbs: max_crumbs.max(2),
        }
    }

    /// Drops a crumb, unless it is too close to the last (the lead stands still) or older.
    pub fn drop_crumb(&mut self, crumb: Breadcrumb) {
        if let Some(last) = self.crumbs.back() {
            if crumb.capture_step <= last.capture_step
                || last.position_world_m.distance(crumb.position_world_m) < self.min_spacing_m
            {
                return;
            }
        }
        self.crumbs.push_back(crumb);
        while self.crumbs.len() > self.max_crumbs {
            self.crumbs.pop_front();
        }
    }

    /// Eats the crumbs the vehicle at `world_from_vehicle` has passed, keeping the last one
    /// behind it so the path still starts behind the rear axle.
    pub fn eat_passed(&mut self, world_from_vehicle: &Pose) {
        while self.crumbs.len() > 2 {
            let second =
                world_from_vehicle.inverse_transform_point(self.crumbs[1].position_world_m);
            if second.x < 0.0 {
                self.crumbs.pop_front();
            } else {
                break;
            }
        }
    }

    /// The crumbs' positions, oldest first.
    pub fn positions(&self) -> Vec<Vector> {
        self.crumbs.iter().map(|c| c.position_world_m).collect()
    }

    /// The crumbs, oldest first.
    pub fn crumbs(&self) -> impl Iterator<Item = &Breadcrumb> {
        self.crumbs.iter()
    }

    /// The newest crumb.
    pub fn newest(&self) -> Option<&Breadcrumb> {
        self.crumbs.back()
    }

    /// How many crumbs there are.
    pub fn len(&self) -> usize {
        self.crumbs.len()
    }

    /// Whether the trail is empty.
    pub fn is_empty(&self) -> bool {
        self.crumbs.is_empty()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn spacing_and_eating() {
        let mut t = BreadcrumbTrail::new(0.5, 100);
        for i in 0..10u64 {
            t.drop_crumb(Breadcrumb {
                capture_step: Step(i),
                position_world_m: Vector::new(i as f32 * 0.3, 0.0, 0.0),
            });
        }
        // 0, 0.6, 1.2, ... every other crumb kept.
        assert_eq!(t.len(), 5);
        t.eat_passed(&Pose::from_translation(Vector::new(1.5, 0.0, 0.0)));
        assert_eq!(t.positions()[0].x, 1.2);
    }
}
