//! Named, independent random streams split from one seed (`docs/src/conventions.md`,
//! "Randomness and seeds").
//!
//! Each consumer (tree placement, pole placement, sensor noise, ...) draws from its own
//! ChaCha8 stream, selected by hashing the stream's name, so adding clutter of one kind never
//! changes the placement of another kind or the sensor noise.

use rand_chacha::ChaCha8Rng;

/// The random stream called `name` for the scenario seed `seed` (the same streams as the
/// vehicle crate's, [`vehicle::named_stream`]).
pub fn stream(seed: u64, name: &str) -> ChaCha8Rng {
    vehicle::named_stream(seed, name)
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::Rng;

    #[test]
    fn streams_are_reproducible_and_independent() {
        let a: u64 = stream(7, "trees").random();
        let b: u64 = stream(7, "trees").random();
        let c: u64 = stream(7, "poles").random();
        assert_eq!(a, b);
        assert_ne!(a, c);
    }
}
