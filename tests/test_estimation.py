"""The legged state estimator against MuJoCo's truth, on readings this file builds itself.

The readings come from MuJoCo's data through this file's own noise (not the library's sensor
code), so that the estimator is tested as a user's driver would feed it.
"""

import mujoco
import numpy as np
import pinocchio as pin
import pytest

import virtual_actuators as va
from virtual_actuators import core
from virtual_actuators.gaits.legged.walk import LeggedWalkConfig, run_legged_walk
from virtual_actuators.simulation import Simulator
from virtual_actuators.simulation.conversions import velocity_from_mujoco

pytestmark = pytest.mark.skipif(
    not core.has("LeggedFilter"), reason="the estimator runs in the compiled core"
)

GYRO, ACCEL = 0.0107, 0.1265  # [rad/s, m/s^2] per reading, this file's own IMU
ENCODER, ENCODER_RATE = 1e-4, 1e-2  # [rad, rad/s]


class ThirdPartyIMU:
    """Readings from MuJoCo's data with this file's noise and biases (a user's driver)."""

    def __init__(self, sim: Simulator, names: tuple[str, ...], seed: int, noisy: bool = True):
        model = sim.robot.model
        self.sim, self.names, self.noisy = sim, names, noisy
        self.iq = np.array([model.joints[model.getJointId(n)].idx_q for n in names])
        self.iv = np.array([model.joints[model.getJointId(n)].idx_v for n in names])
        self.body = sim.mujoco_model.frame_body("base")
        self.rng = np.random.default_rng(seed)
        self.gyro_bias = self.rng.normal(0, 0.0087, 3) if noisy else np.zeros(3)
        self.accel_bias = self.rng.normal(0, 0.05, 3) if noisy else np.zeros(3)

    def noise(self, sigma: float, n: int) -> np.ndarray:
        return self.rng.normal(0.0, sigma, n) if self.noisy else np.zeros(n)

    def read(self) -> va.SensorReading:
        sim = self.sim
        m, d = sim.model, sim.data
        q, v = sim.q, sim.v
        mujoco.mj_rnePostConstraint(m, d)
        acc = np.zeros(6)
        mujoco.mj_objectAcceleration(m, d, mujoco.mjtObj.mjOBJ_XBODY, self.body, acc, 1)
        tau = velocity_from_mujoco(sim.mujoco_model, d.qpos, d.qfrc_actuator)
        n = len(self.names)
        return va.SensorReading(
            time=d.time, joint_names=self.names,
            joint_position=q[self.iq] + self.noise(ENCODER, n),
            joint_velocity=v[self.iv] + self.noise(ENCODER_RATE, n),
            joint_effort=tau[self.iv],
            gyro=v[3:6] + self.gyro_bias + self.noise(GYRO, 3),
            accelerometer=acc[3:] + self.accel_bias + self.noise(ACCEL, 3),
        )  # fmt: skip


def _rotation(q: np.ndarray) -> np.ndarray:
    return pin.Quaternion(q[6], q[3], q[4], q[5]).normalized().toRotationMatrix()


@pytest.mark.slow
def test_go2_trot_estimated_beside_the_truth_from_third_party_readings():
    """go2 trots on the truth at 0.8 m/s; the estimator, fed this file's readings, keeps up."""
    state, rows = {}, []

    def on_tick(sim, gait):
        if not state:
            estimator = va.estimation.LeggedEstimator(sim.robot)
            estimator.reset(sim.q, sim.v)
            state.update(est=estimator, imu=ThirdPartyIMU(sim, estimator.joint_names, seed=3))
        estimate = state["est"].update(state["imu"].read())
        q, v = sim.q, sim.v
        agree = all(estimate.in_contact[f] == sim.in_contact(f) for f in state["est"].feet)
        r, r_est = _rotation(q), _rotation(estimate.q)
        yaw_error = (r @ pin.log3(r.T @ r_est))[2]
        rows.append((
            sim.time, *(r_est @ estimate.v[:3] - r @ v[:3]), estimate.q[2] - q[2], yaw_error,
            agree,
        ))  # fmt: skip

    config = LeggedWalkConfig(robot="go2", speed=0.8, duration=6.0)
    result = run_legged_walk(config, progress=False, on_tick=on_tick)
    assert not result.metrics.fell
    rows = np.array(rows)
    late = rows[:, 0] > 1.0
    velocity_rms = np.sqrt(np.mean(np.sum(rows[late, 1:3] ** 2, axis=1)))
    assert velocity_rms < 0.05
    assert np.sqrt(np.mean(rows[:, 4] ** 2)) < 0.01  # height [m]
    assert abs(rows[-1, 5]) < 0.05  # yaw drift [rad]
    assert rows[:, 6].mean() > 0.95  # every foot's contact as MuJoCo's


def _standing_readings(ticks: int, seed: int, noisy: bool = True):
    """go2 held standing by a joint PD in MuJoCo: its state and this file's readings."""
    robot = va.load_robot("go2")
    sim = Simulator(robot)
    q0 = sim.on_ground(robot.q0.copy() if hasattr(robot, "q0") else robot.neutral())
    sim.reset(q0)
    names = tuple(robot.model.names[j] for j in range(2, robot.model.njoints))
    imu = ThirdPartyIMU(sim, names, seed, noisy)
    readings, states = [], []
    hold = q0[7:].copy()
    for _ in range(ticks):
        q, v = sim.q, sim.v
        tau = np.zeros(robot.model.nv)
        tau[6:] = 60.0 * (hold - q[7:]) - 2.0 * v[6:]
        sim.step(tau, ignore_unactuated=True)
        readings.append(imu.read())
        states.append((sim.q, sim.v))
    return robot, sim, q0, readings, states


def test_bad_readings_leave_the_estimator_exactly_as_it_was():
    """Bad readings interleaved with good ones raise typed errors; the run ends as the clean one."""
    robot, _, q0, readings, _ = _standing_readings(120, seed=1)
    clean = va.estimation.LeggedEstimator(robot)
    mixed = va.estimation.LeggedEstimator(robot)
    clean.reset(q0)
    mixed.reset(q0)
    names = readings[0].joint_names
    renamed = (names[0] + "_typo", *names[1:])

    def bad_variants(reading: va.SensorReading, previous: va.SensorReading | None):
        fields = dict(
            joint_position=reading.joint_position, joint_velocity=reading.joint_velocity,
            joint_effort=reading.joint_effort, gyro=reading.gyro,
            accelerometer=reading.accelerometer,
        )  # fmt: skip
        yield va.SensorReading(time=reading.time, joint_names=renamed, **fields), "joint_names"
        yield va.SensorReading(time=reading.time, joint_names=names[1:], **{
            k: (v[1:] if k.startswith("joint") else v) for k, v in fields.items()
        }), "joint_names"  # fmt: skip
        if previous is not None:  # the time of the last good reading: it did not advance
            yield va.SensorReading(time=previous.time, joint_names=names, **fields), "time"
        huge = dict(fields, accelerometer=np.array([1e300, 0.0, 0.0]))
        yield va.SensorReading(time=reading.time, joint_names=names, **huge), "accelerometer"
        spin = dict(fields, gyro=np.array([0.0, 0.0, 1e4]))
        yield va.SensorReading(time=reading.time, joint_names=names, **spin), "gyro"

    previous = None
    for k, reading in enumerate(readings):
        expected = clean.update(reading)
        if k % 7 == 3:
            for bad, field in bad_variants(reading, previous):
                with pytest.raises(va.InvalidInputError, match=field):
                    mixed.update(bad)
            with pytest.raises(va.InvalidInputError, match="tau"):
                mixed.update(reading, np.zeros(3))
        got = mixed.update(reading)
        previous = reading
        np.testing.assert_array_equal(got.q, expected.q)
        np.testing.assert_array_equal(got.v, expected.v)
        np.testing.assert_array_equal(got.covariance, expected.covariance)
        assert got.in_contact == expected.in_contact


def test_sensor_reading_fields_are_checked_by_name():
    """A reading with a non-finite, missized or duplicated field names that field."""
    good = dict(
        time=0.1, joint_names=("a", "b"), joint_position=[0.0, 0.1], joint_velocity=[0.0, 0.0],
        joint_effort=[0.0, 0.0], gyro=[0.0, 0.0, 0.0], accelerometer=[0.0, 0.0, 9.81],
    )  # fmt: skip
    va.SensorReading(**good)
    for field, value in [
        ("gyro", [0.0, np.nan, 0.0]), ("accelerometer", [0.0, 0.0]),
        ("joint_velocity", [0.0]), ("joint_names", ("a", "a")), ("time", float("inf")),
        ("joint_effort", "x"), ("contacts", {"foot": 1}),
    ]:  # fmt: skip
        with pytest.raises(va.InvalidInputError, match=field):
            va.SensorReading(**{**good, field: value})


def test_estimate_follows_pinocchio_conventions_at_rest():
    """Ideal readings of a standing robot: the estimate stays at the truth (q, v, contacts)."""
    robot, sim, q0, readings, states = _standing_readings(400, seed=0, noisy=False)
    estimator = va.estimation.LeggedEstimator(robot)
    estimator.reset(q0)
    for reading in readings:
        estimate = estimator.update(reading)
    q, v = states[-1]
    assert estimate.q.shape == (robot.model.nq,) and estimate.v.shape == (robot.model.nv,)
    np.testing.assert_allclose(estimate.q[7:], q[7:], atol=1e-12)
    np.testing.assert_allclose(estimate.q[:3], q[:3], atol=3e-3)  # [m] after settling
    assert np.linalg.norm(pin.log3(_rotation(q).T @ _rotation(estimate.q))) < 1e-2  # [rad]
    np.testing.assert_allclose(estimate.v[:6], v[:6], atol=1e-2)
    assert all(estimate.in_contact.values())
    assert all(0.0 <= p <= 1.0 for p in estimate.contact.values())
    assert estimate.covariance.shape == (6, 6)
    np.testing.assert_allclose(estimate.covariance, estimate.covariance.T)


def test_compiled_filter_reads_back_its_reset_before_any_reading():
    """The core's estimate right after a reset is the reset state (it once read unset joints)."""
    robot = va.load_robot("go2")
    estimator = va.estimation.LeggedEstimator(robot)
    q = robot.neutral()
    q[:3] = (0.1, -0.2, 0.3)
    q[7:] += 0.05
    estimator.reset(q)
    q_out, v_out, contact, in_contact, covariance = estimator._filter.estimate()
    np.testing.assert_allclose(q_out, q, atol=1e-15)
    np.testing.assert_array_equal(v_out, 0.0)
    assert list(contact) == list(estimator.feet) and all(in_contact.values())
    assert covariance.shape == (6, 6)


def test_covariance_matches_a_monte_carlo_spread():
    """Over many noise draws, the spread of the velocity and height errors is the covariance's."""
    robot, sim, q0, _, states = _standing_readings(1, seed=0, noisy=False)
    q, v = states[-1]
    tuning = va.estimation.EstimatorTuning(
        gyro_bias_sigma=1e-6, gyro_bias_walk=0.0, foot_slip=0.0, kinematics_noise=1e-5,
        foot_velocity_noise=1e-3, foot_height_noise=1e-5, velocity_process_noise=ACCEL,
    )  # fmt: skip
    names = tuple(robot.model.names[j] for j in range(2, robot.model.njoints))
    model = robot.model
    iq = np.array([model.joints[model.getJointId(n)].idx_q for n in names])
    specific_force = _rotation(q).T @ np.array([0.0, 0.0, 9.81])
    errors, covariances = [], []
    for run in range(60):
        rng = np.random.default_rng(100 + run)
        estimator = va.estimation.LeggedEstimator(robot, tuning=tuning)
        estimator.reset(q)
        for k in range(1, 201):
            estimate = estimator.update(va.SensorReading(
                time=k * 1e-3, joint_names=names,
                joint_position=q[iq] + rng.normal(0, tuning.encoder_noise, len(names)),
                joint_velocity=rng.normal(0, tuning.encoder_velocity_noise, len(names)),
                joint_effort=np.zeros(len(names)),
                gyro=rng.normal(0, tuning.gyro_noise, 3),
                accelerometer=specific_force + rng.normal(0, tuning.accel_noise, 3),
            ), _holding_efforts(robot, q))  # fmt: skip
        velocity = _rotation(estimate.q) @ estimate.v[:3]
        errors.append([*velocity, estimate.q[2] - q[2]])
        covariances.append(np.diag(estimate.covariance)[[3, 4, 5, 2]])
    spread = np.std(np.array(errors), axis=0)
    predicted = np.sqrt(np.mean(covariances, axis=0))
    np.testing.assert_allclose(spread, predicted, rtol=0.3)


def _holding_efforts(robot, q):
    """The efforts that hold the robot on its feet: gravity compensation on the legs."""
    tau = pin.computeGeneralizedGravity(robot.model, robot.model.createData(), q)
    return tau


def test_va_run_computes_on_the_estimate_and_fails_a_bad_reading_by_its_field():
    """va.run with an estimator: readings in, the walker on the estimate; a repeated time fails."""
    from virtual_actuators.simulation import MujocoHardware

    robot = va.load_robot("go2")
    walker = va.LeggedWalker(robot, pattern="trot")
    sim = Simulator(robot)
    sim.reset(sim.on_ground(walker.initial_configuration()))
    hardware = MujocoHardware(sim)
    estimator = va.estimation.LeggedEstimator(robot, feet=walker.feet)
    estimator.reset(sim.q)
    readings = []

    def read():
        readings.append(hardware.read_sensors() if len(readings) % 50 != 49 else readings[-1])
        return readings[-1]

    stats = va.run(
        walker, read, hardware.write_effort, realtime=False, estimator=estimator,
        sense=lambda q, v, t: estimator.last.in_contact, should_stop=lambda: len(readings) >= 400,
    )  # fmt: skip
    assert stats.reasons == {"bad sensor reading: time": 8}
    assert stats.ticks == 400 and estimator.last.time == max(r.time for r in readings)
    assert abs(estimator.last.q[2] - sim.q[2]) < 5e-3  # standing on its estimate


def test_contact_switches_take_precedence_over_the_estimate():
    """A reading's switch on a foot is its contact; the feet without one are estimated."""
    robot, _, q0, readings, _ = _standing_readings(60, seed=2)
    estimator = va.estimation.LeggedEstimator(robot)
    estimator.reset(q0)
    foot, other = estimator.feet[0], estimator.feet[1]
    for reading in readings:
        switched = va.SensorReading(
            time=reading.time, joint_names=reading.joint_names,
            joint_position=reading.joint_position, joint_velocity=reading.joint_velocity,
            joint_effort=reading.joint_effort, gyro=reading.gyro,
            accelerometer=reading.accelerometer, contacts={foot: False, "not_a_foot": True},
        )  # fmt: skip
        estimate = estimator.update(switched)
    assert estimate.in_contact[foot] is False and estimate.contact[foot] == 0.0
    assert estimate.in_contact[other] is True  # standing: its efforts and stillness say so
