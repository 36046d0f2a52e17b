"""Layouts shared by the compiled Newmark/HHT core: the impact log, the counters, the friction state,
the tolerances of the time loop, and the named argument groups its functions pass around.

The groups are namedtuples (numba compiles them as plain structs): the loop hands a kernel a few
named groups instead of dozens of positional arrays, and a kernel reads ``gaps.law[c]`` rather than
the 17th argument. Arrays inside a group are mutable in place; a group is never rebuilt per step.
"""

from __future__ import annotations

from collections import namedtuple

from pounding.integrators.base import PATH_POINTS

#: Layout of the float row of the impact log.
IMP_START, IMP_END, IMP_V0, IMP_VEND, IMP_FMAX, IMP_DMAX, IMP_IMPULSE = range(7)
#: Columns of the impact log after those fields: points kept, steps per kept point, steps seen, then
#: PATH_POINTS (penetration [m], force [N]) pairs at integration steps through the impact, from the
#: closure to the separation; a longer impact keeps every 2nd, 4th, ... step (force-penetration loops
#: drawn from the output grid missed the peak of a 70-90 ms impact by up to 40 %).
IMP_NPTS, IMP_STRIDE, IMP_SEEN, IMP_PATH = 7, 8, 9, 10
IMP_COLUMNS = IMP_PATH + 2 * PATH_POINTS
#: Layout of the integer counters array.
CNT_IMPACTS, CNT_SUBSTEPS, CNT_NEWTON, CNT_LOCATED, CNT_STATUS, CNT_HALVINGS = range(6)
CNT_FRICTION = 6  # located stick-slip events
N_COUNTERS = 7
STATUS_NO_CONVERGENCE, STATUS_IMPACT_LOG_FULL, STATUS_COLLAPSE = 1, 2, 3  # 0: success
#: The dense map is used for the open-gap step while its 3n² products cost less than this many times
#: the band products 3n(2 bw + 1) (small systems, where loop overhead dominates the band form).
DENSE_MAP_RATIO = 0.35
# an event (closure, separation) due within this fraction of a step is taken at the step's end
EVENT_FRACTION = 1e-3
#: After an onset (adaptive stepping) the contact step starts 2^GRADED_STEPS times smaller and doubles.
GRADED_STEPS = 6
#: A contact step is stretched by up to this fraction to end at the base step's end.
SLIVER = 1e-2
#: A step shorter than this fraction of the base step restarts its end acceleration from equilibrium.
SHORT_STEP = 1e-3
#: Columns of the friction state (one row per friction element): stuck (1/0), sliding direction
#: (±1), Bouc-Wen z at the step start, force at the step start [N], trial force [N], trial z,
#: trial tangent ∂f/∂u_b [N/m] (inf for a stuck slab: a constraint).
FS_STUCK, FS_DIR, FS_Z0, FS_F0, FS_F1, FS_Z1, FS_KF = range(7)
N_FS = 7
#: Break-away is located to this fraction of μ_s N, re-sticking to this fraction of the speed scale.
FRICTION_FORCE_TOL = 1e-10
FRICTION_SPEED_TOL = 1e-9
#: Columns of the loop's control array: time [s], step scale, halvings, graded steps left, contact
#: step [s], largest step before a separation [s], ground acceleration at the step start [m/s²].
CT_T, CT_SCALE, CT_HALVINGS, CT_GRADE, CT_HCONTACT, CT_HSEP, CT_GSTART = range(7)
N_CT = 7
#: Columns of the running energy sums [J]: input, damping, contact work, friction work, algorithmic,
#: then the work of each element family (EN_ELEMENTS + its kind: links, stories).
EN_INPUT, EN_DAMP, EN_CONTACT, EN_FRICTION, EN_ALG, EN_ELEMENTS = range(6)
N_FAMILIES = 2
N_EN = EN_ELEMENTS + N_FAMILIES

#: Newmark/HHT coefficients of one scheme (γ, β, α).
Scheme = namedtuple("Scheme", "gamma beta alpha")
#: The structure and its excitation: full and band matrices (M, C, K), M ι, the band LDLᵀ factors
#: of M, the influence
#: vector, the dof below each dof (−1 at a base), the rocking dof tilting each dof's story (−1 if
#: none) and the story height it tilts, the ground record and its step, the rows of every
#: nonlinear element (gaps, then friction, then element families) for the Woodbury update, and the
#: diagonal blocks of the band tangent with the element-family rows inside the band (``band_blocks``).
Model = namedtuple(
    "Model",
    "M C K Mi Lm Dm Mb Cb Kb MbT CbT KbT bw dense iota below tilt tilt_h ag ag_dt x_dof x_sign "
    "blk_el",
)
#: Gap elements: dofs and signs, gap [m], law id, parameters, undamped contact duration
#: t_c = tc_coef v0^tc_exp, and their per-element state (in contact, v0 [m/s], δ and force at the
#: last step, impact index, penetration, rate and force at the step start).
Gaps = namedtuple("Gaps", "dof sign gap law params tc_coef tc_exp inside v0 hd hf imp d0 dd0 f0")
#: Friction elements (pounding.system.FrictionElements) with their state rows (FS_* columns), the
#: stick force of the current step and the located-event flags.
Friction = namedtuple("Friction", "dof kind law params bw normal state p event")
#: Element families: family kind and law id per element, dofs and signs, parameters, committed and
#: trial state rows, and δ, δ̇, force and tangents at the step start (d0, f0) and trial (d1...);
#: ``written``: True where a kernel wrote the trial row since the last commit (else it equals the
#: committed row but for the columns a straight story increment writes).
Elements = namedtuple(
    "Elements", "kind law dof sign params state trial d0 f0 d1 dd1 f1 kd cd written"
)
#: Factors of a tangent without contacts for the step ``h[0]``: band LDLᵀ, the dense inverse (0 × 0
#: unless the system is small or has Coulomb slabs), the condensation of the gaps on it (row c of Z
#: is J⁻¹ b_c, row c of S = Bᵀ J⁻¹ B its column c; valid where ``have[c, 0]``, Z[c] nonzero only
#: on the row ranges in ``have[c, 1:]``), for small systems the dense map of the linear step (Qᵀ, pg;
#: empty when the band form is used), and the diagonal blocks of L (``band_blocks``: one per
#: building without shared dofs).
Factor = namedtuple("Factor", "h L D J_inv Z S Q pg have blk")
#: The story elements condensed on the base step's tangent with each story's current slope kd
#: (k_t − k): row e of Z is (J + w Bᵀ diag(kd) B)⁻¹ b_e, S = B Zᵀ; Z0, S0 the same at kd = 0;
#: ``count[0]`` rank-one updates since Z was last rebuilt from Z0, ``count[1]`` nonzero when a
#: kernel committed since the straight map (Q, pg, p0: u1 = Qᵀ[u; v; a] + pg g_eff + p0) was
#: brought to the stories' branches (by rank one from the linear map Q0, pg0 at kd = 0); ``s``
#: scratch. Empty (0 rows) unless every element is a story with straight branches in a small
#: system without friction.
Slopes = namedtuple("Slopes", "Z S Z0 S0 kd count s Q pg p0 Q0 pg0")
#: What the caller passes: matrices M, C, K, the influence vector, the dof below each dof (−1 at a
#: base), the rocking dof and height of each dof's story, the ground record and its step, and the
#: rows of every nonlinear element.
System = namedtuple("System", "M C K iota below tilt tilt_h ag ag_dt x_dof x_sign")
#: The trial end of a step: u, v, a and the gaps' δ, δ̇, force, ∂F/∂δ, ∂F/∂δ̇.
Trial = namedtuple("Trial", "u1 v1 a1 d1 dd1 f1 kd1 cd1")
#: Scratch arrays (never read before written within a call); Jb, Lw, Dw, e: the band tangent of a
#: step length without stored factors, its LDLᵀ factors and a unit vector; Z[:, c] the column
#: J⁻¹ b_c of element row c, and ``have`` the rows whose column is solved within the current step.
#: nz, phi: the gaps with a nonzero force term α f0 − w f1 of the condensed step, and that term;
#: live: the gaps that are not held open (its Newton rows).
Work = namedtuple(
    "Work", "R J vec Z S lin cw act nz phi Sm theta closing separating Jb Lw Dw e have live"
)
#: The loop's own state: u, v, a at the step start, the control array (CT_*), the running energy
#: sums (EN_*), the residuals at the step's start and end (HHT ledger), and the gaps held open (none;
#: every open gap while a closure is being located).
LoopState = namedtuple("LoopState", "u v a ctl en r0 r1 none_off open_off")
#: Solver options: Newton tolerance and iterations, halvings, onset location, the penetration that
#: counts as contact [m], the v0 floor [m/s], adaptive contact steps and their count, base step [s].
Options = namedtuple(
    "Options", "tol max_iter max_halvings locate_onset d_tol v0_floor adaptive steps_per_contact h"
)
#: Output buffers: u, v, a, ground, δ, F, energy, friction force, stick flag, element-family force
#: per output row; peaks;
#: the impact log (element, values) and the counters; the drift [m] of each dof's story taken as
#: collapse (the loop stops there, STATUS_COLLAPSE).
Output = namedtuple(
    "Output",
    "u v a ag d f e ff st lf peak_u peak_drift peak_aabs peak_f peak_d peak_lf imp_el imp_val "
    "counters collapse",
)
