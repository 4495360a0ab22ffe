"""Inputs that once crashed or corrupted sinew, made small: each now raises an Exception naming
what is wrong, or is simulated finitely; and every world's full state saves and restores."""

import numpy as np
import pytest

import sinew
from conftest import gym_model_path

BODY = '<body><joint type="slide" limited="false"/><geom size="0.1"/></body>'


def test_deep_nesting_is_a_model_error_not_a_crash():
    deep = "<mujoco><worldbody>" + "<body>" * 10000 + '<geom size="1"/>' + "</body>" * 10000 + "</worldbody></mujoco>"
    with pytest.raises(sinew.ModelError, match="nested more than 200"):
        sinew.Model.from_mjcf_string(deep)
    classes = "".join(f'<default class="c{i}">' for i in range(20000)) + "</default>" * 20000
    with pytest.raises(sinew.ModelError, match="nested more than 200"):
        sinew.Model.from_mjcf_string(f"<mujoco><default>{classes}</default><worldbody/></mujoco>")
    # 200 levels load
    ok = "<mujoco><worldbody>" + "<body><joint/><geom size='0.1'/>" * 200 + "</body>" * 200 + "</worldbody></mujoco>"
    assert sinew.Model.from_mjcf_string(ok).nbody == 201


@pytest.mark.parametrize("find, replace, words", [
    ('friction="1 0.5 0.5"', 'friction="1e308 0.5 0.5"', "friction"),
    ('timestep="0.01"', 'timestep="1e308"', "timestep"),
    ('timestep="0.01"', 'timestep="2"', "timestep"),
])
def test_absurd_numbers_are_model_errors(find, replace, words):
    xml = open(gym_model_path("ant")).read()
    assert find in xml
    with pytest.raises(sinew.ModelError, match=words):
        sinew.Model.from_mjcf_string(xml.replace(find, replace))


def test_large_but_accepted_parameters_simulate_or_diverge_cleanly():
    xml = open(gym_model_path("ant")).read().replace('friction="1 0.5 0.5"', 'friction="1e10 0.5 0.5"')
    m = sinew.Model.from_mjcf_string(xml)
    b = sinew.Batch(m, 2)
    b.step(200)
    assert np.isfinite(b.qpos).all()


def test_a_binary_file_is_a_model_error(tmp_path):
    p = tmp_path / "bin.xml"
    p.write_bytes(b"<mujoco>\n\xff\xfe\x00")
    with pytest.raises(sinew.ModelError, match="line 2.*not UTF-8"):
        sinew.Model.from_mjcf(str(p))


def test_an_empty_mujoco_element_is_an_empty_model():
    # as in MuJoCo: a valid model with only the world body; a Sim of it has nothing to move
    m = sinew.Model.from_mjcf_string("<mujoco/>")
    assert (m.nq, m.nbody) == (0, 1)
    sinew.Sim(m).step(3)
    with pytest.raises(ValueError, match="no joints"):
        sinew.Batch(m, 1)


def split_history(state, short, nu):
    """A full state's flat history (layout of History::to_flat) as named parts."""
    h = list(state[short + 2 * nu:])
    nt = int(h[3])
    at = 4 + 6 * nt
    nw = int(h[at])
    warm = h[at + 1:at + 1 + nw]
    at += 1 + nw
    nr = int(h[at])
    rows = [h[at + 1 + 6 * k:at + 7 + 6 * k] for k in range(nr)]
    return h[:at - nw - 1], warm, rows, h[at + 1 + 6 * nr:]


def join_history(state, short, nu, head, warm, rows, tail):
    return np.array(list(state[:short + 2 * nu]) + head + [len(warm)] + warm + [len(rows)] + sum(rows, []) + tail)


def test_a_history_repeating_a_row_identity_is_refused():
    m = sinew.Model.from_mjcf(gym_model_path("ant"))
    sim = sinew.Sim(m)
    sim.step(200)
    state = sim.get_state(full=True)
    short = 1 + m.nq + m.nv + m.nu
    head, warm, rows, tail = split_history(state, short, m.nu)
    assert len(rows) >= 2, "the ant stands on its feet: rows to warm-start"
    sim.set_state(join_history(state, short, m.nu, head, warm, rows, tail))  # unchanged: accepted
    bad = join_history(state, short, m.nu, head, warm, rows[:-1] + [rows[0]], tail)
    with pytest.raises(ValueError, match="more than once"):
        sim.set_state(bad)
    b = sinew.Batch(m, 1)
    with pytest.raises(ValueError, match="world 0.*more than once"):
        b.set_state(bad, 0)


def test_time_is_in_the_divergence_check():
    m = sinew.Model.from_mjcf_string(f"<mujoco><option timestep='1'/><worldbody>{BODY}</worldbody></mujoco>")
    sim = sinew.Sim(m)
    sim.time = 1e10
    with pytest.raises(sinew.SimulationError, match="time"):
        sim.step(2)
    assert sim.time == 1e10, "restored"
    b = sinew.Batch(m, 2)
    b.time[0] = 1e10
    b.step(2)
    assert b.diverged.tolist() == [True, False] and b.time[0] == 0 and b.time[1] == 2


@pytest.mark.parametrize("name", ["ant", "humanoid"])
def test_a_batch_world_saved_and_restored_replays_bit_exactly(name):
    m = sinew.Model.from_mjcf(gym_model_path(name))
    b = sinew.Batch(m, 3, seed=5)
    rng = np.random.default_rng(0)
    lo, hi = m.actuator_ctrlrange.T
    controls = rng.uniform(lo, hi, size=(400, 3, m.nu))
    for c in controls[:100]:
        b.ctrl[:] = c
        b.step(2)
    saved = b.get_state(1, full=True)
    everything = b.get_state(full=True)
    run = []
    for c in controls[100:]:
        b.ctrl[:] = c
        b.step(2)
        run.append(b.qpos.copy())
    b.set_state(saved, 1)
    b.set_state(everything)
    for c, expect in zip(controls[100:], run):
        b.ctrl[:] = c
        b.step(2)
        assert np.array_equal(b.qpos, expect)
    # a Sim given a batch world's full state steps as that world does
    sim = sinew.Sim(m)
    sim.set_state(b.get_state(2, full=True))
    world = b.get_state(2, full=True)
    sim.step(10)
    b.step(10)
    assert np.array_equal(sim.qpos, b.qpos[2]) and world[0] + 10 * m.timestep == pytest.approx(sim.time)


def test_whole_batch_short_states_and_bad_states():
    m = sinew.Model.from_mjcf(gym_model_path("hopper"))
    b = sinew.Batch(m, 2)
    s = b.get_state()
    assert s.shape == (2, 1 + m.nq + m.nv + m.nu)
    s[1, 2] = 0.3
    b.set_state(s)
    assert b.qpos[1, 1] == 0.3
    before = b.get_state()
    bad = s.copy()
    bad[1, 3] = np.nan
    with pytest.raises(ValueError, match="state of world 1"):
        b.set_state(bad)
    with pytest.raises(ValueError, match="out of range"):
        b.get_state(2)
    with pytest.raises(ValueError, match="one state per world"):
        b.set_state(s[:1])
    assert np.array_equal(b.get_state(), before), "untouched"
