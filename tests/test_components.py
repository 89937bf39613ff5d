"""Virtual components (VMC 2001, section 3) against their formulas, written out here by hand.

Every expected wrench is computed in the test from the component's documented formula with
plain numpy; nothing is read back from the component except what is being tested.
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest
from oracles import robot

import virtual_actuators as va
from virtual_actuators.components import (
    Component,
    ConstantForce,
    Damper,
    DogtrackBunny,
    GrannyWalker,
    Spring,
    SpringDamper,
    SwingLegLinkage,
)
from virtual_actuators.control import Controller

AXES3 = ("x", "z", "ry")
TOL = 1e-12


def _random_parameters(rng: np.random.Generator, n: int) -> dict[str, np.ndarray]:
    return {
        "stiffness": rng.uniform(0.0, 2000.0, n),
        "damping": rng.uniform(0.0, 200.0, n),
        "setpoint": rng.uniform(-1.0, 1.0, n),
        "velocity_setpoint": rng.uniform(-1.0, 1.0, n),
        "force": rng.uniform(-100.0, 100.0, n),
    }


# -- SpringDamper and its special cases --------------------------------------------------------
@pytest.mark.parametrize("seed", range(5))
def test_spring_damper_is_k_dx_plus_b_dv_plus_f_per_axis(seed):
    rng = np.random.default_rng(seed)
    p = _random_parameters(rng, 3)
    component = SpringDamper(AXES3, **p)
    for _ in range(5):
        x, v, t = rng.uniform(-1, 1, 3), rng.uniform(-2, 2, 3), rng.uniform(0, 10)
        expected = [
            p["stiffness"][i] * (p["setpoint"][i] - x[i])
            + p["damping"][i] * (p["velocity_setpoint"][i] - v[i])
            + p["force"][i]
            for i in range(3)
        ]
        np.testing.assert_allclose(component.compute_wrench(x, v, t), expected, rtol=0, atol=TOL)


def test_scalar_parameters_broadcast_to_every_axis():
    component = SpringDamper(
        ("x", "y", "rz"),
        stiffness=10.0,
        damping=2.0,
        setpoint=0.5,
        velocity_setpoint=-1.0,
        force=3.0,
    )
    for name in ("stiffness", "damping", "setpoint", "velocity_setpoint", "force", "limit"):
        assert getattr(component, name).shape == (3,)
    np.testing.assert_array_equal(component.stiffness, [10.0, 10.0, 10.0])
    np.testing.assert_array_equal(component.limit, [np.inf, np.inf, np.inf])
    x, v = np.array([0.1, -0.2, 0.3]), np.array([1.0, 0.0, -1.0])
    expected = 10.0 * (0.5 - x) + 2.0 * (-1.0 - v) + 3.0
    np.testing.assert_allclose(component.compute_wrench(x, v, 0.0), expected, rtol=0, atol=TOL)


def test_defaults_give_zero_wrench():
    component = SpringDamper(AXES3)
    out = component.compute_wrench(np.array([1.0, -2.0, 3.0]), np.array([4.0, 5.0, -6.0]), 1.0)
    np.testing.assert_array_equal(out, np.zeros(3))


def test_limit_clips_the_spring_damper_part_and_force_is_added_after():
    component = SpringDamper(
        AXES3, stiffness=100.0, damping=10.0, force=[5.0, -5.0, 1.0], limit=[30.0, 30.0, np.inf]
    )
    # spring-damper part: 100 * (0 - x) + 10 * (0 - v)
    x, v = np.array([-1.0, 1.0, -1.0]), np.array([0.0, 0.0, 0.0])  # raw: 100, -100, 100
    np.testing.assert_allclose(
        component.compute_wrench(x, v, 0.0), [30.0 + 5.0, -30.0 - 5.0, 100.0 + 1.0], atol=TOL
    )
    # inside the limit nothing is clipped
    x, v = np.array([-0.1, 0.1, 0.0]), np.array([0.5, -0.5, 0.0])  # raw: 10 - 5, -10 + 5, 0
    np.testing.assert_allclose(component.compute_wrench(x, v, 0.0), [10.0, -10.0, 1.0], atol=TOL)


@pytest.mark.parametrize("seed", range(3))
def test_limit_saturation_matches_clip_formula(seed):
    rng = np.random.default_rng(100 + seed)
    p = _random_parameters(rng, 3)
    limit = rng.uniform(0.0, 50.0, 3)
    component = SpringDamper(AXES3, limit=limit, **p)
    x, v = rng.uniform(-1, 1, 3), rng.uniform(-1, 1, 3)
    raw = p["stiffness"] * (p["setpoint"] - x) + p["damping"] * (p["velocity_setpoint"] - v)
    expected = np.minimum(np.maximum(raw, -limit), limit) + p["force"]
    np.testing.assert_allclose(component.compute_wrench(x, v, 0.0), expected, rtol=0, atol=TOL)


def test_zero_limit_leaves_only_the_force():
    component = SpringDamper(("z",), stiffness=1e3, damping=1e2, force=42.0, limit=0.0)
    assert component.compute_wrench(np.array([5.0]), np.array([-3.0]), 0.0) == pytest.approx([42.0])


def test_spring_ignores_velocity():
    spring = Spring(("x", "z"), stiffness=[100.0, 200.0], setpoint=[0.1, 0.5])
    x = np.array([0.3, 0.2])
    for v in (np.zeros(2), np.array([10.0, -10.0])):
        np.testing.assert_allclose(
            spring.compute_wrench(x, v, 0.0), [100.0 * (0.1 - 0.3), 200.0 * (0.5 - 0.2)], atol=TOL
        )
    np.testing.assert_array_equal(spring.damping, [0.0, 0.0])
    np.testing.assert_array_equal(spring.force, [0.0, 0.0])


def test_damper_ignores_position():
    damper = Damper(("ry",), damping=7.0, velocity_setpoint=0.25)
    for x in (np.zeros(1), np.array([3.0])):
        assert damper.compute_wrench(x, np.array([1.0]), 0.0) == pytest.approx([7.0 * (0.25 - 1.0)])
    np.testing.assert_array_equal(damper.stiffness, [0.0])


def test_constant_force_is_constant():
    thruster = ConstantForce(("x", "y", "z"), force=[1.0, -2.0, 98.1])
    rng = np.random.default_rng(7)
    for _ in range(3):
        out = thruster.compute_wrench(rng.normal(size=3), rng.normal(size=3), rng.uniform(0, 5))
        np.testing.assert_array_equal(out, [1.0, -2.0, 98.1])


def test_set_points_move_between_calls():
    component = SpringDamper(("x",), stiffness=10.0)
    assert component.compute_wrench(np.array([0.0]), np.array([0.0]), 0.0) == pytest.approx([0.0])
    component.setpoint = 2.0
    assert component.compute_wrench(np.array([0.0]), np.array([0.0]), 0.0) == pytest.approx([20.0])
    component.stiffness = [5.0]
    assert component.compute_wrench(np.array([0.0]), np.array([0.0]), 0.0) == pytest.approx([10.0])


# -- validation ---------------------------------------------------------------------------------
BAD_VALUES = [
    ("stiffness", -1.0),
    ("stiffness", [1.0, -1e-3, 1.0]),
    ("damping", -0.5),
    ("limit", -1.0),
    ("limit", [1.0, 2.0, -np.inf]),
    ("stiffness", np.nan),
    ("stiffness", np.inf),
    ("damping", [1.0, np.nan, 1.0]),
    ("setpoint", np.nan),
    ("velocity_setpoint", np.inf),
    ("force", [0.0, 0.0, -np.inf]),
    ("limit", np.nan),
    ("stiffness", [1.0, 2.0]),
    ("setpoint", [1.0, 2.0, 3.0, 4.0]),
    ("force", [[1.0, 2.0, 3.0]]),
    ("limit", [1.0, 2.0]),
    ("damping", []),
]


@pytest.mark.parametrize(("attribute", "value"), BAD_VALUES)
def test_setters_reject_bad_values_and_name_the_component(attribute, value):
    component = SpringDamper(AXES3, stiffness=1.0, damping=1.0, name="hip_spring")
    before = getattr(component, attribute).copy()
    with pytest.raises(va.InvalidInputError, match="hip_spring"):
        setattr(component, attribute, value)
    np.testing.assert_array_equal(getattr(component, attribute), before)  # unchanged


@pytest.mark.parametrize(("attribute", "value"), BAD_VALUES)
def test_constructor_rejects_bad_values(attribute, value):
    with pytest.raises(va.InvalidInputError, match="SpringDamper"):
        SpringDamper(AXES3, **{attribute: value})


def test_default_name_is_the_class_name_in_errors():
    with pytest.raises(va.InvalidInputError, match="Spring"):
        Spring(("x",), stiffness=-1.0)
    with pytest.raises(va.InvalidInputError, match="Damper"):
        Damper(("x",), damping=[1.0, 2.0])


def test_infinite_limit_is_accepted_and_zero_gains_are_accepted():
    component = SpringDamper(("x", "y"), stiffness=0.0, damping=0.0, limit=[np.inf, 0.0])
    np.testing.assert_array_equal(component.limit, [np.inf, 0.0])


@pytest.mark.parametrize("axes", [(), ("q",), ("z", "x"), ("x", "x"), ("ry", "z")])
def test_bad_axes_raise_invalid_axis_error(axes):
    with pytest.raises(va.InvalidAxisError):
        SpringDamper(axes, stiffness=1.0)


def test_single_axis_string_is_accepted():
    assert SpringDamper("rz", stiffness=1.0).axes == ("rz",)


# -- GrannyWalker --------------------------------------------------------------------------------
def test_granny_walker_formula_with_weight_feed_forward():
    granny = GrannyWalker(
        0.54, stiffness=(1500.0, 200.0), damping=(150.0, 20.0), pitch=0.05, weight=98.1
    )
    assert granny.axes == ("z", "ry")
    assert granny.height == 0.54 and granny.pitch == 0.05
    x, v = np.array([0.5, -0.02]), np.array([0.1, -0.3])
    expected = [
        1500.0 * (0.54 - 0.5) + 150.0 * (0.0 - 0.1) + 98.1,
        200.0 * (0.05 - -0.02) + 20.0 * (0.0 - -0.3),
    ]
    np.testing.assert_allclose(granny.compute_wrench(x, v, 0.0), expected, rtol=0, atol=TOL)
    # at the set point and at rest it holds exactly the weight
    np.testing.assert_allclose(
        granny.compute_wrench(np.array([0.54, 0.05]), np.zeros(2), 0.0), [98.1, 0.0], atol=TOL
    )


def test_granny_walker_height_and_pitch_setters_move_only_their_set_point():
    granny = GrannyWalker(0.5, stiffness=(100.0, 10.0), damping=(1.0, 1.0), pitch=0.1)
    granny.height = 0.7
    assert granny.height == 0.7 and granny.pitch == 0.1
    np.testing.assert_array_equal(granny.setpoint, [0.7, 0.1])
    granny.pitch = -0.2
    assert granny.height == 0.7 and granny.pitch == -0.2
    out = granny.compute_wrench(np.array([0.6, 0.0]), np.zeros(2), 0.0)
    np.testing.assert_allclose(out, [100.0 * 0.1, 10.0 * -0.2], atol=TOL)


@pytest.mark.parametrize("attribute", ["height", "pitch"])
def test_granny_walker_setters_reject_non_finite(attribute):
    granny = GrannyWalker(0.5, stiffness=(100.0, 10.0), damping=(1.0, 1.0), name="granny")
    with pytest.raises(va.InvalidInputError, match="granny"):
        setattr(granny, attribute, np.nan)
    assert granny.height == 0.5 and granny.pitch == 0.0


def test_granny_walker_other_planes():
    granny = GrannyWalker(1.0, stiffness=(10.0, 1.0), damping=(0.0, 0.0), axes=("y", "rx"))
    assert granny.axes == ("y", "rx")
    np.testing.assert_allclose(
        granny.compute_wrench(np.array([0.0, 0.5]), np.zeros(2), 0.0), [10.0, -0.5], atol=TOL
    )


@pytest.mark.parametrize(
    "axes",
    [("x", "z"), ("rx", "ry"), ("z",), ("ry",), ("z", "ry", "rz"), ("x", "z", "ry"), ("ry", "z")],
)
def test_granny_walker_axes_must_be_a_translation_then_a_rotation(axes):
    with pytest.raises(va.InvalidAxisError):
        GrannyWalker(0.5, stiffness=(1.0, 1.0), damping=(1.0, 1.0), axes=axes)


def test_granny_walker_bad_gains():
    with pytest.raises(va.InvalidInputError):
        GrannyWalker(0.5, stiffness=(1.0, -1.0), damping=(1.0, 1.0))
    with pytest.raises(va.InvalidInputError):
        GrannyWalker(0.5, stiffness=(1.0, 1.0, 1.0), damping=(1.0, 1.0))
    with pytest.raises(va.InvalidInputError):
        GrannyWalker(np.nan, stiffness=(1.0, 1.0), damping=(1.0, 1.0))


# -- DogtrackBunny -------------------------------------------------------------------------------
def test_bunny_reset_puts_it_at_the_position_and_time_then_it_runs_at_speed():
    bunny = DogtrackBunny(speed=0.5, damping=80.0)
    bunny.reset(np.array([1.25]), 3.0)
    assert bunny.start_position == 1.25 and bunny.start_time == 3.0
    assert bunny.position_at(3.0) == pytest.approx(1.25, abs=TOL)
    assert bunny.position_at(5.0) == pytest.approx(1.25 + 0.5 * 2.0, abs=TOL)
    assert bunny.position_at(2.0) == pytest.approx(1.25 - 0.5, abs=TOL)
    bunny.speed = -0.2
    assert bunny.position_at(4.0) == pytest.approx(1.25 - 0.2, abs=TOL)


@pytest.mark.parametrize("seed", range(4))
def test_bunny_force_is_damper_to_speed_plus_spring_to_bunny(seed):
    rng = np.random.default_rng(200 + seed)
    speed, b, k = rng.uniform(-1, 1), rng.uniform(0, 100), rng.uniform(0, 300)
    bunny = DogtrackBunny(speed=speed, damping=b, stiffness=k, axis="y")
    assert bunny.axes == ("y",)
    x0, t0 = rng.uniform(-1, 1), rng.uniform(0, 2)
    bunny.reset(np.array([x0]), t0)
    for _ in range(4):
        t, x, v = t0 + rng.uniform(0, 3), rng.uniform(-2, 2), rng.uniform(-2, 2)
        expected = b * (speed - v) + k * (x0 + speed * (t - t0) - x)
        out = bunny.compute_wrench(np.array([x]), np.array([v]), t)
        assert out.shape == (1,)
        assert out[0] == pytest.approx(expected, abs=1e-10)


def test_bunny_limit_saturates():
    bunny = DogtrackBunny(speed=1.0, damping=100.0, stiffness=50.0, limit=60.0)
    bunny.reset(np.array([0.0]), 0.0)
    # far behind: 100 * (1 - 0) + 50 * (1 - 0) = 150 -> 60
    assert bunny.compute_wrench(np.array([0.0]), np.array([0.0]), 1.0) == pytest.approx([60.0])
    # far ahead and too fast: 100 * (1 - 3) + 50 * (1 - 5) = -400 -> -60
    assert bunny.compute_wrench(np.array([5.0]), np.array([3.0]), 1.0) == pytest.approx([-60.0])
    # inside: 100 * (1 - 0.9) + 50 * (1 - 1) = 10
    assert bunny.compute_wrench(np.array([1.0]), np.array([0.9]), 1.0) == pytest.approx([10.0])


def test_bunny_default_is_a_pure_damper_from_the_origin():
    bunny = DogtrackBunny(speed=0.5, damping=80.0)
    assert bunny.position_at(2.0) == pytest.approx(1.0)
    assert bunny.compute_wrench(np.array([9.0]), np.array([0.0]), 2.0) == pytest.approx([40.0])


@pytest.mark.parametrize(
    "kwargs",
    [
        {"speed": np.nan, "damping": 1.0},
        {"speed": np.inf, "damping": 1.0},
        {"speed": 0.5, "damping": -1.0},
        {"speed": 0.5, "damping": 1.0, "stiffness": -1.0},
        {"speed": 0.5, "damping": 1.0, "limit": -1.0},
    ],
)
def test_bunny_validates(kwargs):
    with pytest.raises(va.InvalidInputError):
        DogtrackBunny(**kwargs)


def test_bunny_speed_setter_validates():
    bunny = DogtrackBunny(speed=0.5, damping=1.0, name="bunny")
    with pytest.raises(va.InvalidInputError, match="bunny"):
        bunny.speed = np.nan
    assert bunny.speed == 0.5


def test_bunny_axis_validated():
    with pytest.raises(va.InvalidAxisError):
        DogtrackBunny(speed=0.5, damping=1.0, axis="w")


# -- SwingLegLinkage -----------------------------------------------------------------------------
def test_swing_leg_linkage_place_moves_set_points():
    linkage = SwingLegLinkage((400.0, 600.0), (20.0, 25.0), setpoint=(0.0, -0.5))
    assert linkage.axes == ("x", "z")
    np.testing.assert_array_equal(linkage.setpoint, [0.0, -0.5])
    linkage.place((0.19, -0.48), (0.5, -0.1))
    np.testing.assert_array_equal(linkage.setpoint, [0.19, -0.48])
    np.testing.assert_array_equal(linkage.velocity_setpoint, [0.5, -0.1])
    x, v = np.array([0.1, -0.5]), np.array([0.2, 0.3])
    expected = [
        400.0 * (0.19 - 0.1) + 20.0 * (0.5 - 0.2),
        600.0 * (-0.48 - -0.5) + 25.0 * (-0.1 - 0.3),
    ]
    np.testing.assert_allclose(linkage.compute_wrench(x, v, 0.0), expected, rtol=0, atol=TOL)
    linkage.place((0.0, -0.4))  # velocity set point back to 0 by default
    np.testing.assert_array_equal(linkage.velocity_setpoint, [0.0, 0.0])


def test_swing_leg_linkage_place_validates():
    linkage = SwingLegLinkage(1.0, 1.0, name="swing")
    with pytest.raises(va.InvalidInputError, match="swing"):
        linkage.place((1.0, 2.0, 3.0))
    with pytest.raises(va.InvalidInputError, match="swing"):
        linkage.place((1.0, np.nan))


# -- user components -----------------------------------------------------------------------------
class Friction(Component):
    """The module docstring's example."""

    def __init__(self, axis: str, force: float) -> None:
        super().__init__((axis,))
        self.force = force  # [N]

    def compute_wrench(self, position, velocity, time):
        return -self.force * np.sign(velocity)


def test_component_is_abstract():
    with pytest.raises(TypeError):
        Component(("x",))  # type: ignore[abstract]


def test_default_reset_hook_does_nothing():
    friction = Friction("x", 2.0)
    friction.reset(np.array([1.0]), 1.0)
    assert friction.force == 2.0
    assert friction.name == "Friction" and friction.axes == ("x",)


def test_user_component_works_with_the_controller():
    rob = robot("ur5_robot")
    model = rob.model
    arm = va.VirtualActuator(rob, "tool0", "world", "world", ("x", "y", "z"))
    controller = Controller(rob, clip=False)
    controller.add("arm", arm, [Friction("y", 3.0)])
    rng = np.random.default_rng(3)
    q, v = rng.uniform(-1.0, 1.0, model.nq), rng.uniform(-1.0, 1.0, model.nv)
    # independent oracle: Pinocchio's frame Jacobian (world-aligned, at tool0's origin)
    data = model.createData()
    jac = pin.computeFrameJacobian(
        model, data, q, model.getFrameId("tool0"), pin.ReferenceFrame.LOCAL_WORLD_ALIGNED
    )
    vy = jac[1] @ v
    assert abs(vy) > 1e-3
    out = controller.compute(q, v)
    np.testing.assert_allclose(out.wrenches["arm"], [0.0, -3.0 * np.sign(vy), 0.0], atol=TOL)
    np.testing.assert_allclose(out.tau, jac[1] * (-3.0 * np.sign(vy)), rtol=0, atol=1e-10)


# -- reports -------------------------------------------------------------------------------------
@pytest.mark.parametrize(
    "component",
    [
        SpringDamper(AXES3, stiffness=[1.0, 2.0, 3.0], damping=1.0, setpoint=0.5),
        Spring(("x",), 1.0),
        Damper(("z",), 2.0),
        ConstantForce(("z",), 98.1),
        GrannyWalker(0.5, (1.0, 2.0), (3.0, 4.0)),
        DogtrackBunny(0.5, 80.0),
        SwingLegLinkage(1.0, 2.0),
        Friction("rz", 1.0),
    ],
    ids=lambda c: type(c).__name__,
)
def test_repr_names_the_class_and_axes(component):
    text = repr(component)
    assert text.startswith(type(component).__name__ + "(")
    assert repr(component.axes) in text


def test_spring_damper_repr_shows_gains():
    text = repr(SpringDamper(("x", "z"), stiffness=[12.5, 3.0], damping=0.25, setpoint=[1.0, 2.0]))
    assert "stiffness=[12.5" in text and "damping=[0.25" in text and "setpoint=[1." in text
