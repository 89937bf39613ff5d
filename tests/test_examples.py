"""The seeds' worked examples (VAC section 3 and 2.5.1, VMC 4.1 and 4.2) reproduced."""

import subprocess
import sys

import numpy as np
import pytest
from oracles import external_forces, rnea_torques, zero_gravity_model

from virtual_actuators import examples
from virtual_actuators.cli.options import EXAMPLE_NAMES


@pytest.fixture(scope="module")
def hexapod():
    return examples.hexapod_tripod(verbose=False)


def test_hexapod_tripod_has_the_seed_constants_and_sets(hexapod):
    assert hexapod.details["sizes"] == {
        "n": 6,
        "p": 3,
        "l_total": 9,
        "d_total": 9,
        "r": 3,
        "design": 3,
    }
    sol = hexapod.solution
    assert sol.method == "partitioned"
    assert {k: len(v) for k, v in sol.sets.items()} == {"MFS": 6, "RFS": 3, "CFS": 9}
    # point feet: the constrained force set is the three moments of each leg (eq. 28)
    assert sorted(a for _, a in sol.sets["CFS"]) == sorted(["rx", "ry", "rz"] * 3)


def test_hexapod_tripod_needs_only_3x3_and_6x6_solves(hexapod):
    assert hexapod.details["systems"] == (("CFS", 3, 3), ("MFS", 6, 1))


def test_hexapod_tripod_matches_dense_and_rnea(hexapod):
    assert hexapod.details["dense_difference"] < 1e-9
    # the oracle: Pinocchio's RNEA with the chains' wrenches as external forces, gravity off
    sol, body = hexapod.solution, hexapod.actuator
    pairs = [
        (body.action, r, body.reference, body.axes, f)
        for r, f in zip(sol.reactions, sol.forces, strict=True)
    ]
    model = zero_gravity_model("hexapod")
    tau = rnea_torques(model, hexapod.q, external_forces(model, hexapod.q, pairs))
    np.testing.assert_allclose(sol.tau, tau, rtol=0, atol=1e-9)
    sol = hexapod.solution
    f = {r: sol.force(r) for r in sol.reactions}
    # eq. 26: f_x3 = f_x2, f_y3 = f_y2, f_y1 = 2 f_y2 on the tripod (foot_1, foot_3, foot_5)
    assert f["foot_5"][0] == pytest.approx(f["foot_3"][0], abs=1e-12)
    assert f["foot_5"][1] == pytest.approx(f["foot_3"][1], abs=1e-12)
    assert f["foot_1"][1] == pytest.approx(2 * f["foot_3"][1], abs=1e-12)


@pytest.fixture(scope="module")
def millipede():
    return examples.millipede(verbose=False)


def test_millipede_constants_and_sets(millipede):
    sizes = {"n": 6, "p": 100, "l_total": 400, "d_total": 200, "r": 194, "design": 0}
    assert millipede.details["sizes"] == sizes
    for sol in (millipede.solution, millipede.details["square"]):
        assert {k: len(v) for k, v in sol.sets.items()} == {"MFS": 6, "RFS": 194, "CFS": 400}
    assert millipede.solution.method == "pseudo-inverse"
    assert millipede.details["design"] == 194
    square = millipede.details["square"]
    assert square.method == "partitioned"
    assert square.systems == (("CFS", 4, 100), ("MFS", 6, 1))  # O(p l^3 + n^3)
    assert millipede.details["dense_difference"] < 1e-9


def test_single_leg_matches_closed_form_of_eq_7():
    result = examples.single_leg(verbose=False)
    sol = result.solution
    assert sol.method == "partitioned" and sol.residual < 1e-9
    for key in ("fx", "tau_knee", "tau_hip"):
        assert result.details["library"][key] == pytest.approx(
            result.details["closed_form"][key], rel=1e-10
        )
    assert result.details["library"]["tau_ankle"] == 0.0


def test_single_leg_straight_knee_is_a_singular_configuration():
    result = examples.single_leg(verbose=False)
    assert result.details["straight_knee"].startswith("SingularConfigurationError")
    assert "left_foot" in result.details["straight_knee"]


def test_single_leg_closed_form_is_singular_only_at_straight_knee():
    # eq. 7's matrix [[-L1 L2 s_k / C, -L1 c_a / C], [0, -1]] has determinant L1 L2 s_k / C
    a, l1, l2 = -0.2, 0.42, 0.42
    for k in (0.3, 0.7, 1.2):
        c = l1 * np.cos(a) + l2 * np.cos(a + k)
        t1 = np.array(examples.single_leg_closed_form(a, k, l1, l2, 1.0, 0.0)[1:])
        t2 = np.array(examples.single_leg_closed_form(a, k, l1, l2, 0.0, 1.0)[1:])
        assert np.linalg.det(np.column_stack((t1, t2))) == pytest.approx(l1 * l2 * np.sin(k) / c)
    t1 = np.array(examples.single_leg_closed_form(a, 0.0, l1, l2, 1.0, 0.0)[1:])
    assert np.allclose(t1, 0.0)  # straight knee: f_z produces no torque, it is undetermined


def test_double_support_matches_closed_form_of_eq_14():
    result = examples.double_support(verbose=False)
    sol = result.solution
    assert sol.method == "partitioned" and sol.residual < 1e-9
    for side in ("left", "right"):
        np.testing.assert_allclose(
            result.details["library"][side], result.details["closed_form"][side], rtol=1e-9
        )
    library = result.details["library"]
    assert library["left"][3] == pytest.approx(library["right"][3])


def test_examples_return_what_they_built():
    assert EXAMPLE_NAMES == tuple(examples.EXAMPLES)
    example = examples.double_support(verbose=False)
    assert example.name == "double-support" and example.robot.name == "spring_flamingo"
    assert example.actuator.reactions == ("left_foot", "right_foot")
    again = example.actuator.solve(example.q, example.solution.requested)
    np.testing.assert_array_equal(again.tau, example.solution.tau)
    assert "double-support" in repr(example)


@pytest.mark.slow
@pytest.mark.parametrize("name", ["single-leg", "double-support", "hexapod-tripod"])
def test_examples_run_from_the_command_line(name):
    out = subprocess.run(
        [sys.executable, "-m", "virtual_actuators", "example", name],
        capture_output=True, text=True, timeout=120, check=True,
    )  # fmt: skip
    assert "closed form" in out.stdout or "dense eq. 10-11" in out.stdout
