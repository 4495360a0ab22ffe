"""`<frame>`s read as MuJoCo reads them: nested frames, rotated and with a childclass, posing
bodies, joints, geoms (fromto ones too), sites and inertials; body poses, masses, sites and the
constraint-free acceleration equal MuJoCo's."""

import mujoco
import numpy as np

import sinew
from twins import forward_both

XML = """<mujoco><default><default class="thin"><geom size="0.02"/></default></default>
  <worldbody>
    <frame pos="0.1 0 0.2" euler="0 20 0">
      <geom type="box" size="0.1 0.2 0.05" pos="0 0 -0.3"/>
      <body name="a" pos="0 0 1">
        <frame pos="0.2 0.1 0" axisangle="0 0 1 30" childclass="thin">
          <joint name="h" type="hinge" axis="0 1 0" pos="0.05 0 0"/>
          <geom type="capsule" fromto="0 0 0 0.4 0 0"/>
          <site name="s" pos="0.4 0 0"/>
          <frame quat="0.9 0.1 0.3 0.2">
            <body name="b" pos="0.4 0 0"><joint type="slide" axis="1 0 0"/><geom type="box" size="0.05 0.1 0.02"/></body>
          </frame>
        </frame>
        <geom type="sphere" size="0.05"/>
      </body>
    </frame>
  </worldbody>
  <sensor><framepos objtype="site" objname="s"/></sensor>
</mujoco>"""


def test_frames_pose_their_children_as_mujocos():
    m, mj = sinew.Model.from_mjcf_string(XML), mujoco.MjModel.from_xml_string(XML)
    np.testing.assert_allclose(m.body_mass, mj.body_mass, rtol=1e-12)
    mj.opt.disableflags |= mujoco.mjtDisableBit.mjDSBL_CONSTRAINT
    d, sim = mujoco.MjData(mj), sinew.Sim(m)
    rng = np.random.default_rng(0)
    for _ in range(5):
        q, v = rng.normal(0.0, 0.5, mj.nq), rng.normal(0.0, 1.0, mj.nv)
        forward_both(mj, d, sim, q, v)
        np.testing.assert_allclose(sim.xpos, d.xpos, atol=1e-12)
        np.testing.assert_allclose(sim.xmat.reshape(-1, 9), d.xmat, atol=1e-12)
        np.testing.assert_allclose(sim.sensordata, d.sensordata, atol=1e-12)
        np.testing.assert_allclose(sim.qacc, d.qacc, rtol=1e-10, atol=1e-10)
