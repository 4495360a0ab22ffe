//! No allocation inside a step: a counting global allocator around the system one. A step may
//! grow its buffers the first time it needs more rows than before; once a workload has sized
//! them, running the same workload again allocates nothing. One test in this binary, so that no
//! other test's allocations are counted.

use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicUsize, Ordering};

use sinew::model::{ConstraintMode, FrictionModel, Integrator};
use sinew::{Model, State};

struct Counting;

static ALLOCATIONS: AtomicUsize = AtomicUsize::new(0);

// SAFETY: forwards every call to the system allocator unchanged; only counts.
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        ALLOCATIONS.fetch_add(1, Ordering::Relaxed);
        // SAFETY: the caller's contract is System's.
        unsafe { System.alloc(layout) }
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        // SAFETY: as above.
        unsafe { System.dealloc(ptr, layout) }
    }

    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        ALLOCATIONS.fetch_add(1, Ordering::Relaxed);
        // SAFETY: as above.
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

#[global_allocator]
static COUNTING: Counting = Counting;

/// A free capsule torso with two limited, motored legs over a floor, and a stack of three boxes:
/// capsule–plane, box–plane and box–box contacts, friction, limits and impacts.
const SCENE: &str = r#"<mujoco>
  <option timestep="0.004"/>
  <custom><numeric name="sinew/restitution" data="0.3"/></custom>
  <worldbody>
    <geom type="plane" size="10 10 .1"/>
    <body name="torso" pos="0 0 0.6">
      <freejoint/>
      <geom type="capsule" fromto="-0.2 0 0 0.2 0 0" size="0.06"/>
      <body pos="-0.2 0 0">
        <joint name="hip1" type="hinge" axis="0 1 0" range="-60 60"/>
        <geom type="capsule" fromto="0 0 0 0 0 -0.35" size="0.04"/>
        <body pos="0 0 -0.35">
          <joint name="knee1" type="hinge" axis="0 1 0" range="-90 0"/>
          <geom type="capsule" fromto="0 0 0 0 0 -0.3" size="0.035"/>
        </body>
      </body>
      <body pos="0.2 0 0">
        <joint name="hip2" type="hinge" axis="1 0 0" range="-60 60"/>
        <geom type="capsule" fromto="0 0 0 0 0 -0.35" size="0.04"/>
      </body>
    </body>
    <body pos="1 0 0.1"><freejoint/><geom type="box" size="0.1 0.1 0.1"/></body>
    <body pos="1 0 0.3"><freejoint/><geom type="box" size="0.1 0.1 0.1"/></body>
    <body pos="1.02 0 0.5"><freejoint/><geom type="box" size="0.1 0.1 0.1"/></body>
  </worldbody>
  <actuator>
    <motor joint="hip1" gear="40"/><motor joint="knee1" gear="30"/><motor joint="hip2" gear="40"/>
  </actuator>
</mujoco>"#;

/// `steps` steps from qpos0 at rest, with nothing carried over from earlier steps, under a fixed
/// pseudo-random control sequence: the same workload every time.
fn run(m: &Model, s: &mut State, steps: usize) {
    s.qpos.copy_from_slice(&m.qpos0);
    s.qvel.fill(0.0);
    s.data.forget_history();
    s.data.constraints.history.rng = 7;
    let mut x: u64 = 3;
    for k in 0..steps {
        if k % 10 == 0 {
            for c in s.ctrl.iter_mut() {
                x = x.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
                *c = (x >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0;
            }
        }
        s.step(m);
    }
}

#[test]
fn a_step_allocates_nothing_once_its_buffers_are_sized() {
    let base = Model::from_mjcf(SCENE).unwrap();
    for (friction, mode, integrator) in [
        (FrictionModel::Pyramid, ConstraintMode::Acceleration, Integrator::Euler),
        (FrictionModel::OneTangent, ConstraintMode::Acceleration, Integrator::Euler),
        (FrictionModel::Pyramid, ConstraintMode::Velocity, Integrator::Euler),
        (FrictionModel::Pyramid, ConstraintMode::Acceleration, Integrator::Leapfrog),
        (FrictionModel::Pyramid, ConstraintMode::Acceleration, Integrator::Rk4),
    ] {
        let mut m = base.clone();
        (m.opt.friction, m.opt.constraint_mode, m.opt.integrator) = (friction, mode, integrator);
        let mut s = State::new(&m);
        let start = ALLOCATIONS.load(Ordering::Relaxed);
        run(&m, &mut s, 1000);
        assert!(ALLOCATIONS.load(Ordering::Relaxed) > start, "the first run sizes the buffers (and the count sees it)");
        let (first, stats) = (s.qpos.clone(), s.data.constraints.stats);
        assert!(stats.solves > 500 && stats.pivots > 0, "the workload exercises the LCP: {stats:?}");
        assert!(s.data.constraints.impacts > 0 || mode == ConstraintMode::Velocity, "and impacts");
        let before = ALLOCATIONS.load(Ordering::Relaxed);
        run(&m, &mut s, 1000);
        let during = ALLOCATIONS.load(Ordering::Relaxed) - before;
        assert_eq!(s.qpos, first, "the second run repeats the first");
        assert_eq!(during, 0, "{friction:?}, {mode:?}, {integrator:?}: {during} allocations in 1000 steps");
    }
}
