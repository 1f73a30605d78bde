//! The thin-plate covariance (paper eq. 3) and its derivative blocks in 2D.
//!
//! With d = x − x′ and r = |d|:
//!
//! ```text
//! k(x, x′)                      = 2 r³ − 3 ψ r² + ψ³
//! cov(f(x), ∂f(x′)/∂x′_j)       = 6 d_j (ψ − r)
//! cov(∂f(x)/∂x_i, f(x′))        = 6 d_i (r − ψ)
//! cov(∂f(x)/∂x_i, ∂f(x′)/∂x′_j) = 6 (ψ − r) δ_ij − 6 d_i d_j / r   (→ 6 ψ δ_ij as r → 0)
//! ```
//!
//! ψ is fixed per map and must exceed every distance between two points of the domain:
//! beyond r = ψ the function is not a covariance at all, and a ψ that moved with the data
//! would invalidate every incremental update made so far.

/// What one row of the GP observes at its point: the value f, or one component of ∇f.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum RowKind {
    /// f(x).
    Value,
    /// ∂f/∂x at x.
    GradX,
    /// ∂f/∂y at x.
    GradY,
}

impl RowKind {
    /// The gradient axis (0 = x, 1 = y), or `None` for a value row.
    pub fn axis(self) -> Option<usize> {
        match self {
            RowKind::Value => None,
            RowKind::GradX => Some(0),
            RowKind::GradY => Some(1),
        }
    }
}

/// The thin-plate kernel with a fixed ψ. Cost: a handful of flops per entry.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ThinPlateKernel {
    psi: f64,
}

impl ThinPlateKernel {
    /// A kernel with the given ψ. The caller guarantees ψ exceeds the domain's diameter
    /// ([`crate::gpis::GridSpec`] and [`crate::gpis::Gpis`] check it).
    pub fn new(psi: f64) -> Self {
        Self { psi }
    }

    /// ψ.
    pub fn psi(&self) -> f64 {
        self.psi
    }

    /// Prior variance of a row of this kind at any point: ψ³ for values, 6ψ for gradients.
    pub fn prior_variance(&self, kind: RowKind) -> f64 {
        match kind {
            RowKind::Value => self.psi.powi(3),
            RowKind::GradX | RowKind::GradY => 6.0 * self.psi,
        }
    }

    /// Covariance between row (`a`, `kind_a`) and row (`b`, `kind_b`).
    #[inline]
    pub fn covariance(&self, a: [f64; 2], kind_a: RowKind, b: [f64; 2], kind_b: RowKind) -> f64 {
        let psi = self.psi;
        let d = [a[0] - b[0], a[1] - b[1]];
        let r = (d[0] * d[0] + d[1] * d[1]).sqrt();
        match (kind_a.axis(), kind_b.axis()) {
            (None, None) => (2.0 * r - 3.0 * psi) * r * r + psi * psi * psi,
            (None, Some(j)) => 6.0 * d[j] * (psi - r),
            (Some(i), None) => 6.0 * d[i] * (r - psi),
            (Some(i), Some(j)) => {
                let diagonal = if i == j { 6.0 * (psi - r) } else { 0.0 };
                // |d_i d_j / r| <= r, so the term vanishes continuously at r = 0.
                let cross = if r > 0.0 { 6.0 * d[i] * d[j] / r } else { 0.0 };
                diagonal - cross
            }
        }
    }

    /// The covariances between f at each cell (`cell_xs[i]`, `cell_ys[i]`) and the row
    /// (`point`, `kind`), into `out` (one per cell): a column of the grid's
    /// cross-covariance. Equal, bit for bit, to
    /// [`Self::covariance`]`(cell, Value, point, kind)`. The row's kind is matched once,
    /// outside the loop, the cells come as separate x and y slices, and the loop runs under
    /// `pulp`'s runtime dispatch: it vectorises to the widest instructions the CPU has
    /// (AVX2's four lanes instead of SSE2's two; the square root dominates). Vector and
    /// scalar square roots, products and sums are all correctly rounded, and Rust never
    /// fuses a product and a sum on its own, so every CPU gives the same bits. Cost: O(cells).
    pub fn value_column(
        &self,
        cell_xs: &[f64],
        cell_ys: &[f64],
        point: [f64; 2],
        kind: RowKind,
        out: &mut [f64],
    ) {
        let psi = self.psi;
        let psi_cubed = psi * psi * psi;
        let (cell_xs, cell_ys) = (&cell_xs[..out.len()], &cell_ys[..out.len()]);
        let cells = cell_xs.iter().zip(cell_ys);
        let arch = pulp::Arch::new();
        match kind.axis() {
            None => arch.dispatch(
                #[inline(always)]
                || {
                    for (value, (x, y)) in out.iter_mut().zip(cells) {
                        let (dx, dy) = (x - point[0], y - point[1]);
                        let r = (dx * dx + dy * dy).sqrt();
                        *value = (2.0 * r - 3.0 * psi) * r * r + psi_cubed;
                    }
                },
            ),
            Some(j) => arch.dispatch(
                #[inline(always)]
                || {
                    for (value, (x, y)) in out.iter_mut().zip(cells) {
                        let (dx, dy) = (x - point[0], y - point[1]);
                        let r = (dx * dx + dy * dy).sqrt();
                        let d_j = if j == 0 { dx } else { dy };
                        *value = 6.0 * d_j * (psi - r);
                    }
                },
            ),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The vectorised column is the scalar covariance bit for bit, for every row kind and
    /// for lengths that leave a remainder after the vector lanes.
    #[test]
    fn value_column_equals_covariance_bit_for_bit() {
        let kernel = ThinPlateKernel::new(0.9);
        let cells: Vec<[f64; 2]> = (0..37)
            .map(|i| [0.013 * i as f64 - 0.2, 0.29 - 0.0071 * (i * i % 23) as f64])
            .collect();
        let xs: Vec<f64> = cells.iter().map(|c| c[0]).collect();
        let ys: Vec<f64> = cells.iter().map(|c| c[1]).collect();
        let point = [0.031, -0.047];
        for kind in [RowKind::Value, RowKind::GradX, RowKind::GradY] {
            for len in [0, 1, 3, 4, 5, 8, 37] {
                let mut out = vec![f64::NAN; len];
                kernel.value_column(&xs, &ys, point, kind, &mut out);
                for (cell, value) in cells.iter().zip(&out) {
                    let expected = kernel.covariance(*cell, RowKind::Value, point, kind);
                    assert_eq!(value.to_bits(), expected.to_bits(), "{kind:?}, {len} cells");
                }
            }
        }
    }
}
