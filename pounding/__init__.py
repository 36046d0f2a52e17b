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
from pounding.structure import ModalDamping, RayleighDamping, ShearBuilding
from pounding.system import Contact, PoundingSystem, assemble

__all__ = [
    "CONTACT_LAWS",
    "AnalysisOptions",
    "Case",
    "CaseError",
    "Contact",
    "ConvergenceError",
    "GroundMotion",
    "ImpactResult",
    "ModalDamping",
    "PoundingSystem",
    "RayleighDamping",
    "ShearBuilding",
    "__version__",
    "assemble",
    "contact_parameters",
    "effective_restitution",
    "get_contact_law",
    "harmonic",
    "load_case",
    "open_result",
    "ricker",
    "save",
    "simulate",
    "sine_pulse",
]
