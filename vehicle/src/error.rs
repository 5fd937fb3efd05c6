//! The crate's typed error.

use thiserror::Error;

/// What can go wrong when building vehicles, routes and controllers.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum VehicleError {
    /// A configuration value is out of its allowed range.
    #[error("invalid {field}: {value} ({reason})")]
    InvalidParameter {
        /// The field's name, e.g. `wheelbase_m`.
        field: &'static str,
        /// The offending value.
        value: f64,
        /// Why it is rejected.
        reason: &'static str,
        /// The allowed range `[min, max]`, when the value must lie in one.
        allowed: Option<[f64; 2]>,
    },
    /// A route needs at least two distinct points.
    #[error("route has {points} usable points; at least 2 distinct points are needed")]
    RouteTooShort {
        /// How many distinct points were given.
        points: usize,
    },
    /// A speed profile needs knots in increasing order.
    #[error("speed profile knot {index} at {key} is not after the previous knot")]
    ProfileNotIncreasing {
        /// Index of the bad knot.
        index: usize,
        /// Its key (seconds or metres).
        key: f64,
    },
    /// A speed profile needs at least one knot.
    #[error("speed profile has no knots")]
    ProfileEmpty,
    /// A profile by distance that comes to a stop and then speeds up again: the vehicle
    /// never gets past the stop, so the knots after it are never reached.
    #[error(
        "speed profile by distance stops at knot {index} ({key} m) and speeds up after it: \
         a vehicle that stops there never travels on (script stop-and-go by time)"
    )]
    ProfileStopsForGood {
        /// Index of the knot with speed 0.
        index: usize,
        /// Its key, metres.
        key: f64,
    },
    /// A scripted event is malformed: `field` is its dotted path inside the vehicle's
    /// event list, e.g. `events[2].trigger.to`, for the caller to put under its own
    /// prefix (`lead.` or `actors[0].`).
    #[error("invalid {field}: {reason}")]
    InvalidEvent {
        /// The dotted path of the offending field, e.g. `events[2].trigger.delay_s`.
        field: String,
        /// What is wrong with it (the value, when there is one, and what is allowed).
        reason: String,
    },
    /// A vehicle id that this world did not hand out.
    #[error("no vehicle with id {0}")]
    UnknownVehicle(usize),
}

/// Checks that `value` is finite and inside `[min, max]`.
pub(crate) fn check_range(
    field: &'static str,
    value: f64,
    min: f64,
    max: f64,
) -> Result<(), VehicleError> {
    if value.is_finite() && value >= min && value <= max {
        Ok(())
    } else {
        Err(VehicleError::InvalidParameter {
            field,
            value,
            reason: "out of range or not finite",
            allowed: Some([min, max]),
        })
    }
}
