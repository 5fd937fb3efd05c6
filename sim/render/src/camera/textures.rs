//! Procedural ground textures: asphalt, grass blades and gravel, generated on the CPU when a
//! renderer is set up, from the scene's seed (the `"ground-textures"` stream), so the same
//! seed gives the same texels bit for bit.
//!
//! Each layer is a square, tiling (wrap-around) field of detail factors with mean 1: the
//! main pass multiplies a ground surface's albedo by the layer's trilinear sample at its
//! world position, so surfaces keep their mean grey and gain the texture's gradients. Each
//! layer has a full mip chain, every level the 2×2 box average of the level above, and
//! travels to the GPU as 8-bit texels holding half the factor (0–2).

use crate::scene::stream;
use rand::Rng;
use rand_chacha::ChaCha8Rng;

/// Side of every layer's finest level, texels.
pub const TEXTURE_SIZE: usize = 512;
/// Mip levels of each layer, down to 1×1.
pub const LEVEL_COUNT: usize = TEXTURE_SIZE.trailing_zeros() as usize + 1;

/// The layers of the texture array, in order.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TextureLayer {
    /// Asphalt: 1 cm aggregate grain with a heavy tail, patchiness at a metre or two, and
    /// thin dark meandering tar lines (sealed cracks).
    Asphalt = 0,
    /// Grass: blades 2 mm wide and 3–10 cm long over dark gaps.
    Grass = 1,
    /// Gravel: stones 2–8 cm across, light and dark, over darker fines.
    Gravel = 2,
}

/// How many layers the array holds.
pub const LAYERS: usize = 3;

/// Side of one tile of each layer on the ground, metres (in [`TextureLayer`] order): the
/// asphalt's texel is 1 cm, the grass's 2 mm, the gravel's 5 mm.
pub const TILE_M: [f64; LAYERS] = [5.12, 1.024, 2.56];

/// The generated layers: per layer, its mip levels from the finest (side
/// [`TEXTURE_SIZE`]) to 1×1, each row-major, as detail factors (mean 1, within 0–2).
#[derive(Clone, Debug, PartialEq)]
pub struct GroundTextures {
    /// `levels[layer][level]`: `(TEXTURE_SIZE >> level)²` factors.
    pub levels: Vec<Vec<Vec<f32>>>,
}

impl GroundTextures {
    /// Generates every layer from the scene seed `seed`.
    pub fn generate(seed: u64) -> GroundTextures {
        let mut rng = stream(seed, "ground-textures");
        let n = TEXTURE_SIZE;
        let finest = [
            asphalt(&mut rng, n),
            grass(&mut rng, n),
            gravel(&mut rng, n),
        ];
        GroundTextures {
            levels: finest
                .into_iter()
                .map(|level| mip_chain(normalised(level), n))
                .collect(),
        }
    }

    /// How many mip levels each layer has (down to 1×1).
    pub fn level_count(&self) -> u32 {
        self.levels[0].len() as u32
    }

    /// Level `level` of every layer as 8-bit texels (half the factor, so 0–255 is 0–2),
    /// layer after layer: what the texture array's level holds.
    pub fn texels(&self, level: usize) -> Vec<u8> {
        let mut out = Vec::with_capacity(self.levels.len() * self.levels[0][level].len());
        for layer in &self.levels {
            out.extend(layer[level].iter().map(|&v| quantise(v)));
        }
        out
    }
}

/// A detail factor (0–2) as an 8-bit unsigned-normalised texel.
pub fn quantise(v: f32) -> u8 {
    // Rounded half away from zero, as `f64::round`: the product of an f32 and 127.5 is
    // exact in f64, and so is adding a half to it wherever that could round up; the cast
    // saturates at 0 and 255 (and takes NaN to 0).
    let x = f64::from(v) * 127.5;
    if x >= 0.0 {
        (x + 0.5) as u8
    } else {
        0
    }
}

/// The mip chain of a square `n × n` level (`n` a power of two): the level itself, then
/// each level the 2×2 box average of the one above, down to 1×1.
pub fn mip_chain(level0: Vec<f32>, n: usize) -> Vec<Vec<f32>> {
    let mut levels = vec![level0];
    let mut side = n;
    while side > 1 {
        let above = levels.last().expect("one level");
        let half = side / 2;
        let mut next = Vec::with_capacity(half * half);
        for rows in above.chunks_exact(2 * side) {
            let (upper, lower) = rows.split_at(side);
            for (u, l) in upper.chunks_exact(2).zip(lower.chunks_exact(2)) {
                next.push(0.25 * (u[0] + u[1] + l[0] + l[1]));
            }
        }
        levels.push(next);
        side = half;
    }
    levels
}

/// Scaled to mean 1 and clipped to what a texel holds (0–2), then scaled to mean 1 again
/// (the clipping moves the mean by a fraction of a percent at most).
fn normalised(mut level: Vec<f64>) -> Vec<f32> {
    let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len() as f64;
    let m = mean(&level);
    for v in &mut level {
        *v = (*v / m).clamp(0.0, 2.0);
    }
    let m = mean(&level);
    level
        .iter()
        .map(|v| (v / m).min(2.0 - 1.0 / 255.0) as f32)
        .collect()
}

/// A smooth, tiling value noise on an `n × n` grid: random values, zero mean and unit
/// spread, on a `cells × cells` lattice (`cells` divides `n`), interpolated with a
/// smoothstep.
fn value_noise(rng: &mut ChaCha8Rng, n: usize, cells: usize) -> Vec<f64> {
    let lattice: Vec<f64> = (0..cells * cells)
        .map(|_| rng.random_range(-1.0..1.0) * 3f64.sqrt())
        .collect();
    let at = |i: usize, j: usize| lattice[(j % cells) * cells + i % cells];
    let pitch = n / cells;
    // The smoothstep of each offset within a cell, the same along x and y.
    let s = |t: f64| t * t * (3.0 - 2.0 * t);
    let weights: Vec<f64> = (0..pitch).map(|r| s(r as f64 / pitch as f64)).collect();
    let mut out = Vec::with_capacity(n * n);
    for y in 0..n {
        let (j, fy) = (y / pitch, weights[y % pitch]);
        for i in 0..n / pitch {
            let (a0, a1) = (at(i, j), at(i + 1, j));
            let (b0, b1) = (at(i, j + 1), at(i + 1, j + 1));
            for &fx in &weights {
                let a = a0 + (a1 - a0) * fx;
                let b = b0 + (b1 - b0) * fx;
                out.push(a + (b - a) * fy);
            }
        }
    }
    out
}

/// A sample of the Laplace distribution of unit scale: the heavy-ish tail of aggregate.
fn laplace(rng: &mut ChaCha8Rng) -> f64 {
    let u: f64 = rng.random_range(-0.5..0.5);
    -u.signum() * (1.0 - 2.0 * u.abs()).max(1e-12).ln()
}

/// Wrap-around index of texel `(x, y)` in an `n × n` grid.
fn wrap(n: usize, x: i64, y: i64) -> usize {
    let n = n as i64;
    // Coordinates stray less than a tile beyond it: a subtraction or addition, not a
    // division, in all but the rarest case.
    let within = |v: i64| {
        if v < 0 {
            if v >= -n {
                v + n
            } else {
                v.rem_euclid(n)
            }
        } else if v >= n {
            if v < 2 * n {
                v - n
            } else {
                v.rem_euclid(n)
            }
        } else {
            v
        }
    };
    (within(y) * n + within(x)) as usize
}

/// Asphalt at 1 cm a texel: aggregate grain (Laplace, 8 % spread, with a 2 % chance of a
/// light stone), patches of ±6 % and ±3 % at 1.3 m and 0.6 m, and 6 dark tar lines a tile.
fn asphalt(rng: &mut ChaCha8Rng, n: usize) -> Vec<f64> {
    let broad = value_noise(rng, n, 4);
    let fine = value_noise(rng, n, 8);
    let mut v: Vec<f64> = (0..n * n)
        .map(|k| {
            let mut grain = 0.08 * laplace(rng);
            if rng.random_bool(0.02) {
                grain += rng.random_range(0.2..0.5);
            }
            (1.0 + 0.06 * broad[k] + 0.03 * fine[k]) * (1.0 + grain).max(0.3)
        })
        .collect();
    // Sealed cracks: random walks 1.5–4 m long whose heading drifts, 1–2 cm wide, about
    // half as bright as the asphalt around them.
    for _ in 0..6 {
        let (mut x, mut y) = (
            rng.random_range(0.0..n as f64),
            rng.random_range(0.0..n as f64),
        );
        let mut heading: f64 = rng.random_range(0.0..std::f64::consts::TAU);
        let steps = rng.random_range(150..400);
        let half_width: f64 = rng.random_range(0.5..1.0);
        let darkness = rng.random_range(0.4..0.6);
        for _ in 0..steps {
            heading += rng.random_range(-0.25..0.25);
            x += heading.cos();
            y += heading.sin();
            let r = half_width.ceil() as i64;
            for dy in -r..=r {
                for dx in -r..=r {
                    let (px, py) = (x.floor() as i64 + dx, y.floor() as i64 + dy);
                    let d = ((px as f64 + 0.5 - x).powi(2) + (py as f64 + 0.5 - y).powi(2)).sqrt();
                    if d <= half_width + 0.5 {
                        let k = wrap(n, px, py);
                        v[k] = v[k].min(darkness);
                    }
                }
            }
        }
    }
    v
}

/// Grass at 2 mm a texel: dark gaps (0.55, with a 10 % spread) under 9000 blades, each a
/// line 1 texel wide and 15–50 texels (3–10 cm) long, of brightness 0.9–1.6, leaning
/// mostly one way as mown grass does.
fn grass(rng: &mut ChaCha8Rng, n: usize) -> Vec<f64> {
    let mut v: Vec<f64> = (0..n * n)
        .map(|_| 0.55 * (1.0 + 0.1 * rng.random_range(-1.0..1.0)))
        .collect();
    let lean = rng.random_range(0.0..std::f64::consts::TAU);
    for _ in 0..9000 {
        let (x, y) = (
            rng.random_range(0.0..n as f64),
            rng.random_range(0.0..n as f64),
        );
        let heading = lean + rng.random_range(-0.8..0.8);
        let length: f64 = rng.random_range(15.0..50.0);
        let bright = rng.random_range(0.9..1.6);
        let (c, s) = (heading.cos(), heading.sin());
        let mut t = 0.0;
        while t < length {
            // Blades taper: brightest at the middle.
            let along = 1.0 - 0.3 * (2.0 * t / length - 1.0).abs();
            let k = wrap(n, (x + t * c).floor() as i64, (y + t * s).floor() as i64);
            v[k] = bright * along;
            t += 0.7;
        }
    }
    v
}

/// Gravel at 5 mm a texel: fines (0.6, with a 15 % spread) under 14 000 stones, discs of
/// radius 2–8 texels (1–4 cm), each of its own brightness 0.5–1.5, lit from one side.
fn gravel(rng: &mut ChaCha8Rng, n: usize) -> Vec<f64> {
    let mut v: Vec<f64> = (0..n * n)
        .map(|_| 0.6 * (1.0 + 0.15 * rng.random_range(-1.0..1.0)))
        .collect();
    let light = [
        std::f64::consts::FRAC_1_SQRT_2,
        -std::f64::consts::FRAC_1_SQRT_2,
    ];
    for _ in 0..14_000 {
        let (x, y) = (
            rng.random_range(0.0..n as f64),
            rng.random_range(0.0..n as f64),
        );
        let r: f64 = rng.random_range(2.0..8.0);
        let bright = rng.random_range(0.5..1.5);
        let ri = r.ceil() as i64;
        let (fx, fy) = (x.fract(), y.fract());
        let (cx, cy) = (x.floor() as i64, y.floor() as i64);
        for dy in -ri..=ri {
            let oy = dy as f64 + 0.5 - fy;
            // No texel of a row farther than the radius is inside (adding ox² cannot
            // bring the sum back under it).
            if oy * oy > r * r {
                continue;
            }
            for dx in -ri..=ri {
                let ox = dx as f64 + 0.5 - fx;
                let d2 = ox * ox + oy * oy;
                if d2 <= r * r {
                    let shade = 1.0 + 0.25 * (ox * light[0] + oy * light[1]) / r;
                    v[wrap(n, cx + dx, cy + dy)] = bright * shade;
                }
            }
        }
    }
    v
}

#[cfg(test)]
mod tests {
    use super::*;

    fn mean(v: &[f32]) -> f64 {
        v.iter().map(|&x| f64::from(x)).sum::<f64>() / v.len() as f64
    }

    #[test]
    fn wrapping_and_quantising_agree_with_their_plain_definitions() {
        let n = 512usize;
        for y in [
            -5000i64, -1025, -513, -512, -511, -1, 0, 1, 511, 512, 513, 1023, 1024, 7000,
        ] {
            for x in [-3000i64, -512, -3, 0, 5, 511, 512, 1023, 1024, 5000] {
                let plain = (y.rem_euclid(512) * 512 + x.rem_euclid(512)) as usize;
                assert_eq!(wrap(n, x, y), plain, "({x}, {y})");
            }
        }
        let plain = |v: f32| (f64::from(v) * 127.5).round().clamp(0.0, 255.0) as u8;
        let mut values: Vec<f32> = (0..=600_000)
            .map(|k| k as f32 * (2.1 / 600_000.0))
            .collect();
        // Exact halves (k + 0.5) / 127.5, their neighbours, and values out of range.
        for k in 0..256 {
            let half = (k as f32 + 0.5) / 127.5;
            values.extend([half, half.next_down(), half.next_up()]);
        }
        values.extend([-1.0, -0.001, 0.0, 2.0, 2.5, 1e9, f32::NAN, f32::INFINITY]);
        for v in values {
            assert_eq!(quantise(v), plain(v), "{v}");
        }
    }

    #[test]
    fn generation_is_deterministic_and_seed_dependent() {
        let a = GroundTextures::generate(3);
        assert_eq!(a, GroundTextures::generate(3));
        let b = GroundTextures::generate(4);
        for layer in 0..LAYERS {
            assert_ne!(a.levels[layer][0], b.levels[layer][0], "layer {layer}");
        }
    }

    #[test]
    fn mip_levels_are_box_averages_of_the_level_above() {
        let t = GroundTextures::generate(1);
        assert_eq!(t.level_count(), TEXTURE_SIZE.trailing_zeros() + 1);
        for layer in &t.levels {
            for (k, pair) in layer.windows(2).enumerate() {
                let (above, below) = (&pair[0], &pair[1]);
                let side = TEXTURE_SIZE >> k;
                assert_eq!(above.len(), side * side);
                assert_eq!(below.len(), side * side / 4);
                for y in 0..side / 2 {
                    for x in 0..side / 2 {
                        let box_mean = (above[2 * y * side + 2 * x]
                            + above[2 * y * side + 2 * x + 1]
                            + above[(2 * y + 1) * side + 2 * x]
                            + above[(2 * y + 1) * side + 2 * x + 1])
                            / 4.0;
                        assert!((below[y * side / 2 + x] - box_mean).abs() < 1e-6);
                    }
                }
            }
            // Every level keeps the mean, and the 8-bit texels hold it to within a level.
            let texels: Vec<f32> = layer[0]
                .iter()
                .map(|&v| f32::from(quantise(v)) / 127.5)
                .collect();
            assert!((mean(&texels) - mean(&layer[0])).abs() < 2.0 / 255.0);
            assert!((mean(layer.last().unwrap()) - mean(&layer[0])).abs() < 1e-4);
        }
    }

    /// The asphalt's statistics: mean 1; at 1 cm, texel-to-texel differences of 10–30 %
    /// (RMS) with a heavy tail (kurtosis above 4, a Gaussian's is 3); a spread of 2–12 %
    /// between 0.64 m blocks (the patchiness); and tar lines: 0.2–3 % of texels below 0.65.
    #[test]
    fn asphalt_has_realistic_gradient_statistics() {
        let t = GroundTextures::generate(1);
        let a = &t.levels[TextureLayer::Asphalt as usize];
        let level = &a[0];
        let n = TEXTURE_SIZE;
        assert!((mean(level) - 1.0).abs() < 1e-3, "mean {}", mean(level));
        let diffs: Vec<f64> = (0..n * n)
            .map(|k| f64::from(level[k] - level[(k / n) * n + (k % n + 1) % n]))
            .collect();
        let m2 = diffs.iter().map(|d| d * d).sum::<f64>() / diffs.len() as f64;
        let m4 = diffs.iter().map(|d| d.powi(4)).sum::<f64>() / diffs.len() as f64;
        let (rms, kurtosis) = (m2.sqrt(), m4 / (m2 * m2));
        assert!((0.10..0.30).contains(&rms), "gradient RMS {rms}");
        assert!(kurtosis > 4.0, "gradient kurtosis {kurtosis}");
        // Level 6 averages 64 texels a side: 0.64 m blocks.
        let blocks = &a[6];
        let bm = mean(blocks);
        let spread = (blocks
            .iter()
            .map(|&v| (f64::from(v) - bm).powi(2))
            .sum::<f64>()
            / blocks.len() as f64)
            .sqrt();
        assert!((0.02..0.12).contains(&spread), "patchiness {spread}");
        let dark = level.iter().filter(|&&v| v < 0.65).count() as f64 / level.len() as f64;
        assert!((0.002..0.03).contains(&dark), "tar lines cover {dark}");
    }

    #[test]
    fn every_layer_has_mean_one() {
        let t = GroundTextures::generate(9);
        for (k, layer) in t.levels.iter().enumerate() {
            let m = mean(&layer[0]);
            assert!((m - 1.0).abs() < 1e-3, "layer {k}: mean {m}");
            assert!(layer[0].iter().all(|v| (0.0..2.0).contains(v)));
        }
    }
}
