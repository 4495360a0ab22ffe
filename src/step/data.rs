//! A world's derived data: everything a step derives, one field per room, allocated once per model
//! so that stepping never allocates; and the part of it a batch keeps per world ([`Kept`]).

use glam::DVec3;

use crate::collision::CollisionData;
use crate::constraint::lcp::LcpStats;
use crate::constraint::{AppliedForces, Constraints, History, World};
use crate::dynamics::kinematics::KinCache;
use crate::dynamics::DynamicsData;
use crate::integrate::energy_bound::EnergyBound;
use crate::integrate::Rk4Scratch;
use crate::model::Model;
use crate::state::WorldState;

/// Derived quantities and scratch of one world.
#[derive(Clone, Debug, Default)]
pub struct Data {
    /// Kinematics, ABA quantities, applied forces and q̈ of the last evaluation.
    pub dynamics: DynamicsData,
    /// RK4 stage buffers.
    pub rk4: Rk4Scratch,
    /// The energy budget of a step with contacts.
    pub energy: EnergyBound,
    /// Geom poses and contacts.
    pub coll: CollisionData,
    /// Rows, K, b, the solve, post-stabilisation and the history the next step reads.
    pub constraints: Constraints,
    /// Scratch for `sensors`.
    pub sensors: SensorScratch,
    /// Where a batch world's step call began, restored if it panics, and the panic's message.
    pub fault: Fault,
    /// Nanoseconds spent per pipeline stage, in [`crate::step::Stage`] order.
    #[cfg(feature = "stage-timing")]
    pub stage_ns: [u64; crate::timing::STAGES],
}

/// Scratch for the sensor outputs (`sensors`).
#[derive(Clone, Debug, Default)]
pub struct SensorScratch {
    /// Centre of mass and mass of each root's subtree (nbody).
    pub root_com: Vec<(DVec3, f64)>,
    /// Per-node spatial forces (nnode).
    pub node_force: Vec<crate::math::Force>,
}

impl SensorScratch {
    /// Buffers sized for `m`.
    pub fn new(m: &Model) -> Self {
        SensorScratch { root_com: vec![(DVec3::ZERO, 0.0); m.nbody], node_force: vec![crate::math::Force::ZERO; m.nnode] }
    }
}

impl Data {
    /// Buffers sized for `m`.
    pub fn new(m: &Model) -> Self {
        Data {
            dynamics: DynamicsData::new(m),
            rk4: Rk4Scratch::new(m),
            energy: EnergyBound::new(m),
            coll: CollisionData::new(m),
            constraints: Constraints::new(m),
            sensors: SensorScratch::new(m),
            fault: Fault { qpos: vec![0.0; m.nq], qvel: vec![0.0; m.nv], act: vec![0.0; m.na], time: 0.0, message: None },
            #[cfg(feature = "stage-timing")]
            stage_ns: [0; crate::timing::STAGES],
        }
    }

    /// Runs `f` on the world whose keeping is `k` (this `Data`, a batch thread's, lends it the
    /// scratch) and takes the keeping back after, also when `f` panics (the panic then goes on).
    pub fn with_kept<R>(&mut self, k: &mut Kept, f: impl FnOnce(&mut Data) -> R) -> R {
        self.swap_kept(k);
        let out = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| f(self)));
        self.swap_kept(k);
        out.unwrap_or_else(|e| std::panic::resume_unwind(e))
    }

    /// Exchanges what a world keeps ([`Kept`]) with `k`.
    pub fn swap_kept(&mut self, k: &mut Kept) {
        let c = &mut self.constraints;
        std::mem::swap(&mut self.dynamics.ahead, &mut k.ahead);
        std::mem::swap(&mut self.dynamics.xfrc_applied, &mut k.xfrc_applied);
        std::mem::swap(&mut self.coll, &mut k.coll);
        std::mem::swap(&mut self.energy, &mut k.energy);
        std::mem::swap(&mut c.history, &mut k.history);
        std::mem::swap(&mut c.applied, &mut k.applied);
        std::mem::swap(&mut c.feedforward, &mut k.feedforward);
        std::mem::swap(&mut c.stats, &mut k.stats);
        std::mem::swap(&mut c.impacts, &mut k.impacts);
        std::mem::swap(&mut c.projections, &mut k.projections);
        std::mem::swap(&mut self.fault.message, &mut k.fault);
    }

    /// Forgets what the last steps leave for the next (friction tangents, the LCP's warm start and
    /// regrow rate, cached kinematics, rows and forces), so that the next step is a fresh world's;
    /// the random stream runs on.
    pub fn forget_history(&mut self) {
        let fresh = History { rng: self.constraints.history.rng, ..History::new() };
        self.restore_history(&fresh);
    }

    /// Makes `history` what the next step reads (the rest of the scratch is forgotten), so that a
    /// world given the state and history of another steps exactly as that one does.
    pub fn restore_history(&mut self, history: &History) {
        self.constraints.history.clone_from(history);
        self.forget_scratch();
    }

    /// The feed-forward and history a full state carries ([`crate::step::state::FlatState`]).
    pub fn full_state(&self) -> (&[f64], &History) {
        (&self.constraints.feedforward, &self.constraints.history)
    }

    /// Gives the world the feed-forward `ff` (none: zero) and `history`.
    pub fn restore(&mut self, ff: Option<&[f64]>, history: &History) {
        match ff {
            Some(ff) => self.constraints.feedforward.copy_from_slice(ff),
            None => self.constraints.feedforward.fill(0.0),
        }
        self.restore_history(history);
    }

    /// Drops the rows, forces, contacts and cached kinematics of the last step.
    fn forget_scratch(&mut self) {
        self.constraints.forget_scratch();
        self.coll.forget();
        self.dynamics.ahead.forget();
    }

    /// The world as the constraint stages see it.
    pub fn world(&mut self) -> World<'_> {
        World {
            dynamics: &mut self.dynamics,
            coll: &mut self.coll,
            constraints: &mut self.constraints,
            #[cfg(feature = "stage-timing")]
            stage_ns: &mut self.stage_ns,
        }
    }
}

/// What a world keeps from one step to the next, and what is read after a step: the kinematics
/// computed ahead for the next step, the forces applied to its bodies, collision's poses, caches and contacts, the energy bound,
/// the constraint history, the forces the rows applied, motion control's feed-forward, the
/// counters and the last fault's message. The rest of a [`Data`] — the kinematics being
/// evaluated, the tendons, applied forces, ABA quantities and accelerations, RK4's stages, the
/// constraint stages' rows, solve and post-stabilisation, the sensors', the state a guarded call
/// began with — is scratch a step writes before it reads, and most of a world's memory: a batch
/// keeps a `Kept` per world and one `Data` per thread, which takes each world's keeping for its
/// step ([`Data::with_kept`]).
#[derive(Clone, Debug, Default)]
pub struct Kept {
    ahead: KinCache,
    xfrc_applied: Vec<f64>,
    coll: CollisionData,
    energy: EnergyBound,
    history: History,
    applied: AppliedForces,
    feedforward: Vec<f64>,
    stats: LcpStats,
    impacts: u64,
    projections: u64,
    /// The message of the panic the world's last guarded call met, if any ([`Fault`]).
    pub fault: Option<String>,
}

impl Kept {
    /// A new world's of `m`, with its random stream seeded by `seed`.
    pub fn new(m: &Model, seed: u64) -> Self {
        let mut k = Kept::default();
        Data::new(m).swap_kept(&mut k);
        k.history.rng = crate::math::splitmix64(seed);
        k
    }

    /// The forces applied to the bodies (nbody × 6: force at the centre of mass, then torque,
    /// world axes; empty: none).
    pub fn xfrc_applied(&self) -> &[f64] {
        &self.xfrc_applied
    }

    /// Applies `xfrc` (nbody × 6, as [`Kept::xfrc_applied`]) to the bodies from the next step on;
    /// all zero is kept as none.
    pub fn set_xfrc_applied(&mut self, xfrc: &[f64]) {
        self.xfrc_applied.clear();
        if xfrc.iter().any(|&x| x != 0.0) {
            self.xfrc_applied.extend_from_slice(xfrc);
        }
    }

    /// The world's solver counters since it was made: its LCP statistics, impacts resolved and
    /// position projections.
    pub fn stats(&self) -> (&LcpStats, u64, u64) {
        (&self.stats, self.impacts, self.projections)
    }

    /// Re-seeds the world's random stream (its friction tangents, drawn from it, are redrawn).
    pub fn seed(&mut self, seed: u64) {
        self.history.rng = crate::math::splitmix64(seed);
        self.history.tangents.clear();
    }

    /// [`Data::forget_history`] for a world between its steps.
    pub fn forget_history(&mut self) {
        let fresh = History { rng: self.history.rng, ..History::new() };
        self.restore_history(&fresh);
    }

    /// [`Data::restore_history`] for a world between its steps.
    pub fn restore_history(&mut self, history: &History) {
        self.history.clone_from(history);
        self.coll.forget();
        self.ahead.forget();
        self.applied.clear();
    }

    /// The feed-forward and history a full state carries ([`crate::step::state::FlatState`]).
    pub fn full_state(&self) -> (&[f64], &History) {
        (&self.feedforward, &self.history)
    }

    /// Gives the world the feed-forward `ff` (none: zero) and `history`.
    pub fn restore(&mut self, ff: Option<&[f64]>, history: &History) {
        match ff {
            Some(ff) => self.feedforward.copy_from_slice(ff),
            None => self.feedforward.fill(0.0),
        }
        self.restore_history(history);
    }
}

/// A world's state at the start of a guarded step call ([`crate::step::run::guarded`]), put
/// back if the call panics (a bug), and the message of the last such panic in a batch.
#[derive(Clone, Debug, Default)]
pub struct Fault {
    /// qpos at the start of the call.
    pub qpos: Vec<f64>,
    /// qvel at the start of the call.
    pub qvel: Vec<f64>,
    /// act at the start of the call.
    pub act: Vec<f64>,
    /// Time at the start of the call.
    pub time: f64,
    /// The panic's message, if the call met one.
    pub message: Option<String>,
}

impl Fault {
    /// Records `s` as the start of the call.
    pub fn save(&mut self, s: &WorldState<'_>) {
        self.qpos.copy_from_slice(s.qpos);
        self.qvel.copy_from_slice(s.qvel);
        self.act.copy_from_slice(s.act);
        self.time = *s.time;
    }

    /// Puts `s` back to the start of the call.
    pub fn restore(&self, s: &mut WorldState<'_>) {
        s.qpos.copy_from_slice(&self.qpos);
        s.qvel.copy_from_slice(&self.qvel);
        s.act.copy_from_slice(&self.act);
        *s.time = self.time;
    }
}
