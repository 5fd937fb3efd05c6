//! A scripted speed: piecewise-linear speed against time or against distance travelled.

use crate::error::VehicleError;
use serde::{Deserialize, Serialize};

/// What a speed profile's keys measure.
#[derive(Copy, Clone, Debug, PartialEq, Eq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum ProfileBasis {
    /// Keys are seconds since the start.
    Time,
    /// Keys are metres travelled along the route.
    Distance,
}

/// The fastest a profile may ask for, m/s.
pub const MAX_SPEED_MPS: f32 = 40.0;
/// The largest key a profile may have, either way (seconds or metres).
pub const MAX_KEY: f32 = 1e7;

/// One knot of a speed profile.
#[derive(Copy, Clone, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct SpeedKnot {
    /// Seconds or metres, by the profile's basis.
    pub key: f32,
    /// Speed at this key, m/s.
    pub speed_mps: f32,
}

/// Speed against time or distance, linear between knots and held beyond the ends.
///
/// A step (two knots at nearly the same key) is how hard braking is scripted: the speed
/// controller then brakes as hard as the vehicle can.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct SpeedProfile {
    /// What the keys measure.
    pub basis: ProfileBasis,
    /// The knots, keys strictly increasing.
    pub knots: Vec<SpeedKnot>,
}

impl SpeedProfile {
    /// A checked profile from `(key, speed_mps)` pairs.
    pub fn new(basis: ProfileBasis, knots: &[(f32, f32)]) -> Result<SpeedProfile, VehicleError> {
        let profile = SpeedProfile {
            basis,
            knots: knots
                .iter()
                .map(|&(key, speed_mps)| SpeedKnot { key, speed_mps })
                .collect(),
        };
        profile.validate()?;
        Ok(profile)
    }

    /// A constant speed.
    pub fn constant(speed_mps: f32) -> SpeedProfile {
        SpeedProfile {
            basis: ProfileBasis::Time,
            knots: vec![SpeedKnot {
                key: 0.0,
                speed_mps,
            }],
        }
    }

    /// Checks the knots: at least one, keys strictly increasing and within ±`MAX_KEY`,
    /// speeds 0–`MAX_SPEED_MPS`; by distance, no stop followed by more driving (the
    /// vehicle would wait at the stop for good).
    pub fn validate(&self) -> Result<(), VehicleError> {
        if self.knots.is_empty() {
            return Err(VehicleError::ProfileEmpty);
        }
        for (i, k) in self.knots.iter().enumerate() {
            if !(k.speed_mps.is_finite() && (0.0..=MAX_SPEED_MPS).contains(&k.speed_mps)) {
                return Err(VehicleError::InvalidParameter {
                    field: "speed_mps",
                    value: f64::from(k.speed_mps),
                    reason: "speeds must be finite, not negative and at most 40 m/s",
                    allowed: Some([0.0, f64::from(MAX_SPEED_MPS)]),
                });
            }
            if !(k.key.is_finite() && k.key.abs() <= MAX_KEY) {
                return Err(VehicleError::InvalidParameter {
                    field: "key",
                    value: f64::from(k.key),
                    reason: "keys must be finite and within ±1e7 (s or m)",
                    allowed: Some([-f64::from(MAX_KEY), f64::from(MAX_KEY)]),
                });
            }
            if i > 0 && k.key <= self.knots[i - 1].key {
                return Err(VehicleError::ProfileNotIncreasing {
                    index: i,
                    key: f64::from(k.key),
                });
            }
        }
        if self.basis == ProfileBasis::Distance {
            if let Some(index) = self.knots.iter().position(|k| k.speed_mps == 0.0) {
                if self.knots[index..].iter().any(|k| k.speed_mps > 0.0) {
                    return Err(VehicleError::ProfileStopsForGood {
                        index,
                        key: f64::from(self.knots[index].key),
                    });
                }
            }
        }
        Ok(())
    }

    /// Speed at `key` (seconds or metres), m/s.
    pub fn speed_at(&self, key: f32) -> f32 {
        self.sample(key).0
    }

    /// Speed at `key` and its slope d(speed)/d(key) there.
    pub fn sample(&self, key: f32) -> (f32, f32) {
        let k = &self.knots;
        let i = k.partition_point(|n| n.key <= key);
        if i == 0 {
            return (k[0].speed_mps, 0.0);
        }
        if i == k.len() {
            return (k[k.len() - 1].speed_mps, 0.0);
        }
        let (a, b) = (k[i - 1], k[i]);
        let slope = (b.speed_mps - a.speed_mps) / (b.key - a.key);
        (a.speed_mps + slope * (key - a.key), slope)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn interpolates_and_holds() {
        let p = SpeedProfile::new(ProfileBasis::Time, &[(0.0, 0.0), (10.0, 10.0)]).unwrap();
        assert_eq!(p.speed_at(-1.0), 0.0);
        assert_eq!(p.speed_at(5.0), 5.0);
        assert_eq!(p.sample(5.0).1, 1.0);
        assert_eq!(p.speed_at(20.0), 10.0);
    }

    #[test]
    fn rejects_unordered_knots() {
        assert!(SpeedProfile::new(ProfileBasis::Time, &[(1.0, 0.0), (1.0, 2.0)]).is_err());
    }

    #[test]
    fn rejects_speeds_and_keys_out_of_range() {
        for knots in [
            [(0.0, 41.0)],
            [(0.0, -1.0)],
            [(2e7, 5.0)],
            [(0.0, f32::NAN)],
        ] {
            assert!(
                matches!(
                    SpeedProfile::new(ProfileBasis::Time, &knots),
                    Err(VehicleError::InvalidParameter { .. })
                ),
                "{knots:?}"
            );
        }
        assert!(SpeedProfile::new(ProfileBasis::Time, &[(0.0, 40.0)]).is_ok());
    }

    /// By distance, a stop before more driving strands the vehicle; by time it is
    /// stop-and-go, and a stop at the end is a stop.
    #[test]
    fn a_stop_by_distance_must_be_the_last() {
        let stop_and_go = [(0.0, 8.0), (100.0, 0.0), (105.0, 6.0)];
        assert_eq!(
            SpeedProfile::new(ProfileBasis::Distance, &stop_and_go),
            Err(VehicleError::ProfileStopsForGood {
                index: 1,
                key: 100.0
            })
        );
        assert!(SpeedProfile::new(ProfileBasis::Time, &stop_and_go).is_ok());
        let stop = [(0.0, 8.0), (100.0, 0.0), (150.0, 0.0)];
        assert!(SpeedProfile::new(ProfileBasis::Distance, &stop).is_ok());
    }
}
