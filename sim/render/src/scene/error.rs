//! Why a scene could not be built, and the most geometry a renderer's buffer holds.

use thiserror::Error;

/// Why a scene could not be built.
#[derive(Clone, Debug, Error, PartialEq)]
pub enum SceneError {
    /// A field of the description is out of range.
    #[error("scene description: {field} {reason}")]
    Invalid {
        /// The field, as a dotted path.
        field: String,
        /// What is wrong with it.
        reason: String,
    },
    /// The geometry would not fit the renderer's buffers.
    #[error(
        "the scene's geometry needs {bytes} bytes of {buffer}, more than a renderer's buffer \
         holds ({limit}): shorten the route or lower the clutter's densities"
    )]
    TooLarge {
        /// `"vertices"` or `"indices"`.
        buffer: &'static str,
        /// The bytes it needs.
        bytes: u64,
        /// The most a buffer holds ([`MAX_BUFFER_BYTES`]).
        limit: u64,
    },
}

/// The most bytes the renderer's vertex or index buffer may hold: the `max_buffer_size` of
/// the limits it asks its device for (wgpu's WebGL2 downlevel defaults, 256 MiB).
pub const MAX_BUFFER_BYTES: u64 = 1 << 28;
