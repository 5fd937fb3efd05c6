//! The square-root method against independent solutions: stage 4's Householder QR against
//! the normal equations (eq. 16), and stage 5's recursive filter against the batch weighted
//! least-squares problem of eq. 18, solved from scratch with nalgebra.
//! Run with `cargo test -p tracker --test least_squares`.

use nalgebra::{DMatrix, DVector, Matrix3, Vector3};
use proptest::prelude::*;
use tracker::householder::{back_substitute, residual, triangularize, Row};
use tracker::MotionModel;

/// Solves min ‖b − A x‖² by the normal equations AᵀA x = Aᵀb (Cholesky), independently.
fn normal_equations(rows: &[Row]) -> (Vector3<f64>, f64) {
    let a = DMatrix::from_fn(rows.len(), 3, |i, j| rows[i][j]);
    let b = DVector::from_fn(rows.len(), |i, _| rows[i][3]);
    let ata: Matrix3<f64> = (a.transpose() * &a).fixed_view::<3, 3>(0, 0).into_owned();
    let atb: Vector3<f64> = (a.transpose() * &b).fixed_view::<3, 1>(0, 0).into_owned();
    let x = ata.cholesky().expect("full rank").solve(&atb);
    let r = &b - &a * DVector::from_column_slice(x.as_slice());
    (x, r.norm_squared())
}

fn qr_solve(rows: &[Row]) -> ([f64; 3], f64) {
    let mut work = rows.to_vec();
    triangularize(&mut work);
    let u = [
        [work[0][0], work[0][1], work[0][2]],
        [work[1][0], work[1][1], work[1][2]],
        [work[2][0], work[2][1], work[2][2]],
    ];
    let z = [work[0][3], work[1][3], work[2][3]];
    (
        back_substitute(&u, &z, 3, 1e-12).expect("full rank"),
        residual(&work),
    )
}

#[test]
fn householder_qr_matches_normal_equations_on_a_stage4_system() {
    // Six features of a target: vertical lines give [w, 0, w u | w b], horizontal
    // [0, w, w v | w b], with a little inconsistency so the residual is not zero.
    let feats: [(bool, f64, f64, f64); 6] = [
        (true, -25.0, 100.1, 3.0),
        (true, 25.0, 151.0, 2.0),
        (true, 0.0, 125.7, 1.0),
        (false, -16.0, 88.2, 3.1),
        (false, 16.0, 121.9, 2.5),
        (false, 8.0, 113.0, 0.4),
    ];
    let rows: Vec<Row> = feats
        .iter()
        .map(|&(vertical, off, b, w)| {
            if vertical {
                [w, 0.0, w * off, w * b]
            } else {
                [0.0, w, w * off, w * b]
            }
        })
        .collect();
    let (x, j) = qr_solve(&rows);
    let (xn, jn) = normal_equations(&rows);
    for k in 0..3 {
        assert!(
            (x[k] - xn[k]).abs() < 1e-9,
            "x[{k}]: QR {} vs normal {}",
            x[k],
            xn[k]
        );
    }
    assert!(
        (j - jn).abs() < 1e-9 * jn.max(1.0),
        "J: QR {j} vs normal {jn}"
    );
    assert!(j > 0.1, "the system was meant to be inconsistent, J = {j}");
}

proptest! {
    #[test]
    fn householder_qr_matches_normal_equations(
        rows in prop::collection::vec(prop::array::uniform4(-50.0f64..50.0), 3..20)
    ) {
        let (_, _) = (rows.len(), 0);
        // Skip near-singular draws: the comparison is about the method, not conditioning.
        let a = DMatrix::from_fn(rows.len(), 3, |i, j| rows[i][j]);
        let sv = a.clone().svd(false, false).singular_values;
        prop_assume!(sv.min() > 1e-2 * sv.max());
        let (x, j) = qr_solve(&rows);
        let (xn, jn) = normal_equations(&rows);
        for k in 0..3 {
            prop_assert!((x[k] - xn[k]).abs() < 1e-6 * (1.0 + xn[k].abs()), "x[{}]: {} vs {}", k, x[k], xn[k]);
        }
        prop_assert!((j - jn).abs() < 1e-6 * (1.0 + jn));
    }
}

/// The batch problem of eq. 18–21 for measurements `zs` (oldest first) and weights `ws`:
/// minimise Σ_k λ^age_k w_k² (z_k − (a0 + a1 t_k + a2 t_k²))² with t = 0 for the newest.
/// Solved with nalgebra's SVD: a different method from the filter's.
fn batch(lambda: f64, zs: &[f64], ws: &[f64]) -> [f64; 3] {
    let n = zs.len();
    let a = DMatrix::from_fn(n, 3, |i, j| {
        let t = i as f64 - (n - 1) as f64;
        let weight = lambda.powf(0.5 * (n - 1 - i) as f64) * ws[i];
        weight * t.powi(j as i32)
    });
    let b = DVector::from_fn(n, |i, _| {
        lambda.powf(0.5 * (n - 1 - i) as f64) * ws[i] * zs[i]
    });
    let x = a.svd(true, true).solve(&b, 1e-14).expect("svd solve");
    [x[0], x[1], x[2]]
}

#[test]
fn srif_matches_batch_least_squares_after_three_updates() {
    let zs = [100.0, 102.5, 103.0, 107.2, 110.0, 109.1, 115.3, 118.0];
    let ws = [1.0, 2.0, 0.5, 3.0, 1.5, 1.0, 2.2, 0.8];
    for lambda in [0.5, 0.8, 0.95, 1.0] {
        let mut m = MotionModel::new(lambda);
        for n in 1..=zs.len() {
            m.update(zs[n - 1], ws[n - 1]);
            if n >= 3 {
                let want = batch(lambda, &zs[..n], &ws[..n]);
                let got = m.coefficients();
                for k in 0..3 {
                    assert!(
                        (got[k] - want[k]).abs() < 1e-8 * (1.0 + want[k].abs()),
                        "λ={lambda} n={n} a{k}: filter {} vs batch {}",
                        got[k],
                        want[k]
                    );
                }
            }
        }
    }
}

#[test]
fn srif_recovers_an_exact_quadratic_and_predicts_it() {
    // p(t) = 3 + 2 t − 0.25 t², sampled at t = −5..0 (frames), newest last.
    let p = |t: f64| 3.0 + 2.0 * t - 0.25 * t * t;
    let mut m = MotionModel::new(0.7);
    for k in -5..=0 {
        m.update(p(f64::from(k)), 1.0);
    }
    let [a0, a1, a2] = m.coefficients();
    assert!((a0 - 3.0).abs() < 1e-9 && (a1 - 2.0).abs() < 1e-9 && (a2 + 0.25).abs() < 1e-9);
    // Eq. 34: the next frame is t = 1.
    assert!((m.predict(1.0) - p(1.0)).abs() < 1e-9);
}

#[test]
fn with_fewer_than_three_updates_higher_orders_are_zero() {
    let mut m = MotionModel::new(0.8);
    assert_eq!(m.coefficients(), [0.0; 3]);
    m.update(10.0, 2.0);
    assert_eq!(m.coefficients(), [10.0, 0.0, 0.0]);
    m.update(12.0, 1.0);
    let [a0, a1, a2] = m.coefficients();
    assert!((a0 - 12.0).abs() < 1e-12 && (a1 - 2.0).abs() < 1e-12 && a2 == 0.0);
}

#[test]
fn zero_weight_updates_only_shift_time() {
    let mut m = MotionModel::new(0.8);
    for (k, z) in [1.0, 4.0, 9.0, 16.0].into_iter().enumerate() {
        let _ = k;
        m.update(z, 1.0);
    }
    let before = m.predict(2.0);
    m.update(12345.0, 0.0);
    // One cycle later, "two cycles ahead" became "one cycle ahead".
    assert!((m.predict(1.0) - before).abs() < 1e-9);
}

proptest! {
    #[test]
    fn srif_matches_batch_for_random_sequences(
        lambda in 0.3f64..1.0,
        data in prop::collection::vec((-200.0f64..200.0, 0.1f64..5.0), 3..30),
    ) {
        let zs: Vec<f64> = data.iter().map(|d| d.0).collect();
        let ws: Vec<f64> = data.iter().map(|d| d.1).collect();
        let mut m = MotionModel::new(lambda);
        for (z, w) in zs.iter().zip(&ws) {
            m.update(*z, *w);
        }
        let want = batch(lambda, &zs, &ws);
        let got = m.coefficients();
        for k in 0..3 {
            prop_assert!((got[k] - want[k]).abs() < 1e-6 * (1.0 + want[k].abs()), "a{}: {} vs {}", k, got[k], want[k]);
        }
    }
}
