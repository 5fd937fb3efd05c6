//! Stage 5: the motion model of one location parameter (paper 2.7, eq. 18–33), kept by a
//! square root information filter with exponential forgetting.
//!
//! Each of c_x, c_y and scale follows a second-order model in time (eq. 2):
//! `p[t] = a0 + a1 t + a2 t²`, with t counted in camera cycles and the current image always
//! at t = 0 (eq. 30). The filter keeps the pair (U, z1) of eq. 28: U is upper triangular and
//! proportional to a square root of the coefficients' information matrix (eq. 33).

use crate::householder::{back_substitute, triangularize, Row};

/// One parameter's second-order motion model (eq. 2), updated recursively (eq. 29–32).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MotionModel {
    lambda: f64,
    /// U of eq. 28, upper triangular.
    u: [[f64; 3]; 3],
    /// z1 of eq. 27–28.
    z: [f64; 3],
    /// How many measurements with non-zero weight have been added, capped at 3: the rank of
    /// the information. Until it reaches 3 the higher-order coefficients are held at zero
    /// (paper 2.2: initially the target is taken not to be moving).
    informative: u8,
}

impl MotionModel {
    /// A model with forgetting factor `lambda` (eq. 18, 0 < λ < 1) and zero information.
    ///
    /// # Panics
    /// If `lambda` is not in (0, 1]; callers validate their configuration first.
    pub fn new(lambda: f64) -> Self {
        assert!(
            lambda > 0.0 && lambda <= 1.0,
            "forgetting factor λ must be in (0, 1], got {lambda}"
        );
        MotionModel {
            lambda,
            u: [[0.0; 3]; 3],
            z: [0.0; 3],
            informative: 0,
        }
    }

    /// The forgetting factor λ.
    pub fn lambda(&self) -> f64 {
        self.lambda
    }

    /// True once at least one measurement with non-zero weight has been added.
    pub fn has_information(&self) -> bool {
        self.informative > 0
    }

    /// Ages the information by `cycles` camera cycles: U is post-multiplied by V^cycles
    /// (eq. 30, a time shift of −cycles, so that the newest image is again t = 0) and
    /// (U, z1) are multiplied by √λ^cycles (eq. 29).
    pub fn age(&mut self, cycles: u32) {
        if cycles == 0 {
            return;
        }
        let k = f64::from(cycles);
        // V^k = [[1, −k, k²], [0, 1, −2k], [0, 0, 1]]: rows [1, t, t²] become
        // [1, t − k, (t − k)²].
        let v = [[1.0, -k, k * k], [0.0, 1.0, -2.0 * k], [0.0, 0.0, 1.0]];
        let decay = self.lambda.powf(0.5 * k);
        let mut uv = [[0.0; 3]; 3];
        for (i, row) in self.u.iter().enumerate() {
            for j in 0..3 {
                uv[i][j] = decay * (0..3).map(|l| row[l] * v[l][j]).sum::<f64>();
            }
        }
        self.u = uv;
        for z in &mut self.z {
            *z *= decay;
        }
    }

    /// Adds measurement `z` of the parameter at the current time t = 0 with weight `w`
    /// (the confidence of eq. 17): the top row of eq. 29, `w·[1 0 0 | z]`, is stacked on
    /// (U, z1) and the stack is re-triangularized by Householder reflections (eq. 32).
    /// A zero weight adds nothing.
    pub fn add(&mut self, z: f64, w: f64) {
        if w == 0.0 || !w.is_finite() || !z.is_finite() {
            return;
        }
        let mut rows: [Row; 4] = [
            [w, 0.0, 0.0, w * z],
            [self.u[0][0], self.u[0][1], self.u[0][2], self.z[0]],
            [self.u[1][0], self.u[1][1], self.u[1][2], self.z[1]],
            [self.u[2][0], self.u[2][1], self.u[2][2], self.z[2]],
        ];
        triangularize(&mut rows);
        for ((u, z), row) in self.u.iter_mut().zip(&mut self.z).zip(&rows) {
            *u = [row[0], row[1], row[2]];
            *z = row[3];
        }
        self.informative = (self.informative + 1).min(3);
    }

    /// Moves the parameter by a known amount `delta` at every time, past and future (robust
    /// mode: the image shift the camera's own rotation causes). The coefficients become
    /// (a0 + delta, a1, a2): since U x = z1, z1 gains `delta` times U's first column.
    pub fn shift(&mut self, delta: f64) {
        if !delta.is_finite() {
            return;
        }
        for (z, row) in self.z.iter_mut().zip(&self.u) {
            *z += row[0] * delta;
        }
    }

    /// Scales the information by `factor` in (0, 1] (U and z1 by its square root), as if the
    /// history were older than it is (robust mode, after a surprise).
    pub fn forget(&mut self, factor: f64) {
        let k = factor.clamp(0.0, 1.0).sqrt();
        for row in &mut self.u {
            for v in row {
                *v *= k;
            }
        }
        for z in &mut self.z {
            *z *= k;
        }
    }

    /// One cycle of the filter: ages the old information by one cycle (V, √λ), then adds
    /// measurement `z` with weight `w` (eq. 18–32).
    pub fn update(&mut self, z: f64, w: f64) {
        self.age(1);
        self.add(z, w);
    }

    /// The coefficients (a0, a1, a2) at the current time t = 0: the solution of U x = z1 by
    /// back substitution (eq. 28). With fewer than three informative measurements, the
    /// higher-order coefficients are zero (2.2) and the leading block is solved; with none,
    /// all are zero.
    pub fn coefficients(&self) -> [f64; 3] {
        let scale = self.u.iter().flatten().fold(0.0_f64, |m, v| m.max(v.abs()));
        let tol = scale * 1e-12;
        let mut n = usize::from(self.informative);
        while n > 0 {
            if let Some(x) = back_substitute(&self.u, &self.z, n, tol) {
                return x;
            }
            n -= 1;
        }
        [0.0; 3]
    }

    /// Evaluates the model at time `t` cycles from now (eq. 2; eq. 34 at t = 1).
    pub fn predict(&self, t: f64) -> f64 {
        let [a0, a1, a2] = self.coefficients();
        a0 + a1 * t + a2 * t * t
    }

    /// U of eq. 28, proportional to a square root of the information matrix (eq. 33).
    pub fn sqrt_information(&self) -> [[f64; 3]; 3] {
        self.u
    }
}
