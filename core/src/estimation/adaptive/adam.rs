//! The Adam optimiser's moments and step (Kingma & Ba 2015; seed 001 eq. 55–60), used by the
//! offline training of the density network (Algorithm 1) and its online adaptation (Algorithm 2).

/// Adam moments (Kingma & Ba 2015; seed 001 eq. 55–60) over a flat parameter vector.
#[derive(Debug, Clone, PartialEq)]
pub struct Adam {
    /// Decay rate β₁ of the gradient average.
    pub beta1: f64,
    /// Decay rate β₂ of the squared-gradient average.
    pub beta2: f64,
    /// ε of eq. 57.
    pub epsilon: f64,
    /// Correct the moments for their initialisation bias (standard Adam; seed 001's online
    /// adaptation does not, §IV.B.2).
    pub bias_correction: bool,
    /// Moving average of the gradient ∇̄.
    pub m: Vec<f64>,
    /// Moving average of the squared gradient (∇̄)².
    pub v: Vec<f64>,
    /// Steps taken (for the bias correction).
    pub t: u64,
}

impl Adam {
    /// Zero moments for `n` parameters.
    pub fn new(n: usize, beta1: f64, beta2: f64, epsilon: f64, bias_correction: bool) -> Self {
        Adam {
            beta1,
            beta2,
            epsilon,
            bias_correction,
            m: vec![0.0; n],
            v: vec![0.0; n],
            t: 0,
        }
    }

    /// One step in place: eq. 55–57 (with bias correction if enabled) on `xi` with gradient `g`
    /// and step size `lr`.
    pub fn step(&mut self, xi: &mut [f64], g: &[f64], lr: f64) {
        self.t += 1;
        let (c1, c2) = if self.bias_correction {
            let t = self.t as i32;
            (1.0 - self.beta1.powi(t), 1.0 - self.beta2.powi(t))
        } else {
            (1.0, 1.0)
        };
        let (b1, b2, eps) = (self.beta1, self.beta2, self.epsilon);
        for (((x, g), m), v) in xi.iter_mut().zip(g).zip(&mut self.m).zip(&mut self.v) {
            *m = b1 * *m + (1.0 - b1) * g;
            *v = b2 * *v + (1.0 - b2) * g * g;
            *x -= lr * (*m / c1) / ((*v / c2).sqrt() + eps);
        }
    }

    /// The candidate of eq. 55–57 without modifying `self`: writes ξ*, ∇̄* and (∇̄*)² into the
    /// output slices (no bias correction, as seed 001's Algorithm 2).
    pub fn candidate(
        &self,
        xi: &[f64],
        g: &[f64],
        lr: f64,
        xi_out: &mut [f64],
        m_out: &mut [f64],
        v_out: &mut [f64],
    ) {
        let (b1, b2, eps) = (self.beta1, self.beta2, self.epsilon);
        for k in 0..xi.len() {
            let m = b1 * self.m[k] + (1.0 - b1) * g[k];
            let v = b2 * self.v[k] + (1.0 - b2) * g[k] * g[k];
            m_out[k] = m;
            v_out[k] = v;
            xi_out[k] = xi[k] - lr * m / (v.sqrt() + eps);
        }
    }
}
