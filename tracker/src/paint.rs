//! How a target model is painted on the lead vehicle's back: the one paint rule that the
//! renderer (`sim`) and the synthetic frames ([`crate::synth`]) share, so that what the
//! camera sees is the object the tracker models.
//!
//! The board is a light rectangle, the corners' bounding box plus [`BOARD_MARGIN_M`]; every
//! segment is a dark stripe [`STRIPE_WIDTH_M`] wide, centred on the segment and extended
//! [`STRIPE_EXTENSION_M`] past its end points. A stripe gives two parallel edges, one on each
//! side of the segment, whose mean is the segment itself (eq. 12).

/// Margin of the light board beyond the corners' bounding box, metres. The board's own
/// border is a strong edge parallel to the outer segments; 0.25 m puts it 8 px beyond them at
/// the nominal 10 m and 5.3 px at 15 m, outside the default ζ of 4 px, so it does not pull the
/// outer features (and with them the scale) outwards.
pub const BOARD_MARGIN_M: f64 = 0.25;
/// Width of each painted segment, metres: 2 px at the nominal 10 m, so both of a stripe's
/// edges lie within ζ of the segment at every range from 5 to 15 m.
pub const STRIPE_WIDTH_M: f64 = 0.06;
/// How far each stripe runs past its segment's end points, metres, so that stripes meeting
/// at a corner close it.
pub const STRIPE_EXTENSION_M: f64 = 0.03;
