//! A jar's cross-section ([`JarShape`]) and its footprint in the slice plane: a disc or a
//! rotated square at a pose. The one place that knows the footprint's geometry (signed
//! distance, outline, support), used by the episode's metrics, the approach field, the
//! rendering and the paper's experiments alike. Cost: O(1) per query, O(samples) per
//! outline.

use super::config::TargetShape;
use crate::settings::Choice;

/// The cross-section of a jar.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum JarShape {
    /// A cylinder.
    Round {
        /// Radius, m.
        radius: f64,
    },
    /// A cuboid with a square cross-section.
    Square {
        /// Half the side, m.
        half_side: f64,
    },
}

impl JarShape {
    /// `"round"` or `"square"`: the name `target_shape` gives this shape.
    pub fn name(self) -> &'static str {
        match self {
            Self::Round { .. } => TargetShape::Round.name(),
            Self::Square { .. } => TargetShape::Square.name(),
        }
    }

    /// The shape called `name` (as [`JarShape::name`] gives it) with radius or half side
    /// `half_width`; None for another name.
    pub fn from_name(name: &str, half_width: f64) -> Option<Self> {
        [
            Self::Round { radius: half_width },
            Self::Square {
                half_side: half_width,
            },
        ]
        .into_iter()
        .find(|shape| shape.name() == name)
    }

    /// Radius of the circle around the cross-section, m.
    pub fn bounding_radius(self) -> f64 {
        match self {
            Self::Round { radius } => radius,
            Self::Square { half_side } => half_side * std::f64::consts::SQRT_2,
        }
    }

    /// The radius (round) or half side (square), m.
    pub fn half_width(self) -> f64 {
        match self {
            Self::Round { radius } => radius,
            Self::Square { half_side } => half_side,
        }
    }
}

/// A jar's cross-section placed at `centre` and rotated by `yaw` about z.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Footprint {
    /// Disc or square, and its size.
    pub shape: JarShape,
    /// Centre `(x, y)`, m.
    pub centre: [f64; 2],
    /// Rotation about z, rad (only matters for a square).
    pub yaw: f64,
}

impl Footprint {
    /// `p` in the footprint's own frame (centre at the origin, the square's sides along the
    /// axes).
    fn local(&self, p: [f64; 2]) -> [f64; 2] {
        let (dx, dy) = (p[0] - self.centre[0], p[1] - self.centre[1]);
        let (s, c) = self.yaw.sin_cos();
        [c * dx + s * dy, -s * dx + c * dy]
    }

    /// A point of the footprint's frame in the world.
    fn world(&self, l: [f64; 2]) -> [f64; 2] {
        let (s, c) = self.yaw.sin_cos();
        [
            self.centre[0] + c * l[0] - s * l[1],
            self.centre[1] + s * l[0] + c * l[1],
        ]
    }

    /// Exact signed distance from `p` to the footprint's outline (negative inside), m.
    /// Cost O(1).
    pub fn signed_distance(&self, p: [f64; 2]) -> f64 {
        match self.shape {
            JarShape::Round { radius } => {
                (p[0] - self.centre[0]).hypot(p[1] - self.centre[1]) - radius
            }
            JarShape::Square { half_side } => {
                let [lx, ly] = self.local(p);
                let (qx, qy) = (lx.abs() - half_side, ly.abs() - half_side);
                qx.max(0.0).hypot(qy.max(0.0)) + qx.max(qy).min(0.0)
            }
        }
    }

    /// Support distance along the unit `normal`: how far the footprint reaches from its
    /// centre in that direction, m (a line with this normal at that distance touches it).
    /// Cost O(1).
    pub fn support(&self, normal: [f64; 2]) -> f64 {
        match self.shape {
            JarShape::Round { radius } => radius,
            JarShape::Square { half_side } => {
                let (s, c) = self.yaw.sin_cos();
                let along_u = normal[0] * c + normal[1] * s;
                let along_v = -normal[0] * s + normal[1] * c;
                half_side * (along_u.abs() + along_v.abs())
            }
        }
    }

    /// `samples` points on the outline, evenly spaced in angle (disc) or along the perimeter
    /// (square, starting at its corner (−h, −h) in its own frame), counter-clockwise, not
    /// closed. Cost O(samples).
    pub fn outline(&self, samples: usize) -> Vec<[f64; 2]> {
        (0..samples)
            .map(|k| {
                let t = k as f64 / samples as f64;
                match self.shape {
                    JarShape::Round { radius } => {
                        let (s, c) = (std::f64::consts::TAU * t).sin_cos();
                        [self.centre[0] + radius * c, self.centre[1] + radius * s]
                    }
                    JarShape::Square { half_side } => {
                        const CORNERS: [[f64; 2]; 5] = [
                            [-1.0, -1.0],
                            [1.0, -1.0],
                            [1.0, 1.0],
                            [-1.0, 1.0],
                            [-1.0, -1.0],
                        ];
                        let u = 4.0 * t;
                        let side = (u.floor() as usize).min(3);
                        let f = u - side as f64;
                        let (a, b) = (CORNERS[side], CORNERS[side + 1]);
                        self.world([
                            half_side * (a[0] + f * (b[0] - a[0])),
                            half_side * (a[1] + f * (b[1] - a[1])),
                        ])
                    }
                }
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn square(yaw: f64) -> Footprint {
        Footprint {
            shape: JarShape::Square { half_side: 0.02 },
            centre: [0.1, 0.2],
            yaw,
        }
    }

    #[test]
    fn outline_points_lie_on_the_zero_level_of_the_signed_distance() {
        let disc = Footprint {
            shape: JarShape::Round { radius: 0.025 },
            centre: [-0.05, 0.1],
            yaw: 0.3,
        };
        for footprint in [disc, square(0.0), square(0.7)] {
            for p in footprint.outline(37) {
                assert!(
                    footprint.signed_distance(p).abs() < 1e-12,
                    "{footprint:?} {p:?}"
                );
            }
        }
    }

    #[test]
    fn square_support_and_distance_follow_its_yaw() {
        let turned = square(std::f64::consts::FRAC_PI_4);
        let diagonal = 0.02 * std::f64::consts::SQRT_2;
        assert!((turned.support([1.0, 0.0]) - diagonal).abs() < 1e-12);
        assert!((square(0.0).support([0.0, 1.0]) - 0.02).abs() < 1e-12);
        // The corner of the turned square points along +x.
        assert!(turned.signed_distance([0.1 + diagonal - 1e-4, 0.2]) < 0.0);
        assert!(square(0.0).signed_distance([0.1 + diagonal - 1e-4, 0.2]) > 0.0);
        assert!((square(0.0).signed_distance([0.1, 0.2]) + 0.02).abs() < 1e-12);
    }
}
