"""sinew: articulated-character physics after Kokkevis (GDC 2004) on Featherstone's ABA.

Core API (a contract): ``Model.from_mjcf(path)``, ``Model.from_mjcf_string(xml)``, ``Sim(model)``.
"""

from sinew._core import Model, ModelError, ModelWarning, Sim, SimulationError, __version__

__all__ = ["Model", "ModelError", "ModelWarning", "Sim", "SimulationError", "__version__"]
