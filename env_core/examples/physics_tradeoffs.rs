//! What each physics setting trades, measured side by side in one run: the scene step's
//! time in free motion and in contact, against the properties the scene's tests protect
//! (a resting jar's drift, a sweeping compliant finger's push on a jar, a rigid finger's
//! shove, the readings' distance from the jar's surface, the finger's inertial deflection),
//! for conservative physics settings (4 substeps of 1/240 s, 8 solver iterations, jars
//! awake) and for each cheaper choice on its own: fewer solver iterations, jars that start
//! asleep, fewer and longer substeps.
//!
//! Run: `cargo run --release -p env_core --example physics_tradeoffs`.

use std::hint::black_box;
use std::time::Instant;

use env_core::scene::{HandCommand, JarShape, JarSpec, Layout, Scene, SceneConfig};
use env_core::settings::Checked;

const ROUND: JarShape = JarShape::Round { radius: 0.025 };
const SQUARE: JarShape = JarShape::Square { half_side: 0.024 };

fn jar(shape: JarShape) -> JarSpec {
    JarSpec {
        shape,
        height: 0.11,
        mass: 0.15,
        x: 0.0,
        y: 0.15,
        yaw: 0.0,
    }
}

fn command(dx: f64, dy: f64) -> HandCommand {
    HandCommand { dx, dy, dyaw: 0.0 }
}

/// A scene of one jar with the finger's side `gap` m from the jar's -x side.
fn beside(config: &SceneConfig, shape: JarShape, rigid: bool, gap: f64) -> Scene {
    let jar = jar(shape);
    let mut config = config.clone();
    config.hand.rigid_finger = rigid;
    config.touch.point_noise_std = 0.0;
    config.touch.normal_noise_std = 0.0;
    let x = jar.x - (jar.half_extent_x() + config.hand.finger_half_thickness + gap);
    let joint_offset = config.hand.wrist_half_extent + 0.002;
    config.hand.start = [x, jar.y - 0.07 - joint_offset, 0.0];
    Scene::from_layout(&Checked::new(config).unwrap(), Layout::lone_jar(jar), 0)
        .expect("scene builds")
}

fn median(mut values: Vec<f64>) -> f64 {
    values.sort_by(f64::total_cmp);
    values[values.len() / 2]
}

/// Median µs of a scene step with the hand moving sideways in front of the opening, touching
/// nothing, in layouts of 3-7 jars; and the largest free-space (inertial) deflection, rad.
fn free_step_us(config: &SceneConfig) -> (f64, f64) {
    let mut times = Vec::new();
    let mut peak = 0.0f64;
    for seed in 0..20 {
        let mut scene =
            Scene::new(&Checked::new(config.clone()).unwrap(), seed).expect("scene builds");
        for k in 0..200 {
            let dx = if (k / 5) % 2 == 0 { 0.01 } else { -0.01 };
            let start = Instant::now();
            black_box(scene.step(command(dx, 0.0)).expect("finite"));
            times.push(start.elapsed().as_secs_f64() * 1e6);
            peak = peak.max(scene.finger_angle().abs());
        }
    }
    (median(times), peak)
}

/// Median µs of a scene step while the finger slides along a round jar it presses on.
fn contact_step_us(config: &SceneConfig) -> f64 {
    let mut scene = beside(config, ROUND, false, 0.006);
    for _ in 0..7 {
        scene.step(command(0.002, 0.0)).expect("finite");
    }
    let mut times = Vec::new();
    for k in 0..4000 {
        let dy = if (k / 10) % 2 == 0 { 0.0005 } else { -0.0005 };
        let start = Instant::now();
        black_box(scene.step(command(0.0, dy)).expect("finite"));
        times.push(start.elapsed().as_secs_f64() * 1e6);
    }
    assert!(!scene.true_contacts().is_empty(), "contact lost");
    median(times)
}

/// Largest displacement (m) of any jar after 1000 idle physics steps, seeds 0-3, 3-7 jars.
fn rest_drift(config: &SceneConfig) -> f64 {
    let mut worst = 0.0f64;
    for seed in 0..4 {
        let mut scene =
            Scene::new(&Checked::new(config.clone()).unwrap(), seed).expect("scene builds");
        scene.idle(1000);
        for state in scene.jar_states() {
            worst = worst.max(state.disturbance.displacement);
        }
    }
    worst
}

/// Presses 12 mm past first contact and sweeps 2 cm each way; returns the jar's largest
/// displacement (m) and, on a round jar, the largest distance (m) of a reading from the
/// jar's surface (the finger's penetration and the contact's placement).
fn sweep(config: &SceneConfig, shape: JarShape, rigid: bool) -> (f64, f64) {
    let mut scene = beside(config, shape, rigid, 0.006);
    let script = (0..9)
        .map(|_| command(0.002, 0.0))
        .chain((0..10).map(|_| command(0.0, 0.002)))
        .chain((0..20).map(|_| command(0.0, -0.002)))
        .chain((0..10).map(|_| command(0.0, 0.002)));
    let (mut moved, mut off_surface) = (0.0f64, 0.0f64);
    for step in script {
        scene.step(step).expect("finite");
        let state = scene.jar_states()[0];
        moved = moved.max(state.disturbance.displacement);
        if let (JarShape::Round { radius }, false) = (shape, rigid) {
            for contact in scene.true_contacts() {
                let from_centre = (contact.point[0] - state.position[0])
                    .hypot(contact.point[1] - state.position[1]);
                off_surface = off_surface.max((from_centre - radius).abs());
            }
        }
    }
    (moved, off_surface)
}

fn main() {
    // (name, substeps, dt, solver iterations, jars start asleep); substeps × dt is the
    // 1/60 s of one command in every row.
    let variants = [
        ("4 x 1/240 s, 8 it., awake", 4, 240.0, 8, false),
        ("4 x 1/240 s, 8 it., asleep", 4, 240.0, 8, true),
        ("4 x 1/240 s, 4 it., awake", 4, 240.0, 4, false),
        ("4 x 1/240 s, 4 it., asleep", 4, 240.0, 4, true),
        ("2 x 1/120 s, 4 it., asleep", 2, 120.0, 4, true),
        ("2 x 1/120 s, 2 it., asleep", 2, 120.0, 2, true),
        ("1 x 1/60 s, 4 it., asleep", 1, 60.0, 4, true),
    ];
    println!(
        "{:<36} {:>8} {:>9} {:>9} {:>9} {:>10} {:>10} {:>9} {:>11}",
        "physics settings",
        "free µs",
        "touch µs",
        "free rad",
        "drift µm",
        "round µm",
        "square µm",
        "rigid mm",
        "surface mm"
    );
    for (name, substeps, rate, iterations, asleep) in variants {
        let mut config = SceneConfig::default();
        config.physics.substeps = substeps;
        config.physics.dt = 1.0 / rate;
        config.physics.solver_iterations = iterations;
        config.physics.jars_start_asleep = asleep;
        let (round, off_surface) = sweep(&config, ROUND, false);
        let (square, _) = sweep(&config, SQUARE, false);
        let (rigid, _) = sweep(&config, ROUND, true);
        let (free, deflection) = free_step_us(&config);
        println!(
            "{:<36} {:>8.1} {:>9.1} {:>9.3} {:>9.2} {:>10.1} {:>10.1} {:>9.1} {:>11.3}",
            name,
            free,
            contact_step_us(&config),
            deflection,
            1e6 * rest_drift(&config),
            1e6 * round,
            1e6 * square,
            1e3 * rigid,
            1e3 * off_surface,
        );
    }
    println!(
        "free: median scene step, hand moving in front of the opening, and its largest \
         (inertial) finger deflection; touch: median scene step with the finger sliding on a \
         jar; drift: largest jar displacement after 1000 idle physics steps; round/square: \
         largest jar displacement under the compliant finger's sweep (test bound 2 mm); \
         rigid: the rigid finger's shove (test bound > 10 mm); surface: largest distance of \
         a reading from the round jar's surface (test bound 1 mm). Medians from this one \
         run."
    );
}
