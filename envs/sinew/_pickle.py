"""Rebuilding pickled ``Model``, ``Sim`` and ``Batch`` objects (their ``__reduce__`` names these)."""

from sinew._core import Batch, Model, Sim


def model(xml: str, options: dict, path=None, hfields=None) -> Model:
    """The model compiled from ``xml`` (read as the file ``path``) with ``options``
    (``Model.with_options`` keywords) and its height fields' elevations."""
    m = Model.from_mjcf_string(xml, path).with_options(**options)
    for name, data in (hfields or {}).items():
        m = m.with_hfield_data(name, data)
    return m


def sim(m: Model, state) -> Sim:
    """A Sim of ``m`` in the full ``state``."""
    s = Sim(m)
    s.set_state(state)
    return s


def batch(m: Model, num_envs: int, num_threads: int, task, states, outputs: dict, moved=(), params=(), watched=((), None)) -> Batch:
    """A batch of ``m`` with ``task`` (kind, parameters) set, the worlds' own model values
    (``params``), every world in its full state, the output arrays as the last step left them,
    the geoms and sites placed per world ("geom" or "site", index, positions) and the watched
    sensors with their readings."""
    b = Batch(m, num_envs, num_threads=num_threads)
    b._restore_params(list(params))
    if task is not None:
        b.set_task(task[0], **task[1])
    b.set_state(states)
    for name, values in outputs.items():
        getattr(b, name)[...] = values
    for kind, i, pos in moved:
        getattr(b, f"set_{kind}_pos")(i, pos)
    sensors, readings = watched
    if len(sensors):
        b.watch_sensors(list(sensors))
        b.watched_readings[...] = readings
    return b
