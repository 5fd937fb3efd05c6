//! Householder QR on a small augmented system `[A | b]` with three unknowns: the square-root
//! method of paper 2.7 (eq. 22–28), shared by stage 4 (object location, 2.6) and stage 5
//! (the square root information filter, eq. 29–32).
//!
//! Each row is `[a0, a1, a2, b]`. Reflecting the rows in place turns `A` into `R = [U; 0]`
//! (eq. 23–25) and `b` into `Tb = [z1; z2]` (eq. 27). Then `U x = z1` (eq. 28) is solved by
//! back substitution, and `z2ᵀ z2` is the minimised residual (eq. 26).

/// One row of an augmented system: three coefficients and a right-hand side.
pub type Row = [f64; 4];

/// Reduces `rows` in place by Householder reflections (eq. 24–25), column by column.
/// Afterwards rows `0..min(m, 3)` hold `[U | z1]` (U upper triangular) and the remaining
/// rows hold `[0 | z2]`.
pub fn triangularize(rows: &mut [Row]) {
    let m = rows.len();
    for k in 0..3.min(m) {
        let norm2: f64 = rows[k..].iter().map(|r| r[k] * r[k]).sum();
        if norm2 == 0.0 {
            continue;
        }
        let x0 = rows[k][k];
        // Reflect x onto alpha·e_k, with alpha's sign opposite x0 to avoid cancellation.
        let alpha = if x0 >= 0.0 {
            -norm2.sqrt()
        } else {
            norm2.sqrt()
        };
        let v0 = x0 - alpha;
        // v = x − α e_k shares x's entries below the diagonal, so column k of `rows` holds
        // them; it is therefore updated last (columns run from the right).
        let vtv = v0 * v0 + (norm2 - x0 * x0);
        if vtv == 0.0 {
            continue;
        }
        for j in (k..4).rev() {
            let mut dot = v0 * rows[k][j];
            for r in &rows[k + 1..] {
                dot += r[k] * r[j];
            }
            let s = 2.0 * dot / vtv;
            rows[k][j] -= s * v0;
            for r in rows[k + 1..].iter_mut() {
                r[j] -= s * r[k];
            }
        }
        // Column k below the diagonal is now zero up to rounding; make it exact.
        for r in rows[k + 1..].iter_mut() {
            r[k] = 0.0;
        }
    }
}

/// The minimised residual `z2ᵀ z2` (eq. 26) of a triangularized system.
pub fn residual(rows: &[Row]) -> f64 {
    rows.iter().skip(3).map(|r| r[3] * r[3]).sum()
}

/// Solves `U x = z1` (eq. 28) by back substitution over the leading `n × n` block of `U`
/// (n ≤ 3); the trailing unknowns are held at zero. Returns `None` when a diagonal entry is
/// not larger than `tol` in magnitude (the block is singular).
pub fn back_substitute(u: &[[f64; 3]; 3], z1: &[f64; 3], n: usize, tol: f64) -> Option<[f64; 3]> {
    let mut x = [0.0; 3];
    for i in (0..n).rev() {
        if u[i][i].abs() <= tol {
            return None;
        }
        let mut s = z1[i];
        for j in i + 1..n {
            s -= u[i][j] * x[j];
        }
        x[i] = s / u[i][i];
    }
    Some(x)
}
