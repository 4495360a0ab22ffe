"""Actuator activation dynamics against MuJoCo on the same file: `<general>` with integrator,
filter and filterexact dynamics, affine gain and bias, limited activations, and the shortcuts
`<intvelocity>`, `<damper>`, `<cylinder>` and `<position timeconst>`, stepped with Euler and RK4
under random controls: qpos, qvel and act equal MuJoCo's to round-off. act is state: it is in
`get_state`/`set_state`, pickles, resets, keyframes and a Batch's arrays."""

import pickle

import mujoco
import numpy as np
import pytest

import sinew

XML = """<mujoco><option timestep="0.005" integrator="{integrator}"/>
  <default><geom contype="0" conaffinity="0"/></default>
  <worldbody>
    <body><joint name="a" type="hinge" axis="0 1 0" damping="0.2"/><geom type="capsule" fromto="0 0 0 0.4 0 0" size="0.04"/>
      <body pos="0.4 0 0"><joint name="b" type="hinge" axis="0 1 0"/><geom type="capsule" fromto="0 0 0 0.4 0 0" size="0.04"/>
        <body pos="0.4 0 0"><joint name="c" type="slide" axis="1 0 0"/><geom size="0.05"/></body></body></body>
  </worldbody>
  <tendon><fixed name="t"><joint joint="a" coef="0.5"/><joint joint="b" coef="-1"/></fixed></tendon>
  <actuator>
    <general joint="a" dyntype="filter" dynprm="0.05" gainprm="3" ctrlrange="-1 1" ctrllimited="true"/>
    <general joint="b" dyntype="integrator" gainprm="2" biastype="affine" biasprm="0 -1 -0.1" actlimited="true" actrange="-0.5 0.5"/>
    <general tendon="t" dyntype="filterexact" dynprm="0.1" gaintype="affine" gainprm="1 0.5 -0.2"/>
    <intvelocity joint="c" kp="5" actrange="-0.2 0.2"/>
    <damper joint="a" kv="0.3" ctrlrange="0 1"/>
    <cylinder joint="b" timeconst="0.02" diameter="0.1" bias="0.1 -0.5 0"/>
    <position joint="c" kp="10" kv="1" timeconst="0.03"/>
  </actuator>
  <keyframe><key name="charged" act="0.1 0.2 0.3 0.1 0.2 0.3"/></keyframe>
</mujoco>"""


def step_beside_mujoco(xml, steps, every, controls, seed):
    """sinew and MuJoCo on `xml`, stepped `steps` times under the same random controls (uniform in
    `controls`, drawn every `every` steps); the Sim, MuJoCo's data and the largest actuator force
    MuJoCo met."""
    mj, m = mujoco.MjModel.from_xml_string(xml), sinew.Model.from_mjcf_string(xml)
    d, sim = mujoco.MjData(mj), sinew.Sim(m)
    assert not m.warnings and len(sim.act) == mj.na
    rng = np.random.default_rng(seed)
    force = 0.0
    for k in range(steps):
        if k % every == 0:
            d.ctrl[:] = sim.ctrl[:] = rng.uniform(*controls, mj.nu)
        mujoco.mj_step(mj, d)
        sim.step()
        force = max(force, np.abs(d.actuator_force).max())
    return sim, d, force


@pytest.mark.parametrize("integrator", ["Euler", "RK4"])
def test_activations_step_as_mujocos(integrator):
    sim, d, _ = step_beside_mujoco(XML.format(integrator=integrator), 400, 1, (-1.0, 1.0), 0)
    assert len(sim.act) == 6
    assert np.abs(d.act).max() > 0.1  # the activations moved
    np.testing.assert_allclose(sim.act, d.act, rtol=0, atol=1e-10)
    np.testing.assert_allclose(sim.qpos, d.qpos, rtol=0, atol=1e-10)
    np.testing.assert_allclose(sim.qvel, d.qvel, rtol=0, atol=1e-10)


def test_act_is_state():
    m = sinew.Model.from_mjcf_string(XML.format(integrator="Euler"))
    sim = sinew.Sim(m)
    sim.reset(key="charged")
    np.testing.assert_array_equal(sim.act, [0.1, 0.2, 0.3, 0.1, 0.2, 0.3])
    sim.ctrl[:] = 0.5
    sim.step(10)
    state, copy = sim.get_state(full=True), pickle.loads(pickle.dumps(sim))
    other = sinew.Sim(m)
    other.set_state(state)
    np.testing.assert_array_equal(other.act, sim.act)
    for s in (sim, other, copy):
        s.step(20)
    np.testing.assert_array_equal(other.get_state(), sim.get_state())
    np.testing.assert_array_equal(copy.get_state(), sim.get_state())
    sim.reset()
    assert not sim.act.any()
    # a batch steps its worlds' activations as a Sim does, and resets them
    b = sinew.Batch(m, 3, num_threads=1)
    b.ctrl[:] = 0.5
    b.set_state([state] * 3)
    b.step(20)
    np.testing.assert_array_equal(b.act[1], other.act)
    b.reset(mask=[True, False, False])
    assert not b.act[0].any() and b.act[1].any()


# muscles on a joint (peak force from scale / acc0, smoothed activation) and on a fixed tendon
# (a given peak force), with their length ranges given, as MuJoCo then uses them unchanged
MUSCLES = """<mujoco><option timestep="0.002" integrator="{integrator}" gravity="0 0 -2"/>
  <default><geom contype="0" conaffinity="0"/></default>
  <worldbody>
    <body><joint name="a" type="hinge" axis="0 1 0" damping="0.05" range="-80 80"/><geom type="capsule" fromto="0 0 0 0.4 0 0" size="0.04"/>
      <body pos="0.4 0 0"><joint name="b" type="hinge" axis="0 1 0" damping="0.05"/><geom type="capsule" fromto="0 0 0 0.4 0 0" size="0.04"/></body></body>
  </worldbody>
  <tendon><fixed name="t"><joint joint="a" coef="0.3"/><joint joint="b" coef="-0.2"/></fixed></tendon>
  <actuator>
    <muscle joint="a" gear="0.8" lengthrange="-0.6 0.6" tausmooth="0.2" ctrlrange="0 1" ctrllimited="true"/>
    <muscle joint="a" gear="-0.8" lengthrange="-0.6 0.6" scale="50"/>
    <muscle tendon="t" lengthrange="-0.4 0.3" force="20" range="0.6 1.2" fpmax="2" vmax="3" timeconst="0.02 0.05"/>
  </actuator>
</mujoco>"""


@pytest.mark.parametrize("integrator", ["Euler", "RK4"])
def test_muscles_step_as_mujocos(integrator):
    sim, d, force = step_beside_mujoco(MUSCLES.format(integrator=integrator), 600, 25, (-0.2, 1.2), 1)
    assert len(sim.act) == 3
    # the muscles pulled, lengthened past their optimum and relaxed
    assert force > 5.0 and np.ptp(d.act) > 0.3
    np.testing.assert_allclose(sim.act, d.act, rtol=0, atol=1e-9)
    np.testing.assert_allclose(sim.qpos, d.qpos, rtol=0, atol=1e-9)
    np.testing.assert_allclose(sim.qvel, d.qvel, rtol=0, atol=1e-8)


def test_a_muscle_without_a_length_range_takes_its_joints_with_a_warning_or_is_an_error():
    base = MUSCLES.format(integrator="Euler")
    m = sinew.Model.from_mjcf_string(base.replace('gear="0.8" lengthrange="-0.6 0.6"', 'gear="0.8"'))
    assert any("lengthrange" in w for w in m.warnings)
    with pytest.raises(ValueError, match="lengthrange"):
        sinew.Model.from_mjcf_string(base.replace('lengthrange="-0.4 0.3"', ''))
    for bad in ['timeconst="0 1"', 'range="1 0.5"', 'lmin="1.2"', 'lengthrange="1 -1"']:
        with pytest.raises(ValueError):
            sinew.Model.from_mjcf_string(base.replace('scale="50"', bad))


def test_a_muscles_gain_and_bias_cannot_be_set_per_world():
    b = sinew.Batch(sinew.Model.from_mjcf_string(MUSCLES.format(integrator="Euler")), 2, num_threads=1)
    with pytest.raises(ValueError, match="muscle"):
        b.set_params("actuator_gain", b.params("actuator_gain")[0] + 1.0)
    b.set_params("actuator_gain", b.params("actuator_gain")[0])  # its own values are fine


def test_rk4_advances_activations_as_mujoco_while_a_joint_rests_on_its_limit():
    # with a limit row every step is constrained (positions by semi-implicit Euler), yet the
    # activations, whose rates read ctrl and act alone, advance by RK4 as MuJoCo's do
    xml = MUSCLES.format(integrator="RK4").replace('range="-80 80"', 'range="-1 1"')
    sim, d, _ = step_beside_mujoco(xml, 600, 25, (-0.2, 1.2), 1)
    assert sim.constraint_stats["solves"] > 300 and np.ptp(d.act) > 0.3
    np.testing.assert_allclose(sim.act, d.act, rtol=0, atol=1e-12)
