"""The Franka Emika Panda's forward kinematics and analytic inverse kinematics (He and Liu's
solution, as Playground's ``panda_kinematics.py`` adapts it from
github.com/ffall007/franka_analytical_ik), vectorized over worlds: a row per world."""

from __future__ import annotations

import numpy as np

#: Distances of the arm's Denavit–Hartenberg frames (m): the hand's tip (``d7e``) included.
D1, D3, D5, D7E, A4, A7 = 0.3330, 0.3160, 0.3840, 0.2104, 0.0825, 0.0880
LL24, LL46, L24, L46 = 0.10666225, 0.15426225, 0.326591870689, 0.392762332715
THETA_H46, THETA_342, THETA_46H = 1.35916951803, 1.31542071191, 0.211626808766
Q_MIN = np.array([-2.8973, -1.7628, -2.8973, -3.0718, -2.8973, -0.0175, -2.8973])
Q_MAX = np.array([2.8973, 1.7628, 2.8973, -0.0698, 2.8973, 3.7525, 2.8973])


def dh(theta, alpha: float, a: float, d: float) -> np.ndarray:
    """The transforms (k, 4, 4) of revolute joints at angles ``theta`` (k) with the Denavit–Hartenberg
    parameters (modified convention) alpha, a, d."""
    theta = np.asarray(theta, dtype=np.float64)
    ca, sa, ct, st = np.cos(alpha), np.sin(alpha), np.cos(theta), np.sin(theta)
    m = np.zeros(theta.shape + (4, 4))
    m[..., 0, :] = np.stack([ct, -st, np.zeros_like(ct), np.full_like(ct, a)], axis=-1)
    m[..., 1, :] = np.stack([st * ca, ct * ca, np.full_like(ct, -sa), np.full_like(ct, -d * sa)], axis=-1)
    m[..., 2, :] = np.stack([st * sa, ct * sa, np.full_like(ct, ca), np.full_like(ct, d * ca)], axis=-1)
    m[..., 3, 3] = 1.0
    return m


def forward(q: np.ndarray) -> np.ndarray:
    """The hand's tip pose (k, 4, 4) in the arm's base frame at joint angles ``q`` (k, 7)."""
    q = np.atleast_2d(q)
    frames = [(q[:, 0], 0.0, 0.0, D1), (q[:, 1], -np.pi / 2, 0.0, 0.0), (q[:, 2], np.pi / 2, 0.0, D3),
              (q[:, 3], np.pi / 2, A4, 0.0), (q[:, 4], -np.pi / 2, -A4, D5), (q[:, 5], np.pi / 2, 0.0, 0.0),
              (q[:, 6], np.pi / 2, A7, 0.0), (np.full(len(q), -np.pi / 4), 0.0, 0.0, D7E)]
    t = np.tile(np.eye(4), (len(q), 1, 1))
    for theta, alpha, a, d in frames:
        t = t @ dh(theta, alpha, a, d)
    return t


def _rows(*entries) -> np.ndarray:
    """Matrices (k, 3, 3) from nine entries, each a scalar or (k,)."""
    k = max(np.size(e) for e in entries)
    return np.stack([np.broadcast_to(np.asarray(e, dtype=np.float64), (k,)) for e in entries], axis=-1).reshape(k, 3, 3)


def inverse(t_ee: np.ndarray, q7: np.ndarray, q_actual: np.ndarray) -> np.ndarray:
    """Joint angles (k, 7) that put the hand's tip at the poses ``t_ee`` (k, 4, 4) with joint 7 at
    ``q7`` (k), on the solution branch of the arm's current angles ``q_actual`` (k, 7); NaN where
    the pose is out of reach."""
    k = len(t_ee)
    q = np.zeros((k, 7))
    q[:, 6] = q7
    c, s = np.cos(q_actual), np.sin(q_actual)
    zero, one = np.zeros(k), np.ones(k)
    # the current arm's frames 1–6 (As_a, Ts_a), for its q6 branch
    a_s = [
        _rows(c[:, 0], -s[:, 0], zero, s[:, 0], c[:, 0], zero, zero, zero, one),
        _rows(c[:, 1], -s[:, 1], zero, zero, zero, one, -s[:, 1], -c[:, 1], zero),
        _rows(c[:, 2], -s[:, 2], zero, zero, zero, -one, s[:, 2], c[:, 2], zero),
        _rows(c[:, 3], -s[:, 3], zero, zero, zero, -one, s[:, 3], c[:, 3], zero),
        _rows(one, zero, zero, zero, one, zero, zero, zero, one),
        _rows(c[:, 4], -s[:, 4], zero, zero, zero, one, -s[:, 4], -c[:, 4], zero),
        _rows(c[:, 5], -s[:, 5], zero, zero, zero, -one, s[:, 5], c[:, 5], zero),
    ]
    offsets = [(0, 0, D1), (0, 0, 0), (0, -D3, 0), (A4, 0, 0), (-A4, 0, 0), (0, D5, 0), (0, 0, 0)]
    rot, pos, frames = np.tile(np.eye(3), (k, 1, 1)), np.zeros((k, 3)), []
    for r, p in zip(a_s, offsets):
        pos = pos + rot @ np.array(p, dtype=np.float64)
        rot = rot @ r
        frames.append((rot, pos))
    v62 = frames[1][1] - frames[6][1]
    v6h = frames[4][1] - frames[6][1]
    case6_0 = np.sum(np.cross(v6h, v62) * frames[6][0][:, :, 2], axis=1) <= 0
    case1_1 = q_actual[:, 1] < 0
    r_ee, z_ee, p_ee = t_ee[:, :3, :3], t_ee[:, :3, 2], t_ee[:, :3, 3]
    p_7 = p_ee - D7E * z_ee
    x_ee_6 = np.stack([np.cos(q7 - np.pi / 4), -np.sin(q7 - np.pi / 4), zero], axis=1)
    x_6 = np.einsum("kij,kj->ki", r_ee, x_ee_6)
    x_6 /= np.linalg.norm(x_6, axis=1, keepdims=True)
    p_6 = p_7 - A7 * x_6
    p_2 = np.array([0.0, 0.0, D1])
    v26 = p_6 - p_2
    ll26 = np.sum(v26 * v26, axis=1)
    l26 = np.sqrt(ll26)
    with np.errstate(invalid="ignore", divide="ignore"):
        theta246 = np.arccos((LL24 + LL46 - ll26) / 2.0 / L24 / L46)
        q[:, 3] = theta246 + THETA_H46 + THETA_342 - 2.0 * np.pi
        theta462 = np.arccos((ll26 + LL46 - LL24) / 2.0 / l26 / L46)
        theta26h = THETA_46H + theta462
        d26 = -l26 * np.cos(theta26h)
        z6 = np.cross(z_ee, x_6)
        y6 = np.cross(z6, x_6)
        r_6 = np.stack([x_6, y6 / np.linalg.norm(y6, axis=1, keepdims=True), z6 / np.linalg.norm(z6, axis=1, keepdims=True)], axis=2)
        v_6_62 = np.einsum("kji,kj->ki", r_6, -v26)
        phi6 = np.arctan2(v_6_62[:, 1], v_6_62[:, 0])
        theta6 = np.arcsin(d26 / np.sqrt(v_6_62[:, 0] ** 2 + v_6_62[:, 1] ** 2))
        q[:, 5] = np.where(case6_0, np.pi - theta6 - phi6, theta6 - phi6)
        q[:, 5] = np.where(q[:, 5] <= Q_MIN[5], q[:, 5] + 2.0 * np.pi, q[:, 5])
        q[:, 5] = np.where(q[:, 5] >= Q_MAX[5], q[:, 5] - 2.0 * np.pi, q[:, 5])
        # q1 and q2
        theta_p26 = 3.0 * np.pi / 2 - theta462 - theta246 - THETA_342
        theta_p = np.pi - theta_p26 - theta26h
        lp6 = l26 * np.sin(theta_p26) / np.sin(theta_p)
        z_5 = np.einsum("kij,kj->ki", r_6, np.stack([np.sin(q[:, 5]), np.cos(q[:, 5]), zero], axis=1))
        v2p = p_6 - lp6[:, None] * z_5 - p_2
        l2p = np.linalg.norm(v2p, axis=1)
        straight = np.abs(v2p[:, 2] / l2p) > 0.999
        q[:, 0] = np.where(straight, q_actual[:, 0], np.arctan2(v2p[:, 1], v2p[:, 0]))
        q[:, 1] = np.where(straight, 0.0, np.arccos(v2p[:, 2] / l2p))
        q[:, 0] = np.where(case1_1, np.where(q[:, 0] < 0.0, q[:, 0] + np.pi, q[:, 0] - np.pi), q[:, 0])
        q[:, 1] = np.where(straight, q[:, 1], np.where(case1_1, -q[:, 1], q[:, 1]))
        # q3
        z_3 = v2p / l2p[:, None]
        y_3 = -np.cross(v26, v2p)
        y_3 /= np.linalg.norm(y_3, axis=1, keepdims=True)
        x_3 = np.cross(y_3, z_3)
        c1, s1, c2, s2 = np.cos(q[:, 0]), np.sin(q[:, 0]), np.cos(q[:, 1]), np.sin(q[:, 1])
        r_2 = _rows(c1, -s1, zero, s1, c1, zero, zero, zero, one) @ _rows(c2, -s2, zero, zero, zero, one, -s2, -c2, zero)
        x_2_3 = np.einsum("kji,kj->ki", r_2, x_3)
        q[:, 2] = np.arctan2(x_2_3[:, 2], x_2_3[:, 0])
        # q5
        vh4 = p_2 + D3 * z_3 + A4 * x_3 - p_6 + D5 * z_5
        c6, s6 = np.cos(q[:, 5]), np.sin(q[:, 5])
        r_5 = r_6 @ np.transpose(_rows(c6, -s6, zero, zero, zero, -one, s6, c6, zero), (0, 2, 1))
        v_5_h4 = np.einsum("kji,kj->ki", r_5, vh4)
        q[:, 4] = -np.arctan2(v_5_h4[:, 1], v_5_h4[:, 0])
    return q
