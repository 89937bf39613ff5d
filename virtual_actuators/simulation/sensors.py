"""What a simulated robot measures: an IMU, joint encoders, contact switches, with MEMS noise.

MuJoCo adds no noise to its sensors; this module adds it. The defaults are the ADIS16448
figures that rotors_simulator's IMU plugin (and gz-sensors' examples) use: white-noise densities
gyro 3.39e-4 rad/s/sqrt(Hz) and accelerometer 4.0e-3 m/s^2/sqrt(Hz), turn-on biases gyro
0.5 deg/s and accelerometer 20 mg. A white noise of density N read at f Hz has the per-reading
deviation N sqrt(f) (the deviation of a band-limited sensor sampled at its bandwidth): at 1 kHz,
1.07e-2 rad/s and 0.126 m/s^2.

The gyro comes from the state now (on the floating base's body; MuJoCo's own body velocities lag
it by a physics step after ``mj_step``); the accelerometer from ``mj_rnePostConstraint`` and
``mj_objectAcceleration``, which read the last physics step's acceleration: half a millisecond
old at the default 0.5 ms step, within 0.3 m/s^2 rms of the velocity's finite difference.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, replace
from typing import Protocol

import mujoco
import numpy as np

from ..estimation.reading import SensorReading
from ..estimation.tuning import ACCEL_NOISE_1KHZ, GYRO_BIAS_SIGMA, GYRO_NOISE_1KHZ
from ..exceptions import FrameNotFoundError, InvalidInputError, suggestion
from ..models.feet import body_frame


class Simulated(Protocol):
    """What `Sensors` reads of a simulator (`Simulator`, which holds the sensors)."""

    robot: object
    mujoco_model: object
    model: mujoco.MjModel
    data: mujoco.MjData

    @property
    def q(self) -> np.ndarray: ...  # noqa: D102

    @property
    def v(self) -> np.ndarray: ...  # noqa: D102

    @property
    def time(self) -> float: ...  # noqa: D102

    def in_contact(self, frame: str) -> bool: ...  # noqa: D102

#: The ADIS16448's turn-on accelerometer bias (rotors_simulator: 20 mg) [m/s^2].
ACCEL_BIAS_SIGMA = 20e-3 * 9.8
#: A 14-bit absolute encoder's quantisation, 2 pi / 2^14 / sqrt(12) ~ 1.1e-4 rad [rad].
ENCODER_NOISE = 1e-4
#: Its velocity, differentiated and filtered [rad/s].
ENCODER_VELOCITY_NOISE = 1e-2

_NOISES = ("gyro_noise", "gyro_bias", "accel_noise", "accel_bias", "encoder_noise",
           "encoder_velocity_noise")  # fmt: skip


@dataclass(frozen=True)
class SensorModel:
    """The sensors of a simulated robot and their noise (standard deviations, per reading).

    Args:
        imu: The frame the IMU is fixed to; None: the floating base's body frame.
        gyro_noise: Gyro white noise [rad/s] (default: the ADIS16448 at 1 kHz).
        gyro_bias: Deviation of the gyro's constant bias, drawn per axis at each reset [rad/s].
        accel_noise: Accelerometer white noise [m/s^2].
        accel_bias: Deviation of its constant bias, drawn at each reset [m/s^2].
        encoder_noise: Joint position white noise [rad or m].
        encoder_velocity_noise: Joint velocity white noise [rad/s or m/s].
        contacts: Frames with a contact switch; None: no switches.
        seed: Seeds the draws: a simulator reset with the same seed reads the same noise.

    Raises:
        InvalidInputError: A noise that is negative or not finite, a seed that is not an int,
            contacts that are not frame names (the message names the field).
    """

    imu: str | None = None
    gyro_noise: float = GYRO_NOISE_1KHZ
    gyro_bias: float = GYRO_BIAS_SIGMA
    accel_noise: float = ACCEL_NOISE_1KHZ
    accel_bias: float = ACCEL_BIAS_SIGMA
    encoder_noise: float = ENCODER_NOISE
    encoder_velocity_noise: float = ENCODER_VELOCITY_NOISE
    contacts: Sequence[str] | None = None
    seed: int = 0

    def __post_init__(self) -> None:
        for name in _NOISES:
            value = getattr(self, name)
            if isinstance(value, bool) or not isinstance(value, (int, float)):
                raise InvalidInputError(f"SensorModel.{name} must be a number, not {value!r}.")
            if not (math.isfinite(value) and value >= 0):
                raise InvalidInputError(f"SensorModel.{name} must be finite and >= 0, not {value}.")
        if self.imu is not None and not isinstance(self.imu, str):
            raise InvalidInputError("SensorModel.imu must be a frame name or None.")
        if self.contacts is not None:
            if isinstance(self.contacts, str) or not all(
                isinstance(c, str) for c in self.contacts
            ):
                raise InvalidInputError("SensorModel.contacts must be None or frame names.")
            object.__setattr__(self, "contacts", tuple(self.contacts))
        if isinstance(self.seed, bool) or not isinstance(self.seed, (int, np.integer)):
            raise InvalidInputError(f"SensorModel.seed must be an int, not {self.seed!r}.")

    @classmethod
    def ideal(cls, imu: str | None = None, contacts: Sequence[str] | None = None) -> SensorModel:
        """The same sensors without noise or bias."""
        return cls(imu=imu, contacts=contacts, **{name: 0.0 for name in _NOISES})

    @classmethod
    def from_densities(
        cls, gyro_density: float, accel_density: float, rate_hz: float, **others: object
    ) -> SensorModel:
        """The IMU's white noise from its densities [rad/s/sqrt(Hz), m/s^2/sqrt(Hz)] at a rate.

        Raises:
            InvalidInputError: A rate that is not positive, or a bad field.
        """
        if not (isinstance(rate_hz, (int, float)) and math.isfinite(rate_hz) and rate_hz > 0):
            raise InvalidInputError(f"rate_hz must be a positive number, not {rate_hz!r}.")
        root = math.sqrt(rate_hz)
        return replace(
            cls(**others), gyro_noise=gyro_density * root, accel_noise=accel_density * root
        )


class Sensors:
    """A `SensorModel` compiled for one simulator: its IMU site, joints, switches and draws.

    Args:
        model: The sensor model.
        simulator: The simulation it reads.

    Raises:
        FrameNotFoundError: The IMU or a contact frame is not a frame of the robot (with the
            closest names).
    """

    def __init__(self, model: SensorModel, simulator: Simulated) -> None:
        robot = simulator.robot
        pin_model = robot.model
        self.model, self.simulator = model, simulator
        frames = [frame.name for frame in pin_model.frames]
        imu = model.imu or body_frame(pin_model, robot.floating_base)
        for name in (imu, *(model.contacts or ())):
            if name not in simulator.mujoco_model.frame_sites:
                raise FrameNotFoundError(
                    f"SensorModel: {name!r} is not a frame of {robot.name!r}. "
                    + suggestion(name, frames, "frames")
                )
        self.imu = imu
        self._site = int(simulator.mujoco_model.frame_sites[imu])
        frame = pin_model.frames[pin_model.getFrameId(imu)]
        #: on a floating base's body: the IMU's axes in the free flyer's (the gyro from the
        #: state, which MuJoCo's own velocities lag by a physics step); else None
        self._base_rotation = (
            frame.placement.rotation.copy()
            if robot.floating_base and frame.parentJoint == 1
            else None
        )
        joints = [
            j for j in range(1, pin_model.njoints)
            if pin_model.joints[j].nq == 1 and pin_model.joints[j].nv == 1
        ]  # fmt: skip
        self.joint_names = tuple(pin_model.names[j] for j in joints)
        self._iq = np.array([pin_model.joints[j].idx_q for j in joints], dtype=int)
        self._iv = np.array([pin_model.joints[j].idx_v for j in joints], dtype=int)
        self._effort = np.zeros(len(joints))
        self.reset()

    def reset(self) -> None:
        """Draw the biases again from the seed (a simulator's reset)."""
        m = self.model
        self._rng = np.random.default_rng(m.seed)
        self.gyro_bias = self._rng.normal(0.0, 1.0, 3) * m.gyro_bias  # [rad/s]
        self.accel_bias = self._rng.normal(0.0, 1.0, 3) * m.accel_bias  # [m/s^2]
        self._effort[:] = 0.0

    def applied(self, tau: np.ndarray) -> None:
        """The efforts held during the period that just ran (`Simulator.step`)."""
        self._effort = np.asarray(tau, dtype=float)[self._iv]

    def read(self) -> SensorReading:
        """One reading now, noise added."""
        sim, m, rng = self.simulator, self.model, self._rng
        mj_model, data = sim.model, sim.data
        q, v = sim.q, sim.v
        if self._base_rotation is not None:
            rate_imu = self._base_rotation.T @ v[3:6]  # [rad/s]
        else:  # a body further down the tree: MuJoCo's velocity of its site
            velocity = np.zeros(6)
            mujoco.mj_objectVelocity(
                mj_model, data, mujoco.mjtObj.mjOBJ_SITE, self._site, velocity, 1
            )
            rate_imu = velocity[:3]
        mujoco.mj_rnePostConstraint(mj_model, data)  # cacc: what mj_objectAcceleration reads
        acceleration = np.zeros(6)  # includes -gravity: the specific force an accelerometer feels
        mujoco.mj_objectAcceleration(
            mj_model, data, mujoco.mjtObj.mjOBJ_SITE, self._site, acceleration, 1
        )
        n = len(self.joint_names)
        contacts = None
        if m.contacts is not None:
            contacts = {frame: bool(sim.in_contact(frame)) for frame in m.contacts}
        return SensorReading(
            time=sim.time,
            joint_names=self.joint_names,
            joint_position=q[self._iq] + rng.normal(0.0, 1.0, n) * m.encoder_noise,
            joint_velocity=v[self._iv] + rng.normal(0.0, 1.0, n) * m.encoder_velocity_noise,
            joint_effort=self._effort.copy(),
            gyro=rate_imu + self.gyro_bias + rng.normal(0.0, 1.0, 3) * m.gyro_noise,
            accelerometer=acceleration[3:]
            + self.accel_bias
            + rng.normal(0.0, 1.0, 3) * m.accel_noise,
            contacts=contacts,
        )


__all__ = ["SensorModel", "Sensors"]
