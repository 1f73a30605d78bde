//! The shelf compartment: floor, back, two side walls and top as fixed cuboids around an
//! interior `x ∈ [-W/2, W/2]`, `y ∈ [0, D]` (open front at y = 0), `z ∈ [0, H]`.

use rapier3d::prelude::*;

use super::config::CupboardConfig;
use super::groups;

/// One of the cupboard's five fixed slabs.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Wall {
    /// The shelf floor (top face at z = 0).
    Floor,
    /// The back wall (front face at y = depth).
    Back,
    /// The wall at x = -width/2.
    Left,
    /// The wall at x = +width/2.
    Right,
    /// The top (bottom face at z = height).
    Top,
}

impl Wall {
    /// Lower-case name, as reported to Python.
    pub fn name(self) -> &'static str {
        match self {
            Self::Floor => "floor",
            Self::Back => "back",
            Self::Left => "left",
            Self::Right => "right",
            Self::Top => "top",
        }
    }
}

/// An axis-aligned wall slab.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WallBox {
    /// Which wall.
    pub wall: Wall,
    /// Centre in the world, m.
    pub centre: [f64; 3],
    /// Half extents along x, y, z, m.
    pub half_extents: [f64; 3],
}

impl WallBox {
    fn from_bounds(wall: Wall, lo: [f64; 3], hi: [f64; 3]) -> Self {
        Self {
            wall,
            centre: std::array::from_fn(|i| 0.5 * (lo[i] + hi[i])),
            half_extents: std::array::from_fn(|i| 0.5 * (hi[i] - lo[i])),
        }
    }

    /// The slab's pose (translation only).
    pub fn pose(&self) -> Pose {
        let [x, y, z] = self.centre;
        Pose::translation(x as Real, y as Real, z as Real)
    }

    /// The slab as a parry cuboid (centred at its pose).
    pub fn shape(&self) -> Cuboid {
        let [x, y, z] = self.half_extents;
        Cuboid::new(Vector::new(x as Real, y as Real, z as Real))
    }
}

/// The cupboard's geometry: interior size and the five wall slabs.
#[derive(Debug, Clone, PartialEq)]
pub struct Cupboard {
    width: f64,
    depth: f64,
    height: f64,
    friction: f64,
    walls: Vec<WallBox>,
}

impl Cupboard {
    /// The cupboard of a (validated) config. Cost: O(1).
    pub fn new(config: &CupboardConfig) -> Self {
        let (w, d, h, t) = (
            config.width,
            config.depth,
            config.height,
            config.wall_thickness,
        );
        let xo = 0.5 * w + t;
        let walls = vec![
            WallBox::from_bounds(Wall::Floor, [-xo, 0.0, -t], [xo, d + t, 0.0]),
            WallBox::from_bounds(Wall::Back, [-xo, d, 0.0], [xo, d + t, h]),
            WallBox::from_bounds(Wall::Left, [-xo, 0.0, 0.0], [-0.5 * w, d, h]),
            WallBox::from_bounds(Wall::Right, [0.5 * w, 0.0, 0.0], [xo, d, h]),
            WallBox::from_bounds(Wall::Top, [-xo, 0.0, h], [xo, d + t, h + t]),
        ];
        Self {
            width: w,
            depth: d,
            height: h,
            friction: config.friction,
            walls,
        }
    }

    /// Interior width (x), m.
    pub fn width(&self) -> f64 {
        self.width
    }

    /// Interior depth (y), m.
    pub fn depth(&self) -> f64 {
        self.depth
    }

    /// Interior height (z), m.
    pub fn height(&self) -> f64 {
        self.height
    }

    /// The five wall slabs, in the order floor, back, left, right, top.
    pub fn walls(&self) -> &[WallBox] {
        &self.walls
    }

    /// Inserts the walls as fixed colliders (no rigid body); returns their handles in
    /// [`Self::walls`] order.
    pub(crate) fn insert(&self, world: &mut PhysicsWorld) -> Vec<ColliderHandle> {
        self.walls
            .iter()
            .map(|wall| {
                let [hx, hy, hz] = wall.half_extents;
                let collider = ColliderBuilder::cuboid(hx as Real, hy as Real, hz as Real)
                    .position(wall.pose())
                    .friction(self.friction as Real)
                    .restitution(0.0)
                    .collision_groups(groups::CUPBOARD)
                    .user_data(0);
                world.insert_collider(collider, None)
            })
            .collect()
    }
}
