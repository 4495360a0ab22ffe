"""sinew: articulated-character physics after Kokkevis (GDC 2004) on Featherstone's ABA.

Core API (a contract): ``Model.from_mjcf(path)``, ``Model.from_mjcf_string(xml)``, ``Sim(model)``.
"""

from sinew._core import Batch, Model, ModelError, ModelWarning, Sim, SimulationError, __version__, urdf_to_mjcf
from sinew.randomize import RandomizeParams, VectorRandomizeParams
from sinew.registration import register_envs

__all__ = ["Batch", "Model", "ModelError", "ModelWarning", "RandomizeParams", "Sim", "SimulationError", "VectorRandomizeParams",
           "__version__", "urdf_to_mjcf"]

register_envs()
