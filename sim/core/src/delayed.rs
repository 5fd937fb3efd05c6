//! What travels through the delay line from the tracker to the controller: the estimate of
//! one captured frame, as the built-in controller takes it ([`LeadEstimate`]: the 3-D
//! position in the camera frame, f32, with the pan head's reading at capture) and as a
//! plug-in controller takes it ([`Estimate`], with the image location where the tracker
//! gave one).

use crate::plugin::Estimate;
use vehicle::LeadEstimate;

/// One frame's estimate on its way to the controller.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Delayed {
    /// As the built-in controller takes it.
    pub(crate) lead: LeadEstimate,
    /// As the tracker gave it.
    pub(crate) estimate: Estimate,
}
