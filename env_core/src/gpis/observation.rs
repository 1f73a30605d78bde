//! Observations fed to the GPIS and the rows they expand to.
//!
//! A value observation (a depth point on a surface, f = 0, or other evidence such as f > 0
//! in seen free space) is one row. A contact (point + outward normal) is three rows: the
//! value 0 at the point and the two components of ∇f, each with its own noise variance.

use super::error::GpisError;
use super::kernel::RowKind;

/// One row of the GP: what is observed, and where.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Row {
    /// Location in map coordinates (metres).
    pub point: [f64; 2],
    /// What is observed there.
    pub kind: RowKind,
}

impl Row {
    /// Prior mean of this row: the map's constant for a value, 0 for a gradient component.
    pub fn prior_mean(&self, constant: f64) -> f64 {
        match self.kind {
            RowKind::Value => constant,
            RowKind::GradX | RowKind::GradY => 0.0,
        }
    }
}

/// A validated observation. Build with [`Observation::value`] or [`Observation::contact`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Observation {
    /// f(point) = value, with noise variance `noise_var`.
    Value {
        /// Location.
        point: [f64; 2],
        /// Observed f.
        value: f64,
        /// Noise variance of the value.
        noise_var: f64,
    },
    /// f(point) = 0 and ∇f(point) = normal (unit length).
    Contact {
        /// Contact location.
        point: [f64; 2],
        /// Outward unit normal.
        normal: [f64; 2],
        /// Noise variance of the value row.
        noise_var: f64,
        /// Noise variance of each gradient row.
        normal_noise_var: f64,
    },
}

/// Checks a noise standard deviation and returns its variance.
pub fn noise_variance(what: &'static str, std: f64) -> Result<f64, GpisError> {
    if std.is_finite() && std >= 0.0 {
        Ok(std * std)
    } else {
        Err(GpisError::NegativeParameter { what, value: std })
    }
}

fn check_finite(what: &'static str, index: usize, entries: &[f64]) -> Result<(), GpisError> {
    if entries.iter().all(|v| v.is_finite()) {
        Ok(())
    } else {
        Err(GpisError::NonFiniteInput {
            what,
            index,
            value: entries.to_vec(),
        })
    }
}

impl Observation {
    /// A value observation; `index` names it in errors. Noise is a variance (checked by
    /// [`noise_variance`]).
    pub fn value(
        index: usize,
        point: [f64; 2],
        value: f64,
        noise_var: f64,
    ) -> Result<Self, GpisError> {
        check_finite("points", index, &point)?;
        check_finite("values", index, &[value])?;
        Ok(Observation::Value {
            point,
            value,
            noise_var,
        })
    }

    /// A contact observation; the normal is normalised, and must be non-zero.
    pub fn contact(
        index: usize,
        point: [f64; 2],
        normal: [f64; 2],
        noise_var: f64,
        normal_noise_var: f64,
    ) -> Result<Self, GpisError> {
        check_finite("points", index, &point)?;
        check_finite("normals", index, &normal)?;
        let length = normal[0].hypot(normal[1]);
        if length == 0.0 {
            return Err(GpisError::ZeroNormal {
                index,
                nx: normal[0],
                ny: normal[1],
            });
        }
        Ok(Observation::Contact {
            point,
            normal: [normal[0] / length, normal[1] / length],
            noise_var,
            normal_noise_var,
        })
    }

    /// The paper's circle prior (§IV.A.3): four contacts equally spaced on a circle of the
    /// given diameter, each with its outward radial normal. It shapes f (negative inside the
    /// circle) before any touch, at the price of "faking data": a circle much larger than
    /// the object distorts the estimate (the paper's Fig. 8).
    pub fn circle_prior(
        centre: [f64; 2],
        diameter: f64,
        noise_var: f64,
        normal_noise_var: f64,
    ) -> Result<[Self; 4], GpisError> {
        if !(diameter.is_finite() && diameter > 0.0) {
            return Err(GpisError::NegativeParameter {
                what: "diameter",
                value: diameter,
            });
        }
        let radius = diameter / 2.0;
        let contact = |index: usize| {
            let angle = index as f64 * std::f64::consts::FRAC_PI_2;
            let normal = [angle.cos(), angle.sin()];
            let point = [
                centre[0] + radius * normal[0],
                centre[1] + radius * normal[1],
            ];
            Self::contact(index, point, normal, noise_var, normal_noise_var)
        };
        Ok([contact(0)?, contact(1)?, contact(2)?, contact(3)?])
    }

    /// Where the observation was made.
    pub fn point(&self) -> [f64; 2] {
        match *self {
            Observation::Value { point, .. } | Observation::Contact { point, .. } => point,
        }
    }

    /// Number of GP rows: 1 for a value, 3 for a contact.
    pub fn n_rows(&self) -> usize {
        match self {
            Observation::Value { .. } => 1,
            Observation::Contact { .. } => 3,
        }
    }

    /// Its rows as (row, observed value, noise variance); the value row comes first.
    pub fn rows(&self) -> impl Iterator<Item = (Row, f64, f64)> {
        let mut out = [None; 3];
        match *self {
            Observation::Value {
                point,
                value,
                noise_var,
            } => {
                out[0] = Some((
                    Row {
                        point,
                        kind: RowKind::Value,
                    },
                    value,
                    noise_var,
                ));
            }
            Observation::Contact {
                point,
                normal,
                noise_var,
                normal_noise_var,
            } => {
                let row = |kind| Row { point, kind };
                out[0] = Some((row(RowKind::Value), 0.0, noise_var));
                out[1] = Some((row(RowKind::GradX), normal[0], normal_noise_var));
                out[2] = Some((row(RowKind::GradY), normal[1], normal_noise_var));
            }
        }
        out.into_iter().flatten()
    }
}
