"""The compiled dispatch of the contact and friction laws: one entry per family, the law chosen by its
registry id (generated from the single definitions in pounding.contact.laws and pounding.friction)."""

from __future__ import annotations

from pounding._numba import jit, jit_inline

# --------------------------------------------------------------------------------------------------
# Contact laws: compiled from the single definitions in pounding.contact.laws
# --------------------------------------------------------------------------------------------------
from pounding.contact import laws as _laws  # noqa: E402

_linear = jit(_laws.linear_kernel)
_kelvin = jit(_laws.kelvin_kernel)
_kelvin_approach = jit(_laws.kelvin_approach_kernel)
_hertz = jit(_laws.hertz_kernel)
_hertz_kelvin = jit(_laws.hertz_kelvin_kernel)
_hunt_crossley = jit(_laws.hunt_crossley_kernel)
_jankowski = jit(_laws.jankowski_kernel)
_bilinear = jit(_laws.bilinear_kernel)
_bumper = jit(_laws.bumper_kernel)
_filler = jit(_laws.filler_kernel)
_stored = jit(_laws.stored_energy)
bilinear_rate = jit(_laws.bilinear_rate)

BILINEAR_ID = _laws.CONTACT_LAWS["bilinear"].kernel_id


@jit_inline
def contact_eval(law, d, dd, v0, d_prev, f_prev, p):
    """Force and tangents of the law with kernel id ``law`` (ids of pounding.contact.laws.LAWS_BY_ID)."""
    if law == 0:
        return _linear(d, dd, v0, d_prev, f_prev, p)
    if law == 1:
        return _kelvin(d, dd, v0, d_prev, f_prev, p)
    if law == 2:
        return _kelvin_approach(d, dd, v0, d_prev, f_prev, p)
    if law == 3:
        return _hertz(d, dd, v0, d_prev, f_prev, p)
    if law == 4:
        return _hertz_kelvin(d, dd, v0, d_prev, f_prev, p)
    if law <= 9:  # the Hunt-Crossley family shares one kernel
        return _hunt_crossley(d, dd, v0, d_prev, f_prev, p)
    if law == 10:
        return _jankowski(d, dd, v0, d_prev, f_prev, p)
    if law == 11:
        return _bilinear(d, dd, v0, d_prev, f_prev, p)
    if law == 12:
        return _bumper(d, dd, v0, d_prev, f_prev, p)
    return _filler(d, dd, v0, d_prev, f_prev, p)


@jit
def contact_stored_energy(law, d, f, p):
    """Recoverable energy [J] of a gap element (see pounding.contact.laws.stored_energy)."""
    return _stored(law == BILINEAR_ID, d, f, p)


# --------------------------------------------------------------------------------------------------
# Friction laws: compiled from the single definitions in pounding.friction
# --------------------------------------------------------------------------------------------------
import math  # noqa: E402

from pounding import friction as _friction  # noqa: E402

_FR_ID = {law.name: law.kernel_id for law in _friction.LAWS_BY_ID}
FR_COULOMB_ID = _FR_ID["coulomb"]
FR_VISCOUS_ID = _FR_ID["viscous"]
FR_VISCOUS_NORMAL_ID = _FR_ID["viscous_normal"]
FR_STRIBECK_ID = _FR_ID["stribeck"]
FR_ANDERSSON_ID = _FR_ID["andersson"]
FR_BROWN_MCPHEE_ID = _FR_ID["brown_mcphee"]

_fr_coulomb = jit(_friction.coulomb_kernel)
_fr_viscous = jit(_friction.viscous_kernel)
_fr_viscous_normal = jit(_friction.viscous_normal_kernel)
_fr_stribeck = jit(_friction.stribeck_kernel)
_fr_andersson = jit(_friction.andersson_kernel)
_fr_brown_mcphee = jit(_friction.brown_mcphee_kernel)
_fr_constantinou = jit(_friction.constantinou_kernel)
_fr_constantinou_bw = jit(_friction.constantinou_bouc_wen_kernel)
bouc_wen_rate = jit(_friction.bouc_wen_rate)

#: Bouc-Wen slides are integrated with RK4 sub-steps of at most this fraction of u_y.
BW_SUBSTEP = 0.125


@jit
def friction_eval(law, v, normal, p):
    """Force [N] and ∂f/∂v [N s/m] of the friction law with kernel id ``law`` (ids of
    pounding.friction.LAWS_BY_ID) at sliding speed v [m/s] and normal force [N]."""
    if law == FR_COULOMB_ID:
        return _fr_coulomb(v, normal, p)
    if law == FR_VISCOUS_ID:
        return _fr_viscous(v, normal, p)
    if law == FR_VISCOUS_NORMAL_ID:
        return _fr_viscous_normal(v, normal, p)
    if law == FR_STRIBECK_ID:
        return _fr_stribeck(v, normal, p)
    if law == FR_ANDERSSON_ID:
        return _fr_andersson(v, normal, p)
    if law == FR_BROWN_MCPHEE_ID:
        return _fr_brown_mcphee(v, normal, p)
    return _fr_constantinou(v, normal, p)


@jit
def friction_hysteretic_eval(law, v, normal, z, p):
    """(f, ∂f/∂v, ∂f/∂z) of a law with a Bouc-Wen variable z (only ``constantinou`` has one)."""
    return _fr_constantinou_bw(v, normal, z, p)


@jit
def _bouc_wen_slope(z, s, bw):
    """dz/du [1/m] of a slide in direction s = ±1: Bouc-Wen is rate independent, dz/du = ż/u̇."""
    return bouc_wen_rate(z, s, bw)[0] * s


@jit
def bouc_wen_slide(z0, du, bw):
    """(z1, dz1/d du): the Bouc-Wen variable after a monotonic slide du [m] from z0.

    ż/u̇ depends on z and the direction only (rate independence, Wen 1976), so z1 follows from
    dz/du = Φ(z, sign du) integrated over du with classical RK4 sub-steps of at most BW_SUBSTEP u_y,
    and ∂z1/∂du = Φ(z1) (the flow of an autonomous equation). Exact in the limit of small
    sub-steps whatever du/u_y, unlike a single trapezoidal or backward-Euler update."""
    s = 1.0 if du >= 0.0 else -1.0
    m = int(math.ceil(abs(du) / (BW_SUBSTEP * bw[0])))
    m = max(1, min(m, 100000))
    hu = du / m
    z = z0
    for _ in range(m):
        k1 = _bouc_wen_slope(z, s, bw)
        k2 = _bouc_wen_slope(z + 0.5 * hu * k1, s, bw)
        k3 = _bouc_wen_slope(z + 0.5 * hu * k2, s, bw)
        k4 = _bouc_wen_slope(z + hu * k3, s, bw)
        z += hu * (k1 + 2.0 * k2 + 2.0 * k3 + k4) / 6.0
    return z, _bouc_wen_slope(z, s, bw)


# --------------------------------------------------------------------------------------------------
# Element families beyond gaps and friction: compiled from their single definitions
# --------------------------------------------------------------------------------------------------
from pounding import links as _links  # noqa: E402
from pounding import stories as _stories  # noqa: E402

_kelvin_link = jit(_links.kelvin_link_kernel)
_viscous_link = jit(_links.viscous_link_kernel)
_maxwell_link = jit(_links.maxwell_link_kernel)
_kelvin_link_stored = jit(_links.kelvin_link_stored)
_viscous_link_stored = jit(_links.viscous_link_stored)
_maxwell_link_stored = jit(_links.maxwell_link_stored)
_bilinear_story = jit(_stories.bilinear_story_kernel)
# the rate inlined: five calls per drift increment in a dependent chain
bouc_wen_story_rate = jit_inline(_stories.bouc_wen_story_rate)
_bouc_wen_finish = jit_inline(_stories.bouc_wen_story_finish)
_bouc_wen_piece = jit_inline(_stories.bouc_wen_piece)
_bouc_wen_path = jit(_stories.make_bouc_wen_path(_bouc_wen_piece, jit(_stories.bouc_wen_zero)))
# on rows, inlined into the element loop, which evaluates every Bouc–Wen story at every step: its
# one piece is most steps' whole increment; sub-steps and zero crossings a call
bouc_wen_story_exact = jit_inline(
    _stories.make_bouc_wen_story_exact(_bouc_wen_piece, _bouc_wen_path, _bouc_wen_finish)
)
# what the exact path does not take (degradation, pinching, other n): a call
bouc_wen_story_rk4 = jit(_stories.make_bouc_wen_story_rk4(bouc_wen_story_rate, _bouc_wen_finish))
_bouc_wen_row = jit(_stories.make_bouc_wen_story_row(bouc_wen_story_exact, bouc_wen_story_rk4))
_bouc_wen_story = jit(_stories.make_bouc_wen_story_kernel(_bouc_wen_row))
# inlined into the element loop: a pass re-evaluates each story a round-off away
bouc_wen_story_near = jit_inline(
    _stories.make_bouc_wen_story_near(bouc_wen_story_rate, _bouc_wen_finish)
)
_takeda_story = jit(_stories.takeda_story_kernel)
_imk_story = jit(_stories.imk_story_kernel)
_story_energy = jit(_stories.story_energy)
# inlined into the element loop: most story increments of an analysis take it
story_straight = jit_inline(_stories.story_straight)
#: The state columns a straight story increment writes (the rest stay the committed ones).
STRAIGHT_COLUMNS = (_stories.SS_F, _stories.SS_D, _stories.SS_W, _stories.SS_WX, _stories.SS_E)

FAMILY_LINK = _links.FAMILY_LINK
FAMILY_STORY = _stories.FAMILY_STORY
_IMK = _stories.STORY_MODELS["imk"].kernel_id
_BOUC_WEN = _stories.STORY_MODELS["bouc_wen"].kernel_id
_SS_FAILED = _stories.SS_FAILED


@jit_inline
def has_straight(kind, law):
    """True for an element whose law has straight branches (:func:`story_straight` may take its
    increments): every story model but Bouc–Wen, which is smooth (testing it costs its steps 10 %)."""
    return kind == FAMILY_STORY and law != _BOUC_WEN


@jit_inline
def has_near(kind, law):
    """True for an element whose law continues a trial a round-off away (Bouc–Wen stories,
    :func:`bouc_wen_story_near`)."""
    return kind == FAMILY_STORY and law == _BOUC_WEN


@jit_inline
def element_eval(kind, law, d, dd, h, s0, s1, p):
    """Force and tangents (F, ∂F/∂δ, ∂F/∂δ̇) of an element of family ``kind`` (links, stories)
    with law id ``law`` at the end of a step of length h; writes its trial state s1 from the
    committed s0."""
    if kind == FAMILY_STORY and law == _BOUC_WEN:
        return _bouc_wen_story(d, dd, h, s0, s1, p)
    return element_eval_other(kind, law, d, dd, h, s0, s1, p)


@jit_inline
def element_eval_other(kind, law, d, dd, h, s0, s1, p):
    """:func:`element_eval` of every element but a Bouc–Wen story (which the Newmark core takes on
    rows, :func:`element_eval_row`): a dispatch that does not hold it compiles without it."""
    if kind == FAMILY_STORY:
        if law == 1:
            return _bilinear_story(d, dd, h, s0, s1, p)
        if law == 3:
            return _takeda_story(d, dd, h, s0, s1, p)
        return _imk_story(d, dd, h, s0, s1, p)
    if law == 0:
        return _kelvin_link(d, dd, h, s0, s1, p)
    if law == 1:
        return _viscous_link(d, dd, h, s0, s1, p)
    return _maxwell_link(d, dd, h, s0, s1, p)


@jit_inline
def element_eval_row(kind, law, d, dd, h, state, trial, params, e):
    """:func:`element_eval` of row ``e`` of the committed ``state``, ``trial`` and ``params``; a
    Bouc–Wen story, evaluated at every step, by its row kernel (a view per call costs the element
    loop its reference counts)."""
    if kind == FAMILY_STORY and law == _BOUC_WEN:
        done, g, kd = bouc_wen_story_exact(d, state, trial, params, e)
        if not done:
            g, kd = bouc_wen_story_rk4(d, state, trial, params, e)
        return g, kd, 0.0
    return element_eval_other(kind, law, d, dd, h, state[e], trial[e], params[e])


@jit_inline
def written_columns(kind, law, n):
    """The leading state columns (of ``n``) that a kernel of family ``kind`` and law ``law``
    writes: a commit copies those."""
    return _stories.BW_COLUMNS if kind == FAMILY_STORY and law == _BOUC_WEN else n


@jit
def element_stored(kind, law, d, f, s, p):
    """Recoverable energy [J] of an element at (δ, F, state), beyond what the assembled K holds."""
    if kind == FAMILY_STORY:
        # beyond the k δ²/2 of the assembled K (the whole story holds the E of its state)
        return _story_energy(law, s, p) - 0.5 * p[0] * d * d
    if law == 0:
        return _kelvin_link_stored(d, f, s, p)
    if law == 1:
        return _viscous_link_stored(d, f, s, p)
    return _maxwell_link_stored(d, f, s, p)


@jit_inline
def element_failed(kind, law, s):
    """True when an element's state says it has spent its capacity (an IMK story at β = 1: no force
    from then on, its building has collapsed)."""
    return kind == FAMILY_STORY and law == _IMK and s[_SS_FAILED] > 0.0
