"""The simulated sensors: MuJoCo's own numbers without noise, the declared noise with it."""

import mujoco
import numpy as np
import pinocchio as pin
import pytest

import virtual_actuators as va
from virtual_actuators.simulation import SensorModel, Simulator


def _go2(sensors: SensorModel) -> tuple[Simulator, np.ndarray]:
    robot = va.load_robot("go2")
    sim = Simulator(robot, sensors=sensors)
    q0 = sim.on_ground(robot.neutral())
    q0[2] += 0.05  # dropped: impacts, then a robot collapsing under zero effort
    v0 = np.zeros(robot.model.nv)
    v0[:6] = (0.3, -0.2, 0.1, 0.5, -0.4, 0.8)
    sim.reset(q0, v0)
    return sim, q0


def test_ideal_gyro_and_encoders_are_mujocos_state():
    """Through impacts and a collapse, gyro and encoders equal MuJoCo's own to 1e-9."""
    sim, _ = _go2(SensorModel.ideal())
    model = sim.robot.model
    names = [model.names[j] for j in range(2, model.njoints)]
    site = sim.mujoco_model.frame_sites["base"]
    fresh = mujoco.MjData(sim.model)  # MuJoCo's velocity of the IMU's site at the state now
    for _ in range(300):
        sim.step(np.zeros(model.nv), ignore_unactuated=True)
        reading = sim.read_sensors()
        q, v = sim.q, sim.v
        fresh.qpos[:], fresh.qvel[:] = sim.data.qpos, sim.data.qvel
        mujoco.mj_forward(sim.model, fresh)
        twist = np.zeros(6)
        mujoco.mj_objectVelocity(sim.model, fresh, mujoco.mjtObj.mjOBJ_SITE, site, twist, 1)
        assert reading.joint_names == tuple(names)
        np.testing.assert_allclose(reading.gyro, twist[:3], rtol=0, atol=1e-9)
        np.testing.assert_allclose(reading.joint_position, q[7:], rtol=0, atol=1e-9)
        np.testing.assert_allclose(reading.joint_velocity, v[6:], rtol=0, atol=1e-9)


def test_ideal_accelerometer_is_the_finite_difference_of_mujocos_velocity():
    """Legs swinging in the air: the specific force within 0.3 m/s^2 rms of v's difference."""
    sim, q0 = _go2(SensorModel.ideal())
    q0[2] += 1.0  # no contact for the whole run
    sim.reset(q0)
    model = sim.robot.model
    hold = q0[7:].copy()
    period = sim.control_period
    previous, errors = None, []
    for k in range(300):
        q, v = sim.q, sim.v
        tau = np.zeros(model.nv)
        target = hold + 0.4 * np.sin(2 * np.pi * 3.0 * k * period)
        tau[6:] = 20.0 * (target - q[7:]) - 0.5 * v[6:]
        sim.step(tau, ignore_unactuated=True)
        reading = sim.read_sensors()
        q, v = sim.q, sim.v
        rotation = pin.Quaternion(q[6], q[3], q[4], q[5]).normalized().toRotationMatrix()
        velocity_world = rotation @ v[:3]
        if previous is not None:  # backward difference of the base's world velocity
            accel_world = (velocity_world - previous) / period
            specific = rotation.T @ (accel_world - np.array([0.0, 0.0, -9.81]))
            errors.append(reading.accelerometer - specific)
        previous = velocity_world
    errors = np.array(errors)
    rms = np.sqrt(np.mean(np.sum(errors**2, axis=1)))
    assert rms < 0.3  # [m/s^2]
    assert np.abs(np.array(errors)).max() < 5.0


def test_noise_has_the_declared_spread_and_the_drawn_bias():
    """300 readings of a noisy and an ideal simulator in the same state: the declared deviations."""
    model = SensorModel(seed=7)
    noisy, _ = _go2(model)
    ideal, _ = _go2(SensorModel.ideal())
    n = len(noisy.read_sensors().joint_names)
    samples = {"gyro": [], "accelerometer": [], "joint_position": [], "joint_velocity": []}
    for _ in range(300):  # the same state each time: no step
        a, b = noisy.read_sensors(), ideal.read_sensors()
        for field in samples:
            samples[field].append(getattr(a, field) - getattr(b, field))
    declared = {
        "gyro": (model.gyro_noise, noisy.sensors.gyro_bias),
        "accelerometer": (model.accel_noise, noisy.sensors.accel_bias),
        "joint_position": (model.encoder_noise, np.zeros(n)),
        "joint_velocity": (model.encoder_velocity_noise, np.zeros(n)),
    }
    for field, (sigma, bias) in declared.items():
        values = np.array(samples[field])
        spread = values.std(axis=0, ddof=1)
        np.testing.assert_allclose(spread, sigma, rtol=0.15, err_msg=field)
        np.testing.assert_allclose(values.mean(axis=0), bias, atol=4 * sigma / np.sqrt(300))
    assert np.all(np.abs(noisy.sensors.gyro_bias) > 0)


def test_the_seed_reproduces_the_readings():
    """A reset with the same seed reads the same; another seed reads otherwise."""
    a, q0 = _go2(SensorModel(seed=3))
    b, _ = _go2(SensorModel(seed=3))
    c, _ = _go2(SensorModel(seed=4))
    first = [a.read_sensors().gyro for _ in range(3)]
    assert all(np.array_equal(x, b.read_sensors().gyro) for x in first)
    assert not np.array_equal(first[0], c.read_sensors().gyro)
    a.reset(a.q)  # the draws start again from the seed
    a.reset(q0, np.array(b.v))
    np.testing.assert_array_equal(a.sensors.gyro_bias, b.sensors.gyro_bias)


def test_contact_switches_only_where_named():
    """``contacts=[...]`` gives those frames' switches, as MuJoCo's contacts; else None."""
    feet = ["FL_foot", "RR_foot"]
    sim, _ = _go2(SensorModel(contacts=feet))
    assert _go2(SensorModel())[0].read_sensors().contacts is None
    for _ in range(200):
        sim.step(np.zeros(sim.robot.model.nv), ignore_unactuated=True)
    reading = sim.read_sensors()
    assert set(reading.contacts) == set(feet)
    assert reading.contacts == {foot: sim.in_contact(foot) for foot in feet}
    assert reading.time == pytest.approx(sim.time)
    assert reading.joint_effort.shape == reading.joint_position.shape


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"gyro_noise": -1.0}, "gyro_noise"),
        ({"accel_bias": float("nan")}, "accel_bias"),
        ({"encoder_noise": "x"}, "encoder_noise"),
        ({"contacts": "FL_foot"}, "contacts"),
        ({"seed": 1.5}, "seed"),
    ],
)
def test_bad_sensor_models_name_the_field(kwargs, match):
    with pytest.raises(va.InvalidInputError, match=match):
        SensorModel(**kwargs)


def test_unknown_frames_say_what_exists():
    robot = va.load_robot("go2")
    with pytest.raises(va.FrameNotFoundError, match="FL_foot"):
        Simulator(robot, sensors=SensorModel(contacts=["FL_fot"]))
    with pytest.raises(va.FrameNotFoundError, match="base"):
        Simulator(robot, sensors=SensorModel(imu="bse"))


def test_ideal_accelerometer_in_free_fall_and_at_rest():
    """Falling freely it reads zero; held in the air by nothing but MuJoCo's gravity off, g."""
    sim, q0 = _go2(SensorModel.ideal())
    q0[2] += 1.0  # high above the ground: free fall for the first ticks
    sim.reset(q0)
    sim.step(np.zeros(sim.robot.model.nv), ignore_unactuated=True)
    np.testing.assert_allclose(sim.read_sensors().accelerometer, 0.0, atol=1e-6)
    sim.model.opt.gravity[:] = 0.0
    sim.reset(q0)
    mujoco.mj_forward(sim.model, sim.data)
    np.testing.assert_allclose(sim.read_sensors().accelerometer, 0.0, atol=1e-9)


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["demo", "turkey-walk", "--estimator"], "--estimator: only the stand demo and"),
        (["demo", "stand", "--duration", "2"], "--duration: stand runs a closed loop only with"),
    ],
)
def test_estimator_options_are_usage_errors_where_they_do_not_apply(argv, message, capsys):
    from virtual_actuators.__main__ import main

    with pytest.raises(SystemExit) as exit_info:
        main([*argv, "--quiet"])
    assert exit_info.value.code == 2
    assert message in capsys.readouterr().err
