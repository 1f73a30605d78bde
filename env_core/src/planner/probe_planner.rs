//! The GPIS probe planner: a scripted searcher that plans on the GPIS map without ground
//! truth, choosing the probes of the `probe` action mode. The teacher every recipe clones.
//!
//! Strategy. The target hides in the camera's shadow behind other jars, and touching a jar
//! that is not the target does not end the episode. The planner keeps a [`Belief`]: the
//! GPIS mean and std decoded from the observation, the camera's shadows, the cells its
//! finger swept without contact and the jars it touched. Each action is a probe of the
//! core's grid, `[lane, depth, sweep]`, which the observation-only controller
//! ([`crate::episode::ProbeController`]) carries out as a learned agent's probes are.
//!
//! Per probe it reads one observation, after the probe, and nothing else: the map image and
//! the proprio vector. Its belief learns what the finger swept from the probe it chose (or
//! was told the env carried out, [`ProbePlanner::follow`]) and the pose the probe ended in,
//! and what it touched from the map and the contact in the observation. It then scores
//! every probe of the grid the wrist and arm can make without coming near a cell that may
//! hold a jar ([`super::clearance`]), with a sweep no wider than the largest safe turn, by
//! the hiding weight its finger passes over per motion the controller will make
//! ([`crate::episode::ProbeController::motions`]).
//!
//! The rules and their constants are the Python planner's, computed in its order (numpy's
//! sums and sequences, [`super::numeric`]), so that it makes the same probes.

use std::sync::Arc;

use super::belief::Belief;
use super::clearance::{FieldLayout, TurnProbe};
use super::error::PlannerError;
use super::geometry::PlannerGeometry;
use super::numeric::pairwise_sum;
use super::reachable::{turn_of, Reachable, LANE_TOL};
pub(super) use super::reachable::{Candidate, SweptProbe};
use crate::episode::decode_proprio;
use crate::episode::maps::{decode_image, MapMode};
use crate::episode::{ActionMode, EpisodeConfig, Quantity, PROPRIO_LEN};
use crate::scene::HandPose;
use crate::settings::Choice;

/// Motions added to every probe's cost (favours probes that cover more at once).
const COST_OFFSET: f64 = 15.0;
/// An offset this near the finger's length (as a share) was clipped by the observation.
const CLIPPED_SHARE: f64 = 0.999;

/// One observation as the planner reads it: the map image (`C × H × W` bytes, channel
/// first) and the proprio vector.
#[derive(Debug, Clone, Copy)]
pub struct PlannerObservation<'a> {
    /// The map image, `C × H × W` bytes.
    pub map: &'a [u8],
    /// The proprio vector.
    pub proprio: &'a [f32; PROPRIO_LEN],
}

/// The wrist's pose and the touch, as decoded from the proprio vector.
#[derive(Debug, Clone, Copy)]
pub(super) struct Pose {
    pub x: f64,
    pub y: f64,
    pub yaw: f64,
    pub deflection: f64,
    /// The contact point and the touched jar's outward normal, when the finger touches.
    pub contact: Option<([f64; 2], [f64; 2])>,
    /// Whether the contact point is where the finger touched (false where the observation
    /// clipped its offset and [`ContactRule::FingerSide`] could not put it back).
    pub sure: bool,
}

/// How a contact whose offset the observation clipped (near the fingertip) is put back on
/// the finger.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum ContactRule {
    /// On the finger's centre line, from the first unclipped component that says enough of
    /// the distance along it (else at the tip). The search planner's rule.
    FingerAxis,
    /// On the side of the finger that touches (half its thickness from the centre line,
    /// against the normal), from the unclipped component; where that says little (or both
    /// are clipped) the contact is [`FingerAxis`](ContactRule::FingerAxis)'s and not sure.
    /// The identify planner's rule: a shape is told from its contacts' points.
    FingerSide,
}

/// How the planner's belief reads the observed map (as the GPIS mean and std, m).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum MapReading {
    /// The GPIS map's mean and std as they are.
    Gpis,
    /// The occupancy grid as a map of signed distance: a cell at or above `OCCUPIED` a jar
    /// (mean −0.01), one at or below 1 − `OCCUPIED` free (0.03), both known (std 0); the
    /// rest unknown (mean 0.01, std 0.05). The occupancy mapper's belief.
    Occupancy,
}

/// A decoded map channel: its name and its physical value per cell.
pub(super) type MapChannel = (&'static str, Vec<f64>);

/// The occupancy above which a cell counts as a jar, and below 1 minus which as free.
pub(super) const OCCUPIED: f64 = 0.55;

/// The planner of one episode at a time (see the module docs). Clones share what the
/// settings fix (a batch's planners build it once).
#[derive(Debug, Clone)]
pub struct ProbePlanner {
    statics: Arc<Statics>,
    contact_rule: ContactRule,
    reading: MapReading,
    belief: Option<Belief>,
    chosen: Option<[i64; 3]>,
}

/// What a planner knows before any episode: the settings and the geometry, clearance grid
/// and turn tables they fix.
#[derive(Debug)]
struct Statics {
    config: EpisodeConfig,
    geometry: PlannerGeometry,
    layout: FieldLayout,
    turns: TurnProbe,
    /// The cells each grid probe's finger passes within the sweep radius (its score).
    search_paths: ProbePaths,
}

/// For every probe of the grid (by its row-major action index), the map cells within `hit`
/// of its finger's path ([`covers`]), as bits (`words` 64-bit words per probe): what the
/// settings fix of a probe's score, so that an act sums the weights of a probe's cells of
/// positive weight, a few words ANDed, instead of testing every cell against every probe.
#[derive(Debug)]
pub(super) struct ProbePaths {
    bits: Vec<u64>,
    words: usize,
}

/// The cells where a weight is positive, in [`ProbePaths`]' bits, from the first word that
/// holds any to the last (the words outside are 0).
pub(super) struct PositiveCells {
    bits: Vec<u64>,
    first: usize,
}

impl ProbePaths {
    /// The paths of `g`'s probe grid within `hit`.
    pub(super) fn new(g: &PlannerGeometry, hit: f64) -> Self {
        let sweeps: Vec<(f64, f64)> = g.probe_yaws.iter().map(|&yaw| turn_of(yaw)).collect();
        let words = g.xs.len().div_ceil(64);
        let mut bits =
            vec![0u64; g.probe_lanes.len() * g.probe_depths.len() * sweeps.len() * words];
        let mut probe = 0;
        for &x in &g.probe_lanes {
            for &y in &g.probe_depths {
                for k in 0..g.xs.len() {
                    let from = FromWrist::new(g, [x, y], [g.xs[k], g.ys[k]], hit);
                    if !from.may_be_covered(g, hit) {
                        continue;
                    }
                    for (sweep, &(side, angle)) in sweeps.iter().enumerate() {
                        if from.covered(g, side, angle, hit) {
                            bits[(probe + sweep) * words + k / 64] |= 1 << (k % 64);
                        }
                    }
                }
                probe += sweeps.len();
            }
        }
        Self { bits, words }
    }

    /// The cells where `weight` is positive.
    pub(super) fn positive(&self, weight: &[f64]) -> PositiveCells {
        let mut bits = vec![0u64; self.words];
        for (k, _) in weight.iter().enumerate().filter(|(_, &w)| w > 0.0) {
            bits[k / 64] |= 1 << (k % 64);
        }
        let first = bits
            .iter()
            .position(|&word| word != 0)
            .unwrap_or(self.words);
        let last = bits
            .iter()
            .rposition(|&word| word != 0)
            .map_or(first, |w| w + 1);
        bits.truncate(last);
        PositiveCells { bits, first }
    }

    /// The weight the finger of the probe of row-major index `index` passes: numpy's sum of
    /// `weight` over its cells of positive weight (`positive`), in cell order; 0 where it
    /// passes none. `covered` is scratch space.
    pub(super) fn passed(
        &self,
        index: usize,
        weight: &[f64],
        positive: &PositiveCells,
        covered: &mut Vec<f64>,
    ) -> f64 {
        let path = &self.bits[index * self.words..(index + 1) * self.words];
        covered.clear();
        let words = path.iter().zip(&positive.bits).enumerate();
        for (word, (&cells, &positive)) in words.skip(positive.first) {
            let mut both = cells & positive;
            while both != 0 {
                covered.push(weight[word * 64 + both.trailing_zeros() as usize]);
                both &= both - 1;
            }
        }
        pairwise_sum(covered)
    }
}

impl ProbePlanner {
    /// The planner of episodes of `config`, which must have the GPIS map and the `probe`
    /// action mode.
    pub fn new(config: &EpisodeConfig) -> Result<Self, PlannerError> {
        Self::with_rules(config, ContactRule::FingerAxis, MapReading::Gpis)
    }

    /// [`ProbePlanner::new`] putting clipped contacts back by `contact_rule` and reading the
    /// map by `reading` (the settings' map must be the one it reads).
    pub(super) fn with_rules(
        config: &EpisodeConfig,
        contact_rule: ContactRule,
        reading: MapReading,
    ) -> Result<Self, PlannerError> {
        let wanted = match reading {
            MapReading::Gpis => MapMode::Gpis,
            MapReading::Occupancy => MapMode::Occupancy,
        };
        if config.map.mode != wanted {
            return Err(PlannerError::NeedsMap {
                wanted: wanted.name(),
                got: config.map.mode.name(),
            });
        }
        if config.action_mode != ActionMode::Probe {
            return Err(PlannerError::NeedsProbeActions(config.action_mode.name()));
        }
        let geometry = PlannerGeometry::of(config)?;
        let layout = FieldLayout::new(&geometry);
        Ok(Self {
            statics: Arc::new(Statics {
                config: config.clone(),
                turns: TurnProbe::new(&geometry, &layout),
                search_paths: ProbePaths::new(&geometry, Belief::sweep_radius(&geometry)),
                layout,
                geometry,
            }),
            contact_rule,
            reading,
            belief: None,
            chosen: None,
        })
    }

    /// Starts an episode from its first observation.
    pub fn reset(&mut self, observation: PlannerObservation<'_>) -> Result<(), PlannerError> {
        let (mean, std) = self.decode_map(observation.map)?;
        self.belief = Some(Belief::new(&self.statics.geometry, mean, std));
        self.chosen = None;
        let pose = self.pose(observation.proprio);
        self.remember_touch(&pose);
        Ok(())
    }

    /// Takes `observation` (the one after the last probe) into the belief and chooses the
    /// next probe, `[lane, depth, sweep]`.
    pub fn act(&mut self, observation: PlannerObservation<'_>) -> Result<[i64; 3], PlannerError> {
        let pose = self.observe(observation)?;
        let chosen = self.choose(&pose);
        self.chosen = Some(chosen);
        Ok(chosen)
    }

    /// Takes `action`, not the probe [`ProbePlanner::act`] just chose, as the probe the env
    /// carries out next: the planner then labels states another agent visits (DAgger), its
    /// belief learning from the probes that agent made.
    pub fn follow(&mut self, action: [i64; 3]) -> Result<(), PlannerError> {
        if self.belief.is_none() {
            return Err(PlannerError::NotReset);
        }
        self.statics.geometry.controller.check(&action)?;
        self.chosen = Some(action);
        Ok(())
    }

    /// The map image's channels, decoded (physical values per cell).
    fn decode_channels(&self, image: &[u8]) -> Result<Vec<MapChannel>, PlannerError> {
        let cells = self.statics.geometry.xs.len();
        Ok(decode_image(&self.statics.config.map, cells, image)?)
    }

    /// How the planner reads the map.
    pub(super) fn reading(&self) -> MapReading {
        self.reading
    }

    /// The map image as the belief reads it: the mean and std (see [`MapReading`]).
    fn decode_map(&self, image: &[u8]) -> Result<(Vec<f64>, Vec<f64>), PlannerError> {
        Ok(self.belief_map(self.decode_channels(image)?))
    }

    /// Decoded channels as the belief reads them: the mean and std (see [`MapReading`]).
    fn belief_map(&self, channels: Vec<MapChannel>) -> (Vec<f64>, Vec<f64>) {
        let mut channels = channels.into_iter();
        match (self.reading, channels.next(), channels.next()) {
            (MapReading::Gpis, Some(("mean", mean)), Some(("std", std))) => (mean, std),
            (MapReading::Occupancy, Some(("occupied", occupied)), None) => {
                let known = |p: f64| (p - 0.5).abs() >= OCCUPIED - 0.5;
                let mean = occupied
                    .iter()
                    .map(|&p| match (p >= OCCUPIED, known(p)) {
                        (true, _) => -0.01,
                        (false, true) => 0.03,
                        (false, false) => 0.01,
                    })
                    .collect();
                let std = occupied
                    .iter()
                    .map(|&p| if known(p) { 0.0 } else { 0.05 })
                    .collect();
                (mean, std)
            }
            _ => unreachable!("the settings' map is the one the planner reads"),
        }
    }

    /// The geometry of the settings the planner was made for.
    pub(super) fn geometry(&self) -> &PlannerGeometry {
        &self.statics.geometry
    }

    /// The probe the env carries out next (the planner's own choice or one it follows).
    pub(super) fn set_chosen(&mut self, chosen: [i64; 3]) {
        self.chosen = Some(chosen);
    }

    /// Takes `observation` into the belief (the map, the last probe's swept path, the
    /// touch) and returns the wrist's pose.
    pub(super) fn observe(
        &mut self,
        observation: PlannerObservation<'_>,
    ) -> Result<Pose, PlannerError> {
        Ok(self.observe_reading(observation, |_| ())?.0)
    }

    /// [`ProbePlanner::observe`], also returning what `read` makes of the observation's
    /// decoded map channels (read before the belief takes them: the image is decoded once).
    pub(super) fn observe_reading<T>(
        &mut self,
        observation: PlannerObservation<'_>,
        read: impl FnOnce(&[MapChannel]) -> T,
    ) -> Result<(Pose, T), PlannerError> {
        if self.belief.is_none() {
            return Err(PlannerError::NotReset);
        }
        let channels = self.decode_channels(observation.map)?;
        let reading = read(&channels);
        let (mean, std) = self.belief_map(channels);
        self.belief_mut().update(mean, std);
        let pose = self.pose(observation.proprio);
        if let Some(chosen) = self.chosen {
            self.sweep_probe_path(chosen, &pose);
        }
        self.remember_touch(&pose);
        Ok((pose, reading))
    }

    pub(super) fn belief(&self) -> &Belief {
        self.belief.as_ref().expect("reset before use")
    }

    fn belief_mut(&mut self) -> &mut Belief {
        self.belief.as_mut().expect("reset before use")
    }

    // -- the observation ---------------------------------------------------------------

    fn pose(&self, proprio: &[f32; PROPRIO_LEN]) -> Pose {
        let decoded = decode_proprio(proprio, &self.statics.config);
        let real = |name: &str| match decoded.iter().find(|(n, _)| *n == name) {
            Some((_, Quantity::Real(value))) => *value,
            _ => unreachable!("{name} is a real quantity of the proprio"),
        };
        let touching = matches!(
            decoded.iter().find(|(n, _)| *n == "in_contact"),
            Some((_, Quantity::Flag(true)))
        );
        let (x, y, deflection) = (real("x"), real("y"), real("deflection"));
        // The heading in float32 from the observed sin and cos (the rules' constants were
        // chosen on this angle; the decoded f64 yaw differs in the last bits).
        let entry = |name: &str| {
            proprio[crate::episode::observation::proprio_index(name).expect("an entry")]
        };
        let yaw = f64::from(entry("sin_yaw").atan2(entry("cos_yaw")));
        let mut sure = touching;
        let contact = touching.then(|| {
            let offset = [real("contact_dx"), real("contact_dy")];
            let normal = [real("normal_x"), real("normal_y")];
            let on_axis = self.contact_point([x, y], yaw + deflection, yaw, offset);
            let point = match self.contact_rule {
                ContactRule::FingerAxis => Some(on_axis),
                ContactRule::FingerSide => {
                    self.contact_on_side([x, y], yaw + deflection, yaw, offset, normal)
                }
            };
            sure = point.is_some();
            (point.unwrap_or(on_axis), normal)
        });
        Pose {
            x,
            y,
            yaw,
            deflection,
            contact,
            sure,
        }
    }

    /// [`ContactRule::FingerSide`]'s contact point: the offset itself when neither
    /// component was clipped; else on the touching side of the finger, solved from the
    /// first unclipped component if the finger's direction has at least
    /// `WELL_CONDITIONED` of it; else None (the point is unsure).
    fn contact_on_side(
        &self,
        wrist: [f64; 2],
        heading: f64,
        yaw: f64,
        offset: [f64; 2],
        normal: [f64; 2],
    ) -> Option<[f64; 2]> {
        const WELL_CONDITIONED: f64 = 0.3;
        let g = &self.statics.geometry;
        let clipped = offset.map(|o| o.abs() >= CLIPPED_SHARE * g.finger_length);
        if !clipped[0] && !clipped[1] {
            return Some([wrist[0] + offset[0], wrist[1] + offset[1]]);
        }
        let axis = if clipped[0] { 1 } else { 0 };
        let direction = PlannerGeometry::forward(heading);
        if clipped[0] && clipped[1] || direction[axis].abs() < WELL_CONDITIONED {
            return None;
        }
        let joint = g.joint(wrist, yaw);
        let side = normal.map(|n| -g.finger_half_thickness * n);
        let along = (wrist[axis] + offset[axis] - joint[axis] - side[axis]) / direction[axis];
        let along = along.clamp(0.0, g.finger_length);
        Some([
            joint[0] + along * direction[0] + side[0],
            joint[1] + along * direction[1] + side[1],
        ])
    }

    /// The contact point from its offset to the wrist. The observation clips the offset at
    /// the finger length, which cuts off contacts near the fingertip; those are put back on
    /// the finger from the unclipped component.
    fn contact_point(&self, wrist: [f64; 2], heading: f64, yaw: f64, offset: [f64; 2]) -> [f64; 2] {
        let g = &self.statics.geometry;
        let point = [wrist[0] + offset[0], wrist[1] + offset[1]];
        let clipped = offset.map(|o| o.abs() >= CLIPPED_SHARE * g.finger_length);
        if !clipped[0] && !clipped[1] {
            return point;
        }
        let joint = g.joint(wrist, yaw);
        let direction = PlannerGeometry::forward(heading);
        let mut along = g.finger_length;
        for axis in 0..2 {
            if !clipped[axis] && direction[axis].abs() > 0.3 {
                along = ((point[axis] - joint[axis]) / direction[axis]).clamp(0.0, along);
                break;
            }
        }
        [
            joint[0] + along * direction[0],
            joint[1] + along * direction[1],
        ]
    }

    /// Adds a touched jar, or the finger where it is (touching nothing), to the belief.
    fn remember_touch(&mut self, pose: &Pose) {
        let g = &self.statics.geometry;
        let joint = g.joint([pose.x, pose.y], pose.yaw);
        let heading = PlannerGeometry::forward(pose.yaw + pose.deflection);
        let tip = [
            joint[0] + g.finger_length * heading[0],
            joint[1] + g.finger_length * heading[1],
        ];
        let belief = self.belief.as_mut().expect("reset before use");
        match pose.contact {
            Some((point, normal)) => belief.add_touch(g, point, normal),
            None => belief.sweep_finger(g, joint, tip),
        }
    }

    // -- what the last probe swept -----------------------------------------------------

    /// Marks as swept what the finger passed on its way through probe `chosen` to `after`,
    /// as the controller drives it: straight along the lane to the depth the probe ended
    /// at, then the turn from straight to where it ended. The cells are those the probe's
    /// score counts ([`covers`] at the sweep radius), so a probe that touched nothing
    /// leaves nothing it was chosen for.
    fn sweep_probe_path(&mut self, chosen: [i64; 3], after: &Pose) {
        let g = &self.statics.geometry;
        let lane_x = g.probe_lanes[chosen[0] as usize];
        if (after.x - lane_x).abs() > LANE_TOL {
            return; // stopped before reaching its lane (the hand blocked): nothing known
        }
        let (side, angle) = turn_of(after.yaw);
        let done = SweptProbe {
            x: lane_x,
            y: after.y,
            side,
            angle,
        };
        let hit = Belief::sweep_radius(g);
        let belief = self.belief.as_mut().expect("reset before use");
        belief.mark_swept((0..g.xs.len()).map(|k| (k, covers(g, &done, [g.xs[k], g.ys[k]], hit))));
    }

    // -- choosing the next probe -------------------------------------------------------

    /// The grid probe with the most hiding weight under its finger per motion: where the
    /// target may hide by the strict conditions, or, when no probe the hand can make covers
    /// any of that, by the relaxed ones.
    ///
    /// The result is that of scoring [`ProbePlanner::candidates`] in row-major order, the
    /// first of the highest score winning; but only a probe whose finger passes some weight
    /// can score, and its motions are at least those to its lane and depth, which bounds its
    /// score. The probes are taken from the highest bound down, and only until no bound is
    /// left that could reach the best: so few have their sweep's motions counted, and fewer
    /// still are asked whether the hand can make them (the safe turn).
    pub(super) fn choose(&self, pose: &Pose) -> [i64; 3] {
        let g = &self.statics.geometry;
        let belief = self.belief();
        let paths = &self.statics.search_paths;
        let mut reachable = self.reachable(pose, &belief.solid(0.0));
        // Count what a probe that touches nothing clears from the belief (the cells its
        // sweep marks), not the wider ring within a jar radius of the finger: that ring is
        // never cleared, and counting it made a probe worth repeating.
        let mut covered = Vec::new();
        for relaxed in [false, true] {
            let weight = belief.hiding_weight(g, relaxed);
            let positive = paths.positive(&weight);
            // (bound, row-major index, action, the weight it passes)
            let mut bounded = Vec::new();
            for (index, action) in g.probe_actions().enumerate() {
                if !reachable.reaches_depth(action) {
                    continue;
                }
                let passed = paths.passed(index, &weight, &positive, &mut covered);
                if passed > 0.0 {
                    let least = reachable.least_motions(action) as f64 + COST_OFFSET;
                    bounded.push((passed / least, index, action, passed));
                }
            }
            bounded.sort_by(|a, b| b.0.total_cmp(&a.0).then(a.1.cmp(&b.1)));
            let mut best: Option<(f64, usize, [usize; 3])> = None;
            for (bound, index, action, passed) in bounded {
                if best.is_some_and(|(score, _, _)| bound < score) {
                    break; // neither this probe nor any after it reaches the best
                }
                let score = passed / (reachable.motions(action) as f64 + COST_OFFSET);
                let better = best.is_none_or(|(best_score, best_index, _)| {
                    score > best_score || (score == best_score && index < best_index)
                });
                if better && reachable.turn_is_safe(action) && !reachable.is_wait(action) {
                    best = Some((score, index, action));
                }
            }
            if let Some((_, _, action)) = best {
                return action.map(|i| i as i64);
            }
        }
        // Nothing left to cover: straight in at the middle lane's opening.
        g.opening_probe()
    }

    /// Calls `visit` with each of `candidates` in order and the weight its finger's path
    /// passes (`paths`, [`ProbePaths::passed`]; `weight` per cell, ≥ 0).
    pub(super) fn path_weights(
        &self,
        candidates: &[Candidate],
        weight: &[f64],
        paths: &ProbePaths,
        mut visit: impl FnMut(&Candidate, f64),
    ) {
        let g = &self.statics.geometry;
        let positive = paths.positive(weight);
        let mut covered = Vec::new();
        for candidate in candidates {
            let index = g.probe_index(candidate.action.map(|i| i as usize));
            visit(
                candidate,
                paths.passed(index, weight, &positive, &mut covered),
            );
        }
    }

    /// Every grid probe the wrist and arm can make from `pose` without coming near a cell
    /// that may hold a jar, its sweep no wider than the largest safe turn, except a wait.
    pub(super) fn candidates(&self, pose: &Pose) -> Vec<Candidate> {
        self.clear_probes(pose, &self.belief().solid(0.0))
    }

    /// [`ProbePlanner::candidates`] with the cells the finger must not sweep into given
    /// (`solid_cells`, a mask of the map's cells): every grid probe clear of them and of
    /// every cell that may hold a jar for the wrist and arm, except a wait.
    pub(super) fn clear_probes(&self, pose: &Pose, solid_cells: &[bool]) -> Vec<Candidate> {
        self.reachable(pose, solid_cells).all()
    }

    /// The grid's probes from `pose`, the wrist and arm kept clear of every cell that may
    /// hold a jar and the finger out of `solid_cells`.
    fn reachable(&self, pose: &Pose, solid_cells: &[bool]) -> Reachable<'_> {
        let Statics {
            geometry: g,
            layout,
            turns,
            ..
        } = &*self.statics;
        let blocked = self.belief().blocked(g);
        let pose = HandPose {
            x: pose.x,
            y: pose.y,
            yaw: pose.yaw,
        };
        Reachable::new(g, layout, turns, &blocked, solid_cells, pose)
    }
}

/// A candidate jar centre seen from a probe's wrist position: what [`covers`] needs of it
/// for any sweep of the probes at that position (the distance and the bearings are the
/// same for every sweep, so a position's probes compute them once).
#[derive(Debug, Clone, Copy)]
struct FromWrist {
    /// The centre's offset from the wrist, x (as a turn towards +x sees it) and y.
    dx: f64,
    dy: f64,
    /// Within the finger's reach: the distance and the bearing from straight ahead for a
    /// turn towards −x and towards +x.
    near: Option<(f64, [f64; 2])>,
}

impl FromWrist {
    fn new(g: &PlannerGeometry, wrist: [f64; 2], centre: [f64; 2], hit: f64) -> Self {
        let (dx, dy) = (centre[0] - wrist[0], centre[1] - wrist[1]);
        let limit = g.reach + hit;
        // hypot is at least each leg, so a leg beyond the limit puts the centre beyond it.
        let near = (dx.abs() <= limit && dy.abs() <= limit)
            .then(|| dx.hypot(dy))
            .filter(|&rho| rho <= limit)
            .map(|rho| (rho, [(-dx).atan2(dy), dx.atan2(dy)]));
        Self { dx, dy, near }
    }

    /// Whether some probe at this wrist position may cover the centre: it lies in the lane's
    /// straight path or within the finger's reach ([`FromWrist::covered`] is false for
    /// every sweep otherwise).
    fn may_be_covered(&self, g: &PlannerGeometry, hit: f64) -> bool {
        (self.dx.abs() <= hit && self.dy <= g.reach + hit) || self.near.is_some()
    }

    /// Whether the centre lies within `hit` of the finger's path of a probe at this wrist
    /// position that turns `angle` towards `side` (+1: +x): straight in along the lane,
    /// then the turn.
    fn covered(&self, g: &PlannerGeometry, side: f64, angle: f64, hit: f64) -> bool {
        let dx = self.dx * side;
        if dx.abs() <= hit && self.dy <= g.reach + hit {
            return true;
        }
        let Some((rho, bearings)) = self.near else {
            return false;
        };
        let phi = bearings[usize::from(side > 0.0)];
        let half_pi = std::f64::consts::FRAC_PI_2;
        let beyond = (phi - phi.clamp(0.0, angle)).clamp(-half_pi, half_pi);
        if beyond == 0.0 {
            // Within the turn's sector: on the finger's ray (the sine and cosine of 0 are
            // exactly 0 and 1, so this is the general case's result).
            return rho >= g.joint_offset;
        }
        let off_ray = rho * beyond.abs().sin();
        let along_ray = rho * beyond.cos();
        off_ray <= hit && along_ray >= g.joint_offset
    }
}

/// Whether a jar centre at `centre` lies within `hit` of `probe`'s finger path.
fn covers(g: &PlannerGeometry, probe: &SweptProbe, centre: [f64; 2], hit: f64) -> bool {
    FromWrist::new(g, [probe.x, probe.y], centre, hit).covered(g, probe.side, probe.angle, hit)
}
