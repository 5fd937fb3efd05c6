//! The sensor's noise and blur, applied to the rendered (already gain- and
//! exposure-scaled) image on the CPU.

use crate::scene::{stream, Sensor};
use image::GrayImage;
use rand::RngCore;

/// Random words the noise stream reserves per frame: two, the seed of that frame's
/// pixel generator. (ChaCha8 per pixel costs ~0.7 ms a frame, a quarter of the budget.)
const WORDS_PER_FRAME: u128 = 2;

/// Standard deviation of the sum of four independent uniform bytes (each 0..=255):
/// `sqrt(4 · (256² − 1) / 12)`. Such a sum is Gaussian to within 1 % of sigma out to 2.5 σ
/// (Irwin–Hall), and costs one 32-bit random word per pixel instead of a logarithm.
const SUM4_SIGMA: f32 = 147.800_54;

/// Applies blur (optical, so first) and then additive Gaussian noise to `image`, in place.
/// Frame `frame_index`'s noise is a fixed slice of the `"sensor-noise"` stream of `seed`.
pub fn apply_sensor(image: &mut GrayImage, sensor: &Sensor, seed: u64, frame_index: u64) {
    if let Some(sigma) = sensor.blur_sigma_px {
        blur(image, sigma);
    }
    if sensor.noise_sigma_grey <= 0.0 {
        return;
    }
    let mut rng = stream(seed, "sensor-noise");
    rng.set_word_pos(u128::from(frame_index) * WORDS_PER_FRAME);
    let k = sensor.noise_sigma_grey as f32 / SUM4_SIGMA;
    // SplitMix64 seeded from the frame's ChaCha8 words: fast, and statistically ample for
    // pixel noise; 64 bits give two pixels' four bytes each.
    let mut state = rng.next_u64();
    let mut next = || {
        state = state.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = state;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    };
    let noise = |word: u32, pixel: &mut u8| {
        let [a, b, c, d] = word.to_le_bytes();
        let sum = i32::from(a) + i32::from(b) + i32::from(c) + i32::from(d) - 510;
        let value = f32::from(*pixel) + k * sum as f32;
        *pixel = value.round().clamp(0.0, 255.0) as u8;
    };
    for pair in image.chunks_mut(2) {
        let word = next();
        for (i, pixel) in pair.iter_mut().enumerate() {
            noise((word >> (32 * i)) as u32, pixel);
        }
    }
}

/// Separable Gaussian blur with standard deviation `sigma` pixels, edges clamped.
fn blur(image: &mut GrayImage, sigma: f64) {
    let radius = (2.5 * sigma).ceil().max(1.0) as i64;
    let weights: Vec<f32> = (-radius..=radius)
        .map(|k| (-(k * k) as f64 / (2.0 * sigma * sigma)).exp() as f32)
        .collect();
    let total: f32 = weights.iter().sum();
    let (w, h) = (image.width() as i64, image.height() as i64);
    let src: Vec<f32> = image.iter().map(|&p| f32::from(p)).collect();
    let mut tmp = vec![0f32; src.len()];
    for y in 0..h {
        for x in 0..w {
            let mut acc = 0.0;
            for (i, wt) in weights.iter().enumerate() {
                let xx = (x + i as i64 - radius).clamp(0, w - 1);
                acc += wt * src[(y * w + xx) as usize];
            }
            tmp[(y * w + x) as usize] = acc / total;
        }
    }
    for y in 0..h {
        for x in 0..w {
            let mut acc = 0.0;
            for (i, wt) in weights.iter().enumerate() {
                let yy = (y + i as i64 - radius).clamp(0, h - 1);
                acc += wt * tmp[(yy * w + x) as usize];
            }
            image.as_mut()[(y * w + x) as usize] = (acc / total).round().clamp(0.0, 255.0) as u8;
        }
    }
}
