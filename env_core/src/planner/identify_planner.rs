//! The identify task's planner: it finds the hidden jars with the GPIS probe planner's
//! search, tells a touched jar's shape from the contacts it collects on it, and claims the
//! square one. The teacher of the identify recipes.
//!
//! Strategy. Every jar the camera sees is round (the target, the only square jar, hides
//! behind others, as does one round decoy), so only hidden jars are worth a look. The
//! planner searches as [`ProbePlanner`] does (probes over the hiding weight of its belief).
//! When a probe ends touching a jar whose estimated centre (the contact point less the mean
//! round radius along its normal) lies where a hidden jar may stand (deep enough and in the
//! camera's shadow), the jar becomes a *candidate*, and its contact points and outward
//! normals are collected on it (a contact whose clipped offset cannot be put back on the
//! finger, [`ContactRule::FingerSide`], names the jar but is no evidence). Until its shape
//! is settled the planner inspects it: of the probes the wrist and arm can make clear of
//! every other jar (the finger may enter the candidate's surroundings: the controller stops
//! at the touch), not tried on it yet, the cheapest that on a circle model of the jar
//! touches it on the finger's side, else some millimetres from its contacts.
//!
//! The shape, from two kinds of evidence ([`shape_verdict`]):
//!
//! - *Tangency* (one contact). A smooth jar touches the side of a straight finger
//!   tangentially: its normal is perpendicular to the finger; a square jar meets the
//!   finger's side with a corner, at any angle. A side contact above `CORNER_TANGENCY`
//!   says square, one below `SMOOTH_TANGENCY` round.
//! - *Pairs* ([`pair_evidence`]). For two contacts `d` apart on a round jar of radius `r`
//!   the outward normals turn by about `d / r` and the centres they put the jar at agree;
//!   on one face of a square jar they do not turn, and the contacts lie on a line across
//!   the normal.
//!
//! The planner claims (the action's claim entry 1) while it touches a candidate judged
//! square, moves on when it is judged round or when `MAX_INSPECTIONS` probes did not settle
//! it, and with `LAST_CHANCE` of the time left claims a candidate it touches that is not
//! judged round rather than none.
//!
//! It reads only the observation (the map image and the proprio vector) and the settings,
//! never the ground truth. Every constant was chosen on validation layouts (the first 100
//! from 1,000,000), with the Python planner whose rules these are, in its float order.

use super::error::PlannerError;
use super::geometry::PlannerGeometry;
use super::numeric::{arange, linspace};
use super::probe_planner::{ContactRule, MapReading, PlannerObservation, Pose, ProbePlanner};
use super::reachable::Candidate;
use crate::episode::observation::proprio_index;
use crate::episode::{EpisodeConfig, Task};
use crate::scene::TargetShape;
use crate::settings::Choice;

/// Two contacts closer than this are one jar's if their estimated centres are, m.
const SAME_JAR: f64 = 0.03;
/// A pair of contacts judges the shape only this far apart, m.
const MIN_SEPARATION: f64 = 0.004;
/// Flat: the normals turn by less than this share of a round jar's smallest turn...
const FLAT_FRACTION: f64 = 0.4;
/// ...and the second contact lies at most this far along the first's normal, m.
const FLAT_OFFSET: f64 = 0.0025;
/// Curved: the normals turn by more than this share of a round jar's smallest turn.
const CURVED_FRACTION: f64 = 0.6;
/// A round jar fits two contacts when the centres they give it, at its best radius, are
/// this close, m.
const ROUND_FIT: f64 = 0.004;
/// A contact between these distances along the finger from its joint is on its side, m.
const SIDE_CONTACT: [f64; 2] = [0.04, 0.092];
/// A side contact whose normal is this far from perpendicular to the finger
/// (|n · direction|) met a corner; one this close to it lay tangent to a smooth surface.
const CORNER_TANGENCY: f64 = 0.15;
const SMOOTH_TANGENCY: f64 = 0.06;
/// Adjacent faces of a square: normals this close to a right angle, rad.
const CORNER_TOLERANCE: f64 = 0.25;
/// Inspection probes aim this far from the contacts the jar has, at least and at most, m.
const AIM: [f64; 2] = [0.006, 0.03];
/// A probe surely touches a jar if its finger comes this far inside the smallest round
/// radius of the jar's estimated centre, m.
const SURE_MARGIN: f64 = 0.004;
/// The inspected jar's surroundings the finger may enter beyond its largest radius, m.
const INSIDE_REACH: f64 = 0.01;
/// Inspection probes aim to touch this far along the finger from its joint (its side), m.
const SIDE_AIM: [f64; 2] = [0.045, 0.085];
/// Probes spent on one candidate before moving on.
const MAX_INSPECTIONS: usize = 4;
/// A candidate's estimated centre is at least this much shallower than target_min_depth...
const DEPTH_SLACK: f64 = 0.02;
/// ...and at least this far behind the nearest surface the camera saw on its ray, m.
const SHADOW_DEPTH: f64 = 0.01;
/// With this share of the time left or less, a candidate being touched is claimed.
const LAST_CHANCE: f64 = 0.06;
/// The turn's steps a probe's first touch is looked for at, rad.
const TURN_STEP: f64 = 0.025;
/// A pose is at a probe's lane and depth within this, m.
const AT_DEPTH: f64 = 1e-4;

/// What a jar's contacts say of its shape.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Verdict {
    /// A corner or a flat pair, and no curved pair.
    Square,
    /// A curved pair or a tangent contact, and nothing square.
    Round,
    /// Neither, or both.
    Unknown,
}

/// What two contacts on one jar say of its shape.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PairEvidence {
    /// One face, or adjacent faces where no round jar fits both contacts.
    Flat,
    /// A round jar's turn, and a round jar fits both.
    Curved,
}

/// The contacts collected on one touched jar, and what they say of its shape.
#[derive(Debug, Clone)]
struct JarTrack {
    /// Estimated on the first touch and kept (later touches find the jar by it).
    centre: [f64; 2],
    points: Vec<[f64; 2]>,
    normals: Vec<[f64; 2]>,
    /// Per point, `|normal · finger direction|` of a contact on the finger's side.
    tangency: Vec<Option<f64>>,
    candidate: bool,
    inspections: usize,
    verdict: Verdict,
    /// The probes tried on it (inspections), by their indices.
    tried: Vec<[i64; 3]>,
}

/// The identify planner of one episode at a time (see the module docs).
#[derive(Debug, Clone)]
pub struct IdentifyPlanner {
    search: ProbePlanner,
    /// The smallest and largest radius of a round jar, their mean, and the radius a probe's
    /// finger surely meets.
    radii: [f64; 2],
    mean_radius: f64,
    sure_radius: f64,
    jars: Vec<JarTrack>,
    /// The jar touched last (it stays the one inspected while the finger is off it).
    current: Option<usize>,
}

impl IdentifyPlanner {
    /// The planner of episodes of `config`: the identify task with a square target, the
    /// GPIS map and the `probe` action mode.
    pub fn new(config: &EpisodeConfig) -> Result<Self, PlannerError> {
        if config.task != Task::Identify {
            return Err(PlannerError::NeedsTask {
                planner: "identify",
                task: Task::Identify.name(),
                got: config.task.name(),
            });
        }
        let layout = &config.scene.layout;
        if layout.target_shape != TargetShape::Square {
            return Err(PlannerError::NeedsSquareTarget(layout.target_shape.name()));
        }
        let [low, high] = layout.round_diameter;
        Ok(Self {
            search: ProbePlanner::with_rules(config, ContactRule::FingerSide, MapReading::Gpis)?,
            radii: [0.5 * low, 0.5 * high],
            mean_radius: 0.25 * (low + high),
            sure_radius: 0.5 * low - SURE_MARGIN,
            jars: Vec::new(),
            current: None,
        })
    }

    /// Starts an episode from its first observation.
    pub fn reset(&mut self, observation: PlannerObservation<'_>) -> Result<(), PlannerError> {
        self.jars.clear();
        self.current = None;
        self.search.reset(observation)
    }

    /// Takes `observation` (the one after the last probe) into the belief and chooses the
    /// next action, `[lane, depth, sweep, claim]`: a claim (1) while the finger touches a
    /// candidate judged square, else a probe (claim 0).
    pub fn act(&mut self, observation: PlannerObservation<'_>) -> Result<[i64; 4], PlannerError> {
        let pose = self.search.observe(observation)?;
        let touched = self.record(&pose);
        let time_left = f64::from(observation.proprio[proprio_index("time_left").expect("entry")]);
        if let Some(jar) = touched.map(|k| &self.jars[k]) {
            let last_chance = time_left <= LAST_CHANCE && jar.verdict != Verdict::Round;
            if jar.candidate && (jar.verdict == Verdict::Square || last_chance) {
                let [lane, depth, sweep] = self.wait_indices(&pose);
                return Ok([lane, depth, sweep, 1]);
            }
        }
        let chosen = match self.inspection(&pose) {
            Some(chosen) => chosen,
            None => self.search.choose(&pose),
        };
        self.search.set_chosen(chosen);
        Ok([chosen[0], chosen[1], chosen[2], 0])
    }

    /// Takes `probe`, not the probe [`IdentifyPlanner::act`] just chose, as the probe the
    /// env carries out next (a claim ends the episode, so only a probe is followed).
    pub fn follow(&mut self, probe: [i64; 3]) -> Result<(), PlannerError> {
        self.search.follow(probe)
    }

    fn geometry(&self) -> &PlannerGeometry {
        self.search.geometry()
    }

    // -- the touched jars --------------------------------------------------------------

    /// Adds the observation's contact to its jar's track (a new one for a new jar) and
    /// judges the jar's shape; the jar's index, or None without a contact.
    fn record(&mut self, pose: &Pose) -> Option<usize> {
        let (point, normal) = pose.contact?;
        let centre = [
            point[0] - normal[0] * self.mean_radius,
            point[1] - normal[1] * self.mean_radius,
        ];
        let known = self.jars.iter().position(|jar| {
            (jar.centre[0] - centre[0]).hypot(jar.centre[1] - centre[1]) <= SAME_JAR
        });
        let index = known.unwrap_or_else(|| {
            let candidate = self.may_be_hidden(centre);
            self.jars.push(JarTrack {
                centre,
                points: Vec::new(),
                normals: Vec::new(),
                tangency: Vec::new(),
                candidate,
                inspections: 0,
                verdict: Verdict::Unknown,
                tried: Vec::new(),
            });
            self.jars.len() - 1
        });
        let tangency = self.tangency(pose, point, normal);
        let radii = self.radii;
        let jar = &mut self.jars[index];
        if pose.sure {
            // An unsure point only names the jar.
            jar.points.push(point);
            jar.normals.push(normal);
            jar.tangency.push(tangency);
        }
        jar.verdict = shape_verdict(&jar.points, &jar.normals, &jar.tangency, radii);
        self.current = Some(index);
        Some(index)
    }

    /// `|normal · finger direction|` of a contact on the finger's side (between
    /// `SIDE_CONTACT` along it from the joint), None for one near its ends.
    fn tangency(&self, pose: &Pose, point: [f64; 2], normal: [f64; 2]) -> Option<f64> {
        let g = self.geometry();
        let direction = PlannerGeometry::forward(pose.yaw + pose.deflection);
        let joint = g.joint([pose.x, pose.y], pose.yaw);
        let along = dot([point[0] - joint[0], point[1] - joint[1]], direction);
        (SIDE_CONTACT[0]..=SIDE_CONTACT[1])
            .contains(&along)
            .then(|| dot(normal, direction).abs())
    }

    /// Whether a jar centred at `centre` may be a hidden one: deep enough and in the
    /// camera's shadow (every jar the camera sees is round).
    fn may_be_hidden(&self, centre: [f64; 2]) -> bool {
        let g = self.geometry();
        if centre[1] < g.target_min_depth - DEPTH_SLACK {
            return false;
        }
        let (rows, cols) = g.grid_shape;
        // numpy's searchsorted (left) on the rows' y and the columns' x, clipped to the grid.
        let row = (0..rows)
            .position(|i| g.ys[i * cols] >= centre[1])
            .unwrap_or(rows)
            .min(rows - 1);
        let col = (0..cols)
            .position(|j| g.xs[j] >= centre[0])
            .unwrap_or(cols)
            .min(cols - 1);
        self.search.belief().behind()[row * cols + col] >= SHADOW_DEPTH
    }

    // -- inspecting a candidate --------------------------------------------------------

    /// The cheapest clear probe not tried on it yet that, on a circle model of the
    /// candidate last touched, touches it on the finger's side or some millimetres from its
    /// contacts; None when there is no candidate to inspect (or no such probe).
    fn inspection(&mut self, pose: &Pose) -> Option<[i64; 3]> {
        let index = self.current?;
        let jar = &self.jars[index];
        if !jar.candidate || jar.verdict != Verdict::Unknown || jar.inspections >= MAX_INSPECTIONS {
            return None;
        }
        // While the finger touches, a probe in the same lane at the same depth only turns,
        // which the controller does not do into a touch: it would wait.
        let candidates: Vec<Candidate> = self
            .reaching(pose, jar.centre)
            .into_iter()
            .filter(|c| {
                let turns_in_place = pose.contact.is_some()
                    && (pose.x - c.probe.x).abs() <= AT_DEPTH
                    && (pose.y - c.probe.y).abs() <= AT_DEPTH;
                !turns_in_place && !jar.tried.contains(&c.action)
            })
            .collect();
        let chosen = self.cheapest_touch(pose, &candidates, jar);
        let jar = &mut self.jars[index];
        match chosen {
            Some(action) => {
                jar.inspections += 1;
                jar.tried.push(action);
            }
            None => jar.inspections = MAX_INSPECTIONS,
        }
        chosen
    }

    /// Of `candidates`, the one with the fewest motions among the first kind that some
    /// candidate is, in order: a sure touch of `jar` on the finger's side (its tangency
    /// tells the shape by itself), a sure touch some millimetres from its contacts (a pair),
    /// a touch on the side if the jar is where its contacts put it, a touch some millimetres
    /// from them.
    fn cheapest_touch(
        &self,
        pose: &Pose,
        candidates: &[Candidate],
        jar: &JarTrack,
    ) -> Option<[i64; 3]> {
        let touches: Vec<FirstTouch> = candidates
            .iter()
            .map(|c| self.first_touch(pose, c, jar.centre))
            .collect();
        let gap = |touch: &FirstTouch| match touch.point {
            // Only unsure contacts: any touch of it helps.
            _ if jar.points.is_empty() => AIM[0],
            None => f64::NAN,
            Some(point) => jar
                .points
                .iter()
                .map(|known| (point[0] - known[0]).hypot(point[1] - known[1]))
                .fold(f64::INFINITY, f64::min),
        };
        let kinds: Vec<[bool; 4]> = touches
            .iter()
            .map(|touch| {
                let gap = gap(touch);
                let on_side = (SIDE_AIM[0]..=SIDE_AIM[1]).contains(&touch.along);
                let apart = (AIM[0]..=AIM[1]).contains(&gap);
                [
                    touch.sure && on_side,
                    touch.sure && apart,
                    touch.touches && on_side,
                    touch.touches && apart,
                ]
            })
            .collect();
        (0..4).find_map(|kind| {
            let mut best: Option<(f64, [i64; 3])> = None;
            for (candidate, fits) in candidates.iter().zip(&kinds) {
                if fits[kind] && best.is_none_or(|(motions, _)| candidate.motions < motions) {
                    best = Some((candidate.motions, candidate.action));
                }
            }
            best.map(|(_, action)| action)
        })
    }

    /// The grid probes the wrist and arm can make from `pose` clear of every cell that may
    /// hold a jar, the finger allowed into the surroundings of the jar centred at `centre`
    /// (it stops at the touch).
    fn reaching(&self, pose: &Pose, centre: [f64; 2]) -> Vec<Candidate> {
        let g = self.geometry();
        let limit = g.jar_radius[1] + INSIDE_REACH;
        let mut solid = self.search.belief().solid(0.0);
        for (k, cell) in solid.iter_mut().enumerate() {
            *cell &= (g.xs[k] - centre[0]).hypot(g.ys[k] - centre[1]) > limit;
        }
        self.search.clear_probes(pose, &solid)
    }

    /// How `candidate`, carried out from `pose` as the controller drives it (in along the
    /// lane, then the turn) with the finger undeflected, first meets a jar centred at
    /// `centre`: whether it surely reaches it (within the smallest round radius less
    /// `SURE_MARGIN`), whether it meets the circle of the mean round radius, where on that
    /// circle, and how far along the finger from its joint.
    fn first_touch(&self, pose: &Pose, candidate: &Candidate, centre: [f64; 2]) -> FirstTouch {
        let g = self.geometry();
        let (r_mean, r_sure) = (self.mean_radius, self.sure_radius);
        let probe = &candidate.probe;
        let start = if (pose.x - probe.x).abs() <= AT_DEPTH {
            pose.y.min(probe.y)
        } else {
            g.probe_outside
        };
        // In along the lane: the straight finger's line x; its tip meets the circle's front.
        let dx = centre[0] - probe.x;
        let front = centre[1] - (r_mean * r_mean - dx * dx).max(0.0).sqrt();
        let enter = dx.abs() < r_mean && front <= probe.y + g.reach && front >= start + g.reach;
        let mut sure = dx.abs() < r_sure && front <= probe.y + g.reach - (r_mean - r_sure);
        let mut touch = enter.then_some(([probe.x, front], g.finger_length));
        // The turn at the depth.
        let mut first = None;
        for step in arange(TURN_STEP, g.probe_max_angle + 1e-9, TURN_STEP) {
            let within = step <= probe.angle + 1e-9;
            let yaw = -probe.side * step;
            let (fx, fy) = (-yaw.sin(), yaw.cos());
            let (jx, jy) = (probe.x + g.joint_offset * fx, probe.y + g.joint_offset * fy);
            let t = ((centre[0] - jx) * fx + (centre[1] - jy) * fy).clamp(0.0, g.finger_length);
            let (cx, cy) = (jx + t * fx, jy + t * fy);
            let distance = (cx - centre[0]).hypot(cy - centre[1]);
            sure |= distance <= r_sure && within;
            if first.is_none() && distance <= r_mean && within {
                first = Some(([cx, cy], t));
            }
        }
        let turned = first.is_some() && !enter;
        if turned {
            touch = first;
        }
        // Onto the circle, along the direction from its centre.
        let point = touch.map(|(point, _)| {
            let outward = [point[0] - centre[0], point[1] - centre[1]];
            let norm = outward[0].hypot(outward[1]).max(1e-9);
            [
                centre[0] + outward[0] * (r_mean / norm),
                centre[1] + outward[1] * (r_mean / norm),
            ]
        });
        FirstTouch {
            sure: sure && (enter || turned),
            touches: enter || turned,
            point,
            along: touch.map_or(f64::NAN, |(_, along)| along),
        }
    }

    /// Probe indices for the claim's action (a claim makes no motion): the lane, depth and
    /// sweep nearest the pose.
    fn wait_indices(&self, pose: &Pose) -> [i64; 3] {
        let g = self.geometry();
        let nearest = |values: &[f64], value: f64| {
            let mut best = 0;
            for (i, v) in values.iter().enumerate() {
                if (v - value).abs() < (values[best] - value).abs() {
                    best = i;
                }
            }
            best as i64
        };
        [
            nearest(&g.probe_lanes, pose.x),
            nearest(&g.probe_depths, pose.y),
            nearest(&g.probe_yaws, pose.yaw),
        ]
    }
}

/// How a probe first meets a candidate jar's circle model.
struct FirstTouch {
    sure: bool,
    touches: bool,
    /// Where, on the circle of the mean round radius (None where it does not).
    point: Option<[f64; 2]>,
    /// How far along the finger from its joint (NaN where it does not touch).
    along: f64,
}

fn dot(a: [f64; 2], b: [f64; 2]) -> f64 {
    a[0] * b[0] + a[1] * b[1]
}

/// What two contacts (points and outward normals) on one jar say of its shape: flat,
/// curved or None (too close together, or neither). `radii`: the smallest and largest
/// radius of a round jar.
pub fn pair_evidence(
    p1: [f64; 2],
    n1: [f64; 2],
    p2: [f64; 2],
    n2: [f64; 2],
    radii: [f64; 2],
) -> Option<PairEvidence> {
    let d = (p2[0] - p1[0]).hypot(p2[1] - p1[1]);
    if d < MIN_SEPARATION {
        return None;
    }
    let turn = dot(n1, n2).clamp(-1.0, 1.0).acos();
    // The least turn a round jar gives for two contacts d apart.
    let round_turn = 2.0 * (0.5 * d / radii[1]).min(1.0).asin();
    // How far apart the centres the two contacts put a round jar at, at its best radius.
    let spread = linspace(radii[0], radii[1], 11)
        .into_iter()
        .map(|r| {
            let a = [p1[0] - r * n1[0], p1[1] - r * n1[1]];
            let b = [p2[0] - r * n2[0], p2[1] - r * n2[1]];
            (a[0] - b[0]).hypot(a[1] - b[1])
        })
        .fold(f64::INFINITY, f64::min);
    let sum = [n1[0] + n2[0], n1[1] + n2[1]];
    let length = sum[0].hypot(sum[1]).max(1e-9);
    let mean_normal = [sum[0] / length, sum[1] / length];
    let offset = dot([p2[0] - p1[0], p2[1] - p1[1]], mean_normal);
    if turn < FLAT_FRACTION * round_turn && offset.abs() < FLAT_OFFSET {
        return Some(PairEvidence::Flat); // one face
    }
    if (turn - 0.5 * std::f64::consts::PI).abs() < CORNER_TOLERANCE && spread > 2.0 * ROUND_FIT {
        return Some(PairEvidence::Flat); // adjacent faces, where no round jar fits both
    }
    if turn > CURVED_FRACTION * round_turn && spread <= ROUND_FIT {
        return Some(PairEvidence::Curved);
    }
    None
}

/// What a jar's contacts (points, outward normals, and for each made on the finger's side
/// its tangency) say of its shape: square when a side contact met a corner or a pair is
/// flat, and no pair is curved; round when a pair is curved, or a side contact lay tangent
/// and nothing says square; else unknown.
pub fn shape_verdict(
    points: &[[f64; 2]],
    normals: &[[f64; 2]],
    tangency: &[Option<f64>],
    radii: [f64; 2],
) -> Verdict {
    let (mut flat, mut curved) = (0, 0);
    for i in 0..points.len() {
        for j in i + 1..points.len() {
            match pair_evidence(points[i], normals[i], points[j], normals[j], radii) {
                Some(PairEvidence::Flat) => flat += 1,
                Some(PairEvidence::Curved) => curved += 1,
                None => {}
            }
        }
    }
    let corner = tangency.iter().flatten().any(|&t| t > CORNER_TANGENCY);
    let tangent = tangency.iter().flatten().any(|&t| t < SMOOTH_TANGENCY);
    let square = corner || flat > 0;
    if square && curved == 0 {
        Verdict::Square
    } else if curved > 0 || tangent {
        if square {
            Verdict::Unknown
        } else {
            Verdict::Round
        }
    } else {
        Verdict::Unknown
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const RADII: [f64; 2] = [0.0225, 0.0275];

    fn on_circle(centre: [f64; 2], r: f64, angle: f64) -> ([f64; 2], [f64; 2]) {
        let n = [angle.cos(), angle.sin()];
        ([centre[0] + r * n[0], centre[1] + r * n[1]], n)
    }

    #[test]
    fn two_contacts_on_a_round_jar_are_curved() {
        let (p1, n1) = on_circle([0.0, 0.3], 0.025, -1.8);
        let (p2, n2) = on_circle([0.0, 0.3], 0.025, -1.4);
        assert_eq!(
            pair_evidence(p1, n1, p2, n2, RADII),
            Some(PairEvidence::Curved)
        );
    }

    #[test]
    fn two_contacts_on_one_face_are_flat_and_too_close_ones_say_nothing() {
        let n = [0.0, -1.0];
        let (p1, p2) = ([0.0, 0.28], [0.012, 0.28]);
        assert_eq!(pair_evidence(p1, n, p2, n, RADII), Some(PairEvidence::Flat));
        assert_eq!(pair_evidence(p1, n, [0.002, 0.28], n, RADII), None);
    }

    #[test]
    fn a_corner_says_square_unless_a_pair_is_curved() {
        let (p1, n1) = on_circle([0.0, 0.3], 0.025, -1.8);
        let (p2, n2) = on_circle([0.0, 0.3], 0.025, -1.4);
        assert_eq!(
            shape_verdict(&[p1], &[n1], &[Some(0.4)], RADII),
            Verdict::Square
        );
        assert_eq!(
            shape_verdict(&[p1], &[n1], &[Some(0.01)], RADII),
            Verdict::Round
        );
        assert_eq!(
            shape_verdict(&[p1], &[n1], &[None], RADII),
            Verdict::Unknown
        );
        let both = shape_verdict(&[p1, p2], &[n1, n2], &[Some(0.4), None], RADII);
        assert_eq!(both, Verdict::Unknown);
    }
}
