"""Separation distance: how wide must the seismic gap be? Time-history, spectral and code estimates.

Every estimate answers the same question for each pair of facing points (a floor of the left building
and the floor of its right neighbour it can hit, or a floor and a rigid wall): the clear distance g
below which the pair comes into contact. With the sign convention of :mod:`pounding.system`
(penetration δ = u_left − u_right − g, displacements relative to the ground, positive to the right):

* **exact, from time histories**: with the contacts removed, the pair touches iff g < g* where

  .. math:: g^* = \\max\\Big(0,\\ \\max_t \big[u_\\mathrm{left}(t) - u_\\mathrm{right}(t)\big]\\Big)

  (u ≡ 0 for a wall, so g* = max u for a wall on the right and max(−u) for one on the left). For
  buildings fixed at the base (linear, classically damped) every mode is integrated exactly for the
  record linear between samples (Nigam and Jennings 1969) and the maximum is refined between
  sub-steps by cubic Hermite interpolation: g* is the maximum of the continuous solution to about
  1e-4. Isolated buildings (friction bearings) are run without contacts with the case's own method
  and step, the maximum taken at every integration step;
* **spectral**: floor peaks u_A, u_B from each building's modes and a response spectrum (the
  record's own or a code design spectrum), combined over modes by SRSS or CQC, then over the pair by
  ABS, SRSS or the double-difference combination (DDC) with the CQC correlation of the buildings'
  fundamental modes, and by the CQC of the relative displacement over the modes of both buildings;
* **code rules**: ASCE/SEI 7-16 §12.12.3 and EN 1998-1:2004 §4.4.2.7 applied to the spectral peaks;
* **probability of pounding** over a record suite: P(pound | g) = P(g* > g), empirical and lognormal.

References
----------
.. [1] Der Kiureghian, A. (1981). A response spectrum method for random vibration analysis of MDF
   systems. Earthquake Engineering & Structural Dynamics 9(5), 419-435. doi:10.1002/eqe.4290090503
.. [2] Wilson, E.L., Der Kiureghian, A., Bayo, E.P. (1981). A replacement for the SRSS method in
   seismic analysis. Earthquake Engineering & Structural Dynamics 9(2), 187-192.
   doi:10.1002/eqe.4290090207
.. [3] Jeng, V., Kasai, K., Maison, B.F. (1992). A spectral difference method to estimate building
   separations to avoid pounding. Earthquake Spectra 8(2), 201-223.
.. [4] Penzien, J. (1997). Evaluation of building separation distance required to prevent pounding
   during strong earthquakes. Earthquake Engineering & Structural Dynamics 26(8), 849-858.
.. [5] Lin, J.-H., Weng, C.-C. (2001). Probability analysis of seismic pounding of adjacent
   buildings. Earthquake Engineering & Structural Dynamics 30(10), 1539-1557. doi:10.1002/eqe.76
.. [6] ASCE (2017). Minimum Design Loads and Associated Criteria for Buildings and Other Structures,
   ASCE/SEI 7-16, §12.12.3 (Eqs. 12.12-1, 12.12-2).
.. [7] CEN (2004). Eurocode 8: Design of structures for earthquake resistance - Part 1,
   EN 1998-1:2004, §4.3.4 (Eq. 4.23) and §4.4.2.7.
.. [8] Chopra, A.K. (2017). Dynamics of Structures, 5th ed. Pearson. §13.7 (modal combination rules).
.. [9] Nigam, N.C., Jennings, P.C. (1969). Calculation of response spectra from strong-motion
   earthquake records. Bulletin of the Seismological Society of America 59(2), 909-922.

The package: :mod:`~pounding.separation.rules` (the pure formulas), :mod:`~pounding.separation.pairs`
(facing pairs, exact gaps), :mod:`~pounding.separation.probability` (probability of pounding),
:mod:`~pounding.separation.variables` (estimates, statistics, units and long names),
:mod:`~pounding.separation.analysis` (options, :func:`separation_analysis`) and
:mod:`~pounding.separation.tables` (the comparison table, report data).
"""

from pounding.separation.analysis import (
    SPECTRUM_SOURCES,
    SeparationOptions,
    load_separation_case,
    separation_analysis,
)
from pounding.separation.pairs import (
    MODAL_METHOD,
    MODAL_STEPS_PER_PERIOD,
    FacingPair,
    exact_gaps,
    facing_pairs,
)
from pounding.separation.probability import (
    LognormalFit,
    empirical_pounding_probability,
    fit_lognormal,
    gap_for_probability,
    lognormal_pounding_probability,
)
from pounding.separation.rules import (
    MODAL_COMBINATIONS,
    abs_gap,
    asce7_inelastic_displacement,
    asce7_separation,
    combine_modes,
    cqc_correlation,
    ddc_gap,
    design_spectral_displacements,
    ec8_design_displacement,
    ec8_separation,
    modal_contributions,
    record_spectral_displacements,
    srss_gap,
)
from pounding.separation.tables import separation_summary, separation_table
from pounding.separation.variables import ESTIMATES, STATISTICS

__all__ = [
    "ESTIMATES",
    "MODAL_COMBINATIONS",
    "MODAL_METHOD",
    "MODAL_STEPS_PER_PERIOD",
    "SPECTRUM_SOURCES",
    "STATISTICS",
    "FacingPair",
    "LognormalFit",
    "SeparationOptions",
    "abs_gap",
    "asce7_inelastic_displacement",
    "asce7_separation",
    "combine_modes",
    "cqc_correlation",
    "ddc_gap",
    "design_spectral_displacements",
    "ec8_design_displacement",
    "ec8_separation",
    "empirical_pounding_probability",
    "exact_gaps",
    "facing_pairs",
    "fit_lognormal",
    "gap_for_probability",
    "load_separation_case",
    "lognormal_pounding_probability",
    "modal_contributions",
    "record_spectral_displacements",
    "separation_analysis",
    "separation_summary",
    "separation_table",
    "srss_gap",
]
