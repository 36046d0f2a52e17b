"""pounding: seismic pounding analysis of adjacent buildings.

The public API; everything else lives in its module.
"""

from __future__ import annotations

import importlib
import sys
import types
from typing import TYPE_CHECKING

from pounding._version import __version__

# Every public name loads its module on first use (PEP 562), so `import pounding` and `pounding --help`
# do not pay for numba, xarray or scipy; `from pounding import simulate` works as before.
_LAZY = {
    "Case": "pounding.case",
    "CaseError": "pounding.case",
    "load_case": "pounding.case",
    "ImpactResult": "pounding.contact.calibrate",
    "contact_parameters": "pounding.contact.calibrate",
    "effective_restitution": "pounding.contact.calibrate",
    "CONTACT_LAWS": "pounding.contact.laws",
    "get_contact_law": "pounding.contact.laws",
    "GroundMotion": "pounding.ground_motion",
    "harmonic": "pounding.ground_motion",
    "ricker": "pounding.ground_motion",
    "sine_pulse": "pounding.ground_motion",
    "ConvergenceError": "pounding.errors",
    "PoundingError": "pounding.errors",
    "PoundingInputError": "pounding.errors",
    "IntegrationError": "pounding.errors",
    "ResultWriteError": "pounding.errors",
    "open_result": "pounding.results",
    "save": "pounding.results",
    "AnalysisOptions": "pounding.simulate",
    "simulate": "pounding.simulate",
    "IsolationBase": "pounding.structure",
    "ModalDamping": "pounding.structure",
    "RayleighDamping": "pounding.structure",
    "ShearBuilding": "pounding.structure",
    "Study": "pounding.studies",
    "StudyError": "pounding.studies",
    "StudyInterrupted": "pounding.studies",
    "stop_on_signals": "pounding.studies",
    "load_study": "pounding.studies",
    "run_study": "pounding.studies",
    "Contact": "pounding.system",
    "Link": "pounding.system",
    "LINK_LAWS": "pounding.links",
    "SoilFoundation": "pounding.soil",
    "Stories": "pounding.stories",
    "STORY_MODELS": "pounding.stories",
    "PoundingSystem": "pounding.system",
    "assemble": "pounding.system",
    "separation_analysis": "pounding.separation",
    "load_separation_case": "pounding.separation",
    "write_report": "pounding.report",
}

if TYPE_CHECKING:  # for type checkers and IDEs (not report and separation: import layers)
    from pounding.case import Case, CaseError, load_case
    from pounding.contact.calibrate import ImpactResult, contact_parameters, effective_restitution
    from pounding.contact.laws import CONTACT_LAWS, get_contact_law
    from pounding.errors import (
        ConvergenceError,
        IntegrationError,
        PoundingError,
        PoundingInputError,
        ResultWriteError,
    )
    from pounding.ground_motion import GroundMotion, harmonic, ricker, sine_pulse
    from pounding.links import LINK_LAWS
    from pounding.results import open_result, save
    from pounding.simulate import AnalysisOptions, simulate
    from pounding.soil import SoilFoundation
    from pounding.stories import STORY_MODELS, Stories
    from pounding.structure import IsolationBase, ModalDamping, RayleighDamping, ShearBuilding
    from pounding.studies import (
        Study,
        StudyError,
        StudyInterrupted,
        load_study,
        run_study,
        stop_on_signals,
    )
    from pounding.system import Contact, Link, PoundingSystem, assemble


def __getattr__(name: str):
    module = _LAZY.get(name)
    if module is None:
        raise AttributeError(f"module 'pounding' has no attribute {name!r}")
    value = getattr(importlib.import_module(module), name)
    globals()[name] = value  # later look-ups skip __getattr__
    return value


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(__all__))


class _Package(types.ModuleType):
    """The package module: keeps ``pounding.simulate`` the function once its submodule is imported.

    Importing a submodule sets it as an attribute of the package, which would hide the function
    ``simulate`` behind the module ``pounding.simulate`` (the eager imports used to rebind it)."""

    def __setattr__(self, name: str, value: object) -> None:
        if name == "simulate" and isinstance(value, types.ModuleType):
            value = value.simulate
        super().__setattr__(name, value)


sys.modules[__name__].__class__ = _Package


__all__ = [
    "CONTACT_LAWS",
    "AnalysisOptions",
    "Case",
    "CaseError",
    "Contact",
    "ConvergenceError",
    "LINK_LAWS",
    "Link",
    "STORY_MODELS",
    "SoilFoundation",
    "Stories",
    "IntegrationError",
    "PoundingError",
    "PoundingInputError",
    "ResultWriteError",
    "GroundMotion",
    "ImpactResult",
    "IsolationBase",
    "ModalDamping",
    "PoundingSystem",
    "RayleighDamping",
    "ShearBuilding",
    "Study",
    "StudyError",
    "StudyInterrupted",
    "__version__",
    "assemble",
    "contact_parameters",
    "effective_restitution",
    "get_contact_law",
    "harmonic",
    "load_case",
    "load_separation_case",
    "load_study",
    "open_result",
    "ricker",
    "run_study",
    "save",
    "separation_analysis",
    "simulate",
    "sine_pulse",
    "stop_on_signals",
    "write_report",
]
