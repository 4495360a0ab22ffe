"""What dm_control's tasks read from a physics, for many worlds at once.

:class:`Physics` reads a ``sinew.Batch``'s worlds (all of them, or the rows a reset draws) by
MuJoCo's names: joint positions, body, site and geom poses, file sensors, subtree centres of
mass, contact counts; every read gives one row per world. :func:`tolerance` and
:func:`randomize_joints` are dm_control's ``rewards.tolerance`` and
``randomizers.randomize_limited_and_rotational_joints``, written out here with their formulas
(dm_control is not imported at run time).
"""

from __future__ import annotations

import numpy as np


class Names:
    """A model's name tables and the local frames of its sites and geoms, read once."""

    def __init__(self, model):
        self.model = model
        self.body = {n: i for i, n in enumerate(model.body_names)}
        self.joint = {n: i for i, n in enumerate(model.joint_names)}
        self.site = {n: i for i, n in enumerate(model.site_names)}
        self.geom = {n: i for i, n in enumerate(model.geom_names)}
        #: each sensor's index and dimension
        self.sensor = {n: (i, d) for i, (n, d) in enumerate(zip(model.sensor_names, model.sensor_dim))}
        #: the sensors a task reads together (``Task.sensors``)
        self.declared: list[str] = []
        self.site_body, self.site_pos, self.site_size = model.site_body, model.site_pos, model.site_size
        self.site_mat = model.site_mat
        self.geom_body, self.geom_pos, self.geom_size = model.geom_body, model.geom_pos, model.geom_size
        self.geom_mat = model.geom_mat
        self.body_parent, self.body_mass = model.body_parent, model.body_mass
        self.jnt_qposadr, self.jnt_dofadr = model.jnt_qposadr, model.jnt_dofadr
        self.joint_types, self.jnt_limited, self.jnt_range = model.joint_types, model.jnt_limited, model.jnt_range

    def index(self, table: str, name: str) -> int:
        names = getattr(self, table)
        if name not in names:
            raise KeyError(f"the model has no {table} named {name!r}")
        return names[name]

    def subtree(self, body: int) -> list[int]:
        """Body `body` and every body below it."""
        inside = [body]
        for b in range(body + 1, len(self.body_parent)):
            if self.body_parent[b] in inside:
                inside.append(b)
        return inside


class Physics:
    """Named reads of a batch's worlds: every method returns one row per world of ``rows``
    (all worlds when None). Sensor readings and site and geom positions (read-only) are computed
    once per state (``refresh`` forgets them). The task's declared sensors are read by the batch's
    step itself (``Batch.watch_sensors``): after a step, their readings are taken from it."""

    def __init__(self, batch, names: Names, rows=None):
        self.batch, self.names = batch, names
        self.rows = slice(None) if rows is None else np.asarray(rows)
        self._sensors: dict = {}
        self._points: dict = {}
        # whether the batch's watched readings are of the rows' current state
        self._stepped = False

    def refresh(self) -> None:
        """Forgets readings of an earlier state."""
        self._sensors = {}
        self._points = {}
        self._stepped = False

    def stepped(self) -> None:
        """Forgets readings of an earlier state: the rows' worlds were just stepped (or left
        alone by a step) by ``Batch.step``, whose watched readings are of their state."""
        self.refresh()
        self._stepped = True

    def _mask(self) -> np.ndarray:
        mask = np.zeros(self.batch.num_envs, dtype=bool)
        mask[self.rows] = True
        return mask

    def set_state(self, qpos: np.ndarray, qvel: np.ndarray | None = None, act: np.ndarray | None = None) -> None:
        """Writes the worlds' qpos (and qvel, act) and recomputes what they determine."""
        self.batch.qpos[self.rows] = qpos
        if qvel is not None:
            self.batch.qvel[self.rows] = qvel
        if act is not None:
            self.batch.act[self.rows] = act
        self.batch.forward_kinematics(self._mask())
        self.refresh()

    def set_params(self, field: str, values) -> None:
        """Gives the worlds values of their own of a model field (``Batch.set_params``; one row per
        world, in world order), as a task that edits ``physics.model`` at each episode does."""
        self.batch.set_params(field, values, self._mask())
        self.refresh()

    def step(self, n: int) -> None:
        """Advances the worlds `n` physics steps with their current controls."""
        self.batch.step(n, self._mask())
        self.stepped()

    def penetrations(self) -> np.ndarray:
        """How many contacts penetrate in each world (n,): MuJoCo's ``ncon`` at a reset."""
        return self.batch.penetrations()[self.rows]

    # state, as dm_control's physics.position(), velocity(), control()
    def position(self) -> np.ndarray:
        return self.batch.qpos[self.rows]

    def velocity(self) -> np.ndarray:
        return self.batch.qvel[self.rows]

    def control(self) -> np.ndarray:
        return self.batch.ctrl[self.rows]

    def activation(self) -> np.ndarray:
        return self.batch.act[self.rows]

    def joint_qpos(self, joint: str) -> np.ndarray:
        """A one-dof joint's position (n,)."""
        return self.batch.qpos[self.rows, self.names.jnt_qposadr[self.names.index("joint", joint)]]

    # poses
    def xpos(self, body: str) -> np.ndarray:
        return self.batch.xpos[self.rows, self.names.index("body", body)]

    def xmat(self, body: str) -> np.ndarray:
        """The body's rotation (n, 3, 3)."""
        return self.batch.xmat[self.rows, self.names.index("body", body)].reshape(-1, 3, 3)

    def xipos(self, body: str) -> np.ndarray:
        return self.batch.xipos[self.rows, self.names.index("body", body)]

    def site_xpos(self, site: str) -> np.ndarray:
        """The site's position (n, 3), where each world placed it (``set_site_pos``)."""
        return self._placed("site", site)

    def geom_xpos(self, geom: str) -> np.ndarray:
        """The geom's centre (n, 3), where each world placed it (``set_geom_pos``)."""
        return self._placed("geom", geom)

    def _placed(self, kind: str, name: str) -> np.ndarray:
        """A site's or geom's world position, once per state."""
        if (kind, name) not in self._points:
            i = self.names.index(kind, name)
            body = (self.names.site_body if kind == "site" else self.names.geom_body)[i]
            local = (self.batch.site_pos if kind == "site" else self.batch.geom_pos)(i)[self.rows]
            x = self._point(body, local)
            x.flags.writeable = False
            self._points[kind, name] = x
        return self._points[kind, name]

    def site_xmat(self, site: str) -> np.ndarray:
        """The site's rotation (n, 3, 3)."""
        s = self.names.index("site", site)
        return self.batch.xmat[self.rows, self.names.site_body[s]].reshape(-1, 3, 3) @ self.names.site_mat[s]

    def site_velocity(self, site: str) -> np.ndarray:
        """The site's world linear velocity (n, 3)."""
        return self._velocity(self.names.site_body[self.names.index("site", site)], self.site_xpos(site))

    def geom_velocity(self, geom: str) -> np.ndarray:
        """The geom centre's world linear velocity (n, 3)."""
        return self._velocity(self.names.geom_body[self.names.index("geom", geom)], self.geom_xpos(geom))

    def _velocity(self, body: int, at: np.ndarray) -> np.ndarray:
        """World velocity of points `at` (n, 3) moving with `body`."""
        xvel = self.batch.xvel[self.rows, body]
        return xvel[:, 3:] + np.cross(xvel[:, :3], at - self.batch.xpos[self.rows, body])

    def geom_xmat(self, geom: str) -> np.ndarray:
        """The geom's rotation (n, 3, 3)."""
        g = self.names.index("geom", geom)
        return self.batch.xmat[self.rows, self.names.geom_body[g]].reshape(-1, 3, 3) @ self.names.geom_mat[g]

    def set_geom_pos(self, geom: str, pos: np.ndarray) -> None:
        """Places a geom without contacts (a target) in each world: (n, 3) in its body's frame."""
        self.batch.set_geom_pos(self.names.index("geom", geom), pos, self._mask())
        self.refresh()

    def set_site_pos(self, site: str, pos: np.ndarray) -> None:
        """Places a site in each world: (n, 3) in its body's frame."""
        self.batch.set_site_pos(self.names.index("site", site), pos, self._mask())
        self.refresh()

    def _point(self, body: int, local: np.ndarray) -> np.ndarray:
        """The world position of `local` (3,) or one per world (n, 3), points in `body`'s frame,
        as MuJoCo computes it."""
        xmat = self.batch.xmat[self.rows, body].reshape(-1, 3, 3)
        return self.batch.xpos[self.rows, body] + np.einsum("nij,nj->ni", xmat, np.broadcast_to(local, (len(xmat), 3)))

    def subtree_com(self, body: str) -> np.ndarray:
        """Centre of mass of the body's subtree (MuJoCo's ``subtree_com``) (n, 3)."""
        inside = self.names.subtree(self.names.index("body", body))
        mass = self.names.body_mass[inside]
        return np.einsum("b,nbk->nk", mass, self.batch.xipos[self.rows][:, inside]) / mass.sum()

    def sensor(self, name: str) -> np.ndarray:
        """A file sensor's reading (n, dim), once per state; the sensors the task declares
        (``Task.sensors``) are read together, only they."""
        if name not in self._sensors:
            self.names.index("sensor", name)
            declared = name in self.names.declared
            wanted = self.names.declared if declared else [name]
            if declared and self._stepped:
                values = np.array(self.batch.watched_readings[self.rows])
            else:
                values = self.batch.read_sensors([self.names.sensor[n][0] for n in wanted])[self.rows]
            at = 0
            for n in wanted:
                dim = self.names.sensor[n][1]
                self._sensors[n], at = values[:, at:at + dim], at + dim
        return self._sensors[name]

    # model quantities
    def site_size(self, site: str) -> np.ndarray:
        return self.names.site_size[self.names.index("site", site)]

    def geom_size(self, geom: str) -> np.ndarray:
        return self.names.geom_size[self.names.index("geom", geom)]


def in_frame(x: np.ndarray, rot: np.ndarray) -> np.ndarray:
    """Vectors `x` (n, 3), world axes, in the frames `rot` (n, 3, 3): each row of x times its R."""
    return np.einsum("nk,nkj->nj", x, rot)


def _sigmoid(x, value_at_1: float, sigmoid: str):
    """dm_control's ``rewards._sigmoids``: 1 at x = 0, ``value_at_1`` at |x| = 1."""
    if sigmoid == "gaussian":
        return np.exp(-0.5 * (x * np.sqrt(-2 * np.log(value_at_1))) ** 2)
    if sigmoid == "hyperbolic":
        return 1 / np.cosh(x * np.arccosh(1 / value_at_1))
    if sigmoid == "long_tail":
        return 1 / ((x * np.sqrt(1 / value_at_1 - 1)) ** 2 + 1)
    if sigmoid == "reciprocal":
        return 1 / (abs(x) * (1 / value_at_1 - 1) + 1)
    if sigmoid == "cosine":
        s = x * np.arccos(2 * value_at_1 - 1) / np.pi
        with np.errstate(invalid="ignore"):
            return np.where(abs(s) < 1, (1 + np.cos(np.pi * s)) / 2, 0.0)
    if sigmoid == "linear":
        s = x * (1 - value_at_1)
        return np.where(abs(s) < 1, 1 - s, 0.0)
    if sigmoid == "quadratic":
        s = x * np.sqrt(1 - value_at_1)
        return np.where(abs(s) < 1, 1 - s**2, 0.0)
    if sigmoid == "tanh_squared":
        return 1 - np.tanh(x * np.arctanh(np.sqrt(1 - value_at_1))) ** 2
    raise ValueError(f"unknown sigmoid {sigmoid!r}")


def tolerance(x, bounds=(0.0, 0.0), margin=0.0, sigmoid="gaussian", value_at_margin=0.1):
    """dm_control's ``rewards.tolerance``: 1 where ``x`` lies within ``bounds``, falling off
    outside them to ``value_at_margin`` at distance ``margin`` (0 outside when ``margin`` is 0)."""
    lower, upper = bounds
    x = np.asarray(x, dtype=np.float64)
    inside = (lower <= x) & (x <= upper)
    if margin == 0:
        return np.where(inside, 1.0, 0.0)
    d = np.where(x < lower, lower - x, x - upper) / margin
    return np.where(inside, 1.0, _sigmoid(d, value_at_margin, sigmoid))


def random_limited_quaternion(rng, limit: float) -> np.ndarray:
    """A rotation about a uniformly random axis by an angle uniform in [0, limit)
    (dm_control's ``randomizers.random_limited_quaternion``)."""
    axis = rng.standard_normal(3)
    axis /= np.linalg.norm(axis)
    angle = rng.random() * limit
    return np.concatenate([[np.cos(angle / 2)], np.sin(angle / 2) * axis])


def randomize_joints(names: Names, qpos: np.ndarray, rng) -> None:
    """dm_control's ``randomize_limited_and_rotational_joints`` on one world's ``qpos``: limited
    hinges and slides uniform in their range, free hinges in [−π, π], ball joints uniform on the
    sphere (or within their limit), a free joint's quaternion from four U(0, 1) normalised (as
    dm_control draws it); the free joint's position is kept."""
    for j, kind in enumerate(names.joint_types):
        a = names.jnt_qposadr[j]
        lo, hi = names.jnt_range[j]
        if names.jnt_limited[j]:
            if kind in ("hinge", "slide"):
                qpos[a] = rng.uniform(lo, hi)
            elif kind == "ball":
                qpos[a:a + 4] = random_limited_quaternion(rng, hi)
        elif kind == "hinge":
            qpos[a] = rng.uniform(-np.pi, np.pi)
        elif kind == "ball":
            q = rng.standard_normal(4)
            qpos[a:a + 4] = q / np.linalg.norm(q)
        elif kind == "free":
            q = rng.random(4)
            qpos[a + 3:a + 7] = q / np.linalg.norm(q)
