"""Test oracle: the general virtual-power flow of gear trains (SI: W, rad/s, N m).

Chen & Angeles, "Virtual-power flow and mechanical gear-mesh power losses of epicyclic
gear trains", J. Mech. Des. 129 (2007) 107-113, for any one-degree-of-freedom train given
as members + meshes: each mesh loses ``(1 - eta)`` times the virtual power its driving
member gives it in the frame of the mesh's carrier; the torques come from static
equilibrium *with* the losses. :func:`rv_power_flow` and :func:`khv_power_flow` apply it
to the 2K-V (RV) and K-H-V (cycloid, sine) trains; :func:`khv_efficiency` is the K-H-V
closed form it is tested on. The production model (``toothfem.efficiency``: evaluation,
drive_losses, contact_friction) writes
the 2K-V closed form inline; the RV paper's split-power method it is compared with is
``toothfem.efficiency.rv_paper``. Derivations and the numbers on RV-40E:
``docs/derivations.md``, section 5; tests: ``tests/test_power_flow.py``.

Conventions (those of :mod:`toothfem.geometry.train`): angular velocities about the
reducer axis, counter-clockwise positive, housing frame. A torque is the torque *applied
to* a member; the power a member receives is ``T * omega``. For a planet (or crankshaft)
the speed is its absolute spin and the torque the generalised torque conjugate to it.

Mesh model. A mesh between members ``a`` and ``b`` on carrier ``H`` obeys Willis' row
``(w_a - w_H) - k (w_b - w_H) = 0`` (``k = -z_b/z_a`` external, ``+z_b/z_a`` internal).
It applies torques ``tau_a = lam``, ``tau_b = -k e lam``, ``tau_H = (k e - 1) lam`` with one
unknown ``lam`` per mesh. ``tau_a + tau_b + tau_H = 0`` for any ``e`` (friction does no
work in a rigid rotation of the whole train, so the torques are the same in every frame,
Chen & Angeles); ``e = 1`` is the lossless (Lagrange-multiplier) distribution. In the
carrier frame the virtual power member ``a`` receives is ``lam (w_a - w_H)``; if it is
negative ``a`` drives the mesh and ``e = eta`` (``b`` receives ``eta`` times what ``a``
gives), else ``b`` drives and ``e = 1/eta``. The loss is ``(1 - eta) |P_v,driver|`` and the
torques on every member balance, so input power - output power = sum of losses exactly.
The driver of each mesh is found by iteration (start lossless, set ``e`` by the sign of
the virtual power, re-solve, until the signs and any load-dependent efficiencies settle).
"""
from __future__ import annotations

from dataclasses import dataclass, field
from types import MappingProxyType
from collections.abc import Callable, Mapping

import numpy as np

from toothfem.efficiency.rv_paper import _efficiency, _pins_exceed_disc, _power, _teeth
from toothfem.errors import ToothfemError, check_range
from toothfem.geometry.train import solve_train, willis

__all__ = [
    "Mesh",
    "MeshState",
    "GearTrain",
    "MeshFlow",
    "PowerFlowResult",
    "power_flow",
    "rv_train",
    "rv_power_flow",
    "khv_train",
    "khv_power_flow",
    "khv_efficiency",
]

#: Relative tolerance on the kinematic residual of the speed solve (a few-by-few system).
KINEMATIC_RTOL = 1e-9
#: Relative speed below which a mesh is treated as not turning in its carrier frame.
ZERO_SPEED_RTOL = 1e-12
#: Convergence tolerance on load-dependent mesh efficiencies (absolute, efficiency units).
EFFICIENCY_TOL = 1e-12
#: Iteration cap of the driver/efficiency fixed point.
MAX_ITERATIONS = 200


# ---------------------------------------------------------------------------------------
# 1. General virtual-power flow (Chen & Angeles 2007)
# ---------------------------------------------------------------------------------------

@dataclass(frozen=True)
class MeshState:
    """What a load-dependent mesh efficiency is given (carrier-frame quantities).

    ``omega_a_rel``, ``omega_b_rel``: speeds of a and b relative to the carrier [rad/s];
    ``torque_a_Nm``, ``torque_b_Nm``: torques the mesh applies to a and b [N m];
    ``virtual_power_W``: virtual power the driving member gives the mesh (>= 0) [W];
    ``driver``: name of the driving member (None if the mesh does not turn).
    """

    name: str
    omega_a_rel: float
    omega_b_rel: float
    torque_a_Nm: float
    torque_b_Nm: float
    virtual_power_W: float
    driver: str | None


EfficiencyLike = float | Callable[[MeshState], float]


@dataclass(frozen=True)
class Mesh:
    """One gear mesh: members ``a`` and ``b`` (tooth numbers ``z_a``, ``z_b``) on ``carrier``.

    ``internal``: True for an internal mesh (ring gear, pin ring; the member with more
    teeth is the internal one). ``efficiency``: a number in (0, 1], or a callable taking a
    :class:`MeshState` and returning one (iterated to a fixed point). For a housing-fixed
    axis pair, make the housing the carrier.
    """

    a: str
    b: str
    carrier: str
    z_a: int
    z_b: int
    internal: bool
    efficiency: EfficiencyLike = 1.0
    name: str = ""

    def __post_init__(self):
        za, zb = _teeth("z_a", self.z_a), _teeth("z_b", self.z_b)
        object.__setattr__(self, "z_a", za)
        object.__setattr__(self, "z_b", zb)
        if len({self.a, self.b, self.carrier}) != 3:
            raise ToothfemError(f"mesh members a = {self.a!r}, b = {self.b!r}, carrier = "
                                f"{self.carrier!r} must be three different members")
        if self.internal and za == zb:
            raise ToothfemError(f"z_b = {zb} is outside the valid range z_b != z_a = {za}: "
                                "an internal mesh with equal tooth numbers does not turn "
                                "relative to its carrier")
        if not callable(self.efficiency):
            object.__setattr__(self, "efficiency",
                               _efficiency("efficiency", self.efficiency))
        if not self.name:
            object.__setattr__(self, "name", f"{self.a}-{self.b}")

    @property
    def k(self) -> float:
        """Willis factor: (w_a - w_H) = k (w_b - w_H)."""
        return (self.z_b / self.z_a) if self.internal else -(self.z_b / self.z_a)


@dataclass(frozen=True)
class GearTrain:
    """Members (rigid bodies, each with one rotation speed) joined by meshes.

    ``couplings``: pairs of members that turn together through a lossless joint
    (the RV disc and output carrier, joined through the crankshafts' eccentrics).
    """

    members: tuple
    meshes: tuple
    couplings: tuple = ()

    def __post_init__(self):
        object.__setattr__(self, "members", tuple(self.members))
        object.__setattr__(self, "meshes", tuple(self.meshes))
        object.__setattr__(self, "couplings", tuple(tuple(c) for c in self.couplings))
        if len(set(self.members)) != len(self.members):
            raise ToothfemError(f"members = {self.members!r} must be distinct names")
        known = set(self.members)
        for m in self.meshes:
            for role in ("a", "b", "carrier"):
                if getattr(m, role) not in known:
                    raise ToothfemError(f"mesh {m.name!r}: {role} = {getattr(m, role)!r} "
                                        f"is not one of the members {self.members!r}")
        for c in self.couplings:
            if len(c) != 2 or c[0] not in known or c[1] not in known or c[0] == c[1]:
                raise ToothfemError(f"coupling = {c!r} must name two different members")


@dataclass(frozen=True)
class MeshFlow:
    """Power flow through one mesh, in the frame of its carrier."""

    name: str
    carrier: str
    driver: str | None    #: member giving virtual power to the mesh (None: no motion)
    virtual_power_W: float      #: |P_v| given by the driver, with losses (>= 0)
    efficiency: float           #: mesh efficiency used
    loss_W: float               #: (1 - efficiency) * virtual_power_W
    torque_a_Nm: float          #: torque the mesh applies to a
    torque_b_Nm: float          #: torque the mesh applies to b
    torque_carrier_Nm: float    #: torque the mesh applies to the carrier


@dataclass(frozen=True)
class PowerFlowResult:
    """Steady power flow of a train with mesh losses.

    ``speeds`` [rad/s] and ``external_torques_Nm`` (torque applied to each member from
    outside: input, output, housing reactions; zero for idle members) are read-only maps.
    ``self_locking`` is True when the output power is not positive (the driving torque
    cannot move the load; the efficiency is then <= 0).
    """

    input_member: str
    output_member: str
    input_power_W: float
    output_power_W: float
    loss_W: float
    efficiency: float
    meshes: tuple
    speeds: Mapping[str, float] = field(repr=False)
    external_torques_Nm: Mapping[str, float] = field(repr=False)

    @property
    def self_locking(self) -> bool:
        return self.output_power_W <= 0.0

    def mesh(self, name: str) -> MeshFlow:
        for m in self.meshes:
            if m.name == name:
                return m
        raise KeyError(name)


def _speeds(train, input_member, fixed, w_in):
    eqs = [willis(m.a, m.b, m.carrier, m.z_a, m.z_b, m.internal) for m in train.meshes]
    eqs += [({a: 1.0, b: -1.0}, 0.0) for a, b in train.couplings]
    imposed = {input_member: w_in, **{f: 0.0 for f in fixed}}
    w = solve_train(eqs, imposed, list(train.members))
    scale = max(abs(v) for v in w.values())
    for coeffs, rhs in eqs:
        if abs(sum(c * w[n] for n, c in coeffs.items()) - rhs) > KINEMATIC_RTOL * scale:
            raise ToothfemError("the train's speed constraints are inconsistent with the "
                                f"input {input_member!r} turning while {fixed!r} are held")
    return w


def _torques(train, w, idx, factors, input_member, output_member, fixed, t_in):
    """Solve member equilibrium for the mesh loads, coupling loads, output and reactions."""
    n = len(train.members)
    nm, nc = len(train.meshes), len(train.couplings)
    a = np.zeros((n, nm + nc + 1 + len(fixed)))
    rhs = np.zeros(n)
    for j, (m, e) in enumerate(zip(train.meshes, factors)):
        a[idx[m.a], j] += 1.0
        a[idx[m.b], j] += -m.k * e
        a[idx[m.carrier], j] += m.k * e - 1.0
    for j, (p, q) in enumerate(train.couplings):
        a[idx[p], nm + j] += 1.0
        a[idx[q], nm + j] -= 1.0
    a[idx[output_member], nm + nc] = 1.0
    for j, f in enumerate(fixed):
        a[idx[f], nm + nc + 1 + j] = 1.0
    rhs[idx[input_member]] = -t_in
    if a.shape[0] != a.shape[1] or np.linalg.matrix_rank(a) < a.shape[1]:
        raise ToothfemError(
            f"the train's torques are not determined: {n} members, {nm} meshes, {nc} "
            f"couplings, {len(fixed)} held members (a one-degree-of-freedom train needs "
            "members = meshes + couplings + held members + 1)")
    return np.linalg.solve(a, rhs)


def _mesh_state(m, w, lam, e, scale):
    ra, rb = w[m.a] - w[m.carrier], w[m.b] - w[m.carrier]
    ta, tb = lam, -m.k * e * lam
    pa = ta * ra                       # virtual power received by a
    if abs(ra) <= ZERO_SPEED_RTOL * scale or pa == 0.0:
        return MeshState(m.name, ra, rb, ta, tb, 0.0, None)
    if pa < 0.0:                       # a gives virtual power: a drives
        return MeshState(m.name, ra, rb, ta, tb, -pa, m.a)
    return MeshState(m.name, ra, rb, ta, tb, -tb * rb, m.b)   # b gives -tb*rb > 0


def power_flow(train: GearTrain, *, input_member: str, output_member: str, fixed=(),
               input_power_W: float, input_speed_rad_s: float = 1.0) -> PowerFlowResult:
    """Steady power flow of a one-degree-of-freedom train with virtual-power mesh losses.

    ``input_power_W`` (> 0) enters at ``input_member`` turning at ``input_speed_rad_s``
    (non-zero, either sign); ``fixed`` members are held (speed 0); ``output_member`` takes
    the output power. Speeds: Willis rows solved by :func:`~toothfem.geometry.train.solve_train`.
    Torques: equilibrium of every member with the lossy mesh distribution (module
    docstring), the driver of each mesh fixed by the sign of its virtual power. Returns a
    :class:`PowerFlowResult`; input power - output power = sum of mesh losses.
    """
    p = _power("input_power_W", input_power_W)
    w_in = float(check_range("input_speed_rad_s", input_speed_rad_s))
    if w_in == 0.0:
        raise ToothfemError("input_speed_rad_s = 0.0 is outside the valid range "
                            "(-inf, 0) U (0, inf): the input must turn")
    fixed = tuple([fixed] if isinstance(fixed, str) else fixed)
    roles = [input_member, output_member, *fixed]
    for r in roles:
        if r not in train.members:
            raise ToothfemError(f"member {r!r} is not one of {train.members!r}")
    if len(set(roles)) != len(roles):
        raise ToothfemError(f"input {input_member!r}, output {output_member!r} and held "
                            f"members {fixed!r} must all differ")

    w = {n: float(v) for n, v in _speeds(train, input_member, fixed, w_in).items()}
    idx = {n: i for i, n in enumerate(train.members)}
    t_in = p / w_in
    scale = max(abs(v) for v in w.values())
    nm = len(train.meshes)

    def solve(factors):
        return _torques(train, w, idx, factors, input_member, output_member, fixed, t_in)

    def states(x, factors):
        return [_mesh_state(m, w, x[j], factors[j], scale)
                for j, m in enumerate(train.meshes)]

    def eta_of(m, s):
        if callable(m.efficiency):
            return _efficiency(f"efficiency of mesh {m.name!r}", m.efficiency(s))
        return m.efficiency

    def factor(m, s, eta):
        if s.driver is None:
            return 1.0
        return eta if s.driver == m.a else 1.0 / eta

    factors = [1.0] * nm
    x = solve(factors)
    st = states(x, factors)
    etas = [eta_of(m, s) for m, s in zip(train.meshes, st)]
    for _ in range(MAX_ITERATIONS):
        factors = [factor(m, s, e) for m, s, e in zip(train.meshes, st, etas)]
        x = solve(factors)
        new_st = states(x, factors)
        new_etas = [eta_of(m, s) for m, s in zip(train.meshes, new_st)]
        settled = (all(s.driver == t.driver for s, t in zip(st, new_st))
                   and max((abs(a - b) for a, b in zip(etas, new_etas)), default=0.0)
                   <= EFFICIENCY_TOL)
        st = new_st
        if settled:
            break
        etas = new_etas
    else:
        raise ToothfemError(f"the power-flow directions did not settle in {MAX_ITERATIONS} "
                            "iterations (mesh efficiency depending too strongly on load, or "
                            "a power-circulating train at the edge of self-locking)")

    flows = []
    for j, (m, s, e, f) in enumerate(zip(train.meshes, st, etas, factors)):
        lam = float(x[j])
        flows.append(MeshFlow(name=m.name, carrier=m.carrier, driver=s.driver,
                              virtual_power_W=float(s.virtual_power_W), efficiency=float(e),
                              loss_W=float((1.0 - e) * s.virtual_power_W),
                              torque_a_Nm=lam, torque_b_Nm=-m.k * f * lam,
                              torque_carrier_Nm=(m.k * f - 1.0) * lam))
    ext = {n: 0.0 for n in train.members}
    ext[input_member] = t_in
    ext[output_member] = float(x[nm + len(train.couplings)])
    for j, fm in enumerate(fixed):
        ext[fm] = float(x[nm + len(train.couplings) + 1 + j])
    p_out = float(-ext[output_member] * w[output_member])
    return PowerFlowResult(
        input_member=input_member, output_member=output_member, input_power_W=p,
        output_power_W=p_out, loss_W=sum(fl.loss_W for fl in flows), efficiency=p_out / p,
        meshes=tuple(flows), speeds=MappingProxyType(dict(w)),
        external_torques_Nm=MappingProxyType(ext))


# ---------------------------------------------------------------------------------------
# 2. The RV (2K-V) and K-H-V trains
# ---------------------------------------------------------------------------------------

def rv_train(z_sun, z_planet, z_disc, z_pins, mesh_efficiency_1: EfficiencyLike = 1.0,
             mesh_efficiency_2: EfficiencyLike = 1.0) -> GearTrain:
    """2K-V (RV) train, member names as in :func:`~toothfem.geometry.train.rv_speeds`.

    ``sun`` - ``planet`` mesh (external) on the output ``carrier``; ``disc`` - ``pins``
    mesh (internal) with the crankshaft (= ``planet``, absolute spin w3 = w2) as carrier;
    ``disc`` coupled to ``carrier`` (lossless). All planets/crankshafts and discs are
    lumped (torques summed): the efficiency does not depend on their numbers.
    """
    z_disc, z_pins = _pins_exceed_disc(z_disc, z_pins)
    return GearTrain(
        members=("sun", "planet", "disc", "carrier", "pins"),
        meshes=(Mesh("sun", "planet", "carrier", z_sun, z_planet, internal=False,
                     efficiency=_checked(mesh_efficiency_1, "mesh_efficiency_1"),
                     name="sun-planet"),
                Mesh("disc", "pins", "planet", z_disc, z_pins, internal=True,
                     efficiency=_checked(mesh_efficiency_2, "mesh_efficiency_2"),
                     name="disc-pins")),
        couplings=(("disc", "carrier"),))


def _checked(eta, name):
    return eta if callable(eta) else _efficiency(name, eta)


def rv_power_flow(z_sun, z_planet, z_disc, z_pins, input_power_W, mesh_efficiency_1,
                  mesh_efficiency_2, *, back_drive: bool = False,
                  input_speed_rad_s: float = 1.0) -> PowerFlowResult:
    """General virtual-power flow of a 2K-V (RV) reducer, pins held.

    Driving: input at the sun, output at the carrier; ``back_drive=True``: input at the
    carrier, output at the sun. Closed forms (docs, tested), ``r = z2/z1``,
    ``i = 1 + r z5/(z5 - z4)``, ``e1``/``e2`` the two mesh efficiencies: driving
    ``eta = (1 + r e1 z5/(z5 - z4 e2)) / i`` (RV-40E, 0.94 on both meshes: 0.2874);
    back-driving ``eta = i / (1 + (r/e1) z5 e2/(z5 e2 - z4))`` while ``z5 e2 > z4``.
    """
    train = rv_train(z_sun, z_planet, z_disc, z_pins, mesh_efficiency_1, mesh_efficiency_2)
    src, dst = ("carrier", "sun") if back_drive else ("sun", "carrier")
    return power_flow(train, input_member=src, output_member=dst, fixed=("pins",),
                      input_power_W=input_power_W, input_speed_rad_s=input_speed_rad_s)


def khv_train(z_moving, z_fixed, mesh_efficiency: EfficiencyLike = 1.0) -> GearTrain:
    """K-H-V stage: ``crank`` (H), ``moving`` (disc, planet) in the internal ``fixed``
    member (pin ring, ring gear), names as in :func:`~toothfem.geometry.train.khv_speeds`.
    The V (output) mechanism is taken as lossless and is not modelled."""
    z_moving, z_fixed = _pins_exceed_disc(z_moving, z_fixed, "z_moving", "z_fixed")
    return GearTrain(
        members=("crank", "moving", "fixed"),
        meshes=(Mesh("moving", "fixed", "crank", z_moving, z_fixed, internal=True,
                     efficiency=_checked(mesh_efficiency, "mesh_efficiency"),
                     name="moving-fixed"),))


def khv_power_flow(z_moving, z_fixed, input_power_W, mesh_efficiency, *,
                   back_drive: bool = False, input_speed_rad_s: float = 1.0
                   ) -> PowerFlowResult:
    """General virtual-power flow of a K-H-V stage: crank input, output via the moving
    member (``back_drive=True``: input at the moving member, output at the crank)."""
    train = khv_train(z_moving, z_fixed, mesh_efficiency)
    src, dst = ("moving", "crank") if back_drive else ("crank", "moving")
    return power_flow(train, input_member=src, output_member=dst, fixed=("fixed",),
                      input_power_W=input_power_W, input_speed_rad_s=input_speed_rad_s)


def khv_efficiency(z_moving, z_fixed, mesh_efficiency, *, back_drive: bool = False) -> float:
    """Closed-form efficiency of a K-H-V stage with mesh efficiency ``eta`` (carrier frame).

    With ``c = z_fixed/(z_fixed - z_moving)`` (= |i| + 1; 40 for 39/40, 80 for 79/80):
    driving from the crank ``eta_KHV = 1/(1 + c (1/eta - 1))`` (in the crank frame the
    fixed ring drives the moving member, so the ring gives ``c`` times the input power);
    back-driving from the output ``eta_KHV = 1 - c (1 - eta)`` (the moving member drives;
    <= 0 means self-locking). Derivation in the docs.
    """
    z_moving, z_fixed = _pins_exceed_disc(z_moving, z_fixed, "z_moving", "z_fixed")
    eta = _efficiency("mesh_efficiency", mesh_efficiency)
    c = z_fixed / (z_fixed - z_moving)
    if back_drive:
        return 1.0 - c * (1.0 - eta)
    return 1.0 / (1.0 + c * (1.0 / eta - 1.0))
