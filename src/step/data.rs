//! ③ Per-world scratch: everything a step derives, allocated once per model so that stepping
//! never allocates.

use glam::DVec3;

use crate::model::Model;
use crate::step::aba::AbaData;
use crate::step::collision::CollisionData;
use crate::step::constraint::ConstraintData;
use crate::step::lcp::{LcpStats, LcpWork};
use crate::step::integrate::Rk4Scratch;
use crate::step::kinematics::KinData;
use crate::step::stabilize::StabilizeData;

/// Derived quantities and scratch of one world.
#[derive(Clone, Debug, Default)]
pub struct Data {
    /// Stage 1 output.
    pub kin: KinData,
    /// ABA inward-pass quantities and spatial accelerations.
    pub aba: AbaData,
    /// Total applied generalised force (nv): actuators + passive.
    pub qfrc_applied: Vec<f64>,
    /// Joint accelerations of the last evaluation (nv).
    pub qacc: Vec<f64>,
    /// RK4 stage buffers.
    pub rk4: Rk4Scratch,
    /// Geom poses and contacts.
    pub coll: CollisionData,
    /// Constraint rows, K, b.
    pub con: ConstraintData,
    /// The constraint solves' LCP, answer, warm start and counters.
    pub solve: SolveData,
    /// What building the rows needs besides them.
    pub rows: RowScratch,
    /// Post-stabilisation scratch and counters.
    pub post: StabilizeData,
    /// What the next step reads from the steps before it.
    pub history: History,
    /// Trajectory feed-forward for motion control: reference velocities then accelerations (2 × nu).
    pub feedforward: Vec<f64>,
    /// Scratch for `sensors`.
    pub sensors: SensorScratch,
    /// Where a batch world's step call began, restored if it panics, and the panic's message.
    pub fault: Fault,
    /// Nanoseconds spent per pipeline stage, in [`crate::step::Stage`] order.
    #[cfg(feature = "stage-timing")]
    pub stage_ns: [u64; crate::step::STAGES],
}

/// The LCP of a step's constraint solves (`step::solve`): its matrix and vector, each
/// variable's role, the answer, the warm start, Lemke's tableau and counters.
#[derive(Clone, Debug, Default)]
pub struct SolveData {
    /// Constraint force (acceleration solve) or impulse (impact solve) per row and λ.
    pub force: Vec<f64>,
    /// LCP matrix of the island being solved (row-major).
    pub m: Vec<f64>,
    /// LCP vector.
    pub q: Vec<f64>,
    /// λ variable of each normal row with friction (usize::MAX: none).
    pub lambda: Vec<usize>,
    /// Role of each LCP variable of the island being solved.
    pub role: Vec<crate::step::lcp::Role>,
    /// Island label of each LCP variable (`step::solve::island_labels`).
    pub group: Vec<usize>,
    /// The LCP variables island by island (by label, each island's in their order).
    pub order: Vec<usize>,
    /// Number of each variable in its island's LCP while that is posed (else usize::MAX).
    pub local: Vec<usize>,
    /// The island's q, variables left out, warm set and answer.
    pub island_q: Vec<f64>,
    /// See `island_q`.
    pub island_out: Vec<bool>,
    /// See `island_q`.
    pub island_warm: Vec<bool>,
    /// See `island_q`.
    pub island_z: Vec<f64>,
    /// The island's rows whose test forces are not pushed, with their numbers in its LCP (in
    /// increasing row order): scratch for the matrix.
    pub unpushed: Vec<(usize, usize)>,
    /// Union–find forest over the nodes' trees, scratch for the labels (nnode).
    pub tree_link: Vec<usize>,
    /// LCP variables left out of the solve (held at zero force) and of K.
    pub out: Vec<bool>,
    /// Active set of this step's impact solve, which warm-starts the force solve on the same rows
    /// after it (empty: no impact this step, or rows rebuilt since).
    pub impact_warm: Vec<bool>,
    /// The active set the force solve starts from (`step::solve::warm_guess`).
    pub warm: Vec<bool>,
    /// Last step's λ variable of each of its rows that owns one, scratch for `step::solve::warm_guess`.
    pub warm_lambda: Vec<usize>,
    /// Lemke tableau.
    pub work: LcpWork,
    /// Solver statistics.
    pub stats: LcpStats,
    /// Impact solves run.
    pub impacts: u64,
}

/// What building a step's rows needs besides them (`step::rows`).
#[derive(Clone, Debug, Default)]
pub struct RowScratch {
    /// Limits whose rows this step must include (2 per joint: lower, upper).
    pub limit_forced: Vec<bool>,
    /// Friction tangents being recorded this step.
    pub tangents_next: Vec<((usize, usize, usize), DVec3)>,
}

/// Scratch for the sensor outputs (`sensors`).
#[derive(Clone, Debug, Default)]
pub struct SensorScratch {
    /// Centre of mass and mass of each root's subtree (nbody).
    pub root_com: Vec<(DVec3, f64)>,
    /// Per-node spatial forces (nnode).
    pub node_force: Vec<crate::math::Force>,
}

impl Data {
    /// Buffers sized for `m`.
    pub fn new(m: &Model) -> Self {
        Data {
            kin: KinData::new(m),
            aba: AbaData::new(m),
            qfrc_applied: vec![0.0; m.nv],
            qacc: vec![0.0; m.nv],
            rk4: Rk4Scratch::new(m),
            coll: CollisionData::new(m),
            con: ConstraintData::new(m),
            solve: SolveData::default(),
            rows: RowScratch { limit_forced: vec![false; 2 * m.njnt], tangents_next: vec![] },
            post: StabilizeData::new(m),
            history: History::new(),
            feedforward: vec![0.0; 2 * m.nu],
            sensors: SensorScratch { root_com: vec![(DVec3::ZERO, 0.0); m.nbody], node_force: vec![crate::math::Force::ZERO; m.nnode] },
            fault: Fault { qpos: vec![0.0; m.nq], qvel: vec![0.0; m.nv], time: 0.0, message: None },
            #[cfg(feature = "stage-timing")]
            stage_ns: [0; crate::step::STAGES],
        }
    }

    /// Forgets what the last steps leave for the next (friction tangents, the LCP's warm start and
    /// regrow rate, cached kinematics, rows and forces), so that the next step is a fresh world's;
    /// the random stream runs on.
    pub fn forget_history(&mut self) {
        let fresh = History { rng: self.history.rng, ..History::new() };
        self.restore_history(&fresh);
    }

    /// Makes `history` what the next step reads (the rest of the scratch is forgotten), so that a
    /// world given the state and history of another steps exactly as that one does.
    pub fn restore_history(&mut self, history: &History) {
        self.history.clone_from(history);
        self.forget_scratch();
    }

    /// Drops the rows, forces, contacts and cached kinematics of the last step.
    fn forget_scratch(&mut self) {
        self.solve.force.clear();
        self.solve.impact_warm.clear();
        self.con.clear();
        self.coll.forget();
        self.post.forget();
    }
}

/// What a step reads from the steps before it besides time, qpos, qvel and ctrl: the seed's
/// persistent friction tangents (Kokkevis 2004, §8.1), the LCP's warm start (as MuJoCo's
/// `qacc_warmstart`) and how often leaving rows out failed lately, and the random stream. With the
/// state it makes a step's result bit-exact.
#[derive(Debug, PartialEq)]
pub struct History {
    /// Friction tangent of each contact of the last step, keyed by (geom1, geom2, feature).
    pub tangents: Vec<((usize, usize, usize), DVec3)>,
    /// Active set of the last accepted acceleration-level (or time-stepping) solve.
    pub warm: Vec<bool>,
    /// Identity of the rows `warm` belongs to (`step::solve::row_key`).
    pub warm_rows: Vec<RowKey>,
    /// Moving average of the solves with rows left out that had to bring one back.
    pub regrow_rate: f64,
    /// SplitMix64 state of this world's random tangents.
    pub rng: u64,
    /// Whether the last step had constraint rows: an RK4 model's next step evaluates its dynamics
    /// first as a step with rows does (damping implicit), else as RK4's first stage.
    pub constrained: bool,
}

impl History {
    /// A new world's: nothing kept, the default random stream.
    pub fn new() -> Self {
        History { tangents: vec![], warm: vec![], warm_rows: vec![], regrow_rate: 0.0, rng: 0x5EED, constrained: true }
    }
}

/// A world's state at the start of a batch step call, and the message of a panic (a bug) that
/// call met: the world is then put back to this state.
#[derive(Clone, Debug, Default)]
pub struct Fault {
    /// qpos at the start of the call.
    pub qpos: Vec<f64>,
    /// qvel at the start of the call.
    pub qvel: Vec<f64>,
    /// Time at the start of the call.
    pub time: f64,
    /// The panic's message, if the call met one.
    pub message: Option<String>,
}

/// A constraint row's identity across steps, through which a step reads the last step's active
/// set (`step::solve::warm_guess`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum RowKey {
    /// A joint limit: the joint, and whether it is the lower limit (the row pushes q up).
    Limit {
        /// Joint.
        joint: usize,
        /// Lower limit.
        lower: bool,
    },
    /// A row of a contact: the pair's geoms and feature, and the row's place in the contact (0:
    /// the normal, then its friction rows).
    Contact {
        /// First geom.
        geom1: usize,
        /// Second geom.
        geom2: usize,
        /// The pair's contact feature.
        feature: usize,
        /// Place within the contact.
        within: usize,
    },
    /// A motion-control row: the actuator, whether its force is bounded, and whether it pushes
    /// the joint forward.
    Motion {
        /// Actuator.
        actuator: usize,
        /// Bounded force.
        bounded: bool,
        /// Positive direction.
        positive: bool,
    },
}

impl RowKey {
    /// Five integers (kind 0 limit, 1 contact, 2 motion; then the kind's fields, zeros filling),
    /// as [`History::to_flat`] writes them.
    fn to_flat(self) -> [u64; 5] {
        match self {
            RowKey::Limit { joint, lower } => [0, joint as u64, 0, 0, lower as u64],
            RowKey::Contact { geom1, geom2, feature, within } => [1, geom1 as u64, geom2 as u64, feature as u64, within as u64],
            RowKey::Motion { actuator, bounded, positive } => [2, actuator as u64, 0, bounded as u64, positive as u64],
        }
    }

    /// The key [`RowKey::to_flat`] wrote, or None for integers no key writes.
    fn from_flat([kind, a, b, c, d]: [u64; 5]) -> Option<RowKey> {
        let flag = |x: u64| (x <= 1).then_some(x == 1);
        match kind {
            0 if b == 0 && c == 0 => Some(RowKey::Limit { joint: a as usize, lower: flag(d)? }),
            1 => Some(RowKey::Contact { geom1: a as usize, geom2: b as usize, feature: c as usize, within: d as usize }),
            2 if b == 0 => Some(RowKey::Motion { actuator: a as usize, bounded: flag(c)?, positive: flag(d)? }),
            _ => None,
        }
    }
}

/// Numbers a tangent takes in [`History::to_flat`]: geom1, geom2, feature, then the vector.
const TANGENT_LEN: usize = 6;
/// Numbers a warm-start row's identity takes in [`History::to_flat`].
const ROW_KEY_LEN: usize = 5;
/// Numbers in the shortest flat history (nothing kept): regrow rate, the random state's two
/// halves, the tangent, warm-start variable and row counts, and the last step's kind.
pub const FLAT_HISTORY_MIN: usize = 7;
/// Integers in a flat history are below this (exact in f64).
const FLAT_INT_MAX: f64 = 9_007_199_254_740_992.0;

impl History {
    /// Appends the history as float64 numbers (every integer exact): regrow rate, the random
    /// state as two 32-bit halves, the tangent count T and T × (geom1, geom2, feature, t_x, t_y,
    /// t_z), the warm start's variable count W and W activities (0 or 1; rows, then their λ),
    /// its row count R and R × (kind, three indices and a side), then whether the last step had
    /// rows (0 or 1).
    pub fn to_flat(&self, out: &mut Vec<f64>) {
        out.extend([self.regrow_rate, (self.rng >> 32) as f64, (self.rng & 0xFFFF_FFFF) as f64]);
        out.push(self.tangents.len() as f64);
        for &((g1, g2, feature), t) in &self.tangents {
            out.extend([g1 as f64, g2 as f64, feature as f64, t.x, t.y, t.z]);
        }
        out.push(self.warm.len() as f64);
        out.extend(self.warm.iter().map(|&a| a as u8 as f64));
        out.push(self.warm_rows.len() as f64);
        for key in &self.warm_rows {
            out.extend(key.to_flat().map(|x| x as f64));
        }
        out.push(self.constrained as u8 as f64);
    }

    /// Reads what [`History::to_flat`] wrote, checking every number (`ngeom` bounds the tangents'
    /// geoms); an error names the first that is wrong.
    pub fn from_flat(v: &[f64], ngeom: usize) -> crate::Result<History> {
        let bad = |what: String| crate::Error::Input(format!("history: {what}"));
        let int = |i: usize, what: &str, max: f64| -> crate::Result<u64> {
            let x = *v.get(i).ok_or_else(|| bad(format!("ends at element {i}, where {what} was expected")))?;
            if x.fract() != 0.0 || !(0.0..max).contains(&x) {
                return Err(bad(format!("{what} (element {i}) is {x}, not an integer in [0, {max})")));
            }
            Ok(x as u64)
        };
        let regrow_rate = *v.first().ok_or_else(|| bad("is empty".into()))?;
        if !(0.0..=1.0).contains(&regrow_rate) {
            return Err(bad(format!("regrow rate (element 0) is {regrow_rate}, not in [0, 1]")));
        }
        let rng = (int(1, "random state, high half", 4_294_967_296.0)? << 32) | int(2, "random state, low half", 4_294_967_296.0)?;
        let mut at = 3;
        let nt = int(at, "tangent count", FLAT_INT_MAX)? as usize;
        at += 1;
        let mut tangents = Vec::with_capacity(nt.min(v.len()));
        for _ in 0..nt {
            if v.len() < at + TANGENT_LEN {
                return Err(bad(format!("ends at element {}, inside a tangent", v.len())));
            }
            let g = (int(at, "tangent geom1", ngeom as f64)?, int(at + 1, "tangent geom2", ngeom as f64)?, int(at + 2, "tangent feature", FLAT_INT_MAX)?);
            let t = DVec3::new(v[at + 3], v[at + 4], v[at + 5]);
            if !t.is_finite() || (t.length() - 1.0).abs() > 1e-9 {
                return Err(bad(format!("tangent at element {} is {t}, not a unit vector", at + 3)));
            }
            tangents.push(((g.0 as usize, g.1 as usize, g.2 as usize), t));
            at += TANGENT_LEN;
        }
        let nw = int(at, "warm-start variable count", FLAT_INT_MAX)? as usize;
        at += 1;
        let mut warm = Vec::with_capacity(nw.min(v.len()));
        for _ in 0..nw {
            warm.push(int(at, "warm-start activity", 2.0)? == 1);
            at += 1;
        }
        let nr = int(at, "warm-start row count", FLAT_INT_MAX)? as usize;
        at += 1;
        if nr > nw {
            return Err(bad(format!("warm-start row count {nr} exceeds its variable count {nw}")));
        }
        let mut warm_rows = Vec::with_capacity(nr);
        for _ in 0..nr {
            let mut flat = [0; ROW_KEY_LEN];
            for (k, x) in flat.iter_mut().enumerate() {
                *x = int(at + k, "warm-start row identity", FLAT_INT_MAX)?;
            }
            let key = RowKey::from_flat(flat).ok_or_else(|| bad(format!("warm-start row identity {flat:?} at element {at} is none a step records")))?;
            warm_rows.push(key);
            at += ROW_KEY_LEN;
        }
        check_rows(&warm_rows).map_err(bad)?;
        let constrained = int(at, "constrained last step", 2.0)? == 1;
        at += 1;
        if at != v.len() {
            return Err(bad(format!("has {} numbers, {} more than its counts say", v.len(), v.len() - at)));
        }
        Ok(History { tangents, warm, warm_rows, regrow_rate, rng, constrained })
    }
}

/// Whether warm-start row identities are ones a step records: each once, a limit's and a motion
/// row's side 0 or 1, a contact's friction row after the normal it belongs to.
fn check_rows(rows: &[RowKey]) -> Result<(), String> {
    let mut sorted = rows.to_vec();
    sorted.sort_unstable();
    if let Some(w) = sorted.windows(2).find(|w| w[0] == w[1]) {
        return Err(format!("warm-start row identity {:?} appears more than once", w[0]));
    }
    for (i, &key) in rows.iter().enumerate() {
        let ok = match key {
            RowKey::Contact { geom1, geom2, feature, within } if within > 0 => {
                within <= i && rows[i - within] == RowKey::Contact { geom1, geom2, feature, within: 0 }
            }
            _ => true,
        };
        if !ok {
            return Err(format!("warm-start row {i} has identity {:?}, which no step records", rows[i]));
        }
    }
    Ok(())
}

impl Clone for History {
    fn clone(&self) -> Self {
        let mut h = History::new();
        h.clone_from(self);
        h
    }

    /// Field by field, keeping the buffers' capacity (a derived `clone_from` reallocates).
    fn clone_from(&mut self, from: &Self) {
        self.tangents.clone_from(&from.tangents);
        self.warm.clone_from(&from.warm);
        self.warm_rows.clone_from(&from.warm_rows);
        (self.regrow_rate, self.rng, self.constrained) = (from.regrow_rate, from.rng, from.constrained);
    }
}

impl Default for History {
    fn default() -> Self {
        History::new()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_empty_history_flattens_to_the_shortest_flat_history_and_back() {
        let mut flat = vec![];
        History::new().to_flat(&mut flat);
        assert_eq!(flat.len(), FLAT_HISTORY_MIN);
        assert_eq!(History::from_flat(&flat, 1).unwrap(), History::new());
        assert!(History::from_flat(&flat[..FLAT_HISTORY_MIN - 1], 1).is_err());
    }
}
