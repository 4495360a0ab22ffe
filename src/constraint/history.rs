//! What a step reads from the steps before it: the seed's persistent friction tangents, the
//! LCP's warm start keyed by row identity, and the world's random stream; flattened to float64
//! numbers for `get_state(full=True)`.

use glam::DVec3;

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
    /// Identity of the rows `warm` belongs to (`constraint::solve::row_key`).
    pub warm_rows: Vec<RowKey>,
    /// Moving average of the solves with rows left out that had to bring one back.
    pub regrow_rate: f64,
    /// SplitMix64 state of this world's random tangents.
    pub rng: u64,
    /// Whether the last step had constraint rows: an RK4 model's next step evaluates its dynamics
    /// first as a step with rows does (damping implicit), else as RK4's first stage.
    pub constrained: bool,
    /// The dofs whose dry friction the last step held at its cap, each with the direction it
    /// slid in (true: positive velocity, friction pushing negative), in increasing dof order:
    /// while a dof slides on that way, the next step applies its friction as a known force
    /// (`constraint::dry_friction`).
    pub sliding: Vec<(usize, bool)>,
}

impl History {
    /// A new world's: nothing kept, the default random stream.
    pub fn new() -> Self {
        History { tangents: vec![], warm: vec![], warm_rows: vec![], regrow_rate: 0.0, rng: 0x5EED, constrained: true, sliding: vec![] }
    }
}

/// A constraint row's identity across steps, through which a step reads the last step's active
/// set (`constraint::solve::warm_guess`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum RowKey {
    /// A joint limit: the joint, and whether it is the lower limit (the row pushes q up).
    Limit {
        /// Joint.
        joint: usize,
        /// Lower limit.
        lower: bool,
    },
    /// A row of a contact: the pair's geoms and feature, the row's place in the contact (0: the
    /// normal, then its sliding, torsional and rolling friction rows) and the place of the row
    /// owning its λ (0: the normal's, for the sliding rows).
    Contact {
        /// First geom.
        geom1: usize,
        /// Second geom.
        geom2: usize,
        /// The pair's contact feature.
        feature: usize,
        /// Place within the contact.
        within: usize,
        /// Place of the row owning the row's λ.
        cone: usize,
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
    /// An equality row: the equality, and whether it is the pair's positive row.
    Equality {
        /// Equality.
        equality: usize,
        /// Positive row.
        positive: bool,
    },
    /// A connect row: 3 × the connect + the axis, and whether it is the pair's positive row.
    Connect {
        /// 3 × connect + axis.
        axis: usize,
        /// Positive row.
        positive: bool,
    },
    /// A dry-friction row: the dof, and whether it pushes the dof forward.
    DryFriction {
        /// Dof.
        dof: usize,
        /// Positive direction.
        positive: bool,
    },
}

impl RowKey {
    /// Six integers (kind 0 limit, 1 contact, 2 motion, 3 dry friction, 4 equality, 5 connect; then the kind's fields, zeros filling),
    /// as [`History::to_flat`] writes them.
    fn to_flat(self) -> [u64; ROW_KEY_LEN] {
        match self {
            RowKey::Limit { joint, lower } => [0, joint as u64, 0, 0, lower as u64, 0],
            RowKey::Contact { geom1, geom2, feature, within, cone } => [1, geom1 as u64, geom2 as u64, feature as u64, within as u64, cone as u64],
            RowKey::Motion { actuator, bounded, positive } => [2, actuator as u64, 0, bounded as u64, positive as u64, 0],
            RowKey::DryFriction { dof, positive } => [3, dof as u64, 0, 0, positive as u64, 0],
            RowKey::Equality { equality, positive } => [4, equality as u64, 0, 0, positive as u64, 0],
            RowKey::Connect { axis, positive } => [5, axis as u64, 0, 0, positive as u64, 0],
        }
    }

    /// The key [`RowKey::to_flat`] wrote, or None for integers no key writes.
    fn from_flat([kind, a, b, c, d, e]: [u64; ROW_KEY_LEN]) -> Option<RowKey> {
        let flag = |x: u64| (x <= 1).then_some(x == 1);
        match kind {
            1 => Some(RowKey::Contact { geom1: a as usize, geom2: b as usize, feature: c as usize, within: d as usize, cone: e as usize }),
            _ if e != 0 => None,
            0 if b == 0 && c == 0 => Some(RowKey::Limit { joint: a as usize, lower: flag(d)? }),
            2 if b == 0 => Some(RowKey::Motion { actuator: a as usize, bounded: flag(c)?, positive: flag(d)? }),
            3 if b == 0 && c == 0 => Some(RowKey::DryFriction { dof: a as usize, positive: flag(d)? }),
            4 if b == 0 && c == 0 => Some(RowKey::Equality { equality: a as usize, positive: flag(d)? }),
            5 if b == 0 && c == 0 => Some(RowKey::Connect { axis: a as usize, positive: flag(d)? }),
            _ => None,
        }
    }
}

/// Numbers a tangent takes in [`History::to_flat`]: geom1, geom2, feature, then the vector.
const TANGENT_LEN: usize = 6;
/// Numbers a warm-start row's identity takes in [`History::to_flat`].
const ROW_KEY_LEN: usize = 6;
/// Numbers in the shortest flat history (nothing kept): regrow rate, the random state's two
/// halves, the tangent, warm-start variable and row counts, the last step's kind and the sliding
/// dofs' count.
pub const FLAT_HISTORY_MIN: usize = 8;
/// Integers in a flat history are below this (exact in f64).
const FLAT_INT_MAX: f64 = 9_007_199_254_740_992.0;

impl History {
    /// Appends the history as float64 numbers (every integer exact): regrow rate, the random
    /// state as two 32-bit halves, the tangent count T and T × (geom1, geom2, feature, t_x, t_y,
    /// t_z), the warm start's variable count W and W activities (0 or 1; rows, then their λ),
    /// its row count R and R × (kind, three indices and a side), whether the last step had
    /// rows (0 or 1), then the sliding dofs' count S and S × (2 dof + 1 if sliding positively).
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
        out.push(self.sliding.len() as f64);
        out.extend(self.sliding.iter().map(|&(dof, positive)| (2 * dof + positive as usize) as f64));
    }

    /// Reads what [`History::to_flat`] wrote, checking every number (`ngeom` bounds the tangents'
    /// geoms, `nv` the sliding dofs); an error names the first that is wrong.
    pub fn from_flat(v: &[f64], ngeom: usize, nv: usize) -> crate::error::Result<History> {
        let bad = |what: String| crate::error::Error::Input(format!("history: {what}"));
        let int = |i: usize, what: &str, max: f64| -> crate::error::Result<u64> {
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
        let ns = int(at, "sliding dof count", nv as f64 + 1.0)? as usize;
        at += 1;
        let mut sliding = Vec::with_capacity(ns);
        for _ in 0..ns {
            let x = int(at, "sliding dof", 2.0 * nv as f64)? as usize;
            if sliding.last().is_some_and(|&(dof, _)| dof >= x / 2) {
                return Err(bad(format!("sliding dof {} at element {at} is not after the one before it", x / 2)));
            }
            sliding.push((x / 2, x % 2 == 1));
            at += 1;
        }
        if at != v.len() {
            return Err(bad(format!("has {} numbers, {} more than its counts say", v.len(), v.len() - at)));
        }
        Ok(History { tangents, warm, warm_rows, regrow_rate, rng, constrained, sliding })
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
            RowKey::Contact { geom1, geom2, feature, within, cone } if within > 0 => {
                within <= i
                    && rows[i - within] == RowKey::Contact { geom1, geom2, feature, within: 0, cone: 0 }
                    && cone <= within
                    && (cone == 0 || matches!(rows[i - within + cone], RowKey::Contact { cone: c, within: w, .. } if c == cone && w == cone))
            }
            RowKey::Contact { cone, .. } => cone == 0,
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
        self.sliding.clone_from(&from.sliding);
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
    use super::{History, FLAT_HISTORY_MIN};

    #[test]
    fn an_empty_history_flattens_to_the_shortest_flat_history_and_back() {
        let mut flat = vec![];
        History::new().to_flat(&mut flat);
        assert_eq!(flat.len(), FLAT_HISTORY_MIN);
        assert_eq!(History::from_flat(&flat, 1, 1).unwrap(), History::new());
        assert!(History::from_flat(&flat[..FLAT_HISTORY_MIN - 1], 1, 1).is_err());
    }

    #[test]
    fn sliding_dofs_flatten_and_back_and_bad_ones_are_errors() {
        let h = History { sliding: vec![(0, true), (3, false)], ..History::new() };
        let mut flat = vec![];
        h.to_flat(&mut flat);
        assert_eq!(History::from_flat(&flat, 1, 4).unwrap(), h);
        // a dof the model does not have, and dofs out of order
        let err = History::from_flat(&flat, 1, 3).unwrap_err().to_string();
        assert!(err.contains("sliding dof"), "{err}");
        let n = flat.len();
        flat.swap(n - 1, n - 2);
        let err = History::from_flat(&flat, 1, 4).unwrap_err().to_string();
        assert!(err.contains("not after"), "{err}");
    }
}
