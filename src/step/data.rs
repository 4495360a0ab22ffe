//! Per-world scratch: everything a step derives, one field per room, allocated once per model so
//! that stepping never allocates.

use glam::DVec3;

use crate::collision::CollisionData;
use crate::constraint::{ConstraintScratch, Constraints, History, World};
use crate::dynamics::aba::AbaData;
use crate::dynamics::kinematics::KinData;
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

    /// A batch world's: without the scratch the batch's threads lend it ([`Lent`]).
    pub fn lending(m: &Model) -> Self {
        let mut d = Data::new(m);
        // its own sized buffers go to a set that is dropped
        d.swap_lent(&mut Lent::default());
        d
    }

    /// Runs `f` on this world with the thread's scratch `l` lent to it, and takes it back after,
    /// also when `f` panics (the panic then goes on).
    pub fn with_lent<R>(&mut self, l: &mut Lent, f: impl FnOnce(&mut Data) -> R) -> R {
        self.swap_lent(l);
        let out = std::panic::catch_unwind(std::panic::AssertUnwindSafe(|| f(self)));
        self.swap_lent(l);
        out.unwrap_or_else(|e| std::panic::resume_unwind(e))
    }

    /// Exchanges the scratch of [`Lent`] with `l` (a batch world's is none between its steps).
    pub fn swap_lent(&mut self, l: &mut Lent) {
        std::mem::swap(&mut self.dynamics.kin, &mut l.kin);
        std::mem::swap(&mut self.dynamics.aba, &mut l.aba);
        std::mem::swap(&mut self.rk4, &mut l.rk4);
        std::mem::swap(&mut self.sensors, &mut l.sensors);
        self.constraints.swap_scratch(&mut l.constraints);
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

/// The scratch a step writes before it reads and no later step reads: the kinematics being
/// evaluated (the next step's, computed ahead, stay the world's: `DynamicsData::ahead`), the ABA
/// quantities, RK4's stages, the sensor outputs' and the constraint stages' ([`ConstraintScratch`]:
/// rows, solve, post-stabilisation). They are most of a world's memory, so a batch keeps one set
/// per thread and lends it to each world for its step ([`Data::with_lent`]) instead of keeping one
/// per world; a `Sim` keeps its own.
#[derive(Clone, Debug, Default)]
pub struct Lent {
    kin: KinData,
    aba: AbaData,
    rk4: Rk4Scratch,
    sensors: SensorScratch,
    constraints: ConstraintScratch,
}

impl Lent {
    /// Buffers sized for `m` (and for any world's own copy of it).
    pub fn new(m: &Model) -> Self {
        Lent { kin: KinData::new(m), aba: AbaData::new(m), rk4: Rk4Scratch::new(m), sensors: SensorScratch::new(m), constraints: ConstraintScratch::new(m) }
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
