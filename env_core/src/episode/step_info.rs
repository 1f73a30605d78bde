//! What one step did ([`StepInfo`]) and its field table ([`STEP_INFO_FIELDS`]): the keys of
//! the environments' `info`, each with its type and doc, read by the bindings to build the
//! single env's dict of scalars and the vector env's dict of arrays alike.
//!
//! [`InfoColumns`] writes the infos of a batch as one column per field (the layout of the
//! vector env's dict of arrays). Cost: O(fields) per episode.

/// What one step did: the reward term by term, the episode end, and the metrics. In the
/// `probe` action mode a step is a probe's wrist motions (see [`StepInfo::then`]): its
/// reward terms are the sums of theirs.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct StepInfo {
    /// Total reward: the sum of the seven terms below.
    pub reward: f64,
    /// `reward.success` when the episode succeeded this step (the finger touched the target;
    /// in the identify task, a claim named it), else 0.
    pub reward_success: f64,
    /// `−reward.step_cost` per wrist motion.
    pub reward_step: f64,
    /// `−reward.displacement · max(0, D_t − D_{t−1})`, `D` the jars' summed planar
    /// displacement from their start (m).
    pub reward_displacement: f64,
    /// `−reward.tip` when a jar tipped over this step, else 0.
    pub reward_tip: f64,
    /// `reward.approach ·` how much the fingertip's path distance to the target shrank
    /// this step (a difference of potentials, see `approach`; 0 at the default weight).
    pub reward_approach: f64,
    /// `−reward.wrong_claim` when a claim named a jar other than the target, or none.
    pub reward_wrong_claim: f64,
    /// `reward.map ·` how much the map task's outline distance (`map_score_mm`) shrank
    /// this step.
    pub reward_map: f64,
    /// The map task's score: the IoU of the reconstruction with the true footprints (0 in
    /// other tasks).
    pub map_score_iou: f64,
    /// The map task's outline distance, mm: the mean of the two directed mean distances
    /// between the reconstruction's zero level set and the true outlines (0 in other tasks).
    pub map_score_mm: f64,
    /// The map task's outline distance summed over the motions so far (each step's after
    /// it, times its motions), over `max_steps`, mm; at the episode's end the rest of the
    /// budget counts at the final distance, so it is the mean over the budget (lower is
    /// better, 0 for a perfect map from the first motion).
    pub map_score_area: f64,
    /// The episode ended (success, a tipped jar or a claim).
    pub terminated: bool,
    /// The time limit ended the episode: `steps >= max_steps` and not terminated.
    pub truncated: bool,
    /// The episode succeeded: the finger touched the target (search), a claim named it
    /// (identify).
    pub success: bool,
    /// A claim named a jar other than the target, or none (identify).
    pub wrong_claim: bool,
    /// The jar a claim named this step (its index in the layout), None without a claim or
    /// when the finger touched no jar.
    pub claimed_jar: Option<usize>,
    /// A jar tipped over.
    pub tipped: bool,
    /// Wrist motions since reset (the steps of the time limit).
    pub steps: usize,
    /// Planar displacement since reset, summed over jars, m.
    pub jar_displacement: f64,
    /// Largest jar displacement since reset, m.
    pub max_jar_displacement: f64,
    /// The fingertip's path distance to the target now, m (see [`super::approach`]); 0 in
    /// a task that keeps the target secret (identify).
    pub target_distance: f64,
    /// Largest jar tilt now, rad.
    pub max_tilt: f64,
    /// Jars tipped over now.
    pub tips: usize,
    /// Tactile readings this step.
    pub contacts: usize,
    /// GP rows the readings added.
    pub rows_added: usize,
    /// Readings skipped as uninformative (or rejected as degenerate).
    pub contacts_skipped: usize,
    /// Readings dropped because the map was full.
    pub contacts_dropped: usize,
    /// GP rows held.
    pub gpis_rows: usize,
    /// IoU of the map's interior against the true jar footprints (0 without a map).
    pub iou: f64,
    /// The action was outside [−1, 1] and was clipped.
    pub clipped: bool,
    /// A wall (or the workspace edge) stopped the hand.
    pub blocked: bool,
    /// Wrist motions this step made: 1 in the `wrist` action mode, the probe's in the
    /// `probe` mode (0 after a reset).
    pub motions: usize,
}

impl StepInfo {
    /// This step followed by `next` as one step (a probe's motions): the reward terms,
    /// the readings, rows and motions summed, `clipped` and `blocked` if either was, and
    /// the rest (the episode end and the state's metrics) `next`'s.
    pub fn then(&self, next: &StepInfo) -> StepInfo {
        StepInfo {
            reward: self.reward + next.reward,
            reward_success: self.reward_success + next.reward_success,
            reward_step: self.reward_step + next.reward_step,
            reward_displacement: self.reward_displacement + next.reward_displacement,
            reward_tip: self.reward_tip + next.reward_tip,
            reward_approach: self.reward_approach + next.reward_approach,
            reward_wrong_claim: self.reward_wrong_claim + next.reward_wrong_claim,
            reward_map: self.reward_map + next.reward_map,
            contacts: self.contacts + next.contacts,
            rows_added: self.rows_added + next.rows_added,
            contacts_skipped: self.contacts_skipped + next.contacts_skipped,
            contacts_dropped: self.contacts_dropped + next.contacts_dropped,
            clipped: self.clipped || next.clipped,
            blocked: self.blocked || next.blocked,
            motions: self.motions + next.motions,
            ..*next
        }
    }
}

/// How an info field reads its value: its type (numpy dtype float64, bool, int64) and getter.
#[derive(Clone, Copy)]
pub enum InfoValue {
    /// A real number (float64).
    Float(fn(&StepInfo) -> f64),
    /// A flag (bool).
    Flag(fn(&StepInfo) -> bool),
    /// A count (int64).
    Count(fn(&StepInfo) -> usize),
    /// An index that may be absent (int64, -1 when absent).
    Index(fn(&StepInfo) -> Option<usize>),
}

impl InfoValue {
    /// The value of an integer field (a count or an index) as int64: an absent index is -1.
    /// None for a float or a flag.
    pub fn integer(&self, info: &StepInfo) -> Option<i64> {
        match self {
            Self::Count(get) => Some(get(info) as i64),
            Self::Index(get) => Some(get(info).map_or(-1, |i| i as i64)),
            Self::Float(_) | Self::Flag(_) => None,
        }
    }
}

/// One key of `info`.
pub struct InfoField {
    /// The key.
    pub name: &'static str,
    /// Its type and getter.
    pub value: InfoValue,
    /// What it means.
    pub doc: &'static str,
}

impl InfoField {
    /// `"float64"`, `"bool"` or `"int64"`: the field's numpy dtype.
    pub fn dtype(&self) -> &'static str {
        match self.value {
            InfoValue::Float(_) => "float64",
            InfoValue::Flag(_) => "bool",
            InfoValue::Count(_) | InfoValue::Index(_) => "int64",
        }
    }
}

macro_rules! info_fields {
    ($($name:ident: $kind:ident, $doc:literal;)*) => {
        /// Every key of `info`, in order (the reward terms first, then the episode end and
        /// the metrics).
        pub const STEP_INFO_FIELDS: &[InfoField] = &[$(InfoField {
            name: stringify!($name),
            value: InfoValue::$kind(|info| info.$name),
            doc: $doc,
        }),*];
    };
}

info_fields! {
    reward_success: Float, "reward_success when the episode succeeded this step (the finger touched the target; identify: a claim named it), else 0";
    reward_step: Float, "-reward_step_cost per wrist motion";
    reward_displacement: Float, "-reward_displacement times the jar displacement added this step";
    reward_tip: Float, "-reward_tip when a jar tipped over this step, else 0";
    reward_approach: Float, "reward_approach times the shrink of the fingertip's path distance to the target this step";
    reward_wrong_claim: Float, "-reward_wrong_claim when a claim named a jar other than the target, or none";
    reward_map: Float, "reward_map times the shrink of the map task's outline distance (map_score_mm) this step";
    target_distance: Float, "the fingertip's path distance to the target, m (0 in the identify task, which keeps the target secret)";
    success: Flag, "the episode succeeded: the finger touched the target (search), a claim named it (identify)";
    wrong_claim: Flag, "a claim named a jar other than the target, or none (identify)";
    tipped: Flag, "a jar tipped over";
    steps: Count, "wrist motions since reset (the time limit counts them)";
    claimed_jar: Index, "the jar a claim named this step, by its index in the layout; -1 without a claim or with no jar touched";
    jar_displacement: Float, "planar displacement since reset, summed over jars, m";
    max_jar_displacement: Float, "largest jar displacement since reset, m";
    max_tilt: Float, "largest jar tilt now, rad";
    tips: Count, "jars tipped over now";
    contacts: Count, "tactile readings this step";
    rows_added: Count, "GPIS rows the readings added";
    contacts_skipped: Count, "readings skipped as uninformative";
    contacts_dropped: Count, "readings dropped because the map was full";
    gpis_rows: Count, "GPIS rows held";
    iou: Float, "IoU of the map's interior against the true jar footprints";
    map_score_iou: Float, "the map task's score: IoU of the core's GPIS of the evidence with the true footprints (0 in other tasks)";
    map_score_mm: Float, "the map task's outline distance, mm: mean of the two directed distances between that GPIS's zero level set and the true outlines (0 in other tasks)";
    map_score_area: Float, "the map task's outline distance over the budget: summed over the motions so far (the rest of the budget at the final one when the episode ends), over max_steps, mm (0 in other tasks)";
    clipped: Flag, "the action was outside [-1, 1] and was clipped";
    blocked: Flag, "a wall or the workspace edge stopped the hand";
    motions: Count, "wrist motions this step (1 in the wrist action mode, a probe's in the probe mode)";
}

/// Number of info fields of each type: (floats, flags, counts).
pub fn info_counts() -> (usize, usize, usize) {
    STEP_INFO_FIELDS
        .iter()
        .fold((0, 0, 0), |(f, b, c), field| match field.value {
            InfoValue::Float(_) => (f + 1, b, c),
            InfoValue::Flag(_) => (f, b + 1, c),
            InfoValue::Count(_) | InfoValue::Index(_) => (f, b, c + 1),
        })
}

/// The infos of N episodes, one column per field, grouped by type: float field k of
/// episode i is `floats[k * n + i]` (k counts float fields only), and so on.
pub struct InfoColumns<'a> {
    /// Episodes.
    pub n: usize,
    /// Float fields, field-major.
    pub floats: &'a mut [f64],
    /// Flag fields, field-major.
    pub flags: &'a mut [bool],
    /// Count fields, field-major.
    pub counts: &'a mut [i64],
}

impl InfoColumns<'_> {
    /// Writes episode `i`'s info into its column entries. Cost O(fields).
    pub fn write(&mut self, i: usize, info: &StepInfo) {
        let (mut f, mut b, mut c) = (0, 0, 0);
        for field in STEP_INFO_FIELDS {
            match field.value {
                InfoValue::Float(get) => {
                    self.floats[f * self.n + i] = get(info);
                    f += 1;
                }
                InfoValue::Flag(get) => {
                    self.flags[b * self.n + i] = get(info);
                    b += 1;
                }
                InfoValue::Count(_) | InfoValue::Index(_) => {
                    self.counts[c * self.n + i] = field.value.integer(info).unwrap_or_default();
                    c += 1;
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn info_keys_are_unique() {
        let mut names: Vec<_> = STEP_INFO_FIELDS.iter().map(|f| f.name).collect();
        names.sort_unstable();
        names.dedup();
        assert_eq!(names.len(), STEP_INFO_FIELDS.len());
    }

    #[test]
    fn columns_hold_each_field_of_each_episode() {
        let (nf, nb, nc) = info_counts();
        let n = 2;
        let (mut floats, mut flags, mut counts) =
            (vec![0.0; nf * n], vec![false; nb * n], vec![0; nc * n]);
        let info = StepInfo {
            iou: 0.5,
            blocked: true,
            gpis_rows: 7,
            ..StepInfo::default()
        };
        let mut columns = InfoColumns {
            n,
            floats: &mut floats,
            flags: &mut flags,
            counts: &mut counts,
        };
        columns.write(1, &info);
        let (mut f, mut b, mut c) = (0, 0, 0);
        for field in STEP_INFO_FIELDS {
            match (field.name, field.value) {
                ("iou", _) => assert_eq!(floats[f * n + 1], 0.5),
                ("blocked", _) => assert!(flags[b * n + 1]),
                ("gpis_rows", _) => assert_eq!(counts[c * n + 1], 7),
                _ => {}
            }
            match field.value {
                InfoValue::Float(_) => f += 1,
                InfoValue::Flag(_) => b += 1,
                InfoValue::Count(_) | InfoValue::Index(_) => c += 1,
            }
        }
        assert_eq!(
            floats[..n].iter().sum::<f64>() + counts[..n].iter().sum::<i64>() as f64,
            0.0
        );
    }
}
