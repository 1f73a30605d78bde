//! One mechanical-search episode: the scene, the map built from its depth and touch, the
//! reward and the episode end (`docs/DESIGN.md` §4).
//!
//! reset(seed): new layout, first depth look, the map started from the depth slice, hand at
//! the opening. step(action): scale and clip the wrist motion, step the scene (several
//! physics substeps), add the new contacts to the map, then reward, termination, truncation
//! (the time limit `max_steps` is the episode's own) and metrics. Everything map-specific
//! is the map mode's ([`super::maps::AgentMap`]): the episode never asks which mode it is.
//! In the `probe` action mode a step is a whole probe: the controller's wrist motions, each
//! such a step, with their rewards summed ([`super::probe`]). The task ([`super::task`])
//! says what succeeds: a touch of the target (search) or a claim naming it (identify).

use std::sync::Arc;

use super::action_mode::{Action, ActionMode};
use super::approach::{fingertip, ApproachField};
use super::config::EpisodeConfig;
use super::error::EpisodeError;
use super::map_score::MapScore;
use super::maps::gpis::GpisMap;
use super::maps::occupancy::OccupancyGrid;
use super::maps::{AgentMap, MapKind};
use super::metrics::{footprint_mask, footprint_of};
use super::observation::{proprio, PROPRIO_LEN};
use super::probe::{Phase, ProbeController};
use super::step_info::StepInfo;
use super::task::claimed_jar;
use crate::gpis::{run_each, Gpis, GridSpec, SerialTiles, TileRunner};
use crate::scene::{Contact, HandCommand, Scene, SceneConfig};
use crate::settings::{Checked, Choice};

/// The target's footprint widened by this much counts as reached by the approach field, m.
const APPROACH_CLEARANCE: f64 = 0.01;

/// One episode. Reusable: [`Episode::reset`] keeps the map's storage.
pub struct Episode {
    config: Checked<EpisodeConfig>,
    /// The scene's part of `config`, handed to every reset's scene.
    scene_config: Checked<SceneConfig>,
    grid: GridSpec,
    /// None until the first [`Episode::reset`].
    scene: Option<Scene>,
    /// The map mode's row of the table (its image channels).
    kind: &'static MapKind,
    /// The agent's map, of the configured mode.
    map: Box<dyn AgentMap>,
    steps: usize,
    displacement_sum: f64,
    ended: bool,
    truth: Vec<bool>,
    /// The jars' poses the truth mask was drawn at: it is redrawn only when one moved.
    truth_poses: Vec<[f64; 7]>,
    /// The map's IoU against the truth, until the map or the truth changes.
    iou: Option<f64>,
    approach: ApproachField,
    /// The fingertip's path distance to the target after the last step (the approach
    /// shaping's potential; the info shows it only where the task reveals the target).
    target_distance: f64,
    /// The map task's reconstruction (None in other tasks).
    score: Option<MapScore>,
    /// Its outline distance after the last step, mm, and that distance summed over the
    /// motions since reset (each step's after it, times its motions).
    score_mm: f64,
    score_sum: f64,
    /// Where a reset's two independent pieces (the approach field, the map's prior) and
    /// the map's grid updates run: this thread, or a batch's idle threads too.
    tiles: Arc<dyn TileRunner>,
    probes: ProbeController,
    last_info: StepInfo,
    /// The wrist motions of the last step (see [`Episode::last_motions`]).
    last_motions: Vec<[f64; 3]>,
}

impl Episode {
    /// An episode of `config` that has not started: its map's storage is allocated, and
    /// [`Episode::reset`] starts it. Until then it has no scene, a step fails with
    /// [`EpisodeError::NotReset`] and its observation is zeros.
    ///
    /// # Errors
    /// A map that cannot be built on the config's grid ([`EpisodeError::Gpis`]).
    pub fn new(config: Checked<EpisodeConfig>) -> Result<Self, EpisodeError> {
        let grid = GridSpec::new(config.map_bounds(), config.map.grid_shape)?;
        let kind = config.map.mode.kind();
        let map = (kind.build)(&config.map, &grid)?;
        let probes = ProbeController::for_episode(&config);
        let score = match config.task.scores_map() {
            true => Some(MapScore::new(&config.map, &grid)?),
            false => None,
        };
        Ok(Self {
            scene_config: config.section(|c| &c.scene),
            config,
            grid,
            scene: None,
            kind,
            map,
            steps: 0,
            displacement_sum: 0.0,
            ended: false,
            truth: Vec::new(),
            truth_poses: Vec::new(),
            iou: None,
            approach: ApproachField::default(),
            target_distance: 0.0,
            score,
            score_mm: 0.0,
            score_sum: 0.0,
            tiles: Arc::new(SerialTiles),
            probes,
            last_info: StepInfo::default(),
            last_motions: Vec::new(),
        })
    }

    /// [`Episode::new`], then [`Episode::reset`] to `seed`: an episode ready to step.
    pub fn started(config: Checked<EpisodeConfig>, seed: u64) -> Result<Self, EpisodeError> {
        let mut episode = Self::new(config)?;
        episode.reset(seed)?;
        Ok(episode)
    }

    /// Lets `runner` compute the map's grid updates in tiles and a reset's two independent
    /// pieces (an episode batch shares its threads this way); results do not change.
    pub fn share_tiles(&mut self, runner: Arc<dyn TileRunner>) {
        self.map.share_tiles(runner.clone());
        self.tiles = runner;
    }

    /// Starts the episode of `seed` (new layout, new first look, new prior).
    ///
    /// # Errors
    /// A layout the scene cannot generate for this config ([`EpisodeError::Scene`]).
    pub fn reset(&mut self, seed: u64) -> Result<(), EpisodeError> {
        self.scene = Some(Scene::new(&self.scene_config, seed)?);
        self.start()
    }

    /// Whether a reset has started the episode.
    pub fn is_started(&self) -> bool {
        self.scene.is_some()
    }

    /// The scene, once started.
    ///
    /// # Panics
    /// Before the first [`Episode::reset`]; callers outside the core ask
    /// [`Episode::is_started`] first, and the step path fails with
    /// [`EpisodeError::NotReset`] instead.
    pub fn scene(&self) -> &Scene {
        self.scene
            .as_ref()
            .expect("an episode has a scene once reset() has started it")
    }

    fn scene_mut(&mut self) -> &mut Scene {
        self.scene
            .as_mut()
            .expect("an episode has a scene once reset() has started it")
    }

    fn camera_xy(&self) -> [f64; 2] {
        let p = self.scene().camera().position();
        [p[0], p[1]]
    }

    fn start(&mut self) -> Result<(), EpisodeError> {
        self.steps = 0;
        self.last_motions.clear();
        self.truth_poses.clear();
        self.iou = None;
        self.displacement_sum = 0.0;
        self.ended = false;
        // The approach field and the map's prior need nothing of each other: two pieces of
        // work another thread of a batch may take one of (each piece's result is the same
        // wherever it runs); the thread done with the field can then take tiles of the
        // prior's grid update.
        let (jars, target, camera) = (
            self.scene().jar_states(),
            self.scene().target(),
            self.camera_xy(),
        );
        let scene = self
            .scene
            .as_ref()
            .expect("start() follows a reset's new scene");
        let (slice, grid) = (scene.first_slice(), &self.grid);
        let (approach, map) = (&mut self.approach, &mut self.map);
        let mut map_reset = Ok(());
        let pieces: [Box<dyn FnOnce() + Send + '_>; 2] = [
            Box::new(|| *approach = ApproachField::new(grid, &jars, target, APPROACH_CLEARANCE)),
            Box::new(|| map_reset = map.reset(slice, camera)),
        ];
        run_each(self.tiles.as_ref(), pieces, |piece| piece());
        map_reset?;
        if let Some(score) = &mut self.score {
            score.reset(slice, camera)?;
        }
        self.add_touch();
        let (mut info, _) = self.measure();
        info.iou = self.current_iou();
        self.target_distance = self.distance_to_target();
        self.show_distance(&mut info);
        self.score_sum = 0.0;
        self.score_step(&mut info);
        self.last_info = info;
        Ok(())
    }

    /// Adds this step's readings to the map; returns (readings, rows added, skipped,
    /// dropped).
    fn add_touch(&mut self) -> (usize, usize, usize, usize) {
        let bounds = &self.grid;
        let readings: Vec<Contact> = self
            .scene()
            .contacts()
            .iter()
            .copied()
            .filter(|c| bounds.contains(c.point))
            .collect();
        let count = self.scene().contacts().len();
        let swept = self.swept_point(count);
        let report = self.map.add_touch(&readings, swept);
        if report.changed {
            self.iou = None;
        }
        if let Some(score) = &mut self.score {
            score.add_touch(&readings, swept);
        }
        (count, report.rows_added, report.skipped, report.dropped)
    }

    /// The fingertip, when `swept_free_space` is set (for the GPIS and the occupancy map
    /// alike), the finger read nothing this step (`readings` = 0) and the tip is inside the
    /// map; else None.
    fn swept_point(&self, readings: usize) -> Option<[f64; 2]> {
        self.config.map.swept_free_space?;
        if readings > 0 {
            return None;
        }
        let finger = self.scene().finger_pose();
        let tip = fingertip(
            finger.x,
            finger.y,
            finger.yaw,
            self.config.scene.hand.finger_length,
        );
        self.grid.contains(tip).then_some(tip)
    }

    /// Metrics of the current state (the target distance aside: `show_distance`); also
    /// returns the displacement added since last call.
    fn measure(&mut self) -> (StepInfo, f64) {
        let jars = self.scene().jar_states();
        let mut info = StepInfo {
            steps: self.steps,
            ..StepInfo::default()
        };
        for jar in &jars {
            let d = &jar.disturbance;
            info.jar_displacement += d.displacement;
            info.max_jar_displacement = info.max_jar_displacement.max(d.displacement);
            info.max_tilt = info.max_tilt.max(d.tilt);
            info.tips += usize::from(d.tilt > self.config.tip_angle);
        }
        let added = (info.jar_displacement - self.displacement_sum).max(0.0);
        self.displacement_sum = info.jar_displacement;
        info.tipped = info.tips > 0;
        let target = self.scene().target();
        info.success = self.config.task.touch_succeeds()
            && self.scene().true_contacts().iter().any(|c| c.jar == target);
        info.gpis_rows = self.map.rows();
        // `info.iou` is the step's, filled in once its last motion is made (`current_iou`).
        (info, added)
    }

    /// The jar a claim would name now: of the jars the finger touches, the one whose contact
    /// lies nearest the fingertip (ground truth; None when it touches no jar).
    pub fn touched_jar(&self) -> Option<usize> {
        let contacts = self
            .scene()
            .true_contacts()
            .iter()
            .map(|c| (c.point, c.jar));
        claimed_jar(contacts, self.fingertip())
    }

    /// Where the fingertip is now.
    fn fingertip(&self) -> [f64; 2] {
        let finger = self.scene().finger_pose();
        let length = self.config.scene.hand.finger_length;
        fingertip(finger.x, finger.y, finger.yaw, length)
    }

    /// Puts the target distance of the last step into `info`, where the task reveals the
    /// target (it stays 0 elsewhere).
    fn show_distance(&self, info: &mut StepInfo) {
        if self.config.task.reveals_target() {
            info.target_distance = self.target_distance;
        }
    }

    /// The fingertip's path distance to the target now, m.
    fn distance_to_target(&self) -> f64 {
        self.approach.distance(self.fingertip())
    }

    /// The map's IoU with the jars' true footprints now. Resting jars do not move and most
    /// steps add nothing to the map: the truth mask and the IoU are recomputed only when a
    /// jar moved or the map changed, and only once per step (a probe's wrist motions report
    /// their last motion's IoU, so the motions before it need none). Cost O(G) when
    /// recomputed, O(jars) otherwise.
    fn current_iou(&mut self) -> f64 {
        self.refresh_truth();
        match self.iou {
            Some(iou) => iou,
            None => *self.iou.insert(self.map.iou(&self.truth)),
        }
    }

    /// Redraws the true footprints' mask when a jar moved since it was drawn.
    fn refresh_truth(&mut self) {
        let jars = self.scene().jar_states();
        let poses = jars.iter().map(|jar| {
            let [x, y, z] = jar.position;
            let [qx, qy, qz, qw] = jar.rotation;
            [x, y, z, qx, qy, qz, qw]
        });
        if !poses.clone().eq(self.truth_poses.iter().copied()) {
            footprint_mask(&self.grid, &jars, &mut self.truth);
            self.truth_poses.clear();
            self.truth_poses.extend(poses);
            self.iou = None;
        }
    }

    /// The map task's scores after a reset or a step (measured once per step, however
    /// many motions it made), into `info`: the IoU, the outline distance, the area and the
    /// reward for the distance's shrink (added to `info.reward`). Nothing in other tasks.
    fn score_step(&mut self, info: &mut StepInfo) {
        if self.score.is_none() {
            return;
        }
        self.refresh_truth();
        let footprints: Vec<_> = self.scene().jar_states().iter().map(footprint_of).collect();
        let score = self.score.as_ref().expect("checked above");
        let mm = 1000.0 * score.outline_distance(&footprints);
        info.map_score_iou = score.iou(&self.truth);
        info.map_score_mm = mm;
        if info.motions > 0 {
            info.reward_map = self.config.reward.map * (self.score_mm - mm);
            info.reward += info.reward_map;
        }
        self.score_mm = mm;
        self.score_sum += mm * info.motions as f64;
        // At the episode's end the rest of the budget counts at the final distance, so the
        // area always spans max_steps motions.
        let rest = match info.terminated || info.truncated {
            true => self.config.max_steps.saturating_sub(self.steps) as f64,
            false => 0.0,
        };
        info.map_score_area = (self.score_sum + mm * rest) / self.config.max_steps as f64;
    }

    /// Takes one step. In the `wrist` action mode `action` is a wrist motion in [−1, 1]³
    /// (dx, dy, dyaw; `[f64; 3]` converts to one), scaled by the hand's
    /// `max_step_translation` and `max_step_yaw`; components outside are clipped (and
    /// reported). In the `probe` mode it is the (lane, depth, sweep) indices of a probe
    /// (`[i64; 3]` converts to one).
    ///
    /// # Errors
    /// An action of the other mode, a non-finite motion, a probe index out of its count;
    /// a step before the first reset or after the episode has ended.
    pub fn step(&mut self, action: impl Into<Action>) -> Result<StepInfo, EpisodeError> {
        let action = action.into();
        self.check_action(&action)?;
        self.advance(action)
    }

    /// Fails on an action of the other mode, a non-finite motion, a probe index outside
    /// its count, or a claim in a task that takes none.
    pub(crate) fn check_action(&self, action: &Action) -> Result<(), EpisodeError> {
        match (action, self.config.action_mode) {
            (Action::Wrist(motion), ActionMode::Wrist) => check_finite(motion),
            (Action::Probe(indices), ActionMode::Probe) => self.probes.check(indices),
            (Action::Claim, _) if self.config.task.claims() => Ok(()),
            (Action::Claim, _) => Err(EpisodeError::ClaimOutsideIdentify {
                task: self.config.task.name(),
            }),
            (action, mode) => Err(EpisodeError::WrongActionMode {
                expected: mode.name(),
                got: action.mode().map_or("claim", ActionMode::name),
            }),
        }
    }

    /// [`Episode::step`] for an action already checked (the batch checks all of its
    /// actions once, before stepping any).
    pub(crate) fn advance(&mut self, action: Action) -> Result<StepInfo, EpisodeError> {
        if self.scene.is_none() {
            return Err(EpisodeError::NotReset);
        }
        if self.ended {
            return Err(EpisodeError::Ended);
        }
        self.last_motions.clear();
        let mut info = match action {
            Action::Wrist(motion) => self.move_wrist(motion)?,
            Action::Probe(indices) => self.probe(indices)?,
            Action::Claim => self.claim(),
        };
        info.iou = self.current_iou();
        self.score_step(&mut info);
        self.last_info = info;
        Ok(info)
    }

    /// One probe: the controller's wrist motions until the probe is done, the finger
    /// touches something after a motion that presses on (deeper, or sweeping), the next
    /// motion would press on while the finger touches, the hand is blocked or the episode
    /// ends. A probe that makes no motion (already there, or pressing on a touch) waits a
    /// step. The reward terms and the counts of readings and rows are summed over the
    /// motions; the rest is the last motion's.
    fn probe(&mut self, indices: [i64; 3]) -> Result<StepInfo, EpisodeError> {
        let probe = self.probes.probe(&indices);
        let mut total = StepInfo::default();
        let mut touching = !self.scene().contacts().is_empty();
        loop {
            let (phase, motion) = self.probes.next_motion(self.scene().hand_pose(), &probe);
            if phase == Phase::Done || (touching && phase.presses(&motion)) {
                if total.motions == 0 {
                    total = self.move_wrist([0.0; 3])?;
                }
                break;
            }
            let info = self.move_wrist(motion)?;
            total = total.then(&info);
            touching = info.contacts > 0;
            if info.terminated
                || info.truncated
                || info.blocked
                || (touching && phase.presses(&motion))
            {
                break;
            }
        }
        Ok(total)
    }

    /// A claim (the identify task): names the jar the finger touches now, the one whose
    /// contact lies nearest the fingertip, and ends the episode, a success if it is the
    /// target; no motion, no step of the time limit. Its info without the IoU.
    fn claim(&mut self) -> StepInfo {
        let claimed = self.touched_jar();
        let (mut info, _) = self.measure();
        let weights = &self.config.reward;
        info.claimed_jar = claimed;
        info.success = claimed == Some(self.scene().target());
        info.wrong_claim = !info.success;
        info.reward_success = if info.success { weights.success } else { 0.0 };
        info.reward_wrong_claim = if info.wrong_claim {
            -weights.wrong_claim
        } else {
            0.0
        };
        info.reward = info.reward_success + info.reward_wrong_claim;
        info.terminated = true;
        self.ended = true;
        self.last_info = info;
        info
    }

    /// One wrist motion (the `wrist` mode's step), its info without the IoU (`advance` adds
    /// the step's).
    fn move_wrist(&mut self, action: [f64; 3]) -> Result<StepInfo, EpisodeError> {
        let clipped = action.iter().any(|v| v.abs() > 1.0);
        let [ax, ay, ayaw] = action.map(|v| v.clamp(-1.0, 1.0));
        self.last_motions.push([ax, ay, ayaw]);
        let hand = &self.config.scene.hand;
        let command = HandCommand {
            dx: ax * hand.max_step_translation,
            dy: ay * hand.max_step_translation,
            dyaw: ayaw * hand.max_step_yaw,
        };
        let report = self.scene_mut().step(command)?;
        self.steps += 1;
        let (contacts, rows_added, contacts_skipped, contacts_dropped) = self.add_touch();
        let (mut info, added_displacement) = self.measure();
        let distance = self.distance_to_target();
        let weights = &self.config.reward;
        info.reward_approach = weights.approach * (self.target_distance - distance);
        self.target_distance = distance;
        self.show_distance(&mut info);
        info.reward_success = if info.success { weights.success } else { 0.0 };
        info.reward_step = -weights.step_cost;
        info.reward_displacement = -weights.displacement * added_displacement;
        info.reward_tip = if info.tipped { -weights.tip } else { 0.0 };
        info.reward = info.reward_success
            + info.reward_step
            + info.reward_displacement
            + info.reward_tip
            + info.reward_approach;
        info.terminated = info.success || info.tipped;
        // The time limit is the episode's own: what `max_steps` says is what truncates.
        info.truncated = !info.terminated && self.steps >= self.config.max_steps;
        info.contacts = contacts;
        info.rows_added = rows_added;
        info.contacts_skipped = contacts_skipped;
        info.contacts_dropped = contacts_dropped;
        info.clipped = clipped;
        info.blocked = report.blocked.is_some();
        info.motions = 1;
        self.ended = info.terminated;
        self.last_info = info;
        Ok(info)
    }

    /// Values in the map image: channels · H · W (2 · H · W for the `gpis` and `occupancy`
    /// modes, 0 in the `none` mode).
    pub fn map_len(&self) -> usize {
        self.kind.channels.len() * self.grid.n_cells()
    }

    /// Writes the map image (channels × H × W, channel first; see the mode's
    /// [`super::maps::MapKind::channels`]); zeros before the first reset.
    pub fn write_map(&self, out: &mut [u8]) -> Result<(), EpisodeError> {
        check_length("map", self.map_len(), out.len())?;
        match self.scene {
            Some(_) => self.map.encode(out),
            None => out.fill(0),
        }
        Ok(())
    }

    /// Writes the proprio vector (see [`super::observation::PROPRIO_FIELDS`]); zeros
    /// before the first reset.
    pub fn write_proprio(&self, out: &mut [f32]) -> Result<(), EpisodeError> {
        check_length("proprio", PROPRIO_LEN, out.len())?;
        match &self.scene {
            Some(scene) => out.copy_from_slice(&proprio(&self.config, scene, self.steps)),
            None => out.fill(0.0),
        }
        Ok(())
    }

    /// The metrics of the last reset or step.
    pub fn last_info(&self) -> &StepInfo {
        &self.last_info
    }

    /// The wrist motions the last step made, as `wrist`-mode actions in [−1, 1]³ (clipped):
    /// one in the `wrist` mode, every motion of the probe in the `probe` mode (a wait is
    /// `[0, 0, 0]`); none after a reset. Stepping a `wrist`-mode episode of the same
    /// settings and layout with them reproduces the step motion by motion (what a renderer
    /// needs to draw every motion of a probe).
    pub fn last_motions(&self) -> &[[f64; 3]] {
        &self.last_motions
    }

    /// The agent's map.
    pub fn map(&self) -> &dyn AgentMap {
        self.map.as_ref()
    }

    /// The GPIS map, in the `gpis` mode.
    pub fn gpis(&self) -> Option<&Gpis> {
        self.map
            .as_any()
            .downcast_ref::<GpisMap>()
            .map(GpisMap::gpis)
    }

    /// The map task's reconstruction (None in other tasks).
    pub fn map_score(&self) -> Option<&MapScore> {
        self.score.as_ref()
    }

    /// The occupancy grid, in the `occupancy` mode.
    pub fn occupancy(&self) -> Option<&OccupancyGrid> {
        self.map.as_any().downcast_ref::<OccupancyGrid>()
    }

    /// The configuration.
    pub fn config(&self) -> &Checked<EpisodeConfig> {
        &self.config
    }

    /// The map grid.
    pub fn grid(&self) -> &GridSpec {
        &self.grid
    }
}

fn check_length(what: &'static str, expected: usize, got: usize) -> Result<(), EpisodeError> {
    if expected == got {
        Ok(())
    } else {
        Err(EpisodeError::BufferLength {
            what,
            expected,
            got,
        })
    }
}

/// Fails on the first NaN or infinite component of `action`.
pub(crate) fn check_finite(action: &[f64; 3]) -> Result<(), EpisodeError> {
    match action.iter().enumerate().find(|(_, v)| !v.is_finite()) {
        Some((index, &value)) => Err(EpisodeError::NonFiniteAction { index, value }),
        None => Ok(()),
    }
}
