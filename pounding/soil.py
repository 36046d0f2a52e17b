"""Flexible bases: a rigid surface footing on an elastic half-space, with sway and rocking.

A building on a :class:`SoilFoundation` gains two degrees of freedom, the foundation's sway u_0 [m]
and rocking θ [rad], so that a floor at height H_i moves u_0 + H_i θ + (its story deformations)
relative to the free-field ground. The soil is a translational and a rocking spring with dashpots,
frequency independent, from the static stiffnesses of a rigid circular surface footing [1]_, [2]_
and Wolf's cone dashpots [3]_:

.. math::

    K_x = \\frac{8 G R_x}{2 - \\nu}, \\qquad K_\\theta = \\frac{8 G R_\\theta^3}{3 (1 - \\nu)},
    \\qquad G = \\rho V_s^2

    C_x = \\rho V_s \\pi R_x^2, \\qquad C_\\theta = \\rho c I_f, \\quad I_f = \\pi R_\\theta^4 / 4,
    \\quad c = V_p \\; (\\nu \\le 1/3), \\; 2 V_s \\; (1/3 < \\nu \\le 1/2)

with, for ν > 1/3, the trapped soil's rotational inertia ΔM_θ = 0.3 π (ν − 1/3) ρ I_f R_θ added to
the foundation's [3]_. A rectangular plan B × L (L along the row of buildings, the direction of
shaking) enters through the radii of the circles of equal area and equal moment of inertia,
R_x = √(BL/π) and R_θ = (BL³/(3π))^¼ [4]_.

Assumptions: the footing is rigid, on the surface (no embedment) of a homogeneous half-space; the
coefficients are the static ones (a constant C_θ overstates low-frequency rocking damping [2]_);
no soil material damping; neighbours interact only through their contacts and links, not through
the soil (Mahmoud, Abd-Elhamed & Jankowski 2013 study that coupling). The floors are point masses
(no rotary inertia of their own); gravity acts on the rocking building only with ``p_delta``.

References
----------
.. [1] Veletsos, A. S., Wei, Y. T. (1971). Lateral and rocking vibration of footings. J. Soil Mech.
   Found. Div. 97(9), 1227-1248.
.. [2] Gazetas, G. (1991). Formulas and charts for impedances of surface and embedded foundations.
   J. Geotech. Eng. 117(9), 1363-1381. doi:10.1061/(ASCE)0733-9410(1991)117:9(1363)
.. [3] Wolf, J. P. (1994). *Foundation Vibration Analysis Using Simple Physical Models*.
   Prentice Hall. Ch. 2 (cone models).
.. [4] Richart, F. E., Hall, J. R., Woods, R. D. (1970). *Vibrations of Soils and Foundations*.
   Prentice Hall. Sec. 7.4 (equivalent radii of rectangular footings).
.. [5] Veletsos, A. S., Meek, J. W. (1974). Dynamic behaviour of building-foundation systems.
   Earthq. Eng. Struct. Dyn. 3(2), 121-138. doi:10.1002/eqe.4290030203
"""

from __future__ import annotations

import dataclasses
import math

from pounding.errors import PoundingInputError
from pounding.validation import finite_number


def footing_stiffness(
    shear_modulus: float, poisson: float, radius_sway: float, radius_rocking: float
) -> tuple[float, float]:
    """Static sway K_x [N/m] and rocking K_θ [N m/rad] stiffness of a rigid circular surface
    footing on a half-space (Veletsos & Wei 1971; Gazetas 1991)."""
    k_x = 8.0 * shear_modulus * radius_sway / (2.0 - poisson)
    k_theta = 8.0 * shear_modulus * radius_rocking**3 / (3.0 * (1.0 - poisson))
    return k_x, k_theta


def cone_dashpots(
    density: float,
    shear_wave_velocity: float,
    poisson: float,
    radius_sway: float,
    radius_rocking: float,
) -> tuple[float, float, float]:
    """Wolf's (1994) cone dashpots: sway C_x [N s/m], rocking C_θ [N m s/rad], and the trapped
    soil's rotational inertia ΔM_θ [kg m²] (zero for ν ≤ 1/3)."""
    i_f = math.pi * radius_rocking**4 / 4.0
    c_x = density * shear_wave_velocity * math.pi * radius_sway**2
    if poisson <= 1.0 / 3.0:
        c = shear_wave_velocity * math.sqrt(2.0 * (1.0 - poisson) / (1.0 - 2.0 * poisson))
        trapped = 0.0
    else:
        c = 2.0 * shear_wave_velocity
        trapped = 0.3 * math.pi * (poisson - 1.0 / 3.0) * density * i_f * radius_rocking
    return c_x, density * c * i_f, trapped


def flexible_base_period(
    period: float, stiffness: float, height: float, k_sway: float, k_rocking: float
) -> float:
    """Period [s] of a single-story structure (fixed-base ``period`` [s], ``stiffness`` [N/m],
    ``height`` [m]) on sway and rocking springs, T̃ = T √(1 + k/K_x + k h²/K_θ) (Veletsos & Meek
    1974); exact for a massless foundation without rotary inertia."""
    return period * math.sqrt(1.0 + stiffness / k_sway + stiffness * height**2 / k_rocking)


def _positive(value: object, field: str, unit: str) -> float:
    x = finite_number(value, field, unit)
    if not x > 0.0:
        raise PoundingInputError(f"{field} = {value!r}; allowed: positive and finite [{unit}]")
    return x


@dataclasses.dataclass(frozen=True, eq=False, init=False)
class SoilFoundation:
    """A rigid surface footing on soil, with sway and rocking (module docstring).

    Built with the keys of the case file's ``soil = {...}`` table::

        SoilFoundation(shear_wave_velocity=150.0, density=1800.0, poisson=0.35,
                       width=20.0, length=20.0, mass=8e5)

    Parameters
    ----------
    shear_wave_velocity : float
        V_s of the soil [m/s], > 0 (soft clay ~100-200, stiff soil 200-400, rock > 760).
    density : float
        ρ [kg/m³], > 0.
    poisson : float
        ν [-], 0 ≤ ν ≤ 0.5.
    mass : float
        Mass of the foundation slab [kg], > 0.
    radius : float, optional
        Radius of a circular footing [m]; or give ``width`` and ``length`` instead.
    width, length : float, optional
        Plan of a rectangular footing [m]: B across the row and L along it (the direction of
        shaking); equivalent radii R_x = √(BL/π), R_θ = (BL³/(3π))^¼.
    inertia : float, optional
        Rotational inertia of the foundation about a horizontal axis across the row [kg m²]; default
        that of a thin slab, m R_θ²/4 (circle) or m L²/12 (rectangle), > 0.
    dashpots : bool
        Include the radiation dashpots (default True); False leaves the springs alone.
    """

    shear_wave_velocity: float
    density: float
    poisson: float
    mass: float
    radius: float | None
    width: float | None
    length: float | None
    inertia: float
    dashpots: bool

    def __init__(
        self,
        *,
        shear_wave_velocity: float,
        density: float,
        poisson: float,
        mass: float,
        radius: float | None = None,
        width: float | None = None,
        length: float | None = None,
        inertia: float | None = None,
        dashpots: bool = True,
    ) -> None:
        where = "soil"
        vs = _positive(shear_wave_velocity, f"{where}: shear_wave_velocity", "m/s")
        rho = _positive(density, f"{where}: density", "kg/m^3")
        if isinstance(poisson, bool) or not isinstance(poisson, int | float):
            raise PoundingInputError(f"{where}: poisson = {poisson!r}; allowed: 0 to 0.5")
        nu = float(poisson)
        if not 0.0 <= nu <= 0.5:
            raise PoundingInputError(f"{where}: poisson = {poisson!r}; allowed: 0 to 0.5")
        m = _positive(mass, f"{where}: mass", "kg")
        if radius is not None:
            if width is not None or length is not None:
                raise PoundingInputError(
                    f"{where}: give radius (circular footing) or width and length (rectangular), "
                    "not both"
                )
            radius = _positive(radius, f"{where}: radius", "m")
        elif width is None or length is None:
            raise PoundingInputError(
                f"{where}: the footing's plan is required: radius [m], or width and length [m]"
            )
        else:
            width = _positive(width, f"{where}: width", "m")
            length = _positive(length, f"{where}: length", "m")
        if not isinstance(dashpots, bool):
            raise PoundingInputError(f"{where}: dashpots = {dashpots!r}; allowed: true, false")
        for key, value in (
            ("shear_wave_velocity", vs),
            ("density", rho),
            ("poisson", nu),
            ("mass", m),
            ("radius", radius),
            ("width", width),
            ("length", length),
            ("dashpots", dashpots),
        ):
            object.__setattr__(self, key, value)
        if inertia is None:
            inertia = m * radius**2 / 4.0 if radius is not None else m * length**2 / 12.0  # type: ignore[operator]
        object.__setattr__(self, "inertia", _positive(inertia, f"{where}: inertia", "kg m^2"))

    def __repr__(self) -> str:
        return f"SoilFoundation({', '.join(f'{k}={v!r}' for k, v in self.to_dict().items())})"

    @property
    def shear_modulus(self) -> float:
        """G = ρ V_s² [Pa]."""
        return self.density * self.shear_wave_velocity**2

    @property
    def radius_sway(self) -> float:
        """R_x [m]: the radius, or that of the circle of the plan's area."""
        if self.radius is not None:
            return self.radius
        return math.sqrt(self.width * self.length / math.pi)  # type: ignore[operator]

    @property
    def radius_rocking(self) -> float:
        """R_θ [m]: the radius, or that of the circle of the plan's moment of inertia."""
        if self.radius is not None:
            return self.radius
        return (self.width * self.length**3 / (3.0 * math.pi)) ** 0.25  # type: ignore[operator]

    @property
    def springs(self) -> tuple[float, float]:
        """(K_x [N/m], K_θ [N m/rad])."""
        return footing_stiffness(
            self.shear_modulus, self.poisson, self.radius_sway, self.radius_rocking
        )

    @property
    def dashpot_coefficients(self) -> tuple[float, float]:
        """(C_x [N s/m], C_θ [N m s/rad]); zeros with ``dashpots = false``."""
        if not self.dashpots:
            return 0.0, 0.0
        c_x, c_t, _ = cone_dashpots(
            self.density, self.shear_wave_velocity, self.poisson, self.radius_sway,
            self.radius_rocking,
        )  # fmt: skip
        return c_x, c_t

    @property
    def rotational_inertia(self) -> float:
        """The foundation's rotational inertia with the trapped soil's (ν > 1/3) [kg m²]."""
        _, _, trapped = cone_dashpots(
            self.density, self.shear_wave_velocity, self.poisson, self.radius_sway,
            self.radius_rocking,
        )  # fmt: skip
        return self.inertia + (trapped if self.dashpots else 0.0)

    def to_dict(self) -> dict[str, object]:
        """The keys of the case file's ``soil`` table."""
        fields = (f.name for f in dataclasses.fields(self))
        return {k: getattr(self, k) for k in fields if getattr(self, k) is not None}
