//! Draws from the stochastic distributions of a `ParameterValueDistribution`, each from
//! a ChaCha8 stream of its own, by algorithms written out here so that a file's draws
//! depend on nothing but the file (no library's choice of algorithm, which may change
//! between versions).

use rand::Rng;
use rand_chacha::ChaCha8Rng;

/// How many draws a truncated distribution may reject before its `Range` is said to hold
/// too little of it: a range holding 1 % of the mass needs about 100 on average, and
/// 10,000 rejections in a row happen to such a range with probability e⁻¹⁰⁰.
pub const MAX_REJECTIONS: usize = 10_000;

/// The largest expected value of a Poisson distribution drawn here: the inversion below
/// walks the distribution from 0, about λ + 10√λ steps a draw.
pub const MAX_POISSON_MEAN: f64 = 10_000.0;

/// A uniform draw in `[0, 1)`.
pub fn unit(rng: &mut ChaCha8Rng) -> f64 {
    rng.random::<f64>()
}

/// A standard normal draw by the Box–Muller transform (Box and Muller, "A note on the
/// generation of random normal deviates", Ann. Math. Statist. 29, 1958): two uniforms,
/// one normal (the second of the pair is not kept, so each draw takes two uniforms).
pub fn standard_normal(rng: &mut ChaCha8Rng) -> f64 {
    // 1 − u is in (0, 1]: its logarithm is finite.
    let u1 = 1.0 - unit(rng);
    let u2 = unit(rng);
    (-2.0 * u1.ln()).sqrt() * (std::f64::consts::TAU * u2).cos()
}

/// A Poisson draw of mean `lambda` (0 ≤ λ ≤ [`MAX_POISSON_MEAN`]) by inversion: the least
/// k whose cumulative probability reaches a uniform draw, the probabilities summed in
/// order from p(0) with p(k+1) = p(k)·λ/(k+1), each from its logarithm so that e^−λ's
/// underflow at large λ loses only terms that are zero anyway.
pub fn poisson(rng: &mut ChaCha8Rng, lambda: f64) -> u64 {
    let u = unit(rng);
    let ln_lambda = lambda.ln();
    let mut ln_p = -lambda;
    let mut cumulative = 0.0;
    // Far beyond any mass a double can tell: λ + 40√λ + 40.
    let last = (lambda + 40.0 * lambda.sqrt() + 40.0) as u64;
    for k in 0..=last {
        cumulative += ln_p.exp();
        if cumulative > u {
            return k;
        }
        ln_p += ln_lambda - ((k + 1) as f64).ln();
    }
    last
}

/// An index into `weights` (all finite and ≥ 0, their sum > 0) with probability in
/// proportion to its weight.
pub fn weighted(rng: &mut ChaCha8Rng, weights: &[f64]) -> usize {
    let total: f64 = weights.iter().sum();
    let target = unit(rng) * total;
    let mut sum = 0.0;
    for (i, w) in weights.iter().enumerate() {
        sum += w;
        if target < sum {
            return i;
        }
    }
    // Rounding left the target at the total: the last index of non-zero weight.
    weights.iter().rposition(|w| *w > 0.0).unwrap_or(0)
}

#[cfg(test)]
mod tests {
    use super::*;
    use vehicle::named_stream;

    #[test]
    fn normal_draws_have_the_standard_moments() {
        let mut rng = named_stream(1, "test");
        let n = 100_000;
        let xs: Vec<f64> = (0..n).map(|_| standard_normal(&mut rng)).collect();
        let mean = xs.iter().sum::<f64>() / n as f64;
        let var = xs.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / n as f64;
        assert!(mean.abs() < 0.01, "{mean}");
        assert!((var - 1.0).abs() < 0.02, "{var}");
    }

    #[test]
    fn poisson_draws_have_their_mean_and_variance() {
        for lambda in [0.5, 4.0, 900.0] {
            let mut rng = named_stream(2, "test");
            let n = 20_000;
            let xs: Vec<f64> = (0..n).map(|_| poisson(&mut rng, lambda) as f64).collect();
            let mean = xs.iter().sum::<f64>() / n as f64;
            let var = xs.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / n as f64;
            assert!(
                (mean - lambda).abs() < 0.05 * lambda.max(1.0),
                "{lambda}: {mean}"
            );
            assert!(
                (var - lambda).abs() < 0.1 * lambda.max(1.0),
                "{lambda}: {var}"
            );
        }
    }

    #[test]
    fn weights_choose_in_proportion() {
        let mut rng = named_stream(3, "test");
        let mut counts = [0usize; 3];
        for _ in 0..30_000 {
            counts[weighted(&mut rng, &[1.0, 0.0, 2.0])] += 1;
        }
        assert_eq!(counts[1], 0);
        let ratio = counts[2] as f64 / counts[0] as f64;
        assert!((ratio - 2.0).abs() < 0.1, "{counts:?}");
    }
}
