//! The cupboard scene: a rapier world holding the cupboard, the jars of a layout and the hand,
//! the depth camera's first look, and the tactile readings after each hand command.
//!
//! Determinism: one single-threaded rapier pipeline (no `parallel` feature), contact
//! recycling off, and three ChaCha8 streams derived from the seed (layout, depth noise, touch
//! noise), so the same seed and the same commands give bit-identical states.

use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rapier3d::prelude::*;

use super::config::SceneConfig;
use super::cupboard::Cupboard;
use super::depth_camera::DepthCamera;
use super::disturbance::Disturbance;
use super::error::SceneError;
use super::free_motion::{self, JarObstacle};
use super::hand::{Blocker, Hand, HandPose};
use super::jar::JarSpec;
use super::layout::Layout;
use super::point_cloud::{process_depth, DepthCapture, SliceSpec};
use super::ray_cast::RayTargets;
use super::touch::{finger_contacts, with_noise, Contact};
use super::visibility::target_visibility;
use crate::settings::Checked;

/// ChaCha stream of the depth-camera noise.
const DEPTH_NOISE_STREAM: u64 = 1;
/// ChaCha stream of the touch noise.
const TOUCH_NOISE_STREAM: u64 = 2;

/// How the depth camera's looks are cut, thinned and perturbed, from the settings.
fn slice_spec(config: &SceneConfig) -> SliceSpec {
    SliceSpec {
        height: config.slice_height,
        band: config.camera.slice_band,
        max_points: config.camera.max_slice_points,
        noise_std: config.camera.noise_std,
    }
}

/// The wrist pose substep `k` of `substeps` moves to, from `start` towards `goal` (the start
/// itself for k = 0).
fn substep_target(start: HandPose, goal: HandPose, k: usize, substeps: usize) -> HandPose {
    let s = k as f64 / substeps as f64;
    HandPose {
        x: start.x + s * (goal.x - start.x),
        y: start.y + s * (goal.y - start.y),
        yaw: start.yaw + s * (goal.yaw - start.yaw),
    }
}

/// A wrist motion for one scene step, in the world's slice plane.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct HandCommand {
    /// Motion along x, m.
    pub dx: f64,
    /// Motion along y, m.
    pub dy: f64,
    /// Rotation about z, rad.
    pub dyaw: f64,
}

/// What one [`Scene::step`] did.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct StepReport {
    /// The command after clipping to the configured bounds.
    pub commanded: HandCommand,
    /// Whether clipping changed the command.
    pub clipped: bool,
    /// The wrist motion actually made (less than `commanded` when blocked).
    pub moved: HandCommand,
    /// What stopped the motion, if anything.
    pub blocked: Option<Blocker>,
}

/// A jar's current state.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct JarState {
    /// Its layout entry (shape, size, mass, pose at reset).
    pub spec: JarSpec,
    /// Centre of its body now, m.
    pub position: [f64; 3],
    /// Orientation now as a quaternion `(x, y, z, w)`.
    pub rotation: [f64; 4],
    /// Disturbance since reset.
    pub disturbance: Disturbance,
    /// Whether rapier has it asleep (at rest, costing no contact or solver work).
    pub asleep: bool,
}

/// One episode's physical scene.
pub struct Scene {
    config: Checked<SceneConfig>,
    seed: u64,
    cupboard: Cupboard,
    layout: Layout,
    camera: DepthCamera,
    world: PhysicsWorld,
    jars: Vec<JarObstacle>,
    rest_poses: Vec<Pose>,
    hand: Hand,
    first_slice: Vec<[f64; 2]>,
    first_look_rng: ChaCha8Rng,
    sleep_timers_pending: bool,
    depth_rng: ChaCha8Rng,
    touch_rng: ChaCha8Rng,
    contacts_true: Vec<Contact>,
    contacts: Vec<Contact>,
    steps: u64,
    free_motions: u64,
}

impl Scene {
    /// Builds the scene of `seed`: generates the layout, builds the world, takes the depth
    /// camera's first look at the slice (the image rows that reach the slice band only; the
    /// whole image is rendered when [`Self::first_look`] asks for it). Cost: layout
    /// generation plus about a millisecond.
    ///
    /// # Errors
    /// A layout the generator cannot place within its attempts, or a camera or hand that
    /// does not fit the cupboard ([`SceneError`]).
    pub fn new(config: &Checked<SceneConfig>, seed: u64) -> Result<Self, SceneError> {
        let cupboard = Cupboard::new(&config.cupboard);
        let camera = DepthCamera::new(&config.camera)?;
        let layout = Layout::generate(&config.layout, &cupboard, &camera, seed)?;
        Self::build(config, layout, cupboard, camera, seed)
    }

    /// Builds a scene from an explicit layout (checked; its visibility is re-measured).
    /// `seed` drives the sensor noise.
    pub fn from_layout(
        config: &Checked<SceneConfig>,
        mut layout: Layout,
        seed: u64,
    ) -> Result<Self, SceneError> {
        let cupboard = Cupboard::new(&config.cupboard);
        let camera = DepthCamera::new(&config.camera)?;
        layout.check(&cupboard)?;
        layout.visibility = target_visibility(&camera, &cupboard, &layout.jars, layout.target);
        Self::build(config, layout, cupboard, camera, seed)
    }

    fn build(
        config: &Checked<SceneConfig>,
        layout: Layout,
        cupboard: Cupboard,
        camera: DepthCamera,
        seed: u64,
    ) -> Result<Self, SceneError> {
        let mut world = PhysicsWorld::new();
        world.gravity = Vector::new(0.0, 0.0, -9.81);
        let params = &mut world.integration_parameters;
        params.dt = config.physics.dt as Real;
        params.num_solver_iterations = config.physics.solver_iterations;
        // Recycled contacts let a moving finger tunnel through a jar on stale points.
        params.contact_recycling = false;
        cupboard.insert(&mut world);
        let jars: Vec<JarObstacle> = layout
            .jars
            .iter()
            .enumerate()
            .map(|(i, jar)| {
                let (body, collider) = jar.insert(&mut world, i, config.layout.jar_friction);
                JarObstacle {
                    body,
                    collider,
                    radius: jar.shape.bounding_radius(),
                }
            })
            .collect();
        let hand = Hand::insert(&mut world, &config.hand, config.slice_height, &cupboard)?;
        // A zero-length step builds the broad phase and the contacts (the touch reading at
        // reset) without moving anything.
        let dt = world.integration_parameters.dt;
        world.integration_parameters.dt = 0.0;
        world.step();
        world.integration_parameters.dt = dt;
        if config.physics.jars_start_asleep {
            // Eligible for sleep at once: rapier's own bookkeeping puts the jars (and their
            // islands) to sleep at the first physics step, before they move. The default
            // timer comes back after that step (see `physics_step`).
            for jar in &jars {
                world.bodies[jar.body].activation_mut().time_until_sleep = 0.0;
            }
        }
        let rest_poses = jars
            .iter()
            .map(|j| *world.bodies[j.body].position())
            .collect();

        let mut depth_rng = ChaCha8Rng::seed_from_u64(seed);
        depth_rng.set_stream(DEPTH_NOISE_STREAM);
        let mut touch_rng = ChaCha8Rng::seed_from_u64(seed);
        touch_rng.set_stream(TOUCH_NOISE_STREAM);
        let first_look_rng = depth_rng.clone();
        let slice = slice_spec(config);
        let at_rest = RayTargets::at_rest(&cupboard, &layout.jars);
        let band = [
            slice.height - 0.5 * slice.band,
            slice.height + 0.5 * slice.band,
        ];
        let first_slice = process_depth(
            &camera,
            camera.render_band(&at_rest, band),
            slice,
            &mut depth_rng,
        )
        .slice;
        let config_asleep = config.physics.jars_start_asleep;
        let mut scene = Self {
            config: config.clone(),
            seed,
            cupboard,
            layout,
            camera,
            world,
            jars,
            rest_poses,
            hand,
            first_slice,
            first_look_rng,
            sleep_timers_pending: config_asleep,
            depth_rng,
            touch_rng,
            contacts_true: Vec::new(),
            contacts: Vec::new(),
            steps: 0,
            free_motions: 0,
        };
        scene.sense_touch();
        Ok(scene)
    }

    fn sense_touch(&mut self) {
        self.contacts_true =
            finger_contacts(&self.world, self.hand.finger_collider(), &self.config.touch);
        self.contacts = with_noise(&self.contacts_true, &self.config.touch, &mut self.touch_rng);
    }

    /// Moves the wrist by `command` (clipped to the configured bounds) over
    /// `physics.substeps` physics steps, stopping at walls, then reads the touch sensor.
    /// Fails only on a non-finite command. Cost: `substeps` physics steps.
    pub fn step(&mut self, command: HandCommand) -> Result<StepReport, SceneError> {
        for (what, value) in [
            ("dx", command.dx),
            ("dy", command.dy),
            ("dyaw", command.dyaw),
        ] {
            if !value.is_finite() {
                return Err(SceneError::NonFiniteCommand { what, value });
            }
        }
        let h = &self.config.hand;
        let clip = |v: f64, bound: f64| v.clamp(-bound, bound);
        let commanded = HandCommand {
            dx: clip(command.dx, h.max_step_translation),
            dy: clip(command.dy, h.max_step_translation),
            dyaw: clip(command.dyaw, h.max_step_yaw),
        };
        let start = self.hand.pose();
        let goal = HandPose {
            x: start.x + commanded.dx,
            y: start.y + commanded.dy,
            yaw: start.yaw + commanded.dyaw,
        };
        let blocked = if self.config.physics.fast_free_motion && self.free_motion(start, goal) {
            self.carry_freely(start, goal);
            None
        } else {
            self.step_physics_towards(start, goal)
        };
        self.steps += 1;
        let end = self.hand.pose();
        Ok(StepReport {
            commanded,
            clipped: commanded != command,
            moved: HandCommand {
                dx: end.x - start.x,
                dy: end.y - start.y,
                dyaw: end.yaw - start.yaw,
            },
            blocked,
        })
    }

    /// The stepped command: `substeps` physics steps towards the interpolated poses, each
    /// checked against the walls (the hand holds the last clear pose once one is blocked),
    /// then the touch readings. Returns what blocked the hand, if anything.
    fn step_physics_towards(&mut self, start: HandPose, goal: HandPose) -> Option<Blocker> {
        let substeps = self.config.physics.substeps;
        let mut blocked = None;
        for k in 1..=substeps {
            if blocked.is_none() {
                let target = substep_target(start, goal, k, substeps);
                blocked = self.hand.advance(&mut self.world, target);
            } else {
                // Hold the reached pose (a kinematic body keeps its last target otherwise).
                let here = self.hand.pose();
                self.hand.advance(&mut self.world, here);
            }
            self.physics_step();
        }
        self.sense_touch();
        blocked
    }

    /// The fast path of free motion (see [`Scene::free_motion`]): the hand placed at the
    /// command's end without physics steps, and no reading (no noise drawn for none), as
    /// the stepped command would give.
    fn carry_freely(&mut self, start: HandPose, goal: HandPose) {
        let substeps = self.config.physics.substeps;
        let duration = substeps as f64 * self.config.physics.dt;
        let end = substep_target(start, goal, substeps, substeps);
        self.hand.carry(&mut self.world, end, duration);
        self.free_motions += 1;
        self.contacts_true.clear();
        self.contacts = with_noise(&[], &self.config.touch, &mut self.touch_rng);
    }

    /// Whether the command from `start` to `goal` may take the fast path of free motion
    /// (see [`free_motion`]): the first physics step is behind (the jars' sleep is set up),
    /// nothing moves, no substep target is blocked, and the hand is clear of every jar and
    /// wall at each pose where the stepped command would detect contacts (the start and the
    /// substep targets before the last). Cost: up to `substeps` wall checks and clearance
    /// tests.
    fn free_motion(&self, start: HandPose, goal: HandPose) -> bool {
        if self.sleep_timers_pending
            || !free_motion::jars_at_rest(&self.world, &self.jars)
            || !self.hand.finger_at_rest(
                &self.world,
                free_motion::REST_ANGLE,
                free_motion::REST_FINGER_RATE,
            )
        {
            return false;
        }
        let angle = self.hand.finger_angle(&self.world);
        let substeps = self.config.physics.substeps;
        (1..=substeps).all(|k| {
            let target = substep_target(start, goal, k, substeps);
            self.hand.blocker(target, angle).is_none()
        }) && (0..substeps).all(|k| {
            let pose = substep_target(start, goal, k, substeps);
            free_motion::clear_at(&self.world, &self.hand, &self.jars, pose, angle)
        })
    }

    /// Runs `n` physics steps with the hand held still (no touch update). Cost: n steps.
    pub fn idle(&mut self, n: usize) {
        let here = self.hand.pose();
        for _ in 0..n {
            self.hand.advance(&mut self.world, here);
            self.physics_step();
        }
    }

    /// One physics step. After the first, jars that started asleep get rapier's default
    /// sleep timer back: a jar woken later sleeps again only after resting that long.
    fn physics_step(&mut self) {
        self.world.step();
        if std::mem::take(&mut self.sleep_timers_pending) {
            let timer = RigidBodyActivation::default_time_until_sleep();
            for jar in &self.jars {
                self.world.bodies[jar.body]
                    .activation_mut()
                    .time_until_sleep = timer;
            }
        }
    }

    /// Takes a new depth look at the current state (the hand is not seen), drawing fresh
    /// noise; the first look taken at reset stays in [`Self::first_look`]. Cost: one render.
    pub fn capture(&mut self) -> DepthCapture {
        let image = self.camera.render(&RayTargets::from_world(&self.world));
        process_depth(
            &self.camera,
            image,
            slice_spec(&self.config),
            &mut self.depth_rng,
        )
    }

    /// The depth camera's look at reset (paper: before reaching in), whole: the image of the
    /// jars where the layout put them, its cloud and the slice with the noise drawn at
    /// reset. Rendered on each call (a few ms); its slice is [`Self::first_slice`].
    pub fn first_look(&self) -> DepthCapture {
        let image = self
            .camera
            .render(&RayTargets::at_rest(&self.cupboard, &self.layout.jars));
        process_depth(
            &self.camera,
            image,
            slice_spec(&self.config),
            &mut self.first_look_rng.clone(),
        )
    }

    /// The noisy slice of the first look: what the map starts from. Cost: none (kept).
    pub fn first_slice(&self) -> &[[f64; 2]] {
        &self.first_slice
    }

    /// The configuration.
    pub fn config(&self) -> &SceneConfig {
        &self.config
    }

    /// The seed the scene was built from.
    pub fn seed(&self) -> u64 {
        self.seed
    }

    /// The layout (jar specs at reset, target, corridor, measured visibility).
    pub fn layout(&self) -> &Layout {
        &self.layout
    }

    /// Index of the target jar.
    pub fn target(&self) -> usize {
        self.layout.target
    }

    /// The cupboard.
    pub fn cupboard(&self) -> &Cupboard {
        &self.cupboard
    }

    /// The depth camera.
    pub fn camera(&self) -> &DepthCamera {
        &self.camera
    }

    /// Scene steps taken since reset.
    pub fn steps(&self) -> u64 {
        self.steps
    }

    /// Scene steps since reset made by the fast path of free motion (`fast_free_motion`),
    /// without stepping the physics.
    pub fn free_motions(&self) -> u64 {
        self.free_motions
    }

    /// The commanded wrist pose.
    pub fn hand_pose(&self) -> HandPose {
        self.hand.pose()
    }

    /// The finger's joint position and yaw (wrist yaw + deflection).
    pub fn finger_pose(&self) -> HandPose {
        self.hand.finger_pose(&self.world)
    }

    /// Sensed finger deflection (joint angle), rad.
    pub fn finger_angle(&self) -> f64 {
        self.hand.finger_angle(&self.world)
    }

    /// The tactile readings after the last step, with noise.
    pub fn contacts(&self) -> &[Contact] {
        &self.contacts
    }

    /// The same readings without noise (ground truth).
    pub fn true_contacts(&self) -> &[Contact] {
        &self.contacts_true
    }

    /// Every jar's current state and disturbance since reset.
    pub fn jar_states(&self) -> Vec<JarState> {
        self.jars
            .iter()
            .zip(&self.layout.jars)
            .zip(&self.rest_poses)
            .map(|((handles, spec), rest)| {
                let body = &self.world.bodies[handles.body];
                let pose = *body.position();
                let t = pose.translation;
                let q = pose.rotation;
                JarState {
                    spec: *spec,
                    position: [f64::from(t.x), f64::from(t.y), f64::from(t.z)],
                    rotation: [q.x, q.y, q.z, q.w].map(f64::from),
                    disturbance: Disturbance::between(rest, &pose),
                    asleep: body.is_sleeping(),
                }
            })
            .collect()
    }

    /// Every body's pose and velocity, the hand pose and the touch readings, flattened: two
    /// scenes with equal vectors are in the same state (used to check determinism).
    pub fn state_vector(&self) -> Vec<f64> {
        let mut out = Vec::new();
        for (_, body) in self.world.bodies.iter() {
            let p = body.position();
            out.extend([p.translation.x, p.translation.y, p.translation.z].map(f64::from));
            out.extend([p.rotation.x, p.rotation.y, p.rotation.z, p.rotation.w].map(f64::from));
            let (v, w) = (body.linvel(), body.angvel());
            out.extend([v.x, v.y, v.z, w.x, w.y, w.z].map(f64::from));
        }
        let hand = self.hand.pose();
        out.extend([hand.x, hand.y, hand.yaw, self.finger_angle()]);
        for c in &self.contacts {
            out.extend([
                c.point[0],
                c.point[1],
                c.normal[0],
                c.normal[1],
                c.jar as f64,
            ]);
        }
        out
    }
}
