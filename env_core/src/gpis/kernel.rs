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

    /// The covariances between f at each of `cells` and the row (`point`, `kind`), into
    /// `out` (one per cell): a column of the grid's cross-covariance. Equal, bit for bit, to
    /// [`Self::covariance`]`(cell, Value, point, kind)`; the row's kind is matched once,
    /// outside the loop, so the loop vectorises. Cost: O(cells).
    pub fn value_column(
        &self,
        cells: &[[f64; 2]],
        point: [f64; 2],
        kind: RowKind,
        out: &mut [f64],
    ) {
        let psi = self.psi;
        let cells = &cells[..out.len()];
        let distance = |c: &[f64; 2]| {
            let d = [c[0] - point[0], c[1] - point[1]];
            (d, (d[0] * d[0] + d[1] * d[1]).sqrt())
        };
        match kind.axis() {
            None => {
                for (value, cell) in out.iter_mut().zip(cells) {
                    let (_, r) = distance(cell);
                    *value = (2.0 * r - 3.0 * psi) * r * r + psi * psi * psi;
                }
            }
            Some(j) => {
                for (value, cell) in out.iter_mut().zip(cells) {
                    let (d, r) = distance(cell);
                    *value = 6.0 * d[j] * (psi - r);
                }
            }
        }
    }
}
