//! How a target model is painted on the lead vehicle's back: the one paint rule that the
//! renderer (`sim`) and the synthetic frames ([`crate::synth`]) share, so that what the
//! camera sees is the object the tracker models.
//!
//! The board is a light rectangle, the corners' bounding box plus [`BOARD_MARGIN_M`]; every
//! segment is a dark stripe [`STRIPE_WIDTH_M`] wide, centred on the segment and extended
//! [`STRIPE_EXTENSION_M`] past its end points. A stripe gives two parallel edges, one on each
//! side of the segment, whose mean is the segment itself (eq. 12).

/// Margin of the light board beyond the corners' bounding box, metres. The board's own
/// border is a strong edge parallel to the outer segments (section 4's second failure mode,
/// on the target itself): 0.35 m puts it 11 px beyond them at the nominal 10 m and 7.5 px at
/// 15 m, so only a prediction more than 3.5 px off brings it within the default ζ of 4 px.
/// Once it is within ζ it pulls the outer features, and with them the scale, outwards, the
/// next prediction brings it nearer still, and the track runs away to the border: with a
/// 0.25 m margin (5.8 px at 14 m) that happened in bends on every seed of the 17-minute tape
/// tried (7 of 7), with 0.35 m on none.
pub const BOARD_MARGIN_M: f64 = 0.35;
/// Width of each painted segment, metres: 2 px at the nominal 10 m, so both of a stripe's
/// edges lie within ζ of the segment at every range from 5 to 15 m.
pub const STRIPE_WIDTH_M: f64 = 0.06;
/// How far each stripe runs past its segment's end points, metres, so that stripes meeting
/// at a corner close it.
pub const STRIPE_EXTENSION_M: f64 = 0.03;
