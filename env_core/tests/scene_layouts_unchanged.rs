//! Layouts without hidden decoys are the layouts the generator has always made: the pinned
//! rollouts and every recorded evaluation depend on a seed giving the same jars bit for bit,
//! so any change to the generator must consume its random stream in the same order when
//! `hidden_decoys` is 0.

use env_core::scene::{Cupboard, DepthCamera, JarShape, Layout, SceneConfig, TargetShape};

/// FNV-1a, 64 bit: a hash fixed by its definition (std's hashers may change between Rust
/// releases).
struct Fnv(u64);

impl Fnv {
    fn new() -> Self {
        Self(0xcbf2_9ce4_8422_2325)
    }
    fn bytes(&mut self, bytes: &[u8]) {
        for &b in bytes {
            self.0 ^= u64::from(b);
            self.0 = self.0.wrapping_mul(0x0000_0100_0000_01b3);
        }
    }
    fn f64(&mut self, v: f64) {
        self.bytes(&v.to_bits().to_le_bytes());
    }
    fn usize(&mut self, v: usize) {
        self.bytes(&(v as u64).to_le_bytes());
    }
}

/// The hash of every jar field (as f64 bits), the target index, the corridor and the
/// target's pixel counts of the layouts of `seeds` at `config`.
fn layouts_hash(config: &SceneConfig, seeds: std::ops::Range<u64>) -> u64 {
    let cupboard = Cupboard::new(&config.cupboard);
    let camera = DepthCamera::new(&config.camera).expect("camera");
    let mut hash = Fnv::new();
    for seed in seeds {
        let layout =
            Layout::generate(&config.layout, &cupboard, &camera, seed).expect("layout found");
        hash.usize(layout.jars.len());
        for jar in &layout.jars {
            match jar.shape {
                JarShape::Round { radius } => {
                    hash.usize(0);
                    hash.f64(radius);
                }
                JarShape::Square { half_side } => {
                    hash.usize(1);
                    hash.f64(half_side);
                }
            }
            for v in [jar.height, jar.mass, jar.x, jar.y, jar.yaw] {
                hash.f64(v);
            }
        }
        hash.usize(layout.target);
        let corridor = layout.corridor.expect("generated layouts have a corridor");
        for v in [
            corridor.x[0],
            corridor.x[1],
            corridor.y[0],
            corridor.y[1],
            corridor.side,
        ] {
            hash.f64(v);
        }
        hash.usize(layout.visibility.silhouette_pixels);
        hash.usize(layout.visibility.visible_pixels);
    }
    hash.0
}

/// Recorded by this test on the generator before hidden decoys existed (commit 7b528ea), at
/// the default settings, seeds 0..2000.
const DEFAULT_LAYOUTS_HASH: u64 = 0xebb2_4560_187d_423c;

/// The same for [`other_settings`], seeds 0..1000.
const OTHER_LAYOUTS_HASH: u64 = 0x8155_7bc4_4d5f_6fc2;

/// Settings that take the generator's other paths: single jars (no occluder), a fixed target
/// shape, a tighter visibility bound and a narrower cupboard.
fn other_settings() -> SceneConfig {
    let mut config = SceneConfig::default();
    config.layout.jar_count = [1, 7];
    config.layout.target_shape = TargetShape::Square;
    config.layout.round_fraction = 0.3;
    config.layout.max_visible_fraction = 0.05;
    config.cupboard.width = 0.5;
    config
}

#[test]
fn layouts_without_decoys_are_unchanged() {
    let hash = layouts_hash(&SceneConfig::default(), 0..2000);
    assert_eq!(
        hash, DEFAULT_LAYOUTS_HASH,
        "the default layouts of seeds 0..2000 changed: got {hash:#018x}"
    );
    let hash = layouts_hash(&other_settings(), 0..1000);
    assert_eq!(
        hash, OTHER_LAYOUTS_HASH,
        "the layouts of seeds 0..1000 at other settings changed: got {hash:#018x}"
    );
}
