r"""Contact stiffness from the parts in contact: springs in series and Hertz stiffness of spheres.

Two bodies pressed together both deform; the overall penetration δ is the sum of the local
deformations, so their contact springs act in series (Goldsmith [2]). For elastic spheres (and a
sphere on a flat), Hertz theory gives the stiffness k_h of F = k_h δ^{3/2} from the elastic constants
and radii (Hertz [1], Goldsmith [2] in the compliance form h_k = (1 − ν²)/(π E) used by Lankarani
and Nikravesh [4]; Johnson [3] in the E*, R* form).

All functions are vectorised over numpy arrays and return a float for scalar input.

References
----------
.. [1] Hertz, H. (1882). Über die Berührung fester elastischer Körper. J. Reine Angew. Math. 92,
   156-171. doi:10.1515/crll.1882.92.156
.. [2] Goldsmith, W. (1960). *Impact: The Theory and Physical Behaviour of Colliding Solids*.
   Edward Arnold, London.
.. [3] Johnson, K.L. (1985). *Contact Mechanics*. Cambridge University Press, Sec. 4.2.
   doi:10.1017/CBO9781139171731
.. [4] Lankarani, H.M., Nikravesh, P.E. (1990). A contact force model with hysteresis damping for
   impact analysis of multibody systems. J. Mech. Des. 112(3), 369-376. doi:10.1115/1.2912617
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike

from pounding.errors import PoundingInputError

__all__ = [
    "hertz_compliance",
    "hertz_sphere_plane",
    "hertz_sphere_sphere",
    "springs_in_series",
]


def _as_array(value: ArrayLike, field: str) -> np.ndarray:
    try:
        arr = np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        raise PoundingInputError(
            f"{field} = {value!r}; must be a number or an array of numbers"
        ) from None
    if np.isnan(arr).any():
        raise PoundingInputError(f"{field} = {value!r}; NaN is not allowed")
    return arr


def _out(arr: np.ndarray) -> float | np.ndarray:
    return float(arr) if arr.ndim == 0 else arr


def _check(arr: np.ndarray, ok: np.ndarray, field: str, allowed: str) -> None:
    bad = np.flatnonzero(~np.broadcast_to(ok, arr.shape))
    if bad.size:
        value = float(arr.reshape(-1)[bad[0]])
        raise PoundingInputError(f"{field} = {value:g}; allowed: {allowed}")


def springs_in_series(*stiffnesses: ArrayLike) -> float | np.ndarray:
    r"""Stiffness of contact springs in series [N/m^n] (Goldsmith [2]).

    .. math:: k = \frac{k_1 k_2}{k_1 + k_2}, \qquad
              \text{in general}\quad \frac{1}{k} = \sum_i \frac{1}{k_i}

    Parameters
    ----------
    *stiffnesses : float or array_like
        Two or more (one is allowed and returned unchanged) spring stiffnesses, > 0, all in the
        same unit ([N/m] for linear springs, [N/m^n] for springs of the same exponent n). An
        infinite stiffness is a rigid part and drops out. Arrays broadcast against each other.

    Returns
    -------
    float or numpy.ndarray
        Series stiffness, in the unit of the inputs; smaller than the smallest input.

    Raises
    ------
    ValueError
        No stiffness given, or a stiffness that is not > 0.

    Notes
    -----
    The series rule adds compliances, so it is exact for springs with the same force law
    F = k_i δ_i^n only when n = 1; for Hertzian parts combine the compliances h_k instead
    (:func:`hertz_sphere_sphere`).

    Examples
    --------
    Two equal springs give half the stiffness:

    >>> springs_in_series(2.0, 2.0)
    1.0
    """
    if not stiffnesses:
        raise PoundingInputError("springs_in_series needs at least one stiffness (> 0)")
    compliance = 0.0
    for i, k in enumerate(stiffnesses):
        arr = _as_array(k, f"stiffnesses[{i}]")
        _check(arr, arr > 0.0, f"stiffnesses[{i}]", "> 0 (np.inf for a rigid part)")
        compliance = compliance + 1.0 / arr
    with np.errstate(divide="ignore"):
        return _out(np.asarray(1.0 / compliance))


def hertz_compliance(*, E: ArrayLike, nu: ArrayLike) -> float | np.ndarray:
    r"""Elastic compliance parameter h_k [1/Pa] of a material (Goldsmith [2]; Lankarani & Nikravesh [4]).

    .. math:: h_k = \frac{1 - \nu_k^2}{\pi E_k}

    Parameters
    ----------
    E : float or array_like
        Young's modulus [Pa], > 0 (concrete about 3e10, steel about 2.1e11).
    nu : float or array_like
        Poisson's ratio [-], -1 < ν <= 0.5 (concrete about 0.2, steel about 0.3).

    Returns
    -------
    float or numpy.ndarray
        h_k [1/Pa].

    References
    ----------
    Lankarani & Nikravesh (1990) [4]; Goldsmith (1960) [2].
    """
    return _out(_compliance(E, nu, "E", "nu"))


def _compliance(E: ArrayLike, nu: ArrayLike, E_field: str, nu_field: str) -> np.ndarray:
    E = _as_array(E, E_field)
    nu = _as_array(nu, nu_field)
    _check(E, (E > 0.0) & np.isfinite(E), E_field, "finite and > 0 [Pa]")
    _check(nu, (nu > -1.0) & (nu <= 0.5), nu_field, "-1 < nu <= 0.5")
    return np.asarray((1.0 - nu * nu) / (math.pi * E))


def _radius(R: ArrayLike, field: str) -> np.ndarray:
    arr = _as_array(R, field)
    _check(arr, arr > 0.0, field, "> 0 [m] (np.inf for a flat surface)")
    return arr


def hertz_sphere_sphere(
    *,
    E1: ArrayLike,
    nu1: ArrayLike,
    R1: ArrayLike,
    E2: ArrayLike,
    nu2: ArrayLike,
    R2: ArrayLike,
) -> float | np.ndarray:
    r"""Hertz contact stiffness k_h [N/m^1.5] of two elastic spheres (Hertz [1], Goldsmith [2]).

    .. math:: k_h = \frac{4}{3\pi(h_i + h_j)}\sqrt{\frac{R_i R_j}{R_i + R_j}},
              \qquad h_k = \frac{1 - \nu_k^2}{\pi E_k}

    for the law F = k_h δ^{3/2} (δ the approach of the two centres). This is the classical
    k_h = (4/3) E* √R* of Johnson [3] with 1/E* = π(h_i + h_j) and 1/R* = 1/R_i + 1/R_j.

    Parameters
    ----------
    E1, E2 : float or array_like
        Young's moduli [Pa], > 0.
    nu1, nu2 : float or array_like
        Poisson's ratios [-], -1 < ν <= 0.5.
    R1, R2 : float or array_like
        Radii [m], > 0. One of them may be ``np.inf`` (a flat): the result is then
        :func:`hertz_sphere_plane`.

    Returns
    -------
    float or numpy.ndarray
        k_h [N/m^1.5]. Two 0.1 m steel spheres: about 3.4e10 N/m^1.5.

    References
    ----------
    Hertz (1882) [1]; Goldsmith (1960) [2]; Lankarani & Nikravesh (1990) [4].
    """
    h = _compliance(E1, nu1, "E1", "nu1") + _compliance(E2, nu2, "E2", "nu2")
    r1 = _radius(R1, "R1")
    r2 = _radius(R2, "R2")
    _check(r1, np.isfinite(r1) | np.isfinite(r2), "R1", "finite when R2 is infinite")
    # R_i R_j / (R_i + R_j) written as a sum of curvatures, so R_j = inf gives the flat exactly.
    r_eff = 1.0 / (1.0 / r1 + 1.0 / r2)
    return _out(np.asarray(4.0 / (3.0 * math.pi * h) * np.sqrt(r_eff)))


def hertz_sphere_plane(
    *,
    E_sphere: ArrayLike,
    nu_sphere: ArrayLike,
    R: ArrayLike,
    E_plane: ArrayLike,
    nu_plane: ArrayLike,
) -> float | np.ndarray:
    r"""Hertz contact stiffness k_h [N/m^1.5] of a sphere on a flat (Hertz [1], Goldsmith [2]).

    .. math:: k_h = \frac{4}{3\pi(h_i + h_j)}\sqrt{R_i}

    (the sphere–sphere formula with R_j -> ∞).

    Parameters
    ----------
    E_sphere, E_plane : float or array_like
        Young's moduli [Pa], > 0.
    nu_sphere, nu_plane : float or array_like
        Poisson's ratios [-], -1 < ν <= 0.5.
    R : float or array_like
        Sphere radius [m], finite and > 0.

    Returns
    -------
    float or numpy.ndarray
        k_h [N/m^1.5]. A 0.1 m steel sphere on a steel plate: about 4.9e10 N/m^1.5.

    References
    ----------
    Hertz (1882) [1]; Goldsmith (1960) [2]; Lankarani & Nikravesh (1990) [4].
    """
    h = _compliance(E_sphere, nu_sphere, "E_sphere", "nu_sphere") + _compliance(
        E_plane, nu_plane, "E_plane", "nu_plane"
    )
    r = _radius(R, "R")
    _check(r, np.isfinite(r), "R", "finite and > 0 [m]")
    return _out(np.asarray(4.0 / (3.0 * math.pi * h) * np.sqrt(r)))
