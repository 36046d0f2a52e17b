"""Shear buildings: mass, stiffness and damping matrices and modal properties.

A shear building is a stack of lumped floor masses joined by story springs; each floor has one
horizontal degree of freedom, its displacement relative to the ground [m]. Floors and stories are
numbered from the ground up: story ``i`` joins floor ``i - 1`` (the ground for ``i = 0``) to floor
``i``.

Damping is classical (the undamped mode shapes diagonalise it), either Rayleigh damping anchored on
two modes or modal damping with one ratio per mode.

A building may stand on a base slab carried by sliding isolation bearings (:class:`IsolationBase`):
flat sliders or friction pendulum bearings, with a friction law of :mod:`pounding.friction`. The
building's own matrices (:meth:`ShearBuilding.mass_matrix` ...) and modes stay those of the
superstructure on a fixed base; :mod:`pounding.system` adds the base degree of freedom.

References
----------
.. [1] Chopra, A. K. (2017). *Dynamics of Structures: Theory and Applications to Earthquake
   Engineering*, 5th ed. Pearson. Ch. 9-10 (shear buildings, modal analysis), Sec. 11.4
   (classical damping matrices), Sec. 13.2 (modal participation, effective modal mass).
.. [2] Zayas, V. A., Low, S. S., Mahin, S. A. (1990). A simple pendulum technique for achieving
   seismic isolation. Earthquake Spectra 6(2), 317-333. doi:10.1193/1.1585573
.. [3] Constantinou, M., Mokha, A., Reinhorn, A. (1990). Teflon bearings in base isolation II:
   Modeling. J. Struct. Eng. 116(2), 455-474. doi:10.1061/(ASCE)0733-9445(1990)116:2(455)
"""

from __future__ import annotations

import dataclasses
import functools
import math
import operator

import numpy as np

from pounding import friction as _friction
from pounding.errors import PoundingInputError
from pounding.soil import SoilFoundation
from pounding.stories import Stories
from pounding.units import G
from pounding.validation import finite_number

DEFAULT_STORY_HEIGHT = 3.0
"""Story height [m] used when a building gives none."""


def _check_ratio(value: float, field: str, where: str) -> float:
    try:
        ratio = float(value)
    except (TypeError, ValueError):
        raise PoundingInputError(
            f"{where}: {field} = {value!r}; must be a number in [0, 1)"
        ) from None
    if not (0.0 <= ratio < 1.0):
        raise PoundingInputError(f"{where}: {field} = {ratio:g}; damping ratios must be in [0, 1)")
    return ratio


@dataclasses.dataclass(frozen=True)
class RayleighDamping:
    """Rayleigh damping C = a0 M + a1 K with the same ratio on two anchor modes.

    Parameters
    ----------
    ratio : float
        Critical damping ratio ξ [-] at both anchor modes, in [0, 1). Typical 0.02-0.05.
    modes : tuple of int
        The two anchor modes (1-based, distinct). A building with fewer modes than the highest
        anchor (e.g. one story with the default ``(1, 2)``) gets modal damping with ``ratio`` on
        every mode instead; for one story that is c = 2 ξ √(k m).
    """

    ratio: float = 0.05
    modes: tuple[int, int] = (1, 2)

    def __post_init__(self) -> None:
        where = "RayleighDamping"
        object.__setattr__(self, "ratio", _check_ratio(self.ratio, "ratio", where))
        try:
            modes = tuple(operator.index(m) for m in self.modes)
        except TypeError:
            modes = ()
        if len(modes) != 2 or min(modes) < 1 or modes[0] == modes[1]:
            raise PoundingInputError(
                f"{where}: modes = {self.modes!r}; modes must be two distinct positive "
                "integers (1-based mode numbers), e.g. (1, 2)"
            )
        object.__setattr__(self, "modes", modes)


@dataclasses.dataclass(frozen=True)
class ModalDamping:
    """Classical modal damping with a given ratio per mode.

    Parameters
    ----------
    ratios : tuple of float
        Critical damping ratio ξ_j [-] of each mode, mode 1 first, each in [0, 1). A single value
        applies to every mode; otherwise there must be one per floor of the building.
    """

    ratios: tuple[float, ...] = (0.05,)

    def __post_init__(self) -> None:
        ratios = np.atleast_1d(np.asarray(self.ratios, dtype=object)).ravel()
        if ratios.size == 0:
            raise PoundingInputError(
                "ModalDamping: ratios is empty; give one ratio or one per mode"
            )
        checked = tuple(
            _check_ratio(r, f"ratios[{i}]", "ModalDamping") for i, r in enumerate(ratios)
        )
        object.__setattr__(self, "ratios", checked)


Damping = RayleighDamping | ModalDamping


@dataclasses.dataclass(frozen=True, eq=False)
class ModalProperties:
    """Undamped modes of a building, mode 1 (longest period) first. All arrays are read-only.

    Attributes
    ----------
    periods : ndarray, shape (n_modes,)
        Natural periods T_j = 2π/ω_j [s], descending.
    circular_frequencies : ndarray, shape (n_modes,)
        Natural circular frequencies ω_j [rad/s], ascending.
    shapes : ndarray, shape (n_floors, n_modes)
        Mode shapes φ_j as columns, mass-normalised (Φᵀ M Φ = I) [kg^-0.5], roof component > 0
        (where a mode leaves the roof still, its top-most moving floor's component > 0).
    participation_factors : ndarray, shape (n_modes,)
        Γ_j = φ_jᵀ M 1 [kg^0.5] for a uniform ground motion (influence vector of ones).
    effective_masses : ndarray, shape (n_modes,)
        Effective modal masses M*_j = Γ_j² [kg]; they sum to the total mass.
    damping_ratios : ndarray, shape (n_modes,)
        Critical damping ratio ξ_j [-] each mode gets from the building's damping model.
    """

    periods: np.ndarray
    circular_frequencies: np.ndarray
    shapes: np.ndarray
    participation_factors: np.ndarray
    effective_masses: np.ndarray
    damping_ratios: np.ndarray


def _rayleigh(omega_i: float, omega_j: float, ratio: float) -> tuple[float, float]:
    # Chopra (2017) Sec. 11.4.1: equal ratio at ω_i and ω_j
    a0 = 2.0 * ratio * omega_i * omega_j / (omega_i + omega_j)
    a1 = 2.0 * ratio / (omega_i + omega_j)
    return a0, a1


def _readonly(array: np.ndarray) -> np.ndarray:
    array.setflags(write=False)
    return array


#: Sliding bearing types of an :class:`IsolationBase`, with what each adds to the base slab.
BEARING_TYPES: dict[str, str] = {
    "flat": "flat slider: friction only, no restoring force",
    "friction_pendulum": "concave slider of radius R: friction and a restoring stiffness W/R",
}

_BASE_KEYS = ("type", "mass", "friction", "radius")
#: Smallest friction-pendulum radius [m] (T = 2π √(R/g) = 0.45 s; 1e-12 m asked for 1e8 steps).
MIN_PENDULUM_RADIUS = 0.05


@dataclasses.dataclass(frozen=True, eq=False, init=False)
class IsolationBase:
    """A base slab on sliding isolation bearings under a building.

    Built with the keys of the case file's ``base = {...}`` table::

        IsolationBase(type="friction_pendulum", radius=2.2, friction="constantinou",
                      mu_min=0.04, mu_max=0.1, a=20.0, mass=5e5)

    Parameters
    ----------
    mass : float
        Mass of the base slab [kg], > 0.
    type : {"flat", "friction_pendulum"}
        Bearing type (:data:`BEARING_TYPES`).
    friction : str
        Friction law, a name of :data:`pounding.friction.FRICTION_LAWS`. ``coulomb`` is integrated as
        exact Coulomb stick-slip (its ``v_reg`` is not used): the slab sticks while the force needed
        to hold it stays within μ_s N and slides against μ_d N otherwise. The other laws are
        regularised functions of the sliding speed.
    radius : float, optional
        Radius of curvature R [m] of a friction pendulum's sliding surface, > 0 (required for
        ``friction_pendulum``, not allowed for ``flat``). Typical 1-4 m (isolated period
        2π √(R/g) of 2-4 s).
    **parameters : float
        The friction law's parameters (:func:`pounding.friction.friction_parameters`), e.g.
        ``mu_s``, ``mu_d`` for ``coulomb`` or ``mu_min``, ``mu_max``, ``a`` for ``constantinou``.
        For a law with a hysteretic variant (``constantinou``), giving the Bouc-Wen yield
        displacement ``u_y`` [m] selects it: f = μ(v) N z with z from
        :func:`pounding.friction.bouc_wen_rate`, whose other parameters ``A``, ``beta``, ``gamma``,
        ``eta`` take the defaults of :data:`pounding.friction.BOUC_WEN_PARAMETERS` unless given.

    Notes
    -----
    The normal force on the bearings is the weight of everything they carry, N = W = g (m_base +
    Σ m_i), constant (no vertical excitation, no overturning). A friction pendulum adds the restoring
    force (W/R) u_b to the sliding force at the base [2]_; the superstructure's springs and damping
    act on the floor displacements relative to the slab.
    """

    type: str
    mass: float
    friction: str
    radius: float | None
    parameters: dict[str, float]
    bouc_wen: dict[str, float] | None

    def __init__(
        self,
        *,
        mass: float,
        type: str = "flat",  # noqa: A002 (the case-file key)
        friction: str = "coulomb",
        radius: float | None = None,
        **parameters: float,
    ) -> None:
        where = "base"
        if type not in BEARING_TYPES:
            raise PoundingInputError(
                f"{where}: type = {type!r}; allowed: {', '.join(BEARING_TYPES)}"
            )
        m = finite_number(mass, f"{where}: mass", "kg")
        if not m >= 1.0:  # as a floor's: a lighter slab's frequency has no bound
            raise PoundingInputError(f"{where}: mass = {mass!r} kg; allowed: a finite number >= 1")
        if type == "friction_pendulum":
            if radius is None:
                raise PoundingInputError(
                    f"{where}: radius [m] is required for a friction_pendulum (typical 1-4 m)"
                )
            radius = finite_number(radius, f"{where}: radius", "m")
            if not radius >= MIN_PENDULUM_RADIUS:
                raise PoundingInputError(
                    f"{where}: radius = {radius!r} m; allowed: a finite number >= "
                    f"{MIN_PENDULUM_RADIUS:g} m (typical 1-4 m)"
                )
        elif radius is not None:
            raise PoundingInputError(
                f"{where}: radius = {radius!r} applies to type 'friction_pendulum' only; a "
                f"{type!r} bearing has no restoring force"
            )
        try:
            law = _friction.get_friction_law(friction)
        except ValueError as exc:
            raise PoundingInputError(f"{where}: friction: {exc}") from None
        bw_names = [p.name for p in _friction.BOUC_WEN_PARAMETERS]
        bw = {k: v for k, v in parameters.items() if k in bw_names}
        own = {k: v for k, v in parameters.items() if k not in bw_names}
        allowed = [*_BASE_KEYS, *law.parameter_names]
        if law.hysteretic_kernel is not None:
            allowed += bw_names
        unknown = sorted(set(parameters) - set(allowed))
        if unknown:
            raise PoundingInputError(
                f"{where}: unknown key {unknown[0]!r} for friction law {law.name!r}; allowed: "
                f"{', '.join(allowed)}"
            )
        try:
            _friction.friction_parameters(law, **own)
            if bw:
                _friction.bouc_wen_parameters(**bw)
        except ValueError as exc:
            raise PoundingInputError(f"{where}: {exc}") from None
        object.__setattr__(self, "type", type)
        object.__setattr__(self, "mass", m)
        object.__setattr__(self, "friction", law.name)
        object.__setattr__(self, "radius", radius)
        object.__setattr__(self, "parameters", {k: float(v) for k, v in own.items()})
        object.__setattr__(self, "bouc_wen", {k: float(v) for k, v in bw.items()} or None)

    def __repr__(self) -> str:
        extra = {**self.parameters, **(self.bouc_wen or {})}
        radius = "" if self.radius is None else f", radius={self.radius!r}"
        params = "".join(f", {k}={v!r}" for k, v in extra.items())
        return (
            f"IsolationBase(type={self.type!r}, mass={self.mass!r}{radius}, "
            f"friction={self.friction!r}{params})"
        )

    @property
    def law(self) -> _friction.FrictionLaw:
        """The friction law."""
        return _friction.FRICTION_LAWS[self.friction]

    @property
    def hysteretic(self) -> bool:
        """True when the law is used with a Bouc-Wen variable z (``u_y`` given)."""
        return self.bouc_wen is not None

    @property
    def stick_slip(self) -> bool:
        """True for exact Coulomb stick-slip (the ``coulomb`` law)."""
        return self.friction == "coulomb"

    def friction_array(self) -> np.ndarray:
        """The law's kernel parameter array p (float64, registry order, defaults filled)."""
        return _friction.friction_parameters(self.law, **self.parameters)

    def bouc_wen_array(self) -> np.ndarray | None:
        """The Bouc-Wen parameter array, or None without the hysteretic variant."""
        if self.bouc_wen is None:
            return None
        return _friction.bouc_wen_parameters(**self.bouc_wen)

    def to_dict(self) -> dict[str, object]:
        """The keys of the case file's ``base`` table."""
        out: dict[str, object] = {"type": self.type, "mass": self.mass, "friction": self.friction}
        if self.radius is not None:
            out["radius"] = self.radius
        return {**out, **self.parameters, **(self.bouc_wen or {})}


_FIELD_UNITS = {"masses": "kg", "stiffnesses": "N/m", "heights": "m"}


@dataclasses.dataclass(frozen=True, eq=False)
class ShearBuilding:
    """A lumped-mass shear building fixed at the base.

    Parameters
    ----------
    name : str
        Label used in results and error messages.
    masses : array_like, shape (n,)
        Floor masses [kg], lowest floor first.
    stiffnesses : array_like, shape (n,)
        Story (lateral) stiffnesses [N/m], lowest story first.
    heights : array_like, shape (n,), optional
        Story heights [m]; default 3.0 m each.
    damping : RayleighDamping or ModalDamping
        Damping model; default 5 % Rayleigh damping on modes 1 and 2.
    base : IsolationBase, optional
        A base slab on sliding isolation bearings; None (default) for a building fixed at the base.
        The base slab is not a floor: floors stay numbered 1..n, and :meth:`mass_matrix`,
        :meth:`stiffness_matrix`, :meth:`damping_matrix` and :meth:`modal` describe the
        superstructure on a fixed base (the building while the bearings stick).
    stories : Stories
        Story model (default elastic).
    p_delta : bool
        Add the P-Δ geometric stiffness of the floors' gravity loads (default False).
    soil : SoilFoundation, optional
        A flexible base: the building's foundation sways and rocks on soil springs and dashpots
        (:mod:`pounding.soil`); None (default) for a fixed base. As with ``base``, the building's
        own matrices and modes stay the fixed-base ones; :mod:`pounding.system` adds the sway and
        rocking degrees of freedom.

    Notes
    -----
    The equation of motion relative to the ground is M ü + C u̇ + K u = −M 1 a_g(t), with

    .. math::

        M = \\mathrm{diag}(m_1, \\dots, m_n), \\qquad
        K_{ii} = k_i + k_{i+1}, \\quad K_{i,i+1} = K_{i+1,i} = -k_{i+1}

    (k_{n+1} = 0); Chopra (2017) Sec. 9.2.
    """

    name: str
    masses: np.ndarray
    stiffnesses: np.ndarray
    heights: np.ndarray | None = None
    damping: Damping = RayleighDamping()
    base: IsolationBase | None = None
    stories: Stories = Stories()
    p_delta: bool = False
    soil: SoilFoundation | None = None

    def __post_init__(self) -> None:
        if not isinstance(self.name, str) or not self.name.strip():
            raise PoundingInputError(
                f"building name = {self.name!r}; name must be a non-empty string"
            )
        where = f"building {self.name!r}"
        masses = self._positive_array("masses", self.masses)
        n = masses.size
        heights = np.full(n, DEFAULT_STORY_HEIGHT) if self.heights is None else self.heights
        for field, values in (("stiffnesses", self.stiffnesses), ("heights", heights)):
            array = self._positive_array(field, values)
            if array.size != n:
                raise PoundingInputError(
                    f"{where}: {field} has {array.size} entries but masses has {n}; "
                    f"{field} needs one entry per story"
                )
            object.__setattr__(self, field, _readonly(array))
        object.__setattr__(self, "masses", _readonly(masses))
        if not isinstance(self.damping, RayleighDamping | ModalDamping):
            raise PoundingInputError(
                f"{where}: damping = {self.damping!r}; damping must be a RayleighDamping or "
                "ModalDamping"
            )
        if isinstance(self.damping, ModalDamping) and len(self.damping.ratios) not in (1, n):
            raise PoundingInputError(
                f"{where}: damping.ratios has {len(self.damping.ratios)} values; give 1 (all "
                f"modes) or {n} (one per mode)"
            )
        if self.base is not None and not isinstance(self.base, IsolationBase):
            raise PoundingInputError(
                f"{where}: base = {self.base!r}; allowed: an IsolationBase or None"
            )
        if self.soil is not None and not isinstance(self.soil, SoilFoundation):
            raise PoundingInputError(
                f"{where}: soil = {self.soil!r}; allowed: a SoilFoundation or None"
            )
        if self.soil is not None and self.base is not None:
            raise PoundingInputError(
                f"{where}: soil and base (isolation bearings) together are not supported; give "
                "one of them"
            )
        if self.stories is None:
            object.__setattr__(self, "stories", Stories())
        if not isinstance(self.stories, Stories):
            raise PoundingInputError(
                f"{where}: stories = {self.stories!r}; allowed: a pounding.Stories"
            )
        if not isinstance(self.p_delta, bool | np.bool_):
            raise PoundingInputError(f"{where}: p_delta = {self.p_delta!r}; allowed: true, false")
        theta = self.stability_coefficients()
        if self.p_delta and theta.max() >= 1.0:
            i = int(theta.argmax())
            raise PoundingInputError(
                f"{where}: story {i + 1} is unstable under its own gravity load with p_delta: "
                f"θ = P/(k h) = {theta[i]:.3g} ≥ 1; stiffen it or lighten the floors above"
            )
        if self.stories.yielding:  # per-story parameters checked now, before any analysis
            self.story_parameters()
            self.stories.ultimate_drift(n, where)

    def story_parameters(self) -> np.ndarray:
        """Rows (k, F_y, model parameters) of the story elements of a yielding model (n × p)."""
        return self.stories.element_parameters(
            self.stiffnesses, self.heights, f"building {self.name!r}"
        )

    def _positive_array(self, field: str, values: object) -> np.ndarray:
        where = f"building {self.name!r}"
        try:
            array = np.array(values, dtype=float, copy=True)
        except (TypeError, ValueError):
            raise PoundingInputError(f"{where}: {field} = {values!r}; must be numbers") from None
        if array.ndim != 1 or array.size == 0:
            raise PoundingInputError(
                f"{where}: {field} has shape {array.shape}; must be a non-empty 1-D sequence"
            )
        bad = np.flatnonzero(~(np.isfinite(array) & (array > 0.0)))
        if bad.size:
            i = int(bad[0])
            raise PoundingInputError(
                f"{where}: {field}[{i}] = {array[i]:g} {_FIELD_UNITS[field]}; "
                f"{field} must be positive and finite"
            )
        return array

    @property
    def n_floors(self) -> int:
        """Number of floors (= stories = degrees of freedom)."""
        return int(self.masses.size)

    @property
    def elevations(self) -> np.ndarray:
        """Floor elevations above the ground [m], lowest floor first."""
        return np.cumsum(self.heights)

    @property
    def total_mass(self) -> float:
        """Sum of the floor masses [kg] (without a base slab)."""
        return float(self.masses.sum())

    @property
    def can_collapse(self) -> bool:
        """True when the building can lose lateral strength (yielding stories or P-Δ): only then
        does a drift beyond ``[analysis] collapse_drift`` count as collapse."""
        return self.stories.yielding or self.p_delta

    @property
    def flexible_base(self) -> bool:
        """True when the building stands on a :class:`~pounding.soil.SoilFoundation`."""
        return self.soil is not None

    @property
    def isolated(self) -> bool:
        """True when the building stands on an :class:`IsolationBase`."""
        return self.base is not None

    @property
    def weight(self) -> float:
        """Weight carried by the ground or the bearings, W = g (m_base + Σ m_i) [N]."""
        return G * (self.total_mass + (self.base.mass if self.base is not None else 0.0))

    def mass_matrix(self) -> np.ndarray:
        """Diagonal lumped mass matrix M [kg], shape (n, n)."""
        return np.diag(self.masses)

    def stiffness_matrix(self) -> np.ndarray:
        """Tridiagonal shear-building stiffness matrix K [N/m], shape (n, n) (Chopra Sec. 9.2)."""
        return _shear_pattern(self.stiffnesses)

    def gravity_loads(self) -> np.ndarray:
        """Axial load P_i = g Σ_{j ≥ i} m_j [N] each story carries, lowest story first."""
        return G * np.cumsum(self.masses[::-1])[::-1]

    def stability_coefficients(self) -> np.ndarray:
        """Elastic stability coefficient θ_i = P_i/(k_i h_i) of each story (ASCE 7-16 §12.8.7)."""
        with np.errstate(over="ignore"):  # a story of vanishing k h is θ = inf: unstable, refused
            return self.gravity_loads() / (self.stiffnesses * self.heights)

    def geometric_stiffness_matrix(self) -> np.ndarray:
        """P-Δ geometric stiffness [N/m], shape (n, n): a spring −P_i/h_i across each story
        (Wilson & Habibullah 1987); zero unless ``p_delta``. The dynamic analysis adds it to K;
        the modes and the damping stay those of the elastic K."""
        if not self.p_delta:
            return np.zeros((self.n_floors, self.n_floors))
        return _shear_pattern(-self.gravity_loads() / self.heights)

    def _uses_rayleigh(self) -> bool:
        return (
            isinstance(self.damping, RayleighDamping) and max(self.damping.modes) <= self.n_floors
        )

    def rayleigh_coefficients(self) -> tuple[float, float]:
        """Rayleigh coefficients (a0 [1/s], a1 [s]) such that C = a0 M + a1 K.

        .. math::

            a_0 = \\xi \\frac{2 \\omega_i \\omega_j}{\\omega_i + \\omega_j}, \\qquad
            a_1 = \\xi \\frac{2}{\\omega_i + \\omega_j}

        Chopra (2017) Sec. 11.4.1. Raises ValueError when the damping is not Rayleigh damping or
        the building has fewer modes than the highest anchor mode (modal damping is used then).
        """
        where = f"building {self.name!r}"
        if not isinstance(self.damping, RayleighDamping):
            raise PoundingInputError(
                f"{where}: damping is {type(self.damping).__name__}, not Rayleigh"
            )
        if not self._uses_rayleigh():
            raise PoundingInputError(
                f"{where}: damping.modes = {self.damping.modes} but the building has only "
                f"{self.n_floors} mode(s); it uses modal damping with ratio {self.damping.ratio:g} "
                "on every mode instead, so there are no Rayleigh coefficients"
            )
        omega = self.modal().circular_frequencies
        i, j = self.damping.modes
        return _rayleigh(float(omega[i - 1]), float(omega[j - 1]), self.damping.ratio)

    def damping_matrix(self) -> np.ndarray:
        """Classical damping matrix C [N s/m], shape (n, n).

        Rayleigh damping gives C = a0 M + a1 K. Modal damping (and Rayleigh damping on a building
        with fewer modes than its highest anchor) gives, with mass-normalised Φ,

        .. math::

            C = M \\Phi \\, \\mathrm{diag}(2 \\xi_j \\omega_j) \\, \\Phi^T M

        Chopra (2017) Sec. 11.4.3.
        """
        if self._uses_rayleigh():
            a0, a1 = self.rayleigh_coefficients()
            return a0 * self.mass_matrix() + a1 * self.stiffness_matrix()
        modal = self.modal()
        mphi = self.masses[:, None] * modal.shapes
        c = mphi @ np.diag(2.0 * modal.damping_ratios * modal.circular_frequencies) @ mphi.T
        return 0.5 * (c + c.T)  # exact symmetry, lost to rounding in the triple product

    def modal(self) -> ModalProperties:
        """Undamped modal properties from the generalised eigenproblem K φ = ω² M φ (cached)."""
        return self._modal

    @functools.cached_property
    def _modal(self) -> ModalProperties:
        # M is diagonal: the symmetric standard problem (M^-1/2 K M^-1/2) y = ω² y, φ = M^-1/2 y
        # (Φᵀ M Φ = I), solved by numpy (scipy.linalg would cost a slow import for this one call)
        s = 1.0 / np.sqrt(self.masses)
        eigenvalues, y = np.linalg.eigh(s[:, None] * self.stiffness_matrix() * s[None, :])
        shapes = s[:, None] * y
        omega = np.sqrt(eigenvalues)  # ascending; K is positive definite for positive k
        shapes = shapes * np.sign(shapes[reference_floors(shapes), np.arange(shapes.shape[1])])
        gamma = shapes.T @ self.masses  # Γ_j = φ_jᵀ M 1 with Φᵀ M Φ = I
        if self._uses_rayleigh():
            a0, a1 = _rayleigh(
                *(float(omega[m - 1]) for m in self.damping.modes), self.damping.ratio
            )
            ratios = a0 / (2.0 * omega) + a1 * omega / 2.0  # Chopra (2017) Sec. 11.4.1
        elif isinstance(self.damping, RayleighDamping):
            ratios = np.full(self.n_floors, self.damping.ratio)
        else:
            ratios = np.broadcast_to(np.asarray(self.damping.ratios), (self.n_floors,)).copy()
        return ModalProperties(
            *(_readonly(a) for a in (2.0 * np.pi / omega, omega, shapes, gamma, gamma**2, ratios))
        )

    @classmethod
    def uniform(
        cls,
        name: str,
        n_floors: int,
        *,
        period: float,
        mass: float,
        height: float = DEFAULT_STORY_HEIGHT,
        damping: Damping = RayleighDamping(),  # noqa: B008 (frozen, immutable default)
        base: IsolationBase | None = None,
        stories: Stories | None = None,
        p_delta: bool = False,
        soil: SoilFoundation | None = None,
    ) -> ShearBuilding:
        """A building with equal floor masses and equal story stiffnesses.

        The story stiffness k is chosen so that the fundamental period is ``period``, from the
        frequencies of a uniform fixed-free shear building,

        .. math::

            \\omega_j = 2 \\sqrt{k/m} \\, \\sin\\frac{(2j - 1)\\pi}{2(2n + 1)}, \\quad j = 1..n

        Parameters
        ----------
        name : str
            Building label.
        n_floors : int
            Number of floors n >= 1.
        period : float
            Fundamental period T_1 [s] > 0.
        mass : float
            Mass of each floor m [kg] > 0.
        height : float
            Height of each story [m] > 0.
        damping : RayleighDamping or ModalDamping
            Damping model.
        base : IsolationBase, optional
            Base slab on isolation bearings (the period is the fixed-base one).
        stories : Stories, optional
            Story model (default elastic).
        p_delta : bool
            Add the P-Δ geometric stiffness (default False).
        soil : SoilFoundation, optional
            Flexible base (the period is the fixed-base one).
        """
        where = f"building {name!r}"
        if isinstance(n_floors, bool) or not isinstance(n_floors, int | np.integer) or n_floors < 1:
            raise PoundingInputError(f"{where}: n_floors = {n_floors!r}; must be an integer >= 1")
        period = float(period)
        if not (math.isfinite(period) and period > 0.0):
            raise PoundingInputError(f"{where}: period = {period:g} s; must be positive and finite")
        mass = float(mass)
        if not (math.isfinite(mass) and mass > 0.0):
            raise PoundingInputError(f"{where}: mass = {mass:g} kg; must be positive and finite")
        omega1 = 2.0 * math.pi / period
        s = math.sin(math.pi / (2.0 * (2 * n_floors + 1)))
        k = mass * (omega1 / (2.0 * s)) ** 2
        n = int(n_floors)
        return cls(
            name, np.full(n, mass), np.full(n, k), np.full(n, height), damping, base,
            stories or Stories(), p_delta, soil,
        )  # fmt: skip


def _shear_pattern(k: np.ndarray) -> np.ndarray:
    """The shear-building assembly of story springs k (lowest first): K_ii = k_i + k_(i+1),
    K_i,i+1 = −k_(i+1)."""
    above = np.append(k[1:], 0.0)  # the story above each floor; none above the roof
    return np.diag(k + above) - np.diag(k[1:], 1) - np.diag(k[1:], -1)


def reference_floors(shapes: np.ndarray) -> np.ndarray:
    """Per mode, the floor whose component fixes the sign and scale of the shape: the roof, or, where
    a mode leaves the roof (numerically) still, the top-most floor that moves."""
    moving = np.abs(shapes) > 1e-8 * np.max(np.abs(shapes), axis=0)
    return shapes.shape[0] - 1 - np.argmax(moving[::-1], axis=0)
