"""Every error path: the exact exception type, and a message naming the offending thing."""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest
from oracles import AXES, random_configuration, robot

import virtual_actuators as va

FEET = ["FL_FOOT", "FR_FOOT", "HL_FOOT", "HR_FOOT"]
A, B = ("FL_FOOT", "x"), ("FR_FOOT", "x")


@pytest.fixture(scope="module")
def solo():
    return robot("solo12")


@pytest.fixture(scope="module")
def q(solo):
    return random_configuration(solo, np.random.default_rng(0), 0.3)


def body(solo, reactions=FEET, reference="world", axes=AXES, contact="point", **kw):
    return va.ParallelVirtualActuator(solo, "base_link", reactions, reference, axes, contact, **kw)


def raises(kind, *fragments):
    """Context manager: ``kind`` exactly (not a sibling) with every fragment in the message."""

    class _Check:
        def __enter__(self):
            self.ctx = pytest.raises(kind)
            self.info = self.ctx.__enter__()
            return self.info

        def __exit__(self, *exc):
            handled = self.ctx.__exit__(*exc)
            assert type(self.info.value) is kind, type(self.info.value)
            assert isinstance(self.info.value, va.VirtualActuatorError)
            message = str(self.info.value)
            for fragment in fragments:
                assert fragment in message, (fragment, message)
            return handled

    return _Check()


# -- frames ----------------------------------------------------------------------------------------
@pytest.mark.parametrize(
    ("kwargs", "bad", "suggested"),
    [
        ({"action": "base_link", "reaction": "FL_FOT"}, "FL_FOT", "FL_FOOT"),
        ({"action": "base_lnk", "reaction": "FL_FOOT"}, "base_lnk", "base_link"),
        ({"action": "base_link", "reaction": "FL_FOOT", "reference": "wrld"}, "wrld", "world"),
        ({"action": "base_link", "reaction": "HR_FOOTT"}, "HR_FOOTT", "HR_FOOT"),
    ],
)
def test_unknown_frame_names_it_and_lists_close_matches(solo, kwargs, bad, suggested):
    with raises(va.FrameNotFoundError, repr(bad), repr(suggested)):
        va.VirtualActuator(solo, **kwargs)


def test_unknown_reaction_of_parallel_actuator_names_it(solo):
    with raises(va.FrameNotFoundError, "'HR_FOTO'", "'HR_FOOT'"):
        body(solo, reactions=["FL_FOOT", "HR_FOTO"])


def test_non_string_frame_is_frame_not_found(solo):
    with raises(va.FrameNotFoundError, "3"):
        va.VirtualActuator(solo, "base_link", 3)


def test_frame_errors_are_lookup_errors(solo):
    with pytest.raises(LookupError):
        va.VirtualActuator(solo, "base_link", "nope")


# -- axes ------------------------------------------------------------------------------------------
@pytest.mark.parametrize(
    ("axes", "fragment"),
    [
        (("x", "w"), "'w'"),
        (("X",), "'X'"),
        (("z", "x"), "out of order"),
        (("x", "x"), "twice"),
        (("rx", "x"), "out of order"),
        ((), "At least one axis"),
        ("xyz", "'xyz'"),
    ],
)
def test_bad_axes_raise_invalid_axis_error(solo, axes, fragment):
    with raises(va.InvalidAxisError, fragment):
        va.VirtualActuator(solo, "base_link", "FL_FOOT", axes=axes)
    with raises(va.InvalidAxisError, fragment):
        body(solo, axes=axes)


def test_out_of_order_axes_message_gives_the_canonical_order(solo):
    with raises(va.InvalidAxisError, "('x', 'z')"):
        va.VirtualActuator(solo, "base_link", "FL_FOOT", axes=("z", "x"))


def test_free_axis_not_among_axes_is_invalid_axis(solo, q):
    actuator = body(solo, axes=("x", "y", "z"))
    with raises(va.InvalidAxisError, "'rz'"):
        actuator.solve(q, np.zeros(3), free=("rz",))
    with raises(va.InvalidAxisError, "'w'"):
        actuator.solve(q, np.zeros(3), free=("w",))


def test_design_label_with_axis_not_among_axes_is_invalid_axis(solo):
    with raises(va.InvalidAxisError, "'rz'"):
        body(solo, axes=("x", "y", "z"), design=[va.Equal(A, ("FR_FOOT", "rz"))])


# -- joints ----------------------------------------------------------------------------------------
@pytest.mark.parametrize(
    ("kwargs", "bad", "suggested"),
    [
        ({"unactuated": ["FL_KNEE"]}, "FL_KNEE", "FL_KFE"),
        ({"unactuated": "FL_KNEE"}, "FL_KNEE", "FL_KFE"),
        ({"passive": {"HR_KNE": (1.0, 0.0)}}, "HR_KNE", "HR_KFE"),
        ({"design": [va.EqualTorque("FL_KFE", "HR_KNE")]}, "HR_KNE", "HR_KFE"),
    ],
)
def test_unknown_joint_names_it_and_lists_close_matches(solo, kwargs, bad, suggested):
    with raises(va.JointNotFoundError, repr(bad), repr(suggested)):
        body(solo, **kwargs)


@pytest.mark.parametrize(
    "kwargs",
    [
        {"unactuated": ["HL_KFE"]},
        {"passive": {"HL_KFE": (1.0, 0.0)}},
        {"design": [va.EqualTorque("FL_KFE", "HL_KFE")]},
        {"unactuated": ["root_joint"]},
    ],
)
def test_joint_not_on_any_chain_is_joint_not_found(solo, kwargs):
    name = "root_joint" if kwargs.get("unactuated") == ["root_joint"] else "HL_KFE"
    with raises(va.JointNotFoundError, repr(name), "not on any chain", "FL_KFE"):
        body(solo, reactions=["FL_FOOT", "FR_FOOT"], **kwargs)


# -- array inputs ----------------------------------------------------------------------------------
def test_wrong_configuration_shape(solo, q):
    leg = va.VirtualActuator(solo, "base_link", "FL_FOOT")
    for bad in (q[:-1], q[:, None], np.zeros(solo.model.nv)):
        with raises(va.InvalidInputError, "(19,)"):
            leg.position(bad)
        with raises(va.InvalidInputError, "(19,)"):
            body(solo).solve(bad, np.zeros(6))


@pytest.mark.parametrize("value", [np.nan, np.inf, -np.inf])
def test_non_finite_configuration(solo, q, value):
    bad = q.copy()
    bad[9] = value
    leg = va.VirtualActuator(solo, "base_link", "FL_FOOT")
    for call in (
        lambda: leg.jacobian(bad),
        lambda: leg.torques(bad, np.zeros(6)),
        lambda: leg.is_admissible(bad, np.zeros(6)),
        lambda: body(solo).solve(bad, np.zeros(6)),
    ):
        with raises(va.InvalidInputError, "[9]"):
            call()


@pytest.mark.parametrize("factor", [0.0, 0.5, 1.1, 2.0])
def test_non_unit_quaternion(solo, q, factor):
    bad = q.copy()
    bad[3:7] *= factor
    with raises(va.InvalidInputError, "quaternion", "q[3:7]"):
        va.VirtualActuator(solo, "base_link", "FL_FOOT").position(bad)
    with raises(va.InvalidInputError, "quaternion"):
        body(solo).solve(bad, np.zeros(6))


def test_non_unit_cos_sin_pair_of_continuous_joint_is_rejected():
    """A continuous joint's (cos, sin) pair is as constrained as a quaternion.

    Today (3, 0) is accepted silently and the kinematics are computed with a scaled "rotation"
    (the end effector moves by 0.2 m), while an off-unit quaternion is rejected.
    """
    rob = va.load_robot("double_pendulum_continuous")
    leg = va.VirtualActuator(rob, "link2", "world")
    bad = pin.neutral(rob.model)
    bad[:2] *= 3.0
    with raises(va.InvalidInputError):
        leg.position(bad)


@pytest.mark.parametrize("shape", [(5,), (7,), (6, 1), (1, 6), ()])
def test_wrong_wrench_shape(solo, q, shape):
    leg = va.VirtualActuator(solo, "base_link", "FL_FOOT")
    with raises(va.InvalidInputError, str(shape), "(6,)"):
        leg.torques(q, np.zeros(shape))
    with raises(va.InvalidInputError, str(shape)):
        leg.is_admissible(q, np.zeros(shape))
    with raises(va.InvalidInputError, str(shape)):
        body(solo).solve(q, np.zeros(shape))


@pytest.mark.parametrize("value", [np.nan, np.inf, -np.inf])
def test_non_finite_wrench(solo, q, value):
    wrench = np.array([0.0, 1.0, value, 0.0, 0.0, 0.0])
    leg = va.VirtualActuator(solo, "base_link", "FL_FOOT")
    for call in (
        lambda: leg.torques(q, wrench),
        lambda: leg.is_admissible(q, wrench),
        lambda: body(solo).solve(q, wrench),
    ):
        with raises(va.InvalidInputError, "NaN or inf"):
            call()


def test_non_finite_wrench_on_a_free_axis_is_still_rejected(solo, q):
    with raises(va.InvalidInputError, "NaN or inf"):
        body(solo).solve(q, np.array([np.nan, 0, 0, 0, 0, 0]), free=("x",))


def test_bad_velocity(solo, q):
    leg = va.VirtualActuator(solo, "base_link", "FL_FOOT")
    with raises(va.InvalidInputError, "(18,)"):
        leg.velocity(q, np.zeros(19))
    with raises(va.InvalidInputError, "NaN or inf"):
        leg.velocity(q, np.full(18, np.nan))


def test_bad_method_and_bad_forces(solo, q):
    actuator = body(solo, contact="flat")
    with raises(va.InvalidInputError, "'qr'"):
        actuator.solve(q, np.zeros(6), method="qr")
    with raises(va.InvalidInputError, "(4, 6)"):
        actuator.torques(q, np.zeros((3, 6)))
    with raises(va.InvalidInputError, "(4, 6)"):
        actuator.torques(q, np.full((4, 6), np.inf))


# -- declarations ----------------------------------------------------------------------------------
def test_contradictory_constraints(solo):
    with raises(va.ConstraintError, "contradicts", "rhs=1"):
        body(solo, design=[va.Equal(A, B), va.Linear({A: 1.0, B: -1.0}, rhs=1.0)])


@pytest.mark.parametrize(
    "second",
    [va.Equal(A, B), va.Equal(B, A), va.Linear({A: 2.0, B: -2.0}, rhs=0.0)],
)
def test_redundant_constraints_are_implied(solo, second):
    with raises(va.ConstraintError, "implied"):
        body(solo, design=[va.Equal(A, B), second])


def test_constraint_implied_by_three_others(solo):
    c = ("HL_FOOT", "x")
    with raises(va.ConstraintError, "implied"):
        body(solo, design=[va.Equal(A, B), va.Equal(B, c), va.Equal(A, c)])


def test_limp_joint_at_point_contact_makes_natural_constraints_redundant(solo):
    """Reaction at the knee frame, point contact, limp knee: the knee's zero torque is already
    a zero moment about the reaction origin (its axis passes through it): redundant."""
    with raises(va.ConstraintError, "redundant", "'FL_KFE'"):
        body(solo, reactions=["FL_KFE", "FR_FOOT"], unactuated=["FL_KFE"])
    # the same limp knee with a flat contact is fine
    body(solo, reactions=["FL_KFE", "FR_FOOT"], unactuated=["FL_KFE"], contact="flat")


def test_too_many_design_constraints_at_construction(solo):
    rng = np.random.default_rng(0)
    design = [
        va.Linear({(f, a): float(rng.normal()) for f in FEET for a in AXES}) for _ in range(13)
    ]
    with raises(va.ConstraintError, "Too many", "13", "12"):
        body(solo, design=design)


def test_more_constraints_than_redundancies_rejected_at_solve(solo, q):
    rng = np.random.default_rng(1)
    design = [
        va.Linear({(f, a): float(rng.normal()) for f in FEET for a in AXES}, rhs=1.0)
        for _ in range(7)
    ]
    actuator = body(solo, design=design)
    with raises(va.ConstraintError, "Too many", "7"):
        actuator.solve(q, np.ones(6))
    # one free axis leaves room for the seventh constraint
    assert actuator.solve(q, np.ones(6), free=("x",)).method == "partitioned"


@pytest.mark.parametrize(
    ("design", "fragment"),
    [
        ([va.Equal(A, A)], "itself"),
        ([va.Linear({})], "no coefficient"),
        ([va.Equal(A, ("XX_FOOT", "x"))], "'XX_FOOT'"),
        ([va.Linear({A: float("nan")})], "NaN"),
        ([va.Linear({A: 1.0}, rhs=float("inf"))], "inf"),
        ([va.EqualTorque("FL_KFE", "FL_KFE")], "same joint"),
        (["x"], "Unknown design constraint"),
    ],
)
def test_malformed_design_constraints(solo, design, fragment):
    with raises(va.ConstraintError, fragment):
        body(solo, design=design)


@pytest.mark.parametrize(
    ("kwargs", "fragment"),
    [
        ({"reactions": ["FL_FOOT", "FL_FOOT"]}, "repeat"),
        ({"reactions": []}, "at least one"),
        ({"contact": "line"}, "'line'"),
        ({"contact": {"XX": "flat"}}, "'XX'"),
        ({"contact": {"FL_FOOT": "edge"}}, "'edge'"),
        ({"passive": {"FL_KFE": (1.0,)}}, "'FL_KFE'"),
        ({"passive": {"FL_KFE": (float("nan"), 0.0)}}, "NaN"),
        ({"passive": {"FL_KFE": (1.0, 0.0)}, "unactuated": ["FL_KFE"]}, "both"),
    ],
)
def test_malformed_declarations_are_constraint_errors(solo, kwargs, fragment):
    with raises(va.ConstraintError, fragment):
        body(solo, **kwargs)


def test_reaction_rigidly_attached_to_action():
    anymal = robot("anymal")
    with raises(va.ConstraintError, "'base_inertia'", "rigidly"):
        va.ParallelVirtualActuator(anymal, "base", ["base_inertia", "LF_FOOT"])


def test_multi_dof_joint_cannot_be_passive_or_torque_constrained(solo):
    with raises(va.ConstraintError, "'root_joint'", "6 degrees"):
        va.ParallelVirtualActuator(solo, "base_link", ["world"], passive={"root_joint": (1, 0)})
    with raises(va.ConstraintError, "'root_joint'", "6 degrees"):
        va.ParallelVirtualActuator(
            solo, "base_link", ["world", "FL_FOOT"], design=[va.EqualTorque("root_joint", "FL_KFE")]
        )


# -- configuration-dependent -----------------------------------------------------------------------
def test_straight_legs_are_singular_and_name_the_chain(solo):
    with raises(va.SingularConfigurationError, "'FL_FOOT'"):
        body(solo).solve(pin.neutral(solo.model), np.ones(6))


@pytest.mark.parametrize("method", ["partitioned", "dense"])
def test_one_straight_knee_names_that_leg(solo, q, method):
    bent = q.copy()
    knee = solo.model.joints[solo.model.getJointId("HR_KFE")]
    bent[knee.idx_q] = 0.0
    with raises(va.SingularConfigurationError, "'HR_FOOT'"):
        body(solo).solve(bent, np.ones(6), method=method)
    with raises(va.SingularConfigurationError, "'HR_FOOT'"):
        body(solo).solve(bent, np.ones(6), strict=True)


def test_straight_knee_with_flat_contact_is_not_singular(solo, q):
    """A flat foot's 6-D twists of two parallel joints stay independent at a straight knee."""
    bent = q.copy()
    bent[solo.model.joints[solo.model.getJointId("HR_KFE")].idx_q] = 0.0
    sol = body(solo, contact="flat").solve(bent, np.ones(6))
    assert sol.residual < 1e-9


def test_strict_inadmissible_wrench_carries_the_solution(solo, q):
    actuator = va.ParallelVirtualActuator(solo, "base_link", ["FL_FOOT"])
    with raises(va.InadmissibleWrenchError, "residual") as info:
        actuator.solve(q, np.ones(6), strict=True)
    solution = info.value.solution
    assert solution.method == "least-squares" and solution.residual > 0.1
    # a looser tolerance does not change admissibility of a clearly inadmissible wrench
    with raises(va.InadmissibleWrenchError):
        actuator.solve(q, np.ones(6), strict=True, tol=1e-2)


def test_unknown_robot():
    with raises(va.RobotNotFoundError, "'solo13'", "'solo12'"):
        va.load_robot("solo13")


def test_every_error_class_derives_from_the_base_class():
    classes = [
        va.ConstraintError,
        va.FrameNotFoundError,
        va.InadmissibleWrenchError,
        va.InvalidAxisError,
        va.InvalidInputError,
        va.JointNotFoundError,
        va.RobotDescriptionError,
        va.RobotNotFoundError,
        va.SingularConfigurationError,
    ]
    for cls in classes:
        assert issubclass(cls, va.VirtualActuatorError)
        assert cls is not va.VirtualActuatorError
    assert issubclass(va.VirtualActuatorError, Exception)
    assert len(set(classes)) == len(classes)
