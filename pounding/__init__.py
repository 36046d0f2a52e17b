"""pounding: seismic pounding analysis of adjacent buildings.

The public API; everything else lives in its module.
"""

from __future__ import annotations

from pounding._version import __version__
from pounding.case import Case, CaseError, load_case
from pounding.contact.calibrate import ImpactResult, contact_parameters, effective_restitution
from pounding.contact.laws import CONTACT_LAWS, get_contact_law
from pounding.ground_motion import GroundMotion, harmonic, ricker, sine_pulse
from pounding.integrators.base import ConvergenceError
from pounding.results import open_result, save
from pounding.simulate import AnalysisOptions, simulate
from pounding.structure import IsolationBase, ModalDamping, RayleighDamping, ShearBuilding
from pounding.studies import Study, StudyError, load_study, run_study
from pounding.system import Contact, PoundingSystem, assemble

# Heavier layers (scipy.stats, matplotlib) load on first use, so `import pounding` stays quick.
_LAZY = {
    "separation_analysis": "pounding.separation",
    "load_separation_case": "pounding.separation",
    "write_report": "pounding.report",
}


def __getattr__(name: str):
    if name in _LAZY:
        import importlib

        return getattr(importlib.import_module(_LAZY[name]), name)
    raise AttributeError(f"module 'pounding' has no attribute {name!r}")


__all__ = [
    "CONTACT_LAWS",
    "AnalysisOptions",
    "Case",
    "CaseError",
    "Contact",
    "ConvergenceError",
    "GroundMotion",
    "ImpactResult",
    "IsolationBase",
    "ModalDamping",
    "PoundingSystem",
    "RayleighDamping",
    "ShearBuilding",
    "Study",
    "StudyError",
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
    "write_report",
]
