"""The benchmark models in OpenSeesPy: the same buildings, contacts, record and Newmark scheme.

Model: a 1-D domain (``-ndm 1 -ndf 1``), all nodes at x = 0. Node 1 is the (fixed) ground; each floor
is a node with its lumped mass. Stories are ``zeroLength`` elements with an ``Elastic`` material of
the story stiffness and ``-doRayleigh 1``; each building is a ``region`` with its own Rayleigh factors
(α_M a0 on its nodes, β_K a1 on its story elements), i.e. the same C = a0 M + a1 K per building as
:meth:`pounding.structure.ShearBuilding.damping_matrix` (a single-story building, which has modal
damping in pounding, gets the equivalent β_K = c/k). Contacts are ``zeroLength`` elements from the
left floor (node i) to the right floor (node j) with ``-doRayleigh 0``: their strain u_j − u_i = −(δ + g)
is negative in compression and the materials take the gap as a negative number, −g.

Contact materials, read from the OpenSees source (SRC/material/uniaxial/, OpenSees/OpenSees):

* ``linear`` → ``ElasticPPGap E=k Fy=-1e20 gap=-g eta=0`` (EPPGapMaterial.cpp): F = k δ, never yields.
* ``kelvin`` → ``ViscoelasticGap K=k C=c gap=-g`` (ViscoelasticGap.cpp): F = k δ + c δ̇ with **no
  clamp**: the force turns tensile at the end of each contact (pounding clamps at 0).
* ``hertz`` / ``lankarani_nikravesh`` / ``flores`` → ``Hertzdamp Kh=k xiNorm=α gap=-g n``
  (Hertzdamp.cpp): F = (Kh + ξ δ̇) δ^n with ξ = xiNorm Kh / v0, i.e. k δ^n (1 + α δ̇ / v0) with α = χ v0;
  **v0 is the trial rate of the first step that ends in contact** (re-set at every Newton iteration of
  that step while the committed tangent is 0), not the closing speed at δ = 0 that pounding locates;
  no clamp (tension when 1 + α δ̇/v0 < 0).
* ``jankowski`` → ``JankowskiImpact Kh=k xi=ξ mEff=m̄ gap=-g n`` (JankowskiImpact.cpp):
  F = Kh δ^n + 2ξ √(Kh δ^(n−1) m̄) δ̇ while approaching, Kh δ^n otherwise: the same law.
* ``bilinear`` → ``ImpactMaterial K1 K2 -δy gap=-g`` (ImpactMaterial.cpp): the same loop, but its
  first step in contact adds K1 times the *whole* strain increment of the step, including the part
  before the gap closed (pounding adds K1 δ only), so the first force of every impact is too high by
  K1 × (closing distance covered in that step before contact).

Yielding stories (``system.stories``, :mod:`pounding.stories`) → :func:`story_material`: ``bilinear`` →
``Steel01``, ``bouc_wen`` → ``BoucWen``, ``takeda`` → ``Hysteretic``, ``imk`` →
``ModIMKPeakOriented`` (see there). A building with a yielding story gets
``-rayleigh a0 0 a1 0`` (β_K on the *initial* stiffness, the constant C of pounding); an elastic
building keeps ``a0 a1 0 0`` (the same matrix: its tangent is its initial stiffness).

None of these materials returns a damping tangent (``getDampTangent`` = 0), so OpenSees's Newton uses
∂F/∂δ only; pounding's uses ∂F/∂δ + γ/(βh) ∂F/∂δ̇. Both converge to the same step solution.

Import: the openseespy Linux wheel ships ``libblas.so.3`` in ``openseespylinux/lib`` but its
``liblapack`` does not find it on systems without a system BLAS; :func:`load_opensees` pre-loads it.
"""

from __future__ import annotations

import contextlib
import ctypes
import importlib.util
import os
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from pounding.ground_motion import GroundMotion
from pounding.system import PoundingSystem

#: OpenSees material per pounding law.
MATERIALS = {
    "linear": "ElasticPPGap",
    "kelvin": "ViscoelasticGap",
    "hertz": "Hertzdamp",
    "lankarani_nikravesh": "Hertzdamp",
    "flores": "Hertzdamp",
    "jankowski": "JankowskiImpact",
    "bilinear": "ImpactMaterial",
}

GROUND = 1


def load_opensees():
    """``openseespy.opensees``, pre-loading the wheel's own BLAS when the system has none."""
    spec = importlib.util.find_spec("openseespylinux")
    if spec is not None and spec.origin:
        lib = Path(spec.origin).parent / "lib" / "libblas.so.3"
        if lib.exists():
            with contextlib.suppress(OSError):
                ctypes.CDLL(str(lib), mode=ctypes.RTLD_GLOBAL)
    with _quiet():
        import openseespy.opensees as ops
    return ops


@contextlib.contextmanager
def _quiet():
    """Silence OpenSees's stderr chatter (material banners, 'impact detected' lines)."""
    sys.stderr.flush()
    fd = os.dup(2)
    devnull = os.open(os.devnull, os.O_WRONLY)
    os.dup2(devnull, 2)
    try:
        yield
    finally:
        os.dup2(fd, 2)
        os.close(fd)
        os.close(devnull)


def node_of_dof(i: int) -> int:
    return i + 2


def contact_material(ops, tag: int, law: str, gap: float, p: np.ndarray) -> None:
    """Define the OpenSees material of a gap element with pounding kernel parameters ``p``."""
    if gap <= 0.0:
        raise ValueError(f"OpenSees gap materials need a gap > 0 (got {gap})")
    if law == "linear":
        ops.uniaxialMaterial("ElasticPPGap", tag, p[0], -1.0e20, -gap, 0.0)
    elif law == "kelvin":
        ops.uniaxialMaterial("ViscoelasticGap", tag, p[0], p[2], -gap)
    elif law == "hertz":
        ops.uniaxialMaterial("Hertzdamp", tag, p[0], 0.0, -gap, p[1])
    elif law in ("lankarani_nikravesh", "flores"):
        ops.uniaxialMaterial("Hertzdamp", tag, p[0], p[2], -gap, p[1])
    elif law == "jankowski":
        ops.uniaxialMaterial("JankowskiImpact", tag, p[0], p[2], p[3], -gap, p[1])
    elif law == "bilinear":
        ops.uniaxialMaterial("ImpactMaterial", tag, p[0], p[1], -p[2], -gap)
    else:
        raise ValueError(f"no OpenSees material for law {law!r}; allowed: {', '.join(MATERIALS)}")


#: OpenSees material per pounding story model (:func:`story_material`).
STORY_MATERIALS = {
    "bilinear": "Steel01",
    "bouc_wen": "BoucWen",
    "takeda": "Hysteretic",
    "imk": "ModIMKPeakOriented",
}
#: Hysteretic's second and third backbone points [δ_y]; the last segment continues past the third.
TAKEDA_POINTS = (10.0, 20.0)
#: ModIMKPeakOriented's fracDisp (deformation at which the force drops to 0) [m]: never reached.
IMK_FRAC_DISP = 1.0e3
#: BoucWen's own Newton on z: tolerance [m] on the z increment and iteration cap (the material's
#: defaults are 1e-8 m and 20; 1e-8 m is ~1e-6 δ_y here).
BW_TOL = 1.0e-13
BW_MAX_ITER = 50


def story_material(ops, tag: int, model: str, p: np.ndarray) -> None:
    """Define the OpenSees material of a yielding story with pounding parameters ``p`` (a row of
    ``system.stories.params``: k [N/m], F_y [N], then the model's parameters, drifts in metres).

    * ``bilinear`` → ``Steel01 Fy=F_y E0=k b a1=0 a2=1 a3=0 a4=1`` (Steel01.cpp: the trial stress
      E0 Δε + σ_n bounded by b E0 ε ± (1 − b) Fy (shiftP = shiftN = 1 with a1 = a3 = 0), tangent E0
      or b E0): pounding's return map. a2 = a4 = 1 only keep ``a1 pow(x/(2 a2 ε_y), 0.8)`` finite.
    * ``bouc_wen`` → ``BoucWen alpha=α ko=k n gamma=γ/δ_y^n beta=β/δ_y^n Ao=A
      deltaA=δ_A/(F_y δ_y) deltaNu=δ_ν/(F_y δ_y) deltaEta=δ_η/(F_y δ_y) tol maxIter``
      (BoucWenMaterial.cpp: z in metres, z = δ_y ζ, F = α k x + (1 − α) k z = α k x + (1 − α) F_y ζ;
      dz/dx = A − |z|^n (γ' + β' sgn(Δx z)) gives γ' = γ/δ_y^n; its energy
      e = Σ(1 − α) k z Δx = F_y δ_y ε). No pinching (ζ_s = 0). OpenSees integrates z by **backward
      Euler over the whole step** (z1 = z0 + Φ(z1) Δx, solved by Newton); pounding by RK4 sub-steps
      of at most 0.02 δ_y.
    * ``takeda`` → ``Hysteretic`` with the backbone (F_y, δ_y), (F_y + b k (x − δ_y), x) at
      x = 10 δ_y and 20 δ_y on each side (the last segment continues past 20 δ_y since its slope
      b k > 0), pinchX = pinchY = 1, damage1 = damage2 = 0, beta = a (HystereticMaterial.cpp:
      unloading at Eup (CrotMax/rot1p)^(−beta) = k μ^(−a), reload from the zero-force drift
      TrotNu to the peak (max(CrotMax, rot1p)), a partial unload reloads at the unloading
      stiffness until it meets that line: pounding's rules).
    * ``imk`` → ``ModIMKPeakOriented Ke=k alfaPos=alfaNeg=α_s My_pos=F_y My_neg=−F_y
      Ls=γ_s δ_y Ld=γ_c δ_y La=γ_a δ_y Lk=γ_k δ_y/2 Cs=Cd=Ca=Ck=c thetaP±=δ_p thetaPC±=δ_pc
      Resfac±=κ fracDisp±=IMK_FRAC_DISP D±=1`` (ModIMKPeakOriented.cpp: energy capacities
      Ls My, Ld My, La My and 2 Lk My against pounding's γ F_y δ_y; the cap at My/Ke + thetaP, the
      post-cap slope −F_cap/thetaPC as pounding's −F_c/δ_pc; thetaP/thetaPC are deformations [m]
      here, drift × h). A mode that is off in pounding (γ = 0) must not be 0 for Ld: the material
      then sets betac = 1 (``Enrgtot >= Enrgtd && Enrgtd == 0.0``) at the first deteriorating
      reversal.
    """
    k, fy = float(p[0]), float(p[1])
    if model == "bilinear":
        ops.uniaxialMaterial("Steel01", tag, fy, k, float(p[2]), 0.0, 1.0, 0.0, 1.0)
    elif model == "bouc_wen":
        alpha, n, beta, gamma, a, d_a, d_nu, d_eta, zeta_s = (float(x) for x in p[2:11])
        if zeta_s > 0.0:
            raise ValueError("Bouc–Wen pinching (zeta_s > 0) has no BoucWen equivalent")
        dy = fy / k
        e_y = fy * dy
        ops.uniaxialMaterial(
            "BoucWen", tag, alpha, k, n, gamma / dy**n, beta / dy**n, a,
            d_a / e_y, d_nu / e_y, d_eta / e_y, BW_TOL, BW_MAX_ITER,
        )  # fmt: skip
    elif model == "takeda":
        b, a = float(p[2]), float(p[3])
        dy = fy / k
        pts = [(fy + b * k * (x - 1.0) * dy, x * dy) for x in TAKEDA_POINTS]
        pos = [fy, dy, *pts[0], *pts[1]]
        ops.uniaxialMaterial("Hysteretic", tag, *pos, *(-x for x in pos), 1.0, 1.0, 0.0, 0.0, a)
    elif model == "imk":
        alpha, dp, dpc, kappa, g_s, g_c, g_a, g_k, c = (float(x) for x in p[2:11])
        if g_c == 0.0:
            raise ValueError("IMK gamma_c = 0 has no ModIMKPeakOriented equivalent (Ld = 0 bug)")
        dy = fy / k
        ops.uniaxialMaterial(
            "ModIMKPeakOriented", tag, k, alpha, alpha, fy, -fy,
            g_s * dy, g_c * dy, g_a * dy, g_k * dy / 2.0, c, c, c, c,
            dp, dp, dpc, dpc, kappa, kappa, IMK_FRAC_DISP, IMK_FRAC_DISP, 1.0, 1.0,
        )  # fmt: skip
    else:
        raise ValueError(
            f"no OpenSees material for story model {model!r}; allowed: {', '.join(STORY_MATERIALS)}"
        )


def build(
    ops,
    system: PoundingSystem,
    ground: GroundMotion,
    *,
    tol: float = 1e-12,
    max_iter: int = 50,
    solver: str = "BandGeneral",
    numberer: str = "RCM",
) -> dict:
    """Build the OpenSees model of ``system`` under ``ground`` and set up the transient analysis.

    Returns the tags: ``nodes`` (per dof), ``contacts`` (per gap element) and ``stories`` (per
    row of ``system.stories``: the yielding story elements).
    """
    st = system.stories
    yielding = {(int(st.building[r]), int(st.story[r])): r for r in range(len(st))}
    story_tags = [0] * len(st)
    with _quiet():
        ops.wipe()
        ops.model("basic", "-ndm", 1, "-ndf", 1)
        ops.node(GROUND, 0.0)
        ops.fix(GROUND, 1)
        n = system.n_dof
        for i in range(n):
            ops.node(node_of_dof(i), 0.0)
            ops.mass(node_of_dof(i), float(system.mass[i, i]))
        mat = 1
        ele = 1
        for b, building in enumerate(system.buildings):
            off = int(system.dof_offset[b])
            stories = []
            for s, k in enumerate(building.stiffnesses):
                r = yielding.get((b, s + 1))
                if r is None:
                    ops.uniaxialMaterial("Elastic", mat, float(k))
                else:
                    if not np.isclose(st.params[r, 0], k, rtol=1e-12, atol=0.0):
                        raise ValueError(f"story row {r}: k {st.params[r, 0]} != building's {k}")
                    story_material(ops, mat, st.model[r], st.params[r])
                    story_tags[r] = ele
                below = GROUND if s == 0 else node_of_dof(off + s - 1)
                ops.element(
                    "zeroLength", ele, below, node_of_dof(off + s),
                    "-mat", mat, "-dir", 1, "-doRayleigh", 1,
                )  # fmt: skip
                stories.append(ele)
                mat += 1
                ele += 1
            a0, a1 = _rayleigh(building)
            if any(bb == b for bb, _ in yielding):
                # damping on the initial stiffness (pounding's constant C), not the tangent
                ops.region(b + 1, "-ele", *stories, "-rayleigh", a0, 0.0, a1, 0.0)
            else:
                ops.region(b + 1, "-ele", *stories, "-rayleigh", a0, a1, 0.0, 0.0)
        el = system.elements
        contacts = []
        for c in range(len(el)):
            ia, ib = (int(x) for x in el.el_dof[c])
            if ia < 0 or ib < 0:
                raise ValueError("walls are not part of the OpenSees benchmark models")
            contact_material(ops, mat, el.law[c], float(el.el_gap[c]), el.el_params[c])
            ops.element(
                "zeroLength", ele, node_of_dof(ia), node_of_dof(ib),
                "-mat", mat, "-dir", 1, "-doRayleigh", 0,
            )  # fmt: skip
            contacts.append(ele)
            mat += 1
            ele += 1
        ops.timeSeries(
            "Path", 1, "-dt", float(ground.dt), "-values", *map(float, ground.acceleration)
        )
        ops.pattern("UniformExcitation", 1, 1, "-accel", 1)
        ops.constraints("Plain")
        ops.numberer(numberer)
        ops.system(solver)
        ops.test("NormDispIncr", tol, max_iter, 0)
        ops.algorithm("Newton")
        ops.integrator("Newmark", 0.5, 0.25)
        ops.analysis("Transient")
    return {
        "nodes": [node_of_dof(i) for i in range(system.n_dof)],
        "contacts": contacts,
        "stories": story_tags,
    }


def _rayleigh(building) -> tuple[float, float]:
    """(α_M, β_K) giving the building's damping matrix in pounding."""
    if building._uses_rayleigh():
        return building.rayleigh_coefficients()
    if building.n_floors == 1:
        c = float(building.damping_matrix()[0, 0])
        return 0.0, c / float(building.stiffnesses[0])
    raise ValueError(f"building {building.name!r}: modal damping has no Rayleigh equivalent")


def time_analysis(ops, n_steps: int, dt: float) -> float:
    """Wall time [s] of ``analyze(n_steps, dt)`` on a freshly built model; raises if it fails."""
    with _quiet():
        t0 = time.perf_counter()
        status = ops.analyze(n_steps, dt)
        elapsed = time.perf_counter() - t0
    if status != 0:
        raise RuntimeError(f"OpenSees analyze failed (status {status}) at t = {ops.getTime()}")
    return elapsed


def run_histories(
    ops, tags: dict, n_steps: int, dt: float, output_every: int, *, per_step: bool = False
) -> dict:
    """Run the built model: displacements on the output grid and full-resolution peaks.

    Calls ``analyze(output_every, dt)`` per output step (``per_step``: ``analyze(1, dt)`` per step,
    summing ``testIter()``, OpenSees's Newton iterations) and reads the nodal displacements and the
    yielding stories' spring forces (``eleResponse(tag, 'force')`` at node j = +F); peaks of |u|,
    of the contact force and of the story forces come from ``EnvelopeNode``/``EnvelopeElement``
    recorders, which see every step. (Not used for timing.)
    """
    nodes = tags["nodes"]
    contacts = tags["contacts"]
    stories = tags.get("stories", [])
    n_out = n_steps // output_every + 1
    u_out = np.zeros((n_out, len(nodes)))
    f_out = np.zeros((n_out, len(stories)))
    iterations = 0
    with tempfile.TemporaryDirectory() as tmp:
        fn = os.path.join(tmp, "nodes.txt")
        fe = os.path.join(tmp, "contacts.txt")
        fs = os.path.join(tmp, "stories.txt")
        with _quiet():
            ops.recorder("EnvelopeNode", "-file", fn, "-precision", 17, "-node", *nodes,
                         "-dof", 1, "disp")  # fmt: skip
            if contacts:
                ops.recorder("EnvelopeElement", "-file", fe, "-precision", 17, "-ele", *contacts,
                             "force")  # fmt: skip
            if stories:
                ops.recorder("EnvelopeElement", "-file", fs, "-precision", 17, "-ele", *stories,
                             "force")  # fmt: skip
            for k in range(n_steps // output_every):
                if per_step:
                    for _ in range(output_every):
                        if ops.analyze(1, dt) != 0:
                            raise RuntimeError(f"OpenSees analyze failed at t = {ops.getTime()}")
                        iterations += ops.testIter()
                elif ops.analyze(output_every, dt) != 0:
                    raise RuntimeError(f"OpenSees analyze failed at t = {ops.getTime()}")
                u_out[k + 1] = [ops.nodeDisp(nd, 1) for nd in nodes]
                f_out[k + 1] = [ops.eleResponse(e, "force")[1] for e in stories]
            ops.remove("recorders")
        peak_u = np.loadtxt(fn, ndmin=2)[2]
        # element force at node i is -stress = +F (compression); rows: min, max, |max|
        peak_f = np.loadtxt(fe, ndmin=2)[1, 0::2] if contacts else np.zeros(0)
        # story element: node j carries +F (the spring force); row |max|
        peak_s = np.loadtxt(fs, ndmin=2)[2, 1::2] if stories else np.zeros(0)
    out = {"u": u_out, "peak_u": peak_u, "peak_f": peak_f}
    if stories:
        out.update({"story_force": f_out, "peak_story_force": peak_s})
    if per_step:
        out["newton_iterations"] = iterations
    return out
