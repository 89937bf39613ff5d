"""The 1996 hexapod's walks (VAC 1996, section 4) in MuJoCo: the issue's targets.

Every figure is measured on MuJoCo's state (the trace), never on the controller's own numbers.
The closed-loop runs are a few simulated seconds each and marked slow.
"""

from __future__ import annotations

import importlib.util
import json
import math
import subprocess
import sys
from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest
from oracles import requires_core, yaw_pitch_roll

import virtual_actuators as va
from virtual_actuators.__main__ import main
from virtual_actuators.control.state_machine import Context
from virtual_actuators.gaits.attitude import attitude_and_velocity, rotation_vector_angles
from virtual_actuators.gaits.hexapod import HexapodWalker
from virtual_actuators.gaits.hexapod.body import HeadingAttitude, HeadingDamper
from virtual_actuators.gaits.hexapod.footholds import behind
from virtual_actuators.gaits.hexapod.pendulum import lqr_gain, pendulum_model
from virtual_actuators.gaits.hexapod.walk import (
    HexapodWalkConfig,
    hexapod_robot,
    run_hexapod_walk,
)
from virtual_actuators.simulation import Simulator

ROOT = Path(__file__).resolve().parents[1]
BUILD = ROOT / "robots" / "hexapod" / "build.py"


def walk(**options) -> va.gaits.hexapod.walk.HexapodResult:
    result = run_hexapod_walk(HexapodWalkConfig(**options), progress=False)
    assert not result.metrics.fell, result.metrics.summary()
    return result


def assert_support_feet_push_and_stick(metrics) -> None:
    """MuJoCo's contact forces on the feet the gait has in support (from 20 ms after they
    enter support, every tick): pushing with at least 1 N (never pulling, never unloaded) and
    well inside MuJoCo's friction coefficient of 1 (a ratio of 1 is a sliding foot)."""
    assert metrics.stance_normal_min_n >= 1.0, metrics
    assert metrics.stance_friction_ratio_max < 0.9, metrics


# -- fast: the robot variant, the components and the LQR ------------------------------------------


def test_pendulum_variant_matches_build_script_and_is_unactuated():
    spec = importlib.util.spec_from_file_location("hexapod_build", BUILD)
    build = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(build)
    folder = BUILD.parent
    assert (folder / "hexapod_pendulum.urdf").read_text() == build.build_urdf(pendulum=True)
    assert (folder / "hexapod_pendulum.srdf").read_text() == build.build_srdf(pendulum=True)
    robot = hexapod_robot(pendulum=True)
    model = robot.model
    assert robot.passive_joints == ("pendulum_joint",)
    joint = model.joints[model.getJointId("pendulum_joint")]
    inertia = model.inertias[model.getJointId("pendulum_joint")]
    assert inertia.mass == pytest.approx(0.18)
    assert np.linalg.norm(inertia.lever) == pytest.approx(0.15)  # uniform 0.30 m rod
    # the pin turns about the body's y axis: a positive angle moves the rod's top toward +x
    q = robot.neutral()
    q[joint.idx_q] = 0.1
    data = pin.Data(model)
    pin.forwardKinematics(model, data, q)
    top = data.oMi[model.getJointId("pendulum_joint")].act(np.array([0.0, 0.0, 0.3]))
    pivot = data.oMi[model.getJointId("pendulum_joint")].translation
    assert top - pivot == pytest.approx(0.3 * np.array([math.sin(0.1), 0.0, math.cos(0.1)]))
    simulator = Simulator(robot)
    assert simulator.model.nu == 18  # the legs only
    names = {simulator.model.actuator(i).name for i in range(simulator.model.nu)}
    assert not any("pendulum" in name for name in names)


def test_lqr_gain_solves_the_riccati_equation():
    model = pendulum_model(3.69, 0.18, 0.15, 0.18 * 0.3**2 / 3)
    q, r = np.diag([100.0, 1.0, 300.0]), np.array([[0.01]])
    gain = lqr_gain(model.a, model.b, q, r)
    # P from the gain (K = R^-1 B^T P has rank 1: recover P from the Lyapunov equation of the
    # closed loop, an independent linear solve), then the Riccati residual
    closed = model.a - model.b @ gain
    n = 3
    lyapunov = np.kron(np.eye(n), closed.T) + np.kron(closed.T, np.eye(n))
    p = np.linalg.solve(lyapunov, -(q + gain.T @ r @ gain).reshape(-1)).reshape(n, n)
    residual = model.a.T @ p + p @ model.a - p @ model.b @ np.linalg.inv(r) @ model.b.T @ p + q
    assert np.abs(residual).max() < 1e-8 * np.abs(q).max()
    assert np.all(np.linalg.eigvals(closed).real < 0)
    # the open loop is unstable (an inverted pendulum) and the gain leans the body back first
    assert np.max(np.linalg.eigvals(model.a).real) > 5.0


def test_pendulum_model_matches_finite_differences_of_the_cart_pole():
    body, mass, com = 3.69, 0.18, 0.15
    inertia = mass * 0.3**2 / 3

    def accelerations(theta: float, force: float) -> np.ndarray:
        # Lagrange's equations, nonlinear, at rest: M(theta) (a, theta'') = (F, m g l sin theta)
        matrix = [
            [body + mass, mass * com * math.cos(theta)],
            [mass * com * math.cos(theta), inertia],
        ]
        return np.linalg.solve(matrix, [force, mass * 9.81 * com * math.sin(theta)])

    model = pendulum_model(body, mass, com, inertia)
    h = 1e-6
    d_theta = (accelerations(h, 0.0) - accelerations(-h, 0.0)) / (2 * h)
    d_force = (accelerations(0.0, h) - accelerations(0.0, -h)) / (2 * h)
    assert model.a[1, 0] == pytest.approx(d_theta[1], rel=1e-6)
    assert model.a[2, 0] == pytest.approx(d_theta[0], rel=1e-6)
    assert model.b[1, 0] == pytest.approx(d_force[1], rel=1e-6)
    assert model.b[2, 0] == pytest.approx(d_force[0], rel=1e-6)


def test_heading_components_match_world_springs_at_zero_yaw_and_turn_with_the_heading():
    attitude = HeadingAttitude((30.0, 40.0), (1.0, 2.0, 8.0))
    reference = va.SpringDamper(("rx", "ry", "rz"), (30.0, 40.0, 0.0), (1.0, 2.0, 8.0))
    small = np.array([2e-4, -3e-4, 0.0])
    omega = np.array([0.3, -0.2, 0.5])
    attitude.yaw_rate = reference.velocity_setpoint[2] = 0.0
    expected = reference.compute_wrench(small, omega, 0.0)
    got = attitude.compute_wrench(small, omega, 0.0)
    assert got == pytest.approx(expected, rel=1e-3, abs=1e-6)
    # the same body turned by a yaw: the same moment, turned with it
    for yaw in (0.7, 2.5, -3.0):
        turn = pin.utils.rotate("z", yaw)
        rotated = pin.log3(turn @ pin.exp3(small))
        moment = attitude.compute_wrench(rotated, turn @ omega, 0.0)
        assert moment == pytest.approx(turn @ got, rel=1e-9, abs=1e-12)
        assert rotation_vector_angles(*rotated.tolist())[0] == pytest.approx(yaw)
    damper = HeadingDamper((80.0, 60.0))
    damper.yaw, damper.velocity = 0.9, np.array([0.3, 0.1])
    c, s = math.cos(0.9), math.sin(0.9)
    world = np.array([c * 0.3 - s * 0.1, s * 0.3 + c * 0.1])  # exactly the commanded velocity
    assert damper.compute_wrench(np.zeros(2), world, 0.0) == pytest.approx([0.0, 0.0], abs=1e-12)


def test_rotation_vector_angles_are_those_of_pinocchios_exp3():
    """The float angles of a rotation vector: Pinocchio's exp3 then the angles, bit for bit.

    Every scale from the Taylor branch (|v| < eps^(1/4)) to angles near pi, and the axes.
    """
    rng = np.random.default_rng(11)
    vectors = [rng.normal(size=3) * scale for scale in (1e-12, 1e-6, 1e-4, 0.01, 1.0, 1.8)
               for _ in range(300)]  # fmt: skip
    vectors += [np.eye(3)[axis] * angle for axis in range(3) for angle in (0.0, 1e-4, 3.1)]
    for vector in vectors:
        assert rotation_vector_angles(*vector.tolist()) == yaw_pitch_roll(pin.exp3(vector))
    # and the angles are the rotation's: Rz(yaw) Ry(pitch) Rx(roll) is exp3(v)
    yaw, pitch, roll = rotation_vector_angles(0.3, -0.2, 1.1)
    built = pin.utils.rotate("z", yaw) @ pin.utils.rotate("y", pitch) @ pin.utils.rotate("x", roll)
    assert built == pytest.approx(pin.exp3(np.array([0.3, -0.2, 1.1])), abs=1e-14)


def test_hexapod_options_are_refused_elsewhere_and_bad_values_are_usage_errors(capsys):
    for argv in (
        ["demo", "turkey-walk", "--pendulum"],
        ["demo", "stand", "--yaw-rate", "0.2"],
        ["demo", "hexapod-walk", "--amplitude", "0.2"],
        ["demo", "hexapod-walk", "--yaw-rate", "nan"],
        ["demo", "hexapod-walk", "--path", "sine", "--track"],
        ["demo", "hexapod-walk", "--wavelength", "0", "--path", "sine"],
    ):
        with pytest.raises(SystemExit) as exit_info:
            main(argv)
        assert exit_info.value.code == 2, argv
    assert "only hexapod-walk uses it" in capsys.readouterr().err


@requires_core
@pytest.mark.parametrize("pendulum", [False, True])
@pytest.mark.parametrize("distribution", ["qp", "partitioned"])
def test_the_walker_is_lowered_whole_and_reads_its_command_from_the_plan(pendulum, distribution):
    """No Python piece; the command set after lowering is in the plan's registers."""
    robot = hexapod_robot(pendulum)
    gait = HexapodWalker(robot, va.gaits.HexapodParameters(distribution=distribution))
    q = gait.initial_configuration()
    gait.warm_up(q)
    assert gait.compiled is not None and gait.compiled.pieces == []
    gait.set_command((0.3, -0.1), 0.2)
    assert gait.memory.command == (0.3, -0.1, 0.2)
    assert gait.velocity.tolist() == [0.3, -0.1] and gait.yaw_rate == 0.2
    with pytest.raises(va.InvalidInputError):
        gait.set_command((math.nan, 0.0), 0.0)
    v = np.zeros(robot.model.nv)
    gait.compute(q, v, 0.0)
    gait.compute(q, v, 0.01)  # the set point moves toward the command, acceleration-limited
    vx, vy = gait.memory.setpoint
    step = gait.parameters.acceleration * 0.01
    assert math.hypot(vx, vy) == pytest.approx(step) and vx > 0.0 > vy


def test_walker_needs_the_hexapod_frames():
    with pytest.raises(va.FrameNotFoundError):
        HexapodWalker(va.load_robot("spring_turkey"))


def test_stance_ends_when_the_swing_tripod_is_down_or_a_step_is_done():
    robot = hexapod_robot()
    gait = HexapodWalker(robot)
    q, v = gait.initial_configuration(), np.zeros(robot.model.nv)
    down = {f"foot_{i}": True for i in range(1, 7)}  # tripod a's stance: 2, 4 and 6 swing

    def over(phase: float, contacts: dict[str, bool] | None) -> bool:
        gait.memory.phase = phase
        context = Context(robot, q, v, 0.0, contacts)
        context.state = "tripod_a"
        return gait._stance_over(context)

    assert over(0.6, down)  # all three swing feet touched down
    assert not over(0.4, down)  # first half of the swing: the contacts are the lift-off's
    assert not over(0.9, {**down, "foot_4": False})  # one still in the air
    assert not over(0.9, None)  # no switches: the step decides
    assert over(1.0, None)


def test_support_feet_are_read_from_their_nominal_places_along_their_motion():
    gait = HexapodWalker(hexapod_robot())
    p = gait.parameters
    # walking along +x: the feet move backward relative to the body; half a step behind = 0.5
    speed = np.full(3, 0.5)
    offsets = np.zeros((3, 3))
    offsets[:, 0] = -0.5 * p.step_length
    assert behind(p, offsets, speed, np.zeros(3)) == pytest.approx(0.5)
    offsets[:, 0] = 0.5 * p.step_length  # just landed, half a step ahead
    assert behind(p, offsets, speed, np.zeros(3)) == pytest.approx(-0.5)
    # crabbing along +y: the step width is the stride
    offsets[:] = 0.0
    offsets[2, 1] = -0.25 * p.step_width  # one foot a quarter stride behind
    assert behind(p, offsets, np.zeros(3), speed) == pytest.approx(0.25)
    assert behind(p, offsets, np.zeros(3), np.zeros(3)) == 0.0  # standing: no progress


# -- slow: closed-loop MuJoCo runs ----------------------------------------------------------------


@pytest.mark.slow
def test_line_at_0p8_mps():
    metrics = walk(speed=0.8, duration=3.0).metrics
    assert metrics.speed_mps == pytest.approx(0.8, rel=0.15)
    assert metrics.direction_error_rad < 0.15
    assert metrics.heading_drift_rad < 0.15
    assert metrics.roll_max_rad < 0.15 and metrics.pitch_max_rad < 0.15
    assert metrics.steps >= 10  # a tripod gait, not a slide
    assert_support_feet_push_and_stick(metrics)


@pytest.mark.slow
def test_crab_walk_direction_90():
    result = walk(speed=0.3, direction=math.pi / 2, duration=3.0)
    metrics = result.metrics
    assert metrics.speed_mps == pytest.approx(0.3, rel=0.15)
    assert metrics.direction_error_rad < 0.15
    assert metrics.heading_drift_rad < 0.15
    assert result.log["y"][-1] > 0.5  # it went left, facing +x
    assert_support_feet_push_and_stick(metrics)


@pytest.mark.slow
def test_circle_radius_is_speed_over_yaw_rate():
    result = walk(speed=0.3, yaw_rate=0.6, duration=4.0)
    metrics = result.metrics
    assert metrics.circle_radius_m == pytest.approx(0.5, rel=0.15)
    assert metrics.yaw_rate_radps == pytest.approx(0.6, rel=0.15)
    assert result.log["yaw"][-1] > 1.8  # most of a half turn, unwrapped
    assert_support_feet_push_and_stick(metrics)


@pytest.mark.slow
def test_sine_path_holding_the_heading():
    amplitude = 0.2
    result = walk(speed=0.3, path="sine", amplitude=amplitude, wavelength=1.5, duration=5.0)
    metrics = result.metrics
    assert metrics.path_error_max_m <= 0.35 * amplitude
    assert metrics.heading_drift_rad < 0.15
    assert np.max(result.log["y"]) > 0.8 * amplitude  # it did swing out to the crest
    assert np.min(result.log["y"]) < -0.8 * amplitude
    assert_support_feet_push_and_stick(metrics)


@pytest.mark.slow
def test_pendulum_balanced_while_walking_at_0p2():
    result = walk(speed=0.2, pendulum=True, duration=4.0)
    metrics = result.metrics
    assert metrics.pendulum_peak_rad < 0.1
    assert metrics.pendulum_rms_rad < 0.03
    assert metrics.vx_second_half_mps == pytest.approx(0.2, abs=0.05)
    assert metrics.vx_min_early_mps < -0.01  # the non-minimum-phase back-step
    # the angle in the trace is MuJoCo's own (joint angle plus body pitch), and it moved
    assert np.ptp(result.log["pendulum"]) > 0.01
    assert result.metrics.steps >= 8  # walking all along
    assert_support_feet_push_and_stick(metrics)


@pytest.mark.slow
def test_tracking_an_object():
    result = walk(speed=0.2, direction=math.pi / 2, track=True, duration=5.0)
    metrics = result.metrics
    assert metrics.bearing_error_max_rad < 0.2
    assert metrics.bearing_error_rms_rad < 0.08
    assert abs(result.log["yaw"][-1]) > 0.5  # the body turned to follow it
    assert_support_feet_push_and_stick(metrics)


@pytest.mark.slow
def test_cli_writes_trace_and_plot(tmp_path):
    trace_path, plot_path = tmp_path / "walk.json", tmp_path / "walk.png"
    command = [
        sys.executable,
        "-m",
        "virtual_actuators",
        "demo",
        "hexapod-walk",
        "--pendulum",
        "--duration",
        "1.5",
        "--quiet",
        "--json",
        str(trace_path),
        "--plot",
        str(plot_path),
    ]
    done = subprocess.run(command, capture_output=True, text=True, cwd=ROOT, timeout=300)
    assert done.returncode == 0, done.stderr
    assert "real time" in done.stdout
    data = json.loads(trace_path.read_text())
    assert data["fell"] is False and data["steps"] >= 3 and data["realtime_factor"] > 0
    trace = data["trace"]
    required = ["t", "x", "y", "z", "roll", "pitch", "yaw", "vx", "vy", "pendulum"]
    assert all(name in trace for name in required)
    assert len({len(values) for values in trace.values()}) == 1
    assert np.max(np.diff(trace["t"])) <= 1 / 50 + 1e-9
    assert plot_path.stat().st_size > 10_000


def test_loop_attitude_and_velocity_match_pinocchio():
    rng = np.random.default_rng(7)
    for _ in range(50):
        quaternion = pin.Quaternion(*rng.normal(size=4)).normalized()  # (w, x, y, z)
        q = np.r_[rng.normal(size=3), quaternion.coeffs()]  # coeffs: (x, y, z, w)
        v = rng.normal(size=6)
        rotation = quaternion.toRotationMatrix()
        roll, pitch, yaw = pin.rpy.matrixToRpy(rotation)
        got = attitude_and_velocity(q, v)
        assert got[:3] == pytest.approx((yaw, pitch, roll), abs=1e-12)
        assert got[3:] == pytest.approx((rotation @ v[:3])[:2], abs=1e-12)
