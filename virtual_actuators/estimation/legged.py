"""The base state of a legged robot from its IMU, its encoders and its efforts."""

from __future__ import annotations

import threading
from collections.abc import Sequence

import numpy as np
import pinocchio as pin

from .. import core
from ..exceptions import InvalidInputError, MissingDependencyError, suggestion
from ..kinematics.tree import KinematicTree, tree_of
from ..models.feet import find_feet
from ..models.robot import Robot
from ..models.soles import sole_sphere
from .estimate import Estimate
from .reading import SensorReading
from .tuning import EstimatorTuning

#: Readings beyond these are no IMU's (the largest MEMS ranges: 2000 deg/s, 50 g).
GYRO_RANGE = 35.0  # [rad/s]
ACCEL_RANGE = 500.0  # [m/s^2]


_EMPTY = np.zeros(0)  # to the core: no tau (the reading's joint_effort), no switches
#: Why the compiled filter refused a reading (its update_reading's codes).
_REJECTED = {
    1: "SensorReading.gyro {reading.gyro} is beyond any IMU's range (+-35 rad/s).",
    2: "SensorReading.accelerometer {reading.accelerometer} is beyond any IMU's range "
    "(+-500 m/s^2).",
    3: "tau holds non-finite entries: every effort must be finite.",
    4: "SensorReading at t={reading.time} would make the estimate non-finite or its covariance "
    "not positive (numbers out of any robot's range); the estimator is unchanged.",
}


def _compiled_filter(
    robot: Robot, tree: KinematicTree, feet: tuple[str, ...], foot_ids: list[int], imu_id: int,
    tuning: EstimatorTuning,
) -> object:  # fmt: skip
    """The core's filter for these feet and IMU: each leg's velocity columns, its sole, weights."""
    rows = tree.frame_tables[0]
    legs = [np.array([c for c in tree.frame_columns(f) if c >= 6], dtype=np.int64)
            for f in foot_ids]  # fmt: skip
    offsets = np.cumsum([0] + [len(leg) for leg in legs]).astype(np.int64)
    columns = np.concatenate(legs) if legs else np.zeros(0, np.int64)
    gravity = np.array(robot.model.gravity.linear, dtype=float)
    return core.CORE.LeggedFilter(
        tree.core_tree,
        np.array([rows[f] for f in foot_ids], dtype=np.int64),
        int(rows[imu_id]),
        offsets,
        columns,
        np.unique(columns).astype(np.int64),
        tree.masses,
        np.ascontiguousarray(tree.levers),
        np.array([sole_sphere(robot, foot) for foot in feet]),
        gravity,
        tree.mass * float(np.linalg.norm(gravity)) / len(feet),
        tuning.packed(),
        list(feet),
    )


class LeggedEstimator:
    """Orientation, position, velocity and contacts of a legged robot's floating base.

    An error-state filter on the orientation (gyro, accelerometer, stance feet) and a linear
    Kalman filter on the base's position and velocity and the feet's positions (accelerometer,
    leg kinematics), with each foot's contact from its leg's efforts and its speed; the update
    runs in the compiled core. The equations and what drifts: the estimation page of the docs.

    Args:
        robot: A floating-base robot whose joints are all 1-DoF (revolute or prismatic).
        feet: The foot frames; None: those ``demo legged`` finds (`find_feet`).
        imu: The frame the IMU is fixed to, on the base's body; None: the base's body frame.
        tuning: The filter's noise figures and thresholds; None: `EstimatorTuning()` (the
            library's simulated MEMS IMU and encoders).

    Raises:
        InvalidInputError: The robot has a fixed base or a joint that is not 1-DoF, or the IMU
            frame is not on the base's body.
        FrameNotFoundError: A foot or the IMU frame is not a frame of the robot (with the
            closest names), or the robot has no feet to find.
        MissingDependencyError: The compiled core is not available (``VA_CORE=0`` or a source
            tree without a build): the estimator runs only there.
    """

    def __init__(
        self,
        robot: Robot,
        feet: Sequence[str] | None = None,
        imu: str | None = None,
        *,
        tuning: EstimatorTuning | None = None,
    ) -> None:
        model = robot.model
        if not robot.floating_base:
            raise InvalidInputError(
                f"LeggedEstimator needs a floating-base robot; {robot.name!r} has a fixed base "
                "(its state is its encoders)."
            )
        if not core.has("LeggedFilter"):
            raise MissingDependencyError(
                "LeggedEstimator runs in the compiled core, which is not loaded (VA_CORE=0, or "
                "a source tree without a build): reinstall with `pip install -e .`."
            )
        self.tuning = EstimatorTuning() if tuning is None else tuning
        if not isinstance(self.tuning, EstimatorTuning):
            raise InvalidInputError("tuning must be an EstimatorTuning.")
        found = find_feet(robot) if feet is None or imu is None else None
        self.feet = tuple(found.feet if feet is None else feet)
        self.imu = found.body if imu is None else imu
        if not self.feet or not all(isinstance(foot, str) for foot in self.feet):
            raise InvalidInputError("feet must be a non-empty sequence of frame names.")
        if len(set(self.feet)) != len(self.feet):
            raise InvalidInputError(f"feet names a frame twice: {list(self.feet)}.")
        self.robot = robot
        tree = tree_of(robot)
        foot_ids = [tree.frame_id(foot) for foot in self.feet]
        imu_id = tree.frame_id(self.imu)
        if model.frames[imu_id].parentJoint != 1:
            raise InvalidInputError(
                f"imu frame {self.imu!r} is not on the floating base's body (it moves with "
                f"joint {model.names[model.frames[imu_id].parentJoint]!r})."
            )
        joints = [model.joints[j] for j in range(2, model.njoints)]
        wide = [model.names[j] for j, joint in enumerate(joints, 2) if joint.nq != 1]
        if wide:
            raise InvalidInputError(
                f"LeggedEstimator takes 1-DoF joints only; {wide} are not (continuous, "
                "spherical or planar joints have no single encoder reading)."
            )
        #: the encoders' joints, each with its index in q and in v
        self.joint_names = tuple(model.names[j] for j in range(2, model.njoints))
        self._index_q = {name: model.joints[j].idx_q for j, name in enumerate(model.names)}
        self._index_v = {name: model.joints[j].idx_v for j, name in enumerate(model.names)}
        self._filter = _compiled_filter(robot, tree, self.feet, foot_ids, imu_id, self.tuning)
        self._tree = tree
        self._nv = model.nv
        self._lock = threading.Lock()
        self._maps: dict[tuple[str, ...], tuple[np.ndarray, np.ndarray]] = {}
        #: the last list of names and its indices (a reader passes the same tuple each time)
        self._last_map: tuple[tuple[str, ...] | None, tuple[np.ndarray, np.ndarray]] = (
            None, (_EMPTY, _EMPTY)
        )
        self._time: float | None = None
        self._started = False
        self.last: Estimate | None = None

    def reset(self, q: np.ndarray, v: np.ndarray | None = None) -> None:
        """Start again from a known state (e.g. the robot standing on level ground).

        Args:
            q: ``(nq,)`` configuration (Pinocchio's conventions).
            v: ``(nv,)`` velocity (the free flyer's in its own axes); None: at rest.

        Raises:
            InvalidInputError: ``q`` or ``v`` has the wrong shape or non-finite entries.
        """
        q = self._tree.check_configuration(q)
        v = np.zeros(self.robot.model.nv) if v is None else self._tree.check_velocity(v)
        with self._lock:
            self._reset(q, v)

    def _reset(self, q: np.ndarray, v: np.ndarray) -> None:
        rotation = pin.Quaternion(q[6], q[3], q[4], q[5]).normalized().toRotationMatrix()
        q_local = q.copy()
        q_local[:7] = (0, 0, 0, 0, 0, 0, 1)
        self._filter.reset(q_local, q[:3].copy(), np.ascontiguousarray(rotation), rotation @ v[:3])
        self._time = None
        self._started = True

    def _map(self, names: tuple[str, ...]) -> tuple[np.ndarray, np.ndarray]:
        """The indices in q and v of a reading's joints (checked once per list of names)."""
        last_names, last_map = self._last_map  # one attribute: read and written whole (threads)
        if names is last_names:  # a reader's own tuple, reading after reading
            return last_map
        cached = self._maps.get(names)
        if cached is not None:
            self._last_map = (names, cached)
            return cached
        for name in names:
            if name not in self.joint_names:
                raise InvalidInputError(
                    f"SensorReading.joint_names has {name!r}, not a 1-DoF joint of "
                    f"{self.robot.name!r}. " + suggestion(name, self.joint_names, "joints")
                )
        missing = [name for name in self.joint_names if name not in names]
        if missing:
            raise InvalidInputError(
                f"SensorReading.joint_names lacks {missing}: the estimator needs every joint."
            )
        cached = (
            np.array([self._index_q[name] for name in names], dtype=np.int64),
            np.array([self._index_v[name] for name in names], dtype=np.int64),
        )
        self._maps[names] = cached
        self._last_map = (names, cached)
        return cached

    def update(self, reading: SensorReading, tau: np.ndarray | None = None) -> Estimate:
        """Take one reading: the estimate at its time.

        A foot the reading's ``contacts`` name takes the switch's word for its contact; the
        others are estimated from their legs' efforts and their speed.

        Without a [`reset`][virtual_actuators.estimation.LeggedEstimator.reset] first, the
        estimator starts at the first reading: base at the world's origin over its feet (on
        level ground at height 0), level, heading along x, at rest.

        Args:
            reading: What the robot measured.
            tau: ``(nv,)`` the efforts commanded for the last period; None: the reading's
                ``joint_effort``.

        Returns:
            The estimate at ``reading.time``.

        Raises:
            InvalidInputError: ``reading`` is not a `SensorReading`, names a joint the robot
                does not have or lacks one, its IMU reads beyond any IMU's range
                (`GYRO_RANGE`, `ACCEL_RANGE`), its time does not advance, ``tau`` has the wrong
                shape or non-finite entries, or its numbers would make the estimate non-finite.
                The estimator is then exactly as it was.
        """
        if not isinstance(reading, SensorReading):
            raise InvalidInputError(
                f"update takes a SensorReading, not {type(reading).__name__}."
            )
        index_q, index_v = self._map(reading.joint_names)
        if tau is None:
            tau = _EMPTY
        elif not (isinstance(tau, np.ndarray) and tau.dtype == np.float64 and tau.ndim == 1):
            try:
                tau = np.ascontiguousarray(tau, dtype=float)
            except (TypeError, ValueError):
                raise InvalidInputError("tau must be an array of numbers [N m or N].") from None
        nv = self._nv
        if tau.shape != (nv,) and tau is not _EMPTY:
            raise InvalidInputError(f"tau must be ({nv},) efforts (model.nv), got {tau.shape}.")
        with self._lock:
            if self._time is not None and not reading.time > self._time:
                raise InvalidInputError(
                    f"SensorReading.time {reading.time} does not advance (the last reading was "
                    f"at {self._time})."
                )
            if not self._started:
                self._start(reading, index_q)
            code = self._filter.update_reading(
                reading.joint_position, reading.joint_velocity, reading.joint_effort, index_q,
                index_v, reading.gyro, reading.accelerometer, np.ascontiguousarray(tau),
                reading.time, GYRO_RANGE, ACCEL_RANGE, self._switches(reading.contacts),
            )  # fmt: skip
            if code:
                raise InvalidInputError(_REJECTED[code].format(reading=reading))
            self._time = reading.time
            q, v, contact, in_contact, covariance = self._filter.estimate()
            self.last = Estimate(reading.time, q, v, contact, in_contact, covariance)
            return self.last

    def _switches(self, contacts: dict[str, bool] | None) -> np.ndarray:
        """The reading's contact switches on the feet: 1 closed, 0 open, -1 none."""
        if not contacts:
            return _EMPTY
        return np.array([float(contacts[f]) if f in contacts else -1.0 for f in self.feet])

    def _start(self, reading: SensorReading, index_q: np.ndarray) -> None:
        """Reset from a first reading: level (tilt from gravity), heading x, over the feet."""
        q_local = self.robot.neutral()
        q_local[:7] = (0, 0, 0, 0, 0, 0, 1)
        q_local[index_q] = reading.joint_position
        up = reading.accelerometer / max(float(np.linalg.norm(reading.accelerometer)), 1e-9)
        rotation = pin.Quaternion.FromTwoVectors(up, np.array([0.0, 0.0, 1.0])).toRotationMatrix()
        data = pin.Data(self.robot.model)
        pin.framesForwardKinematics(self.robot.model, data, q_local)
        heights = [(rotation @ data.oMf[self._tree.frame_id(f)].translation)[2] for f in self.feet]
        q = q_local.copy()
        q[:3] = (0.0, 0.0, -float(np.mean(heights)))
        q[3:7] = pin.Quaternion(rotation).coeffs()
        self._reset(q, np.zeros(self.robot.model.nv))

    def __repr__(self) -> str:
        return f"LeggedEstimator({self.robot.name!r}, feet={list(self.feet)}, imu={self.imu!r})"
