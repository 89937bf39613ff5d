"""Parallel virtual actuators: force distributions checked against independent oracles.

For each solve, on quadrupeds (solo12, anymal, hyq) and a humanoid (talos_reduced):

- the chain wrenches sum to the produced wrench, which equals an admissible request;
- RNEA with "+F_i on {B}, -F_i on {A_i}" reproduces ``sol.tau`` at actuated joints, gives zero
  at limp joints, the spring torque at passive joints and zero on the floating base;
- point contacts exert no moment about the reaction frame's origin;
- design constraints hold; the distribution is the minimum-norm feasible one (an independent
  dense solver built from Pinocchio Jacobians) and the partitioned solver equals the dense one;
- inadmissible requests give the least-squares solution with exact constraints, and ``strict``
  raises; the millipede's set sizes follow the seed's counts.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import pinocchio as pin
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from oracles import (
    AXES,
    ReferenceDistribution,
    external_forces,
    frame_id,
    joint_angle,
    joint_v,
    millipede,
    placements,
    random_configuration,
    relative_error,
    rnea_torques,
    robot,
)

import virtual_actuators as va

TOL = 1e-8


def feet(name: str) -> tuple[str, ...]:
    """The four foot frames of a quadruped: body frames whose name ends with 'foot'."""
    model = robot(name).model
    out = tuple(
        f.name
        for f in model.frames
        if f.type == pin.FrameType.BODY and f.name.lower().endswith("_foot")
    )
    assert len(out) == 4, out
    return out


BASES = {"solo12": "base_link", "anymal": "base", "hyq_no_sensors": "base_link"}
SOLES = ("left_sole_link", "right_sole_link")
TALOS_ARMS = ("left_sole_link", "gripper_left_base_link", "gripper_right_base_link")


@dataclass(frozen=True)
class Setup:
    robot: str
    action: str
    reactions: tuple[str, ...]
    reference: str = "world"
    contact: object = "point"
    unactuated: tuple[str, ...] = ()
    passive: dict = field(default_factory=dict)
    design: tuple = ()
    free: tuple[str, ...] = ()
    axes: tuple[str, ...] = AXES
    scale: float = 0.3

    def actuator(self) -> va.ParallelVirtualActuator:
        return va.ParallelVirtualActuator(
            robot(self.robot),
            self.action,
            list(self.reactions),
            self.reference,
            self.axes,
            self.contact,
            unactuated=list(self.unactuated),
            passive=dict(self.passive),
            design=list(self.design),
        )

    def oracle(self) -> ReferenceDistribution:
        return ReferenceDistribution(
            robot(self.robot),
            self.action,
            self.reactions,
            self.reference,
            self.axes,
            self.contact,
            self.unactuated,
            self.passive,
            self.design,
        )

    def contacts(self) -> dict[str, str]:
        if isinstance(self.contact, str):
            return {r: self.contact for r in self.reactions}
        return {r: self.contact.get(r, "point") for r in self.reactions}

    def __str__(self) -> str:
        contact = self.contact if isinstance(self.contact, str) else "mixed"
        extras = "".join(
            f"-{k}{len(v)}"
            for k, v in (
                ("limp", self.unactuated),
                ("spring", self.passive),
                ("design", self.design),
                ("free", self.free),
            )
            if v
        )
        return f"{self.robot}:{self.action}:{self.reference}:{contact}{extras}"


def quadruped_setups() -> list[Setup]:
    out = []
    for name, base in BASES.items():
        legs = feet(name)
        mixed = {legs[0]: "flat", legs[3]: "flat", legs[1]: "point"}
        for reference in ("world", base):
            for contact in ("point", "flat", mixed):
                out.append(Setup(name, base, legs, reference, contact))
    return out


def _solo_design() -> tuple:
    fl, fr, hl, hr = feet("solo12")
    return (
        va.Equal((fr, "x"), (hl, "x")),
        va.Linear({(fl, "y"): 1.0, (fr, "y"): -2.0}, rhs=0.0),
        va.Linear({(hl, "z"): 1.0, (hr, "z"): 1.0, (fl, "rx"): 0.5}, rhs=3.0),
        va.EqualTorque("FL_KFE", "HR_KFE"),
    )


def special_setups() -> list[Setup]:
    fl, fr, hl, hr = feet("solo12")
    return [
        # humanoid: torso action, the chains share the two waist joints
        Setup("talos_reduced", "torso_2_link", SOLES, "world", "flat", scale=0.2),
        Setup("talos_reduced", "torso_2_link", SOLES, "base_link", "flat", scale=0.2),
        # limp waist yaw shared by both chains: it fixes the yaw moment, left free
        Setup(
            "talos_reduced",
            "torso_2_link",
            SOLES,
            "torso_1_link",
            "flat",
            unactuated=("torso_1_joint",),
            free=("rz",),
            scale=0.2,
        ),
        # waist shared by the two arm chains only: a true coupling (limp yaw, spring pitch)
        Setup(
            "talos_reduced",
            "base_link",
            TALOS_ARMS,
            "world",
            "flat",
            unactuated=("torso_1_joint",),
            passive={"torso_2_joint": (40.0, 0.1)},
            scale=0.2,
        ),
        Setup(
            "talos_reduced",
            "base_link",
            TALOS_ARMS,
            "base_link",
            {
                "left_sole_link": "flat",
                "gripper_left_base_link": "point",
                "gripper_right_base_link": "flat",
            },
            design=(va.EqualTorque("arm_left_4_joint", "arm_right_4_joint"),),
            scale=0.2,
        ),
        # limp and passive joints that belong to one chain each
        Setup(
            "solo12",
            "base_link",
            (fl, fr, hl, hr),
            "world",
            "flat",
            unactuated=("FL_HAA",),
            passive={"HR_KFE": (5.0, 1.2)},
        ),
        Setup(
            "solo12",
            "base_link",
            (fl, fr, hl, hr),
            "base_link",
            {fl: "flat", hr: "flat"},
            passive={"FR_HFE": (2.0, 0.7), "HL_KFE": (3.0, -1.0)},
        ),
        Setup("solo12", "base_link", (fl, fr, hl, hr), "world", "point", design=_solo_design()),
        Setup(
            "anymal",
            "base",
            feet("anymal"),
            "base",
            "point",
            design=(va.EqualTorque("LF_KFE", "RF_KFE"), va.EqualTorque("LH_HFE", "RH_HFE")),
        ),
        Setup("solo12", "base_link", (fl, fr, hl, hr), "world", "point", free=("x", "rz")),
        # three legs: r = 3
        Setup("hyq_no_sensors", "base_link", feet("hyq_no_sensors")[:3], "world", "point"),
        # subset of axes (a planar-like actuator)
        Setup("solo12", "base_link", (fl, fr, hl, hr), "world", "point", axes=("x", "z", "ry")),
    ]


SETUPS = quadruped_setups() + special_setups()
ACTUATORS: dict[str, va.ParallelVirtualActuator] = {}


def actuator(setup: Setup) -> va.ParallelVirtualActuator:
    key = str(setup) + repr(setup)
    if key not in ACTUATORS:
        ACTUATORS[key] = setup.actuator()
    return ACTUATORS[key]


def solve_random(setup: Setup, seed: int, method: str = "partitioned"):
    rob = robot(setup.robot)
    rng = np.random.default_rng(seed)
    q = random_configuration(rob, rng, setup.scale)
    wrench = rng.normal(scale=20.0, size=len(setup.axes))
    body = actuator(setup)
    return rob, body, q, wrench, body.solve(q, wrench, free=setup.free, method=method)


def rnea_of_forces(setup: Setup, q, forces) -> np.ndarray:
    pairs = [
        (setup.action, r, setup.reference, setup.axes, f)
        for r, f in zip(setup.reactions, forces, strict=True)
    ]
    return rnea_torques(setup.robot, q, external_forces(robot(setup.robot).model, q, pairs))


def kept(setup: Setup) -> np.ndarray:
    return np.array([a not in setup.free for a in setup.axes])


seeds = st.integers(0, 2**32 - 1)


@pytest.mark.parametrize("setup", SETUPS, ids=str)
@given(seed=seeds)
@settings(max_examples=8)
def test_forces_sum_to_wrench_and_admissible_request_is_met(setup, seed):
    """sol.forces.sum(0) == sol.wrench == request (prescribed axes), residual ~ 0."""
    _, _, _, wrench, sol = solve_random(setup, seed)
    keep = kept(setup)
    assert sol.forces.shape == (len(setup.reactions), len(setup.axes))
    np.testing.assert_allclose(
        sol.forces.sum(axis=0), sol.wrench, rtol=0, atol=1e-12 * max(1.0, np.abs(sol.forces).max())
    )
    assert sol.method in ("partitioned", "pseudo-inverse")
    assert sol.residual < TOL * max(1.0, np.linalg.norm(wrench))
    assert relative_error(sol.wrench[keep], wrench[keep]) < TOL
    np.testing.assert_array_equal(sol.requested[keep], wrench[keep])
    np.testing.assert_allclose(sol.requested[~keep], sol.wrench[~keep], atol=1e-12)
    for i, reaction in enumerate(setup.reactions):
        np.testing.assert_array_equal(sol.force(reaction), sol.forces[i])


@pytest.mark.parametrize("setup", SETUPS, ids=str)
@given(seed=seeds)
@settings(max_examples=8)
def test_tau_equals_rnea_of_chain_forces_with_limp_and_passive_joints(setup, seed):
    """RNEA(+F_i on B, -F_i on A_i): = sol.tau where actuated, 0 where limp, spring torque where
    passive, 0 on the floating base (no reaction is the world)."""
    rob, body, q, _, sol = solve_random(setup, seed)
    model = rob.model
    tau = rnea_of_forces(setup, q, sol.forces)
    scale = max(1.0, np.abs(tau).max())
    limp = [joint_v(model, j) for j in setup.unactuated]
    springs = {
        joint_v(model, j): -k * (joint_angle(model, q, j) - rest)
        for j, (k, rest) in setup.passive.items()
    }
    expected_passive = np.zeros(model.nv)
    for v, t in springs.items():
        expected_passive[v] = t
    np.testing.assert_allclose(sol.tau_passive, expected_passive, rtol=1e-12, atol=1e-12)
    actuated = np.ones(model.nv, dtype=bool)
    actuated[limp + list(springs)] = False
    np.testing.assert_allclose(sol.tau[actuated], tau[actuated], rtol=0, atol=TOL * scale)
    np.testing.assert_array_equal(sol.tau[~actuated], 0.0)
    np.testing.assert_allclose(tau[limp], 0.0, atol=TOL * scale)
    np.testing.assert_allclose(
        tau[list(springs)], expected_passive[list(springs)], atol=TOL * scale
    )
    np.testing.assert_allclose(tau[:6], 0.0, atol=TOL * scale)
    np.testing.assert_array_equal(sol.tau[:6], 0.0)
    # the public torques() of a given distribution is the full J^T F (limp/passive included)
    np.testing.assert_allclose(body.torques(q, sol.forces), tau, atol=TOL * scale)


@pytest.mark.parametrize("setup", [s for s in SETUPS if "point" in s.contacts().values()], ids=str)
@given(seed=seeds)
@settings(max_examples=8)
def test_point_contacts_exert_no_moment_about_reaction_origin(setup, seed):
    """m + d x f = 0 on the selected rotational axes, d = p_B - p_A in {O} (point contact)."""
    rob, _, q, _, sol = solve_random(setup, seed)
    model = rob.model
    data = placements(model, q)
    rot_o = data.oMf[frame_id(model, setup.reference)].rotation
    p_b = data.oMf[frame_id(model, setup.action)].translation
    rot_rows = [k for k in range(3) if AXES[3 + k] in setup.axes]
    for i, reaction in enumerate(setup.reactions):
        if setup.contacts()[reaction] != "point":
            continue
        f6 = np.zeros(6)
        f6[[AXES.index(a) for a in setup.axes]] = sol.forces[i]
        d = rot_o.T @ (p_b - data.oMf[frame_id(model, reaction)].translation)
        moment_at_a = f6[3:] + np.cross(d, f6[:3])
        scale = max(1.0, np.abs(f6).max())
        np.testing.assert_allclose(moment_at_a[rot_rows], 0.0, atol=TOL * scale)


@pytest.mark.parametrize("setup", SETUPS, ids=str)
@given(seed=seeds)
@settings(max_examples=8)
def test_distribution_is_the_minimum_norm_feasible_one(setup, seed):
    """Equals an independent pinv solution of the full system; no feasible change lowers it."""
    rob, body, q, wrench, sol = solve_random(setup, seed)
    oracle = setup.oracle()
    expected = oracle.solve(q, wrench, setup.free)
    assert relative_error(sol.forces, expected) < 1e-8
    directions = oracle.feasible_directions(q, wrench, setup.free)
    # optimality: the solution is orthogonal to every feasible direction
    flat = sol.forces.ravel()
    if directions.size:
        assert sol.method == "pseudo-inverse"
        assert np.abs(directions.T @ flat).max() < 1e-8 * max(1.0, np.abs(flat).max())
        rng = np.random.default_rng(seed)
        for _ in range(5):
            step = directions @ rng.normal(size=directions.shape[1])
            assert np.sum((flat + 1e-3 * step) ** 2) > np.sum(flat**2)
    else:
        assert sol.method == "partitioned"


@pytest.mark.parametrize("setup", SETUPS, ids=str)
@given(seed=seeds)
@settings(max_examples=12)
def test_partitioned_solver_equals_dense_solver(setup, seed):
    """method="partitioned" and method="dense" give the same forces, tau and method label."""
    _, _, _, _, sol = solve_random(setup, seed)
    _, _, _, _, dense = solve_random(setup, seed, method="dense")
    assert sol.solver == "partitioned" and dense.solver == "dense"
    assert relative_error(sol.forces, dense.forces) < TOL
    assert relative_error(sol.tau, dense.tau) < TOL
    assert sol.method == dense.method


DESIGNED = [s for s in SETUPS if s.design]


@pytest.mark.parametrize("setup", DESIGNED, ids=str)
@given(seed=seeds)
@settings(max_examples=10)
def test_design_constraints_hold(setup, seed):
    """Equal, Linear (with rhs) and EqualTorque hold exactly in the solution."""
    rob, _, q, _, sol = solve_random(setup, seed)
    model = rob.model
    index = {
        (r, a): (i, j) for i, r in enumerate(setup.reactions) for j, a in enumerate(setup.axes)
    }
    scale = max(1.0, np.abs(sol.forces).max())
    tau = rnea_of_forces(setup, q, sol.forces)
    for c in setup.design:
        if isinstance(c, va.Equal):
            assert abs(sol.forces[index[c.a]] - sol.forces[index[c.b]]) < TOL * scale
        elif isinstance(c, va.Linear):
            total = sum(k * sol.forces[index[label]] for label, k in c.coefficients.items())
            assert abs(total - c.rhs) < TOL * scale
        else:
            a, b = joint_v(model, c.joint_a), joint_v(model, c.joint_b)
            assert abs(sol.tau[a] - sol.tau[b]) < TOL * scale
            assert abs(tau[a] - tau[b]) < TOL * scale
            assert abs(sol.tau[a]) > 1e-6  # not trivially satisfied by zeros


# -- random design-constraint sets ----------------------------------------------------------------
RANDOM_SETUPS = [
    Setup("solo12", "base_link", feet("solo12"), "world", "point"),
    Setup("solo12", "base_link", feet("solo12"), "base_link", "flat"),
    Setup("anymal", "base", feet("anymal"), "world", {"LF_FOOT": "flat"}),
    Setup("talos_reduced", "torso_2_link", SOLES, "world", "flat", scale=0.2),
]


@st.composite
def design_sets(draw, setup: Setup, max_count: int):
    label = st.tuples(st.sampled_from(setup.reactions), st.sampled_from(setup.axes))
    count = draw(st.integers(0, max_count))
    out = []
    for _ in range(count):
        if draw(st.booleans()):
            out.append(va.Equal(draw(label), draw(label)))
        else:
            labels = draw(st.lists(label, min_size=1, max_size=4, unique=True))
            coeffs = [draw(st.sampled_from([-2.0, -1.0, -0.5, 0.5, 1.0, 3.0])) for _ in labels]
            rhs = draw(st.sampled_from([0.0, 1.0, -2.5]))
            out.append(va.Linear(dict(zip(labels, coeffs, strict=True)), rhs=rhs))
    return out


@pytest.mark.parametrize("base", RANDOM_SETUPS, ids=str)
@given(data=st.data(), seed=seeds)
@settings(max_examples=100)
def test_random_design_sets_partitioned_equals_dense_and_oracle(base, data, seed):
    """Random Equal/Linear sets (up to r): both solvers agree (forces, tau, method or error)."""
    r = actuator(base).sizes()["r"]
    design = data.draw(design_sets(base, r))
    setup = Setup(
        base.robot,
        base.action,
        base.reactions,
        base.reference,
        base.contact,
        design=tuple(design),
        scale=base.scale,
    )
    try:
        body = setup.actuator()
    except va.ConstraintError:
        return  # redundant or contradictory declaration: reported at construction
    rob = robot(setup.robot)
    rng = np.random.default_rng(seed)
    q = random_configuration(rob, rng, setup.scale)
    wrench = rng.normal(scale=20.0, size=6)
    outcomes = []
    for method in ("partitioned", "dense"):
        try:
            outcomes.append(body.solve(q, wrench, method=method))
        except (va.SingularConfigurationError, va.ConstraintError) as exc:
            outcomes.append(type(exc))
    part, dense = outcomes
    if isinstance(part, type) or isinstance(dense, type):
        assert part == dense, (part, dense)
        return
    assert part.method == dense.method
    assert part.method == ("partitioned" if len(design) == r else "pseudo-inverse") or (
        part.method == "least-squares"
    )
    assert relative_error(part.forces, dense.forces) < TOL
    assert relative_error(part.tau, dense.tau) < TOL
    if part.method != "least-squares":
        assert relative_error(part.forces, setup.oracle().solve(q, wrench)) < 1e-7


def generic_design(setup: Setup, count: int, rng) -> list:
    """``count`` Linear constraints with random coefficients on every entry (generic)."""
    out = []
    for _ in range(count):
        coeffs = {(r, a): float(rng.normal()) for r in setup.reactions for a in setup.axes}
        out.append(va.Linear(coeffs, rhs=float(rng.normal())))
    return out


@pytest.mark.parametrize("base", RANDOM_SETUPS, ids=str)
def test_generic_design_sets_up_to_r_are_accepted_and_labelled(base):
    """With <= r generic constraints construction and solving succeed; == r is "partitioned"
    (unique solution = oracle), < r is "pseudo-inverse" (minimum norm = oracle)."""
    r = actuator(base).sizes()["r"]
    rng = np.random.default_rng(42)
    rob = robot(base.robot)
    for count in range(r + 1):
        design = generic_design(base, count, rng)
        setup = Setup(
            base.robot,
            base.action,
            base.reactions,
            base.reference,
            base.contact,
            design=tuple(design),
            scale=base.scale,
        )
        body = setup.actuator()
        assert body.sizes()["design"] == count
        assert body.sizes()["r"] == r
        for _ in range(3):
            q = random_configuration(rob, rng, setup.scale)
            wrench = rng.normal(scale=20.0, size=6)
            sol = body.solve(q, wrench)
            assert sol.method == ("partitioned" if count == r else "pseudo-inverse")
            assert len(sol.sets["RFS"]) == r and len(sol.sets["MFS"]) == 6
            assert relative_error(sol.forces, setup.oracle().solve(q, wrench)) < 1e-7
            assert relative_error(sol.forces, body.solve(q, wrench, method="dense").forces) < TOL


@pytest.mark.parametrize("setup", SETUPS, ids=str)
def test_sets_partition_all_force_entries(setup):
    """MFS, RFS and CFS are disjoint and cover every (reaction, axis) label; sizes match sizes()."""
    _, body, _, _, sol = solve_random(setup, 3)
    sizes = body.sizes()
    labels = [(r, a) for r in setup.reactions for a in setup.axes]
    together = sol.sets["MFS"] + sol.sets["RFS"] + sol.sets["CFS"]
    assert sorted(together) == sorted(labels)
    assert len(sol.sets["CFS"]) == sizes["l_total"]
    assert len(sol.sets["MFS"]) == len(setup.axes) - len(setup.free)
    assert sizes["l_total"] + sizes["d_total"] == len(labels)
    assert sizes["r"] == sizes["d_total"] - len(setup.axes)


# -- linearity and free axes ----------------------------------------------------------------------
LINEAR_SETUPS = [
    s for s in SETUPS if not s.passive and all(getattr(c, "rhs", 0.0) == 0.0 for c in s.design)
]


@pytest.mark.parametrize("setup", LINEAR_SETUPS, ids=str)
@given(seed=seeds, a=st.floats(-3, 3), b=st.floats(-3, 3))
@settings(max_examples=5)
def test_distribution_is_linear_in_the_wrench(setup, seed, a, b):
    """Without springs or constraint right-hand sides: F(a w1 + b w2) = a F(w1) + b F(w2)."""
    rob = robot(setup.robot)
    rng = np.random.default_rng(seed)
    q = random_configuration(rob, rng, setup.scale)
    w1, w2 = rng.normal(scale=10.0, size=(2, len(setup.axes)))
    body = actuator(setup)
    f1, f2, f12 = (body.solve(q, w, free=setup.free).forces for w in (w1, w2, a * w1 + b * w2))
    assert relative_error(f12, a * f1 + b * f2) < 1e-9 * max(1.0, abs(a) + abs(b))


@pytest.mark.parametrize("setup", [s for s in SETUPS if s.robot == "solo12"][:4], ids=str)
@given(seed=seeds, x=st.floats(-1e3, 1e3))
@settings(max_examples=5)
def test_free_axis_value_is_ignored(setup, seed, x):
    """free=("x",): the request's x entry does not change the solution."""
    rob = robot(setup.robot)
    rng = np.random.default_rng(seed)
    q = random_configuration(rob, rng, setup.scale)
    wrench = rng.normal(scale=10.0, size=6)
    body = actuator(setup)
    other = wrench.copy()
    other[0] = x
    s1, s2 = body.solve(q, wrench, free=("x",)), body.solve(q, other, free=("x",))
    np.testing.assert_array_equal(s1.forces, s2.forces)
    assert s1.free == ("x",)
    np.testing.assert_allclose(s1.wrench[1:], wrench[1:], atol=TOL * 10)
    assert s1.requested[0] == s1.wrench[0]
    # free x (r = 7 with no design constraint): minimum norm with x unconstrained
    expected = setup.oracle().solve(q, wrench, free=("x",))
    assert relative_error(s1.forces, expected) < 1e-8


# -- inadmissible requests -----------------------------------------------------------------------
def test_single_point_leg_with_six_axes_is_least_squares_projection():
    """One solo12 leg, point foot, 6 axes: only forces through the foot; least squares."""
    rob = robot("solo12")
    model = rob.model
    body = va.ParallelVirtualActuator(rob, "base_link", ["FL_FOOT"], "world", AXES, "point")
    assert body.sizes()["r"] == -3
    rng = np.random.default_rng(0)
    for _ in range(10):
        q = random_configuration(rob, rng)
        wrench = rng.normal(scale=10.0, size=6)
        sol = body.solve(q, wrench)
        data = placements(model, q)
        d = (
            data.oMf[frame_id(model, "base_link")].translation
            - data.oMf[frame_id(model, "FL_FOOT")].translation
        )
        # producible wrenches: (f, -d x f); least squares = orthogonal projection on that space
        basis = np.array([np.concatenate((e, -np.cross(d, e))) for e in np.eye(3)]).T
        expected = basis @ np.linalg.lstsq(basis, wrench, rcond=None)[0]
        assert sol.method == "least-squares"
        assert not sol.admissible
        np.testing.assert_allclose(sol.forces[0], expected, atol=1e-9 * np.abs(wrench).max())
        assert sol.residual == pytest.approx(np.linalg.norm(wrench - expected), rel=1e-9)
        assert sol.residual > 1e-3
        with pytest.raises(va.InadmissibleWrenchError) as info:
            body.solve(q, wrench, strict=True)
        assert info.value.solution.method == "least-squares"
        np.testing.assert_allclose(info.value.solution.forces, sol.forces)
        # the produced wrench itself is admissible, and strict accepts it
        again = body.solve(q, sol.wrench, strict=True)
        assert again.residual < TOL


def test_shared_limp_waist_with_six_axes_is_least_squares_with_exact_constraints():
    """talos torso on two soles, limp waist yaw shared by both chains, all 6 axes prescribed:
    the waist fixes one wrench component, so a generic request is met in the least-squares
    sense while the limp joint and the design constraints hold exactly."""
    design = (
        va.Equal(("left_sole_link", "z"), ("right_sole_link", "z")),
        va.Linear({("left_sole_link", "x"): 1.0, ("right_sole_link", "y"): 2.0}, rhs=4.0),
    )
    setup = Setup(
        "talos_reduced",
        "torso_2_link",
        SOLES,
        "world",
        "flat",
        unactuated=("torso_1_joint",),
        design=design,
        scale=0.2,
    )
    body = setup.actuator()
    rob = robot(setup.robot)
    model = rob.model
    rng = np.random.default_rng(1)
    for _ in range(4):
        q = random_configuration(rob, rng, setup.scale)
        wrench = rng.normal(scale=20.0, size=6)
        sol = body.solve(q, wrench)
        assert sol.method == "least-squares" and sol.residual > 1e-3
        tau = rnea_of_forces(setup, q, sol.forces)
        scale = max(1.0, np.abs(sol.forces).max())
        assert abs(tau[joint_v(model, "torso_1_joint")]) < TOL * scale
        f = dict(zip(SOLES, sol.forces, strict=True))
        assert abs(f["left_sole_link"][2] - f["right_sole_link"][2]) < TOL * scale
        assert abs(f["left_sole_link"][0] + 2 * f["right_sole_link"][1] - 4.0) < TOL * scale
        expected = setup.oracle().least_squares(q, wrench)
        assert relative_error(sol.forces, expected) < 1e-8
        assert relative_error(body.solve(q, wrench, method="dense").forces, expected) < 1e-8
        with pytest.raises(va.InadmissibleWrenchError):
            body.solve(q, wrench, strict=True)


@pytest.mark.parametrize(
    ("name", "action", "stance"),
    [("solo12", "base_link", ("FL_FOOT", "HR_FOOT")), ("talos_reduced", "torso_2_link", SOLES)],
    ids=["solo12-trot", "talos-point-soles"],
)
def test_two_point_feet_admissible_wrench_is_solved(name, action, stance):
    """Two point feet (a trot stance): (f1, -d1 x f1) + (f2, -d2 x f2) is producible.

    The chains produce any wrench with no moment about the line through the two feet and can
    squeeze along that line (one redundancy), so such a request must be met (residual ~ 0) by
    the minimum-norm distribution, not refused as a singular configuration.
    """
    rob = robot(name)
    model = rob.model
    body = va.ParallelVirtualActuator(rob, action, list(stance), "world", AXES, "point")
    rng = np.random.default_rng(0)
    q = random_configuration(rob, rng, 0.2)
    data = placements(model, q)
    p_b = data.oMf[frame_id(model, action)].translation
    wrench = np.zeros(6)
    for foot in stance:
        f = rng.normal(size=3) + np.array([0.0, 0.0, 10.0])
        d = p_b - data.oMf[frame_id(model, foot)].translation
        wrench += np.concatenate((f, -np.cross(d, f)))
    expected = ReferenceDistribution(rob, action, stance, "world", AXES, "point").solve(q, wrench)
    np.testing.assert_allclose(expected.sum(axis=0), wrench, atol=1e-9 * np.abs(wrench).max())
    sol = body.solve(q, wrench)
    assert sol.residual < TOL * np.linalg.norm(wrench)
    assert relative_error(sol.forces, expected) < 1e-8


@pytest.mark.parametrize("method", ["partitioned", "dense"])
@pytest.mark.parametrize(
    ("name", "action", "stance"),
    [("solo12", "base_link", ("FL_FOOT", "HR_FOOT")), ("talos_reduced", "torso_2_link", SOLES)],
    ids=["solo12-trot", "talos-point-soles"],
)
def test_two_point_feet_generic_request_is_least_squares(name, action, stance, method):
    """A moment about the line through two point feet cannot be produced: least squares, zero
    moments about each foot kept exactly, equal to the independent least-squares oracle."""
    rob = robot(name)
    setup = Setup(name, action, stance, "world", "point")
    body = setup.actuator()
    rng = np.random.default_rng(2)
    for _ in range(3):
        q = random_configuration(rob, rng, 0.2)
        wrench = rng.normal(scale=10.0, size=6)
        sol = body.solve(q, wrench, method=method)
        expected = setup.oracle().least_squares(q, wrench)
        assert sol.method == "least-squares"
        assert relative_error(sol.forces, expected) < 1e-8
        assert sol.residual == pytest.approx(np.linalg.norm(expected.sum(0) - wrench), rel=1e-8)
        assert sol.residual > 1e-3
        data = placements(rob.model, q)
        p_b = data.oMf[frame_id(rob.model, action)].translation
        for foot, f in zip(stance, sol.forces, strict=True):
            d = p_b - data.oMf[frame_id(rob.model, foot)].translation
            np.testing.assert_allclose(f[3:] + np.cross(d, f[:3]), 0.0, atol=TOL * np.abs(f).max())


@pytest.mark.parametrize("method", ["partitioned", "dense"])
@pytest.mark.parametrize("case", ["shared-limp-waist", "design-fixes-wrench"])
def test_square_but_structurally_singular_declaration_gives_least_squares(case, method):
    """Square counts (design == r) whose rows are dependent at every q: least squares with
    exact constraints, not a SingularConfigurationError.

    shared-limp-waist: torso on both soles with a limp waist yaw shared by both chains (its
    coupling row restates a wrench component) plus 5 Equal constraints; design-fixes-wrench:
    Equal constraints that together force w_x = w_y.
    """
    left, right = SOLES
    if case == "shared-limp-waist":
        design = tuple(va.Equal((left, a), (right, a)) for a in AXES[:5])
        limp = ("torso_1_joint",)
    else:
        design = (va.Equal((left, "x"), (left, "y")), va.Equal((right, "x"), (right, "y"))) + tuple(
            va.Equal((left, a), (right, a)) for a in AXES[2:]
        )
        limp = ()
    setup = Setup(
        "talos_reduced",
        "torso_2_link",
        SOLES,
        "world",
        "flat",
        unactuated=limp,
        design=design,
        scale=0.2,
    )
    body = setup.actuator()
    assert body.sizes()["design"] == body.sizes()["r"] == 6
    rng = np.random.default_rng(3)
    model = robot(setup.robot).model
    for _ in range(3):
        q = random_configuration(robot(setup.robot), rng, setup.scale)
        wrench = rng.normal(scale=10.0, size=6)
        sol = body.solve(q, wrench, method=method)
        assert sol.method == "least-squares" and sol.residual > 1e-3
        assert relative_error(sol.forces, setup.oracle().least_squares(q, wrench)) < 1e-8
        scale = max(1.0, np.abs(sol.forces).max())
        index = {(r, a): (i, j) for i, r in enumerate(SOLES) for j, a in enumerate(AXES)}
        for c in design:
            assert abs(sol.forces[index[c.a]] - sol.forces[index[c.b]]) < TOL * scale
        if limp:
            tau = rnea_of_forces(setup, q, sol.forces)
            assert abs(tau[joint_v(model, "torso_1_joint")]) < TOL * scale


@pytest.mark.parametrize("free", [(), ("rz",)])
def test_both_solvers_agree_when_design_constraints_exceed_redundancy(free):
    """r < design count <= sum d: "partitioned" and "dense" must give the same outcome.

    The dense solver is documented as the partitioned solver's reference with the same
    semantics; with 7 generic constraints and r = 6 one raises and the other does not.
    """
    base = Setup("solo12", "base_link", feet("solo12"), "world", "point")
    rng = np.random.default_rng(1)
    body = Setup(
        base.robot,
        base.action,
        base.reactions,
        design=tuple(generic_design(base, 7 + len(free), rng)),
    ).actuator()
    q = random_configuration(robot("solo12"), rng, 0.3)
    wrench = rng.normal(scale=10.0, size=6)
    outcomes = []
    for method in ("partitioned", "dense"):
        try:
            sol = body.solve(q, wrench, free=free, method=method)
            outcomes.append((sol.method, np.round(sol.forces, 9).tolist()))
        except va.VirtualActuatorError as exc:
            outcomes.append(type(exc).__name__)
    assert outcomes[0] == outcomes[1]


# -- chains to the world, limp chains, call history --------------------------------------------
def test_single_world_chain_equals_serial_actuator():
    """ur5 tool0 on the world, flat, 6 axes: r = 0, F = w, tau = serial torques = RNEA."""
    rob = robot("ur5_robot")
    body = va.ParallelVirtualActuator(rob, "tool0", ["world"], "world", AXES, "flat")
    assert body.sizes()["r"] == 0
    leg = va.VirtualActuator(rob, "tool0", "world", "world", AXES)
    rng = np.random.default_rng(4)
    for _ in range(5):
        q = random_configuration(rob, rng)
        wrench = rng.normal(scale=10.0, size=6)
        sol = body.solve(q, wrench)
        assert sol.method == "partitioned"
        np.testing.assert_allclose(sol.forces[0], wrench, atol=1e-9 * np.abs(wrench).max())
        tau = rnea_torques(
            "ur5_robot",
            q,
            external_forces(rob.model, q, [("tool0", "world", "world", AXES, wrench)]),
        )
        np.testing.assert_allclose(sol.tau, tau, atol=1e-9 * np.abs(tau).max())
        np.testing.assert_allclose(sol.tau, leg.torques(q, wrench), atol=1e-12)
        assert sol.base_effort.size == 0


def test_chain_to_world_reports_floating_base_effort():
    """solo12 base on the world and on one flat leg: the base chain's effort is reported."""
    rob = robot("solo12")
    setup = Setup("solo12", "base_link", ("world", "FL_FOOT"), "world", "flat")
    body = setup.actuator()
    rng = np.random.default_rng(5)
    for _ in range(5):
        q = random_configuration(rob, rng)
        wrench = rng.normal(scale=10.0, size=6)
        sol = body.solve(q, wrench)
        tau = rnea_of_forces(setup, q, sol.forces)
        np.testing.assert_allclose(sol.tau, tau, atol=TOL * np.abs(tau).max())
        assert np.abs(tau[:6]).max() > 1e-3
        np.testing.assert_array_equal(sol.base_effort, sol.tau[:6])
        assert relative_error(sol.forces, setup.oracle().solve(q, wrench)) < 1e-8


def test_fully_limp_leg_exerts_nothing():
    """Every joint of one flat leg limp: that chain's wrench is zero, the others carry all."""
    fl, fr, hl, hr = feet("solo12")
    setup = Setup(
        "solo12",
        "base_link",
        (fl, fr, hl, hr),
        "world",
        "flat",
        unactuated=("FL_HAA", "FL_HFE", "FL_KFE"),
    )
    body = setup.actuator()
    assert body.sizes()["r"] == 3
    rng = np.random.default_rng(6)
    for _ in range(5):
        q = random_configuration(robot("solo12"), rng)
        wrench = rng.normal(scale=10.0, size=6)
        sol = body.solve(q, wrench)
        np.testing.assert_allclose(sol.forces[0], 0.0, atol=1e-9 * np.abs(wrench).max())
        assert relative_error(sol.wrench, wrench) < TOL
        assert relative_error(sol.forces, setup.oracle().solve(q, wrench)) < 1e-8


def test_results_do_not_depend_on_call_history():
    """Interleaved solves (methods, free axes, configurations) on one actuator equal the
    solves of a fresh actuator: caches keyed on free axes / sets must not leak."""
    base = Setup("solo12", "base_link", feet("solo12"), "world", "flat")
    rng = np.random.default_rng(8)
    design = tuple(generic_design(base, 6, rng)) + (va.EqualTorque("FL_KFE", "HR_HFE"),)
    setup = Setup(base.robot, base.action, base.reactions, base.reference, "flat", design=design)
    shared = setup.actuator()
    frees = [("x",), ("x", "rz"), ("y", "z"), ("x",)]
    calls = []
    for k in range(16):
        q = random_configuration(robot("solo12"), rng, 0.5)
        calls.append(
            (q, rng.normal(scale=10.0, size=6), frees[k % 4], ("partitioned", "dense")[k % 3 == 0])
        )
    first = [shared.solve(q, w, free=f, method=m) for q, w, f, m in calls]
    for (q, w, f, m), sol in zip(calls, first, strict=True):
        fresh = setup.actuator().solve(q, w, free=f, method=m)
        assert sol.method == fresh.method
        assert relative_error(sol.forces, fresh.forces) < 1e-10
        # and the free-axis result is the minimum-norm one over all free values
        assert relative_error(sol.forces, setup.oracle().solve(q, w, free=f)) < 1e-7


# -- millipede -------------------------------------------------------------------------------------
@pytest.mark.parametrize("legs", [3, 10, 100])
def test_millipede_sizes_and_sets(legs):
    """N legs of 2 joints, point feet, 6 axes: l = 4 per leg, d = 2, r = 2N - 6."""
    rob = millipede(legs)
    reactions = [f"foot_{i}" for i in range(1, legs + 1)]
    body = va.ParallelVirtualActuator(rob, "body", reactions, "world", AXES, "point")
    assert body.sizes() == {
        "n": 6,
        "p": legs,
        "l_total": 4 * legs,
        "d_total": 2 * legs,
        "r": 2 * legs - 6,
        "design": 0,
    }
    rng = np.random.default_rng(legs)
    q = random_configuration(rob, rng, 0.2)
    wrench = rng.normal(scale=10.0, size=6)
    sol = body.solve(q, wrench)
    assert sol.method == ("partitioned" if legs == 3 else "pseudo-inverse")
    assert {k: len(v) for k, v in sol.sets.items()} == {
        "MFS": 6,
        "RFS": 2 * legs - 6,
        "CFS": 4 * legs,
    }
    assert sol.residual < TOL * np.linalg.norm(wrench)
    dense = body.solve(q, wrench, method="dense")
    assert relative_error(sol.forces, dense.forces) < TOL
    assert relative_error(sol.tau, dense.tau) < TOL
    setup = Setup("millipede", "body", tuple(reactions))
    tau = rnea_torques(
        zero_g_millipede(legs),
        q,
        external_forces(
            rob.model,
            q,
            [("body", r, "world", AXES, f) for r, f in zip(reactions, sol.forces, strict=True)],
        ),
    )
    np.testing.assert_allclose(sol.tau, tau, atol=TOL * max(1.0, np.abs(tau).max()))
    np.testing.assert_allclose(tau[:6], 0.0, atol=TOL * max(1.0, np.abs(tau).max()))
    if legs <= 10:
        oracle = ReferenceDistribution(rob, setup.action, reactions, "world", AXES, "point")
        assert relative_error(sol.forces, oracle.solve(q, wrench)) < 1e-7


def zero_g_millipede(legs: int) -> pin.Model:
    model = pin.Model(millipede(legs).model)
    model.gravity.setZero()
    return model


@given(seed=seeds)
@settings(max_examples=15)
def test_millipede_ten_legs_with_r_equal_constraints_is_partitioned_and_equals_dense(seed):
    """N = 10, r = 14 random Equal constraints over the legs' free entries: "partitioned"."""
    legs = 10
    rob = millipede(legs)
    reactions = [f"foot_{i}" for i in range(1, legs + 1)]
    rng = np.random.default_rng(seed)
    design = []
    # Equal x and z entries of random leg pairs (each leg can set forces in its plane)
    pairs = [(i, j) for i in range(legs) for j in range(i + 1, legs)]
    for k in rng.permutation(len(pairs))[:14]:
        i, j = pairs[k]
        axis = "y" if rng.random() < 0.5 else "z"
        design.append(va.Equal((reactions[i], axis), (reactions[j], axis)))
    try:
        body = va.ParallelVirtualActuator(
            rob, "body", reactions, "world", AXES, "point", design=design
        )
    except va.ConstraintError:
        return
    q = random_configuration(rob, rng, 0.2)
    wrench = rng.normal(scale=10.0, size=6)
    try:
        sol = body.solve(q, wrench)
    except va.SingularConfigurationError:
        with pytest.raises(va.SingularConfigurationError):
            body.solve(q, wrench, method="dense")
        return
    assert sol.method == "partitioned"
    assert len(sol.sets["RFS"]) == 14
    dense = body.solve(q, wrench, method="dense")
    assert relative_error(sol.forces, dense.forces) < TOL
    assert (
        relative_error(
            sol.forces,
            ReferenceDistribution(
                rob, "body", reactions, "world", AXES, "point", design=design
            ).solve(q, wrench),
        )
        < 1e-7
    )


def test_millipede_ten_legs_generic_constraints_count_r_is_partitioned():
    """r = 14 generic Linear constraints: always accepted, "partitioned", equals the oracle."""
    legs = 10
    rob = millipede(legs)
    reactions = tuple(f"foot_{i}" for i in range(1, legs + 1))
    setup = Setup("millipede", "body", reactions)
    rng = np.random.default_rng(7)
    design = generic_design(setup, 14, rng)
    body = va.ParallelVirtualActuator(
        rob, "body", list(reactions), "world", AXES, "point", design=design
    )
    for _ in range(5):
        q = random_configuration(rob, rng, 0.2)
        wrench = rng.normal(scale=10.0, size=6)
        sol = body.solve(q, wrench)
        assert sol.method == "partitioned"
        assert relative_error(sol.forces, body.solve(q, wrench, method="dense").forces) < TOL
        oracle = ReferenceDistribution(
            rob, "body", reactions, "world", AXES, "point", design=design
        )
        assert relative_error(sol.forces, oracle.solve(q, wrench)) < 1e-7
