//! The range errors of a run's tracked frames, for `summary.json`'s `range_error_m`: their
//! mean and their exact nearest-rank 95th percentile, in bounded memory.
//!
//! The mean is a running sum. The percentile needs every value, so the values go to disk as
//! they come: up to [`BLOCK`] of them stay in memory (a run of up to 73 minutes at 15 Hz
//! never touches the disk), and beyond that they are written a block at a time to an
//! anonymous temporary file. At the end the percentile is selected from the file by radix
//! passes over the values' bits (for non-negative floats the bits order as the values do):
//! each pass counts the values under the prefix found so far by their next 16 bits, and
//! once few enough values share the prefix they are read in, sorted and ranked. The result
//! is the value a sort of all of them would give, bit for bit.

use std::fs::File;
use std::io::{BufReader, Read, Seek, SeekFrom, Write};

/// Values kept in memory before they go to disk: 65 536 (512 KiB).
const BLOCK: usize = 1 << 16;

/// The radix of a selection pass: 16 bits, so a pass's counts take 512 KiB.
const RADIX_BITS: u32 = 16;

/// The absolute range errors of the tracked frames, in the order they came.
#[derive(Debug)]
pub(super) struct RangeErrors {
    count: u64,
    sum: f64,
    /// The values not yet written out.
    block: Vec<f64>,
    /// Where full blocks went, and how many values it holds.
    spill: Option<(File, u64)>,
    /// Values kept before spilling, and the most values a selection sorts in memory:
    /// [`BLOCK`], smaller in tests.
    block_len: usize,
}

impl Default for RangeErrors {
    fn default() -> RangeErrors {
        RangeErrors::with_block(BLOCK)
    }
}

impl RangeErrors {
    fn with_block(block_len: usize) -> RangeErrors {
        RangeErrors {
            count: 0,
            sum: 0.0,
            block: Vec::new(),
            spill: None,
            block_len: block_len.max(1),
        }
    }

    /// Takes the next error: finite and not negative.
    pub fn push(&mut self, e: f64) {
        debug_assert!(e.is_finite() && e >= 0.0, "range error {e}");
        self.count += 1;
        self.sum += e;
        self.block.push(e);
        if self.block.len() >= self.block_len {
            self.write_out();
        }
    }

    /// Writes the block to the spill file. Where the file cannot be made or written, the
    /// values stay in memory (the run goes on; only its memory grows).
    fn write_out(&mut self) {
        if self.spill.is_none() {
            match tempfile::tempfile() {
                Ok(file) => self.spill = Some((file, 0)),
                Err(_) => {
                    self.block_len = usize::MAX;
                    return;
                }
            }
        }
        let Some((file, written)) = &mut self.spill else {
            return;
        };
        let bytes: Vec<u8> = self.block.iter().flat_map(|v| v.to_le_bytes()).collect();
        if file.write_all(&bytes).is_ok() {
            *written += self.block.len() as u64;
            self.block.clear();
        } else {
            // What was written of this block is cut off; it and the rest stay in memory.
            let _ = file.set_len(*written * 8);
            self.block_len = usize::MAX;
        }
    }

    /// How many errors were taken.
    pub fn count(&self) -> u64 {
        self.count
    }

    /// Their mean (summed in order), and their nearest-rank 95th percentile (`None` only if
    /// the spill file cannot be read back); `None` for no errors.
    pub fn finish(self) -> Option<(f64, Option<f64>)> {
        if self.count == 0 {
            return None;
        }
        let mean = self.sum / self.count as f64;
        let rank = ((0.95 * self.count as f64).ceil() as u64).clamp(1, self.count);
        if self.spill.is_none() {
            let mut sorted = self.block;
            sorted.sort_by(f64::total_cmp);
            return Some((mean, Some(sorted[rank as usize - 1])));
        }
        Some((mean, self.select(rank).ok()))
    }

    /// Calls `f` with the bits of every value: the file's, then the block's.
    fn for_each(&self, f: &mut dyn FnMut(u64)) -> std::io::Result<()> {
        if let Some((file, written)) = &self.spill {
            let mut file = file;
            file.seek(SeekFrom::Start(0))?;
            let mut reader = BufReader::with_capacity(1 << 16, file);
            let mut bytes = [0u8; 8];
            for _ in 0..*written {
                reader.read_exact(&mut bytes)?;
                f(u64::from_le_bytes(bytes));
            }
        }
        for v in &self.block {
            f(v.to_bits());
        }
        Ok(())
    }

    /// The value of 1-based `rank` in ascending order, among the file's values and the
    /// block's.
    fn select(&self, mut rank: u64) -> std::io::Result<f64> {
        // The values whose top `fixed` bits are `prefix`'s hold the rank (at `rank` among
        // them); `within` is how many they are.
        let (mut prefix, mut fixed, mut within) = (0u64, 0u32, self.count);
        let under = |bits: u64, prefix: u64, fixed: u32| {
            fixed == 0 || bits >> (64 - fixed) == prefix >> (64 - fixed)
        };
        while fixed < 64 && within > self.block_len as u64 {
            let shift = 64 - fixed - RADIX_BITS;
            let mut counts = vec![0u64; 1 << RADIX_BITS];
            self.for_each(&mut |bits| {
                if under(bits, prefix, fixed) {
                    counts[((bits >> shift) & ((1 << RADIX_BITS) - 1)) as usize] += 1;
                }
            })?;
            let mut digit = 0;
            while rank > counts[digit] {
                rank -= counts[digit];
                digit += 1;
            }
            within = counts[digit];
            prefix |= (digit as u64) << shift;
            fixed += RADIX_BITS;
        }
        if fixed == 64 {
            return Ok(f64::from_bits(prefix));
        }
        let mut candidates = Vec::with_capacity(within as usize);
        self.for_each(&mut |bits| {
            if under(bits, prefix, fixed) {
                candidates.push(f64::from_bits(bits));
            }
        })?;
        candidates.sort_by(f64::total_cmp);
        Ok(candidates[rank as usize - 1])
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand::{Rng, SeedableRng};
    use rand_chacha::ChaCha8Rng;

    /// What a sort of everything gives: the mean summed in order and the nearest-rank 95th
    /// percentile.
    fn sorted(values: &[f64]) -> (f64, f64) {
        let mean = values.iter().sum::<f64>() / values.len() as f64;
        let mut s = values.to_vec();
        s.sort_by(f64::total_cmp);
        let rank = ((0.95 * s.len() as f64).ceil() as usize).clamp(1, s.len());
        (mean, s[rank - 1])
    }

    fn check(values: &[f64], block: usize) {
        let mut errors = RangeErrors::with_block(block);
        for &v in values {
            errors.push(v);
        }
        let spilled = errors.spill.is_some();
        assert_eq!(spilled, values.len() >= block, "spilled {spilled}");
        let (mean, p95) = errors.finish().unwrap();
        let (want_mean, want_p95) = sorted(values);
        assert_eq!(mean.to_bits(), want_mean.to_bits(), "mean");
        assert_eq!(
            p95.unwrap().to_bits(),
            want_p95.to_bits(),
            "{} values, block {block}",
            values.len()
        );
    }

    #[test]
    fn the_percentile_from_disk_is_the_sorted_ones() {
        let mut rng = ChaCha8Rng::seed_from_u64(7);
        for n in [1usize, 2, 19, 20, 21, 999, 5000] {
            // Spread over decades, with exact zeros and repeats.
            let values: Vec<f64> = (0..n)
                .map(|_| match rng.random_range(0..10) {
                    0 => 0.0,
                    1 => 0.25,
                    _ => 10f64.powf(rng.random_range(-6.0..2.0)),
                })
                .collect();
            for block in [1, 3, 64, 4096, 1 << 16] {
                check(&values, block);
            }
        }
    }

    #[test]
    fn values_that_share_their_leading_bits_are_still_ranked_exactly() {
        let mut rng = ChaCha8Rng::seed_from_u64(3);
        // Values a few ulps apart, all under one 48-bit prefix; and all equal.
        let close: Vec<f64> = (0..3000)
            .map(|_| f64::from_bits(0.13f64.to_bits() + rng.random_range(0..40)))
            .collect();
        let equal = vec![0.2; 3000];
        for values in [close, equal] {
            for block in [1, 7, 100] {
                check(&values, block);
            }
        }
    }

    #[test]
    fn no_errors_give_nothing() {
        assert!(RangeErrors::default().finish().is_none());
    }
}
