"""The legged estimator's noise figures and thresholds, with where each default comes from."""

from __future__ import annotations

import math
from dataclasses import dataclass, fields

import numpy as np

from ..exceptions import InvalidInputError

#: The ADIS16448's noise densities, as rotors_simulator's IMU plugin and gz-sensors use them:
#: gyro 3.39e-4 rad/s/sqrt(Hz), accelerometer 4.0e-3 m/s^2/sqrt(Hz); per reading at 1 kHz
#: (density x sqrt(rate)) 1.07e-2 rad/s and 0.126 m/s^2.
GYRO_NOISE_1KHZ = 2.0 * 35.0 / 3600.0 / 180.0 * math.pi * math.sqrt(1000.0)  # [rad/s]
ACCEL_NOISE_1KHZ = 2.0 * 2.0e-3 * math.sqrt(1000.0)  # [m/s^2]
#: Its turn-on gyro bias (rotors_simulator: 0.5 deg/s), the filter's prior on the bias.
GYRO_BIAS_SIGMA = 0.5 / 180.0 * math.pi  # [rad/s]


@dataclass(frozen=True)
class EstimatorTuning:
    """What the legged estimator assumes of the sensors and the feet.

    The sensor figures are per reading (a density times the square root of the rate) and
    default to the library's simulated MEMS IMU and encoders
    ([`SensorModel`][virtual_actuators.simulation.SensorModel]); the others are the filter's
    model of the feet, in SI units. Every field must be finite and >= 0.

    Attributes:
        gyro_noise: Gyro white noise [rad/s].
        gyro_bias_walk: The gyro bias's random walk [rad/s/sqrt(s)].
        gyro_bias_sigma: Prior deviation of the gyro bias at reset [rad/s].
        accel_noise: Accelerometer white noise [m/s^2].
        tilt_acceleration: The base's own acceleration that the tilt correction takes as noise
            [m/s^2] (larger: a slower, smoother tilt).
        gravity_gate: Accelerometer readings whose norm is farther than this from gravity's are
            not used for the tilt [m/s^2].
        stance_rate_noise: Noise of the rate between two stance feet from the joints [m/s]:
            how much they are trusted on the gyro's bias (yaw's included); a pair whose
            residual is a chi-square outlier (1 in 1000) is skipped.
        velocity_process_noise: The world acceleration's noise in the position filter: the
            accelerometer's and what the orientation misses of gravity [m/s^2].
        foot_slip: A stance foot's random walk in the world [m/sqrt(s)].
        foot_swing: A swinging foot's random walk [m/sqrt(s)].
        encoder_noise: Joint position noise [rad].
        encoder_velocity_noise: Joint velocity noise [rad/s].
        kinematics_noise: Floor of a foot's position error from the legs (link lengths, foot
            rolling) [m].
        foot_velocity_noise: Floor of a stance foot's velocity (slip, rolling) [m/s].
        foot_height_noise: A stance foot's height above its level at reset [m].
        force_low: Normal force, as a fraction of the weight per foot, below which the
            efforts say "no contact".
        force_high: ... above which they say "contact".
        still_speed: A foot slower than this in the world may be in contact [m/s].
        moving_speed: ... faster than this, it is not [m/s].
        contact_on: Probability above which a foot comes into contact (hysteresis).
        contact_off: Probability below which it leaves.
        contact_low_height: On level ground, a still foot this close to its level is taken to
            stand on it whatever its efforts say (a touchdown before the gait expects it) [m].
        contact_high_height: ... and not above this [m].
        tilt_sigma: Roll and pitch deviation at reset [rad].
        yaw_sigma: Yaw deviation at reset [rad].
        level_ground: Whether stance feet stand at their height at reset (flat ground): it makes
            the height observable and tells the tilt from the accelerometer's bias; on slopes
            and steps turn it off (the height then drifts slowly, the bias tilts the estimate
            by about bias / g).
        accel_bias_walk: The accelerometer bias's random walk [m/s^2/sqrt(s)].
        level_noise: Two stance feet's height difference on level ground (the ground's
            unevenness, the legs' errors) [m].
        output_rate_time: Time constant of the first-order low-pass on the rates the estimate
            gives the controller (the base's angular velocity, the joints' velocities) [s]: the
            gyro's and encoders' white noise, which a controller's damping would pass to the
            motors, down by about sqrt(dt / (2 T)); 0: the raw rates. The filtered rate never
            strays more than three noise deviations (``gyro_noise``, ``encoder_velocity_noise``)
            from the reading, so that it follows a jump (a foot's impact) without lag.
        accel_bias_sigma: Prior deviation of the accelerometer bias at reset [m/s^2] (the
            ADIS16448's turn-on bias, 20 mg).
    """

    gyro_noise: float = GYRO_NOISE_1KHZ
    gyro_bias_walk: float = 1e-4
    gyro_bias_sigma: float = GYRO_BIAS_SIGMA
    accel_noise: float = ACCEL_NOISE_1KHZ
    tilt_acceleration: float = 1.0
    gravity_gate: float = 2.0
    stance_rate_noise: float = 0.005
    velocity_process_noise: float = 0.3
    foot_slip: float = 0.005
    foot_swing: float = 2.0
    encoder_noise: float = 1e-4
    encoder_velocity_noise: float = 1e-2
    kinematics_noise: float = 0.002
    foot_velocity_noise: float = 0.02
    foot_height_noise: float = 0.005
    force_low: float = 0.15
    force_high: float = 0.35
    still_speed: float = 0.2
    moving_speed: float = 0.6
    contact_on: float = 0.6
    contact_off: float = 0.4
    contact_low_height: float = 0.005
    contact_high_height: float = 0.015
    tilt_sigma: float = 0.01
    yaw_sigma: float = 1e-3
    level_ground: bool = True
    accel_bias_walk: float = 1e-3
    level_noise: float = 0.005
    accel_bias_sigma: float = 20e-3 * 9.8
    output_rate_time: float = 0.005

    def __post_init__(self) -> None:
        for field in fields(self):
            value = getattr(self, field.name)
            if field.name == "level_ground":
                if not isinstance(value, bool):
                    raise InvalidInputError("EstimatorTuning.level_ground must be True or False.")
                continue
            if isinstance(value, bool) or not isinstance(value, (int, float)):
                raise InvalidInputError(f"EstimatorTuning.{field.name} must be a number.")
            if not math.isfinite(value) or value < 0:
                raise InvalidInputError(
                    f"EstimatorTuning.{field.name} must be finite and >= 0, not {value}."
                )
        if not self.force_low < self.force_high:
            raise InvalidInputError("EstimatorTuning: force_low must be below force_high.")
        if not self.contact_low_height < self.contact_high_height:
            raise InvalidInputError(
                "EstimatorTuning: contact_low_height must be below contact_high_height."
            )
        if not self.still_speed < self.moving_speed:
            raise InvalidInputError("EstimatorTuning: still_speed must be below moving_speed.")
        if not 0 < self.contact_off <= self.contact_on < 1:
            raise InvalidInputError(
                "EstimatorTuning: 0 < contact_off <= contact_on < 1 (the hysteresis)."
            )

    def packed(self) -> np.ndarray:
        """The 31 numbers of the compiled filter, in its order."""
        t = self
        return np.array(
            [
                t.gyro_noise, t.gyro_bias_walk, t.accel_noise, t.tilt_acceleration,
                t.gravity_gate, t.stance_rate_noise,
                t.velocity_process_noise, t.foot_slip, t.foot_swing, t.encoder_noise,
                t.encoder_velocity_noise, t.gyro_noise, t.kinematics_noise,
                t.foot_velocity_noise, t.foot_height_noise,
                t.force_low, t.force_high, t.still_speed, t.moving_speed, t.contact_on,
                t.contact_off, t.contact_low_height, t.contact_high_height,
                t.tilt_sigma, t.yaw_sigma, t.gyro_bias_sigma, float(t.level_ground),
                t.accel_bias_walk, t.level_noise, t.accel_bias_sigma, t.output_rate_time,
            ],
            dtype=float,
        )  # fmt: skip
