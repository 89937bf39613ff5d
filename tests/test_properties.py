"""Property-based tests (hypothesis) of the parallel force distribution.

Random declarations on robots from example-robot-data (solo12, anymal, hyq, talos) and the
project's own (spring_turkey, hexapod, millipedes): a random non-empty subset of the feet, a
random ordered subset of the axes, point / flat / mixed contacts, limp joints and passive springs
among the chains' joints, up to two design constraints, random configurations and wrenches whose
magnitude spans 21 orders of magnitude (10**-9 .. 10**12). Properties:

1. ``solve`` returns a :class:`va.Solution` or raises a :class:`va.VirtualActuatorError`
   subclass, and every returned array is finite;
2. every constraint holds to 1e-8 relative (limp and passive joints, zero moment at point
   contacts, zero force along directions a chain cannot produce, design constraints) and ``tau``
   equals Pinocchio's RNEA of the chain forces (oracle: ``tests/oracles.py``, no library code),
   or, where the exact rows contradict each other at ``q`` (the oracle's least squares), a typed
   error is raised; the compiled kernel agrees with its numpy reference (``compiled=False``);
3. the partitioned residual is no larger than the dense reference's;
4. determinism: the same call gives the same bits, whatever was solved before;
5. homogeneity: ``solve(q, s w) == s solve(q, w)`` with the same label (no springs, no rhs);

plus one actuator shared by four threads, bitwise equal to the sequential answers, and the
failures these properties found, replayed on every property (``REGRESSIONS``).

The default profile is derandomized and fast; ``VA_HYPOTHESIS_PROFILE=long`` runs many more
(random) examples.
"""

from __future__ import annotations

import concurrent.futures
import os
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
import pinocchio as pin
import pytest
from hypothesis import HealthCheck, Phase, assume, given, settings
from hypothesis import event as _event
from hypothesis import note as _note
from hypothesis import strategies as st
from hypothesis.errors import InvalidArgument
from oracles import (
    AXES,
    ReferenceDistribution,
    external_forces,
    frame_id,
    joint_angle,
    joint_v,
    relative_jacobian,
)

import virtual_actuators as va

# -- hypothesis profiles (applied per test: the suite's global "ci" profile is left alone) -------
_HEALTH = [HealthCheck.too_slow, HealthCheck.filter_too_much, HealthCheck.data_too_large]
settings.register_profile(
    "va-properties",
    derandomize=True,
    deadline=None,
    database=None,
    print_blob=True,
    phases=[Phase.explicit, Phase.generate, Phase.shrink],
    suppress_health_check=_HEALTH,
)
settings.register_profile(
    "va-properties-long",
    derandomize=False,
    deadline=None,
    print_blob=True,
    suppress_health_check=_HEALTH,
)
LONG = os.environ.get("VA_HYPOTHESIS_PROFILE", "").lower() == "long"
_PROFILE = settings.get_profile("va-properties-long" if LONG else "va-properties")


def examples(count: int) -> settings:
    """The file's profile with ``count`` examples (30 times more in the long profile)."""
    return settings(_PROFILE, max_examples=count * (30 if LONG else 1))


def event(text: str) -> None:
    """``hypothesis.event`` (statistics), a no-op when a regression case runs outside it."""
    try:
        _event(text)
    except InvalidArgument:
        pass


def note(text: str) -> None:
    """``hypothesis.note`` (printed with a failing example), printed outside hypothesis."""
    try:
        _note(text)
    except InvalidArgument:
        print(text)


TOL = 1e-8  # constraints and RNEA, relative
HOMOGENEITY_TOL = 1e-9
ADMISSIBILITY_TOL = 1e-6  # solve()'s default tol
ROUNDING = 1e-12  # README: residuals below 1e-12 max|F| are rounding (forces that cancel)
TYPED = va.VirtualActuatorError


# -- robots ---------------------------------------------------------------------------------------
@dataclass(frozen=True)
class RobotSpec:
    key: str
    loader: str  # a Python expression (for the repro snippets)
    load: Callable[[], va.Robot]
    actions: tuple[str, ...]
    feet: tuple[str, ...]
    scale: float = 0.4  # size of the random tangent step from the standing pose


def _feet(prefix: str, count: int) -> tuple[str, ...]:
    return tuple(f"{prefix}{i}" for i in range(1, count + 1))


SPECS = {
    spec.key: spec
    for spec in (
        RobotSpec(
            "solo12",
            'va.load_robot("solo12")',
            lambda: va.load_robot("solo12"),
            ("base_link",),
            ("FL_FOOT", "FR_FOOT", "HL_FOOT", "HR_FOOT"),
        ),
        RobotSpec(
            "anymal",
            'va.load_robot("anymal")',
            lambda: va.load_robot("anymal"),
            ("base",),
            ("LF_FOOT", "LH_FOOT", "RF_FOOT", "RH_FOOT"),
        ),
        RobotSpec(  # example-robot-data's hyq: the loader's name is hyq_no_sensors
            "hyq",
            'va.load_robot("hyq_no_sensors")',
            lambda: va.load_robot("hyq_no_sensors"),
            ("base_link",),
            ("lf_foot", "lh_foot", "rf_foot", "rh_foot"),
        ),
        RobotSpec(  # example-robot-data's talos: talos_reduced (soles and grippers)
            "talos",
            'va.load_robot("talos_reduced")',
            lambda: va.load_robot("talos_reduced"),
            ("base_link", "torso_2_link"),
            (
                "left_sole_link",
                "right_sole_link",
                "gripper_left_base_link",
                "gripper_right_base_link",
            ),
            scale=0.25,
        ),
        RobotSpec(
            "spring_turkey",
            'va.load_robot("spring_turkey")',
            lambda: va.load_robot("spring_turkey"),
            ("body",),
            ("left_foot", "right_foot"),
        ),
        RobotSpec(
            "hexapod",
            'va.load_robot("hexapod")',
            lambda: va.load_robot("hexapod"),
            ("body",),
            _feet("foot_", 6),
        ),
        RobotSpec(
            "millipede4",
            "va.millipede(legs=4)",
            lambda: va.millipede(legs=4),
            ("body",),
            _feet("foot_", 4),
        ),
        RobotSpec(
            "millipede8",
            "va.millipede(legs=8)",
            lambda: va.millipede(legs=8),
            ("body",),
            _feet("foot_", 8),
        ),
    )
}

_ROBOTS: dict[str, va.Robot] = {}
_ZERO_G: dict[str, pin.Model] = {}
_ACTUATORS: dict[object, object] = {}


def robot(key: str) -> va.Robot:
    if key not in _ROBOTS:
        _ROBOTS[key] = SPECS[key].load()
    return _ROBOTS[key]


def zero_gravity(key: str) -> pin.Model:
    if key not in _ZERO_G:
        model = pin.Model(robot(key).model)
        model.gravity.setZero()
        _ZERO_G[key] = model
    return _ZERO_G[key]


def chain_joints(key: str, action: str, reaction: str) -> list[str]:
    """Names of the one-dof joints between the two frames (Pinocchio's supports)."""
    model = robot(key).model
    ja = model.frames[frame_id(model, reaction)].parentJoint
    jb = model.frames[frame_id(model, action)].parentJoint
    joints = sorted(set(model.supports[ja]) ^ set(model.supports[jb]))
    return [model.names[j] for j in joints if j != 0 and model.joints[j].nv == 1]


# -- declarations ----------------------------------------------------------------------------------
@dataclass(frozen=True)
class Decl:
    robot: str
    action: str
    reactions: tuple[str, ...]
    reference: str
    axes: tuple[str, ...]
    contact: object  # "point", "flat" or a tuple of (reaction, contact) pairs
    unactuated: tuple[str, ...] = ()
    passive: tuple[tuple[str, tuple[float, float]], ...] = ()
    design: tuple = ()
    free: tuple[str, ...] = ()

    def contact_arg(self):
        return self.contact if isinstance(self.contact, str) else dict(self.contact)

    def contacts(self) -> dict[str, str]:
        if isinstance(self.contact, str):
            return {r: self.contact for r in self.reactions}
        return dict(self.contact)

    @property
    def homogeneous(self) -> bool:
        return not self.passive and all(getattr(c, "rhs", 0.0) == 0.0 for c in self.design)

    def build(self) -> va.ParallelVirtualActuator:
        return va.ParallelVirtualActuator(
            robot(self.robot),
            self.action,
            list(self.reactions),
            self.reference,
            self.axes,
            self.contact_arg(),
            unactuated=list(self.unactuated),
            passive=dict(self.passive),
            design=list(self.design),
        )

    def snippet(self) -> str:
        return (
            f"robot = {SPECS[self.robot].loader}\n"
            f"body = va.ParallelVirtualActuator(robot, {self.action!r}, {list(self.reactions)!r}, "
            f"{self.reference!r}, {self.axes!r}, {self.contact_arg()!r}, "
            f"unactuated={list(self.unactuated)!r}, passive={dict(self.passive)!r}, "
            f"design={list(self.design)!r})"
        )


def actuator(decl: Decl) -> va.ParallelVirtualActuator:
    """The cached actuator of a declaration; ``assume`` away the ones the library rejects."""
    if decl not in _ACTUATORS:
        try:
            _ACTUATORS[decl] = decl.build()
        except TYPED as error:  # a declaration the library rejects (typed): fine
            _ACTUATORS[decl] = error
    built = _ACTUATORS[decl]
    if isinstance(built, TYPED):
        event(f"declaration rejected: {type(built).__name__}")
        assume(False)
    return built


STIFFNESS = (0.5, 5.0, 50.0)
RESTS = (-0.6, 0.0, 0.3, 1.2)
COEFFS = (-2.0, -1.0, -0.5, 0.5, 1.0, 3.0)
RHS = (0.0, 1.5, -20.0)


def some(names: list[str]) -> st.SearchStrategy[list[str]]:
    """0 (half of the time), 1 or 2 distinct names."""
    return st.sampled_from((0, 0, 0, 1, 1, 2)).flatmap(
        lambda k: st.lists(
            st.sampled_from(names), min_size=min(k, len(names)), max_size=k, unique=True
        )
    )


@st.composite
def declarations(draw, robots=tuple(SPECS), homogeneous: bool = False) -> Decl:
    key = draw(st.sampled_from(robots))
    spec = SPECS[key]
    action = draw(st.sampled_from(spec.actions))
    reactions = tuple(
        draw(st.lists(st.sampled_from(spec.feet), min_size=1, max_size=len(spec.feet), unique=True))
    )
    reference = draw(st.sampled_from(("world", action, reactions[0])))
    subset = st.lists(st.sampled_from(AXES), min_size=1, max_size=6, unique=True).map(
        lambda axes: tuple(sorted(axes, key=AXES.index))
    )
    axes = draw(st.one_of(st.just(AXES), subset))
    kind = draw(st.sampled_from(("point", "flat", "mixed")))
    if kind == "mixed":
        contact = tuple((r, draw(st.sampled_from(("point", "flat")), label=r)) for r in reactions)
    else:
        contact = kind
    joints = sorted({j for r in reactions for j in chain_joints(key, action, r)})
    limp = tuple(draw(some(joints)))
    others = [j for j in joints if j not in limp]
    passive = ()
    if not homogeneous and others:
        names = draw(some(others))
        passive = tuple(
            (j, (draw(st.sampled_from(STIFFNESS)), draw(st.sampled_from(RESTS)))) for j in names
        )
    label = st.tuples(st.sampled_from(reactions), st.sampled_from(axes))
    design = []
    for _ in range(draw(st.integers(0, 2))):
        which = draw(st.sampled_from(("equal", "linear", "torque")))
        if which == "equal":
            design.append(va.Equal(draw(label), draw(label)))
        elif which == "linear":
            labels = draw(st.lists(label, min_size=1, max_size=4, unique=True))
            coeffs = {lb: draw(st.sampled_from(COEFFS)) for lb in labels}
            rhs = 0.0 if homogeneous else draw(st.sampled_from(RHS))
            design.append(va.Linear(coeffs, rhs=rhs))
        elif len(joints) >= 2:
            a, b = draw(st.lists(st.sampled_from(joints), min_size=2, max_size=2, unique=True))
            design.append(va.EqualTorque(a, b))
    free = ()
    if draw(st.integers(0, 5)) == 0:
        free = (draw(st.sampled_from(axes)),)
    return Decl(
        key, action, reactions, reference, axes, contact, limp, passive, tuple(design), free
    )


def configuration(key: str, seed: int) -> np.ndarray:
    """The standing pose moved by a random tangent step (seeded)."""
    rob = robot(key)
    model = rob.model
    rng = np.random.default_rng(seed)
    step = rng.uniform(-SPECS[key].scale, SPECS[key].scale, model.nv)
    return pin.normalize(model, pin.integrate(model, rob.neutral(), step))


seeds = st.integers(0, 2**32 - 1)
exponents = st.integers(-9, 12)


def wrench_of(n: int, seed: int, exponent: int) -> np.ndarray:
    """A random direction (sometimes sparse) of magnitude 10**exponent."""
    rng = np.random.default_rng(seed)
    direction = rng.normal(size=n)
    if n > 1 and rng.uniform() < 0.25:
        direction[rng.uniform(size=n) < 0.5] = 0.0
    if not np.any(direction):
        direction[0] = 1.0
    return direction / np.linalg.norm(direction) * 10.0**exponent


def repro(decl: Decl, q: np.ndarray, wrench: np.ndarray, **kwargs) -> str:
    args = "".join(f", {k}={v!r}" for k, v in kwargs.items())
    return (
        "import numpy as np, virtual_actuators as va\n"
        f"{decl.snippet()}\n"
        f"q = np.array({q.tolist()!r})\n"
        f"w = np.array({wrench.tolist()!r})\n"
        f"sol = body.solve(q, w, free={decl.free!r}{args})"
    )


def solve(body, q, wrench, free=(), **kwargs):
    """A Solution, or the typed error; any other exception propagates (a failure)."""
    try:
        return body.solve(q, wrench, free=free, **kwargs)
    except TYPED as error:
        return error


def draw_case(decl: Decl, qseed: int, wseed: int, exponent: int):
    body = actuator(decl)
    q = configuration(decl.robot, qseed)
    wrench = wrench_of(len(decl.axes), wseed, exponent)
    note(repro(decl, q, wrench))
    return body, q, wrench


# -- oracle checks (Pinocchio and numpy only) ------------------------------------------------------
def finite_solution(sol: va.Solution) -> None:
    for name in ("tau", "forces", "wrench", "requested", "tau_passive", "base_effort"):
        value = np.asarray(getattr(sol, name), dtype=float)
        assert np.all(np.isfinite(value)), f"sol.{name} is not finite: {value}"
    assert np.isfinite(sol.residual), sol.residual
    assert sol.method in ("partitioned", "pseudo-inverse", "least-squares"), sol.method


def rnea_of_forces(decl: Decl, q: np.ndarray, forces: np.ndarray) -> np.ndarray:
    """``-rnea(q, 0, 0, fext)`` without gravity, ``+F_i`` on {B} and ``-F_i`` on {A_i}."""
    model = zero_gravity(decl.robot)
    pairs = [
        (decl.action, r, decl.reference, decl.axes, f)
        for r, f in zip(decl.reactions, forces, strict=True)
    ]
    fext = external_forces(model, q, pairs)
    zero = np.zeros(model.nv)
    return -pin.rnea(model, model.createData(), q, zero, zero, fext)


def unproducible_directions(decl: Decl, q: np.ndarray, reaction: str) -> np.ndarray:
    """Orthonormal columns: wrench directions (selected axes) the chain cannot exert.

    The chain produces ``range(J_i)`` (rows of the selected axes, columns of its own joints);
    a point contact also exerts no moment about its origin (the rows of ``ball``). Directions
    with a singular value below 1e-9 relative (or 1e-12 absolute) count as unproducible.
    """
    model = robot(decl.robot).model
    rows = [AXES.index(a) for a in decl.axes]
    jac = relative_jacobian(model, q, decl.action, reaction, decl.reference)[rows]
    cols = []
    for name in chain_joints(decl.robot, decl.action, reaction):
        cols.append(joint_v(model, name))
    full = jac[:, cols]
    if decl.contacts()[reaction] == "point":
        data = model.createData()
        pin.framesForwardKinematics(model, data, q)
        rot_o = data.oMf[frame_id(model, decl.reference)].rotation
        d = rot_o.T @ (
            data.oMf[frame_id(model, decl.action)].translation
            - data.oMf[frame_id(model, reaction)].translation
        )
        ball = [
            np.concatenate((np.cross(np.eye(3)[k], d), np.eye(3)[k]))[rows]
            for k in range(3)
            if AXES[3 + k] in decl.axes
        ]
        if ball:
            full = np.hstack((full, np.array(ball).T))
    if full.shape[1] == 0:
        return np.eye(len(rows))
    u, s, _ = np.linalg.svd(full)
    rank = int(np.sum(s > max(1e-9 * s[0], 1e-12))) if s.size else 0
    return u[:, rank:]


class StructuralReference(ReferenceDistribution):
    """The oracles.py oracle's exact rows, with Jacobian entries below 1e-9 of the chain's largest
    set to zero: rounding noise (1e-17) or URDF rounding (``rpy`` 1.5708: 5e-12) is no lever."""

    def chain_jacobians(self, q):
        out = []
        for jac in super().chain_jacobians(q):
            out.append(np.where(np.abs(jac) < 1e-9 * np.abs(jac).max(initial=0.0), 0.0, jac))
        return out


def infeasible(decl: Decl, q: np.ndarray) -> float:
    """Relative residual of the exact rows (natural, limp, passive, coupling, design) in the
    least-squares sense (``rcond`` 1e-9): > 1e-6 means they contradict each other at ``q``
    (e.g. a spring that no selected axis loads), and no distribution can satisfy them."""
    oracle = StructuralReference(
        robot(decl.robot),
        decl.action,
        decl.reactions,
        decl.reference,
        decl.axes,
        decl.contact_arg(),
        decl.unactuated,
        dict(decl.passive),
        decl.design,
    )
    hard, rhs, _, _ = oracle.system(q, np.zeros(len(decl.axes)), decl.free)
    size = np.linalg.norm(rhs)
    if not hard.size or size == 0.0:
        return 0.0
    x = np.linalg.lstsq(hard, rhs, rcond=1e-9)[0]
    return float(np.linalg.norm(hard @ x - rhs) / size)


def check_constraints(decl: Decl, q: np.ndarray, wrench: np.ndarray, sol: va.Solution) -> None:
    """Every constraint of the declaration, and tau == RNEA of the chain forces."""
    model = robot(decl.robot).model
    contradiction = infeasible(decl, q)
    assert contradiction <= 1e-6, (
        f"the exact rows contradict each other at q (relative residual {contradiction:.3g}): "
        f"expected a typed error, got {sol!r} with |F| = {np.abs(sol.forces).max():.3g}"
    )
    p, n = len(decl.reactions), len(decl.axes)
    forces = np.asarray(sol.forces)
    assert forces.shape == (p, n)
    assert sol.tau.shape == (model.nv,) and sol.tau_passive.shape == (model.nv,)
    keep = np.array([a not in decl.free for a in decl.axes])
    scale_f = max(np.abs(forces).max(), np.abs(wrench[keep]).max(initial=0.0), 1e-300)

    # the produced wrench, the request, the residual and the label
    np.testing.assert_allclose(forces.sum(axis=0), sol.wrench, rtol=0, atol=TOL * scale_f)
    np.testing.assert_array_equal(sol.requested[keep], wrench[keep])
    np.testing.assert_array_equal(sol.requested[~keep], sol.wrench[~keep])
    miss = np.linalg.norm(wrench[keep] - sol.wrench[keep])
    assert abs(sol.residual - miss) <= TOL * scale_f, (sol.residual, miss)
    # the label: admissible iff residual <= tol * (the larger of the request and the production)
    # + the rounding of chain forces that cancel (1e-12 |F|); no verdict within 2x of the bar
    bar = (
        ADMISSIBILITY_TOL * max(np.linalg.norm(wrench[keep]), np.linalg.norm(sol.wrench[keep]))
        + ROUNDING * np.abs(forces).max()
    )
    if sol.residual > 2 * bar:
        assert sol.method == "least-squares", (sol.method, sol.residual, bar)
    elif sol.residual < bar / 2:
        assert sol.method != "least-squares", (sol.method, sol.residual, bar)

    # joint torques: RNEA of +F_i on {B}, -F_i on {A_i}
    tau = rnea_of_forces(decl, q, forces)
    springs = {
        joint_v(model, j): -k * (joint_angle(model, q, j) - rest) for j, (k, rest) in decl.passive
    }
    scale_t = max(
        scale_f,
        np.abs(tau).max(),
        np.abs(sol.tau).max(),
        max(map(abs, springs.values()), default=0),
    )
    limp = [joint_v(model, j) for j in decl.unactuated]
    actuated = np.ones(model.nv, dtype=bool)
    actuated[limp + list(springs)] = False
    np.testing.assert_allclose(sol.tau[actuated], tau[actuated], rtol=0, atol=TOL * scale_t)
    np.testing.assert_array_equal(sol.tau[~actuated], 0.0)  # limp and passive: no command
    np.testing.assert_allclose(tau[limp], 0.0, rtol=0, atol=TOL * scale_t)  # limp: J^T F = 0
    expected_passive = np.zeros(model.nv)
    for v, torque in springs.items():
        expected_passive[v] = torque
    np.testing.assert_allclose(sol.tau_passive, expected_passive, rtol=1e-12, atol=1e-300)
    np.testing.assert_allclose(  # passive joints: J^T F = the spring torque
        tau[list(springs)], expected_passive[list(springs)], rtol=0, atol=TOL * scale_t
    )

    # natural constraints of each chain
    data = model.createData()
    pin.framesForwardKinematics(model, data, q)
    rot_o = data.oMf[frame_id(model, decl.reference)].rotation
    p_b = data.oMf[frame_id(model, decl.action)].translation
    rot_rows = [k for k in range(3) if AXES[3 + k] in decl.axes]
    for i, reaction in enumerate(decl.reactions):
        f6 = np.zeros(6)
        f6[[AXES.index(a) for a in decl.axes]] = forces[i]
        if decl.contacts()[reaction] == "point":  # no moment about the foot on selected axes
            d = rot_o.T @ (p_b - data.oMf[frame_id(model, reaction)].translation)
            moment_at_a = f6[3:] + np.cross(d, f6[:3])
            np.testing.assert_allclose(
                moment_at_a[rot_rows], 0.0, rtol=0, atol=TOL * scale_f, err_msg=reaction
            )
        null = unproducible_directions(decl, q, reaction)  # no force the chain cannot exert
        np.testing.assert_allclose(
            null.T @ forces[i], 0.0, rtol=0, atol=TOL * scale_f, err_msg=reaction
        )

    # design constraints
    index = {(r, a): (i, j) for i, r in enumerate(decl.reactions) for j, a in enumerate(decl.axes)}
    for c in decl.design:
        if isinstance(c, va.Equal):
            gap = forces[index[c.a]] - forces[index[c.b]]
            assert abs(gap) <= TOL * scale_f, (c, gap, scale_f)
        elif isinstance(c, va.Linear):
            total = sum(k * forces[index[label]] for label, k in c.coefficients.items())
            size = max(scale_f * sum(abs(k) for k in c.coefficients.values()), abs(c.rhs))
            assert abs(total - c.rhs) <= TOL * size, (c, total, size)
        else:
            a, b = joint_v(model, c.joint_a), joint_v(model, c.joint_b)
            assert abs(tau[a] - tau[b]) <= TOL * scale_t, (c, tau[a], tau[b], scale_t)


# -- regressions: failures these properties found (replayed by test_regression, at the end) ----
_HEX4 = _feet("foot_", 4)
REGRESSIONS = {
    # ValueError "cannot reshape array of size 0" in PartitionedSolver._reduce (fixed since)
    "reshape": (
        Decl(
            "solo12",
            "base_link",
            ("FL_FOOT", "FR_FOOT"),
            "world",
            ("x",),
            "point",
            passive=(("FL_HAA", (0.5, -0.6)),),
            design=(va.Equal(("FL_FOOT", "x"), ("FR_FOOT", "x")),),
            free=("x",),
        ),
        0,
        0,
        0,
    ),
    # kernel: 3e16 N forces, nothing produced, labelled "pseudo-inverse"; numpy: ConstraintError
    "kernel-garbage": (
        Decl(
            "hexapod",
            "body",
            _HEX4,
            "body",
            ("x",),
            "point",
            passive=(("hip1_1", (0.5, -0.6)), ("hip2_2", (0.5, -0.6))),
        ),
        0,
        0,
        0,
    ),
    # kernel raises SingularConfigurationError (any q); numpy falls back to the dense reference
    "kernel-raises": (
        Decl("hexapod", "body", _HEX4, "body", ("z", "rx"), "point", unactuated=("hip1_1",)),
        0,
        0,
        0,
    ),
    # a spring that no selected axis loads (lever 1e-17): 4e19 N forces instead of an error
    "unloaded-spring": (
        Decl(
            "talos",
            "torso_2_link",
            ("gripper_left_base_link", "right_sole_link"),
            "torso_2_link",
            ("y",),
            "flat",
            passive=(("arm_left_1_joint", (50.0, -0.6)),),
        ),
        0,
        0,
        -2,
    ),
    # the same on a millipede: 4e18 N, residual 513 for a 1 N request, "pseudo-inverse"
    "kernel-garbage-millipede": (
        Decl(
            "millipede4", "body", _HEX4, "body", ("x",), "point", passive=(("knee_3", (50.0, 1.2)),)
        ),
        0,
        0,
        0,
    ),
    # every path: 3e11 N balance a hip spring whose y lever is URDF rounding (1e-12)
    "unloaded-spring-hyq": (
        Decl(
            "hyq",
            "base_link",
            ("rh_foot", "lh_foot", "rf_foot", "lf_foot"),
            "base_link",
            ("y",),
            "point",
            passive=(("lh_haa_joint", (0.5, 1.2)),),
        ),
        0,
        0,
        0,
    ),
    # ill-conditioned (|F| 5e5 for |w| 100): partitioned limp torques 0.05 N m (1e-7 |F|),
    # numpy-partitioned residual 0.068 "least-squares"; dense: 2.5e-10, limp torques 3e-11
    "ill-conditioned": (
        Decl(
            "talos",
            "base_link",
            (
                "left_sole_link",
                "gripper_left_base_link",
                "gripper_right_base_link",
                "right_sole_link",
            ),
            "base_link",
            AXES,
            "point",
            unactuated=("arm_right_7_joint", "arm_right_2_joint"),
            passive=(("leg_left_2_joint", (50.0, 0.3)), ("arm_right_3_joint", (50.0, 0.3))),
        ),
        627,
        3793556,
        2,
    ),
    # hip at the body's origin: the limp hip's x row vanishes; partitioned (both paths) keeps
    # it, right foot x = 0, "least-squares" residual 1.94; dense: residual 0
    "vacuous-limp-row": (
        Decl(
            "spring_turkey",
            "body",
            ("left_foot", "right_foot"),
            "body",
            ("x",),
            "point",
            unactuated=("right_hip",),
            passive=(("left_knee", (0.5, -0.6)),),
        ),
        2276298250,
        0,
        0,
    ),
    # kernel forces [[0, 0], [0, -1]], numpy and dense the minimum norm [[-.048, -.005], [.048,
    # -.995]]; both labelled "pseudo-inverse" (limp FL_HAA's row is degenerate on x, y)
    "kernel-not-min-norm": (
        Decl(
            "solo12",
            "base_link",
            ("FL_FOOT", "FR_FOOT"),
            "base_link",
            ("x", "y"),
            "point",
            unactuated=("FL_HAA",),
        ),
        0,
        0,
        0,
    ),
    # compiled "pseudo-inverse" (residual 1.6e-14), numpy "least-squares" (9.4e-12), |F| 35
    "label-flip": (
        Decl(
            "hexapod",
            "body",
            ("foot_1", "foot_4", "foot_6", "foot_2", "foot_5"),
            "world",
            AXES,
            "point",
            passive=(("knee_5", (0.5, -0.6)), ("hip2_5", (5.0, -0.6))),
            design=(
                va.Equal(("foot_4", "rx"), ("foot_2", "rx")),
                va.EqualTorque("knee_4", "knee_5"),
            ),
        ),
        2029011,
        735010,
        -6,
    ),
    # a 1.8e-12 lever (URDF rpy rounding) credited: 0.2 N along a direction the leg cannot push
    "structural-lever": (
        Decl("hyq", "base_link", ("lf_foot",), "base_link", ("x", "y", "ry"), "flat", free=("x",)),
        0,
        0,
        0,
    ),
}


# -- 1. typed errors only, finite arrays -----------------------------------------------------------
@given(decl=declarations(), qseed=seeds, wseed=seeds, exponent=exponents)
@examples(100)
def test_solve_returns_a_finite_solution_or_a_typed_error(decl, qseed, wseed, exponent):
    body, q, wrench = draw_case(decl, qseed, wseed, exponent)
    for kwargs in ({}, {"compiled": False}, {"method": "dense"}):
        outcome = solve(body, q, wrench, decl.free, **kwargs)
        if isinstance(outcome, TYPED):
            event(f"typed error: {type(outcome).__name__}")
            continue
        assert isinstance(outcome, va.Solution)
        event(f"method: {outcome.method}")
        finite_solution(outcome)


@given(decl=declarations(), qseed=seeds, wseed=seeds, exponent=exponents)
@examples(80)
def test_compiled_kernel_agrees_with_the_numpy_reference(decl, qseed, wseed, exponent):
    """README: the kernel hands every tick it cannot decide to numpy, its reference, so both
    paths give the same outcome: the same typed error, or the same distribution and label."""
    body, q, wrench = draw_case(decl, qseed, wseed, exponent)
    fast = solve(body, q, wrench, decl.free)
    reference = solve(body, q, wrench, decl.free, compiled=False)
    dense = solve(body, q, wrench, decl.free, method="dense")
    event(f"outcomes: {type(fast).__name__} / {type(reference).__name__} / {type(dense).__name__}")
    assert type(fast) is type(reference), (fast, reference)
    if isinstance(fast, TYPED):
        return
    scale = max(np.abs(reference.forces).max(), np.abs(wrench).max())
    np.testing.assert_allclose(fast.forces, reference.forces, rtol=0, atol=TOL * scale)
    scale_t = max(scale, np.abs(reference.tau).max())
    np.testing.assert_allclose(fast.tau, reference.tau, rtol=0, atol=TOL * scale_t)
    if fast.method != reference.method:  # only when a residual is on the bar (rounding)
        bar = ADMISSIBILITY_TOL * np.linalg.norm(wrench) + ROUNDING * scale
        near = [bar / 2 <= r <= 2 * bar for r in (fast.residual, reference.residual)]
        assert any(near), (fast.method, fast.residual, reference.method, reference.residual, bar)


# -- 2. constraints and the RNEA oracle ------------------------------------------------------------
@given(decl=declarations(), qseed=seeds, wseed=seeds, exponent=exponents)
@examples(150)
def test_solution_satisfies_every_constraint_and_rnea(decl, qseed, wseed, exponent):
    body, q, wrench = draw_case(decl, qseed, wseed, exponent)
    sol = solve(body, q, wrench, decl.free)
    if isinstance(sol, TYPED):
        event(f"typed error: {type(sol).__name__}")
        return
    event(f"method: {sol.method}, solver: {sol.solver}, compiled: {sol.compiled}")
    finite_solution(sol)
    check_constraints(decl, q, wrench, sol)


@given(decl=declarations(), qseed=seeds, wseed=seeds, exponent=exponents)
@examples(60)
def test_dense_and_numpy_solutions_satisfy_every_constraint_and_rnea(decl, qseed, wseed, exponent):
    body, q, wrench = draw_case(decl, qseed, wseed, exponent)
    for kwargs in ({"compiled": False}, {"method": "dense"}):
        sol = solve(body, q, wrench, decl.free, **kwargs)
        if isinstance(sol, TYPED):
            event(f"typed error: {type(sol).__name__}")
            continue
        finite_solution(sol)
        check_constraints(decl, q, wrench, sol)


# -- 3. residual no larger than the dense reference's ----------------------------------------------
@given(decl=declarations(), qseed=seeds, wseed=seeds, exponent=exponents)
@examples(80)
def test_partitioned_residual_is_at_most_the_dense_residual(decl, qseed, wseed, exponent):
    """Residual <= the dense reference's; a pseudo-inverse answer is the minimum-norm one."""
    body, q, wrench = draw_case(decl, qseed, wseed, exponent)
    dense = solve(body, q, wrench, decl.free, method="dense")
    for kwargs in ({}, {"compiled": False}):
        part = solve(body, q, wrench, decl.free, **kwargs)
        if isinstance(part, TYPED) or isinstance(dense, TYPED):
            event(f"outcomes: {type(part).__name__} / {type(dense).__name__}")
            continue
        scale = max(  # the problem's size: the request and the forces (springs, rhs)
            np.linalg.norm(wrench),
            np.abs(part.forces).max(),
            np.abs(dense.forces).max(),
        )
        assert part.residual <= dense.residual * (1 + 1e-6) + 1e-9 * scale, (
            kwargs,
            part.residual,
            dense.residual,
            scale,
        )
        if part.method == "pseudo-inverse" and dense.method != "least-squares":
            # the pseudo-inverse path is truly minimum norm: no larger than the dense reference's
            # least-squares minimum-norm answer (eq. 10-11 by lstsq)
            size_part, size_dense = np.linalg.norm(part.forces), np.linalg.norm(dense.forces)
            event("pseudo-inverse: norm compared with dense")
            assert size_part <= size_dense * (1 + 1e-6) + 1e-9 * scale, (
                kwargs,
                size_part,
                size_dense,
            )


# -- 4. determinism --------------------------------------------------------------------------------
def fingerprint(outcome) -> tuple:
    if isinstance(outcome, TYPED):
        return (type(outcome).__name__, str(outcome))
    return (
        outcome.tau.tobytes(),
        outcome.forces.tobytes(),
        outcome.wrench.tobytes(),
        float(outcome.residual),
        outcome.method,
        outcome.solver,
    )


@given(
    decl=declarations(),
    qseed=seeds,
    wseed=seeds,
    exponent=exponents,
    others=st.lists(st.tuples(seeds, seeds, exponents), min_size=1, max_size=4),
    kwargs=st.sampled_from(({}, {"compiled": False}, {"method": "dense"})),
)
@examples(50)
def test_same_call_gives_the_same_bits(decl, qseed, wseed, exponent, others, kwargs):
    body, q, wrench = draw_case(decl, qseed, wseed, exponent)
    first = fingerprint(solve(body, q.copy(), wrench.copy(), decl.free, **kwargs))
    assert fingerprint(solve(body, q.copy(), wrench.copy(), decl.free, **kwargs)) == first
    for oq, ow, oe in others:  # other calls in between, on the same actuator
        for other_kwargs in ({}, {"compiled": False}, {"method": "dense"}):
            solve(
                body,
                configuration(decl.robot, oq),
                wrench_of(len(decl.axes), ow, oe),
                decl.free,
                **other_kwargs,
            )
            solve(
                body,
                configuration(decl.robot, oq),
                wrench_of(len(decl.axes), ow, oe),
                (),
                **other_kwargs,
            )
    again = fingerprint(solve(body, q.copy(), wrench.copy(), decl.free, **kwargs))
    assert again == first, "a solve changed the actuator: the same call now gives other bits"
    fresh = fingerprint(solve(decl.build(), q.copy(), wrench.copy(), decl.free, **kwargs))
    assert fresh == first, "a fresh actuator of the same declaration gives other bits"


# -- 5. homogeneity --------------------------------------------------------------------------------
@given(
    decl=declarations(homogeneous=True),
    qseed=seeds,
    wseed=seeds,
    exponent=st.integers(-3, 3),
    factor=st.integers(-9, 12),
    kwargs=st.sampled_from(({}, {"compiled": False}, {"method": "dense"})),
)
@examples(100)
def test_solution_is_homogeneous_in_the_wrench(decl, qseed, wseed, exponent, factor, kwargs):
    assert decl.homogeneous
    body, q, wrench = draw_case(decl, qseed, wseed, exponent)
    s = 10.0**factor
    base = solve(body, q, wrench, decl.free, **kwargs)
    scaled = solve(body, q, s * wrench, decl.free, **kwargs)
    note(f"scaled: w * {s!r}, kwargs {kwargs}")
    if isinstance(base, TYPED) or isinstance(scaled, TYPED):
        assert type(base) is type(scaled), (base, scaled)
        event(f"typed error: {type(base).__name__}")
        return
    event(f"method: {base.method}")
    assert scaled.method == base.method, (base.method, scaled.method, base.residual)
    size = s * max(np.abs(base.forces).max(), np.abs(wrench).max())
    np.testing.assert_allclose(scaled.forces, s * base.forces, rtol=0, atol=HOMOGENEITY_TOL * size)
    size_t = max(size, s * np.abs(base.tau).max())
    np.testing.assert_allclose(scaled.tau, s * base.tau, rtol=0, atol=HOMOGENEITY_TOL * size_t)
    assert abs(scaled.residual - s * base.residual) <= HOMOGENEITY_TOL * size


# -- threads ---------------------------------------------------------------------------------------
THREADED = [
    Decl(  # a waist shared by two arm chains (limp yaw, spring pitch), a torque constraint
        "talos",
        "base_link",
        ("left_sole_link", "gripper_left_base_link", "gripper_right_base_link"),
        "world",
        AXES,
        (
            ("left_sole_link", "flat"),
            ("gripper_left_base_link", "point"),
            ("gripper_right_base_link", "flat"),
        ),
        unactuated=("torso_1_joint",),
        passive=(("torso_2_joint", (40.0, 0.1)),),
        design=(va.EqualTorque("arm_left_4_joint", "arm_right_4_joint"),),
    ),
    Decl(
        "hexapod",
        "body",
        _feet("foot_", 6),
        "body",
        AXES,
        "point",
        unactuated=("knee_2",),
        design=(
            va.Equal(("foot_1", "z"), ("foot_4", "z")),
            va.Linear({("foot_3", "x"): 1.0, ("foot_5", "y"): -2.0}, rhs=1.5),
        ),
    ),
]


@pytest.mark.parametrize("decl", THREADED, ids=lambda d: d.robot)
def test_one_actuator_shared_by_four_threads(decl):
    """400 (q, w) pairs (magnitudes 1e-9..1e12; compiled, numpy and dense; some with a free
    axis) from four threads: every answer (or typed error) equals the sequential one, bitwise.
    Seen: no typed error; about 1% "least-squares", the rest "pseudo-inverse"."""
    body = decl.build()
    rng = np.random.default_rng(11)
    variants = ({}, {"compiled": False}, {"method": "dense"})
    cases = []
    for k in range(400):
        q = configuration(decl.robot, int(rng.integers(2**32)))
        wrench = wrench_of(len(decl.axes), int(rng.integers(2**32)), int(rng.integers(-9, 13)))
        free = ("rz",) if k % 7 == 0 else ()
        cases.append((q, wrench, free, variants[k % 3]))

    def run(case):
        q, wrench, free, kwargs = case
        return fingerprint(solve(body, q, wrench, free, **kwargs))

    sequential = [run(case) for case in cases]
    with concurrent.futures.ThreadPoolExecutor(max_workers=4) as pool:
        threaded = list(pool.map(run, cases))
    mismatches = [k for k, (a, b) in enumerate(zip(sequential, threaded, strict=True)) if a != b]
    assert not mismatches, f"{len(mismatches)} of {len(cases)} differ, first {mismatches[:5]}"


# -- regressions: every generated property replayed on the cases listed in REGRESSIONS ------------
PROPERTIES = (
    test_solve_returns_a_finite_solution_or_a_typed_error,
    test_compiled_kernel_agrees_with_the_numpy_reference,
    test_solution_satisfies_every_constraint_and_rnea,
    test_dense_and_numpy_solutions_satisfy_every_constraint_and_rnea,
    test_partitioned_residual_is_at_most_the_dense_residual,
)


# Regression cases that still fail, if any (xfail, not strict): every case listed passes today.
_KNOWN: dict[str, tuple[str, tuple[str, ...]]] = {}  # case: (reason, properties failing on it)
KNOWN_FAILING: dict[tuple[str, str], str] = {
    (prop, case): reason for case, (reason, props) in _KNOWN.items() for prop in props
}


# Cases whose declaration the library now rejects (a spring no selected axis loads): the typed
# error is the answer, checked here instead of replaying the properties on them.
REJECTED = {
    "kernel-garbage": "hip2_2",
    "kernel-garbage-millipede": "knee_3",
    "unloaded-spring": "arm_left_1_joint",
    "unloaded-spring-hyq": "lh_haa_joint",
}


@pytest.mark.parametrize("case", sorted(REJECTED))
def test_regression_rejected_at_declaration(case):
    decl = REGRESSIONS[case][0]
    with pytest.raises(va.ConstraintError, match=f"loads the passive joint '{REJECTED[case]}'"):
        decl.build()


def _regression_params() -> list:
    params = []
    for prop in PROPERTIES:
        for case in (c for c in REGRESSIONS if c not in REJECTED):
            name = prop.__name__[5:]
            reason = KNOWN_FAILING.get((name, case))
            marks = [pytest.mark.xfail(strict=False, reason=reason)] if reason else []
            params.append(pytest.param(prop, case, id=f"{name}-{case}", marks=marks))
    return params


@pytest.mark.parametrize(("prop", "case"), _regression_params())
def test_regression(prop, case):
    decl, qseed, wseed, exponent = REGRESSIONS[case]
    prop.hypothesis.inner_test(decl=decl, qseed=qseed, wseed=wseed, exponent=exponent)
