//! The follower's own lane ahead, as a tracker in traffic is told it.

/// The follower's lane ahead, in the camera frame at the frame's capture: what a
/// lane-keeping assist knows from its map and its place in its lane. The loop gives it to
/// the tracker in traffic ([`super::TrackerInput::lane`]) so that the tracker acquires the
/// vehicle in the lane, not one beside it, and lets go of a target that leaves the lane.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct LaneAhead {
    /// Points of the lane's centre line on the ground, `[x, y, z]` in the camera frame
    /// (x right, y down, z forward), metres, by increasing z.
    pub centre_m: Vec<[f64; 3]>,
    /// Half the lane's width, metres.
    pub half_width_m: f64,
}

impl LaneAhead {
    /// The lane's centre on the ground, `[x, y]` metres in the camera frame, at range
    /// `z_m`: interpolated between the points about it; `None` before the first point or
    /// beyond the last.
    pub fn centre_at(&self, z_m: f64) -> Option<[f64; 2]> {
        let i = self.centre_m.partition_point(|p| p[2] < z_m);
        if i == self.centre_m.len() || !z_m.is_finite() {
            return None;
        }
        let b = self.centre_m[i];
        if i == 0 {
            return (z_m == b[2]).then_some([b[0], b[1]]);
        }
        let a = self.centre_m[i - 1];
        let t = (z_m - a[2]) / (b[2] - a[2]);
        Some([a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])])
    }

    /// The lane's centre, `x` metres in the camera frame, at range `z_m` (see
    /// [`LaneAhead::centre_at`]).
    pub fn centre_x_m(&self, z_m: f64) -> Option<f64> {
        self.centre_at(z_m).map(|[x, _]| x)
    }

    /// How far right of the lane's centre a point at `[x, z]` in the camera frame lies,
    /// metres; `None` where the lane is not known.
    pub fn offset_m(&self, x_m: f64, z_m: f64) -> Option<f64> {
        self.centre_x_m(z_m).map(|c| x_m - c)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn offsets_are_from_the_centre_between_points() {
        let lane = LaneAhead {
            centre_m: vec![[0.0, 1.5, 5.0], [1.0, 1.3, 15.0], [3.0, 1.1, 25.0]],
            half_width_m: 1.75,
        };
        assert_eq!(lane.centre_x_m(10.0), Some(0.5));
        assert_eq!(lane.centre_at(20.0), Some([2.0, 1.2000000000000002]));
        assert_eq!(lane.offset_m(2.5, 20.0), Some(0.5));
        assert_eq!(lane.centre_x_m(5.0), Some(0.0));
        assert_eq!(lane.centre_x_m(4.9), None);
        assert_eq!(lane.centre_x_m(25.1), None);
        assert_eq!(lane.centre_x_m(f64::NAN), None);
    }
}
