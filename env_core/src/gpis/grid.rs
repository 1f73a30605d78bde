//! The rectangular map domain and its grid of test cells.
//!
//! Cell (i, j) has its centre at (x0 + (j + ½)(x1 − x0)/W, y0 + (i + ½)(y1 − y0)/H): row i
//! runs along y, column j along x, and cells are stored row-major (index i·W + j), which is
//! numpy's C order for an (H, W) array.

use super::error::GpisError;

/// Bounds `[[x0, x1], [y0, y1]]` (metres) and a grid shape (H, W).
#[derive(Debug, Clone, PartialEq)]
pub struct GridSpec {
    bounds: [[f64; 2]; 2],
    shape: (usize, usize),
}

impl GridSpec {
    /// Checks that the bounds are finite and non-empty and the shape positive (with a cell
    /// count that fits in a usize).
    pub fn new(bounds: [[f64; 2]; 2], shape: (usize, usize)) -> Result<Self, GpisError> {
        for (axis, [lower, upper]) in ["x", "y"].into_iter().zip(bounds) {
            if !(lower.is_finite() && upper.is_finite() && lower < upper) {
                return Err(GpisError::InvalidBounds { axis, lower, upper });
            }
        }
        if shape.0 == 0 || shape.1 == 0 || shape.0.checked_mul(shape.1).is_none() {
            return Err(GpisError::InvalidShape {
                height: shape.0,
                width: shape.1,
            });
        }
        Ok(Self { bounds, shape })
    }

    /// `[[x0, x1], [y0, y1]]`.
    pub fn bounds(&self) -> [[f64; 2]; 2] {
        self.bounds
    }

    /// (H, W).
    pub fn shape(&self) -> (usize, usize) {
        self.shape
    }

    /// Number of cells, H·W.
    pub fn n_cells(&self) -> usize {
        self.shape.0 * self.shape.1
    }

    /// Length of the bounds' diagonal: the largest distance between two points of the domain.
    pub fn diagonal(&self) -> f64 {
        let [[x0, x1], [y0, y1]] = self.bounds;
        (x1 - x0).hypot(y1 - y0)
    }

    /// Centre of cell (i, j).
    pub fn cell_centre(&self, i: usize, j: usize) -> [f64; 2] {
        let [[x0, x1], [y0, y1]] = self.bounds;
        let (h, w) = self.shape;
        [
            x0 + (j as f64 + 0.5) * (x1 - x0) / w as f64,
            y0 + (i as f64 + 0.5) * (y1 - y0) / h as f64,
        ]
    }

    /// All cell centres in row-major order.
    pub fn cell_centres(&self) -> Vec<[f64; 2]> {
        self.cell_centres_iter().collect()
    }

    /// The cell centres in row-major order, one at a time.
    pub fn cell_centres_iter(&self) -> impl Iterator<Item = [f64; 2]> + '_ {
        let (h, w) = self.shape;
        (0..h)
            .flat_map(move |i| (0..w).map(move |j| (i, j)))
            .map(|(i, j)| self.cell_centre(i, j))
    }

    /// Whether `p` lies inside the closed bounds.
    pub fn contains(&self, p: [f64; 2]) -> bool {
        let [[x0, x1], [y0, y1]] = self.bounds;
        (x0..=x1).contains(&p[0]) && (y0..=y1).contains(&p[1])
    }

    /// `Ok` if `p` is inside the bounds, else the error naming `points[index]`.
    pub fn check_inside(&self, index: usize, p: [f64; 2]) -> Result<(), GpisError> {
        if self.contains(p) {
            return Ok(());
        }
        let [[x0, x1], [y0, y1]] = self.bounds;
        Err(GpisError::PointOutsideBounds {
            index,
            x: p[0],
            y: p[1],
            x0,
            x1,
            y0,
            y1,
        })
    }
}
