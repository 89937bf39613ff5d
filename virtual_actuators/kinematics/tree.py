"""A robot's kinematic tree, its tables made once (`KinematicTree`), and its pass's buffer."""

from __future__ import annotations

import threading
from collections.abc import Iterable

import numpy as np
import pinocchio as pin

from .. import core
from ..core import CORE
from ..exceptions import InvalidInputError
from ..vocabulary.arguments import as_float_array
from ..vocabulary.axes import resolve_frame
from .kernels import finite, placement_row, read_joints

#: finiteness and unit norms of q in one compiled pass (the core's), or None: numpy's checks
_UNIT_NORM_ERROR = core.kernel("unit_norm_error", None)


class KinematicTree:
    """What the kinematics of one model needs, computed once.

    Args:
        model: The Pinocchio model.

    Attributes:
        model: The model.
        compiled: Whether the compiled kernel handles every joint of the model (revolute,
            continuous, prismatic, free-flyer and spherical); False without the core.
        unsupported: Names of the joints the kernel does not handle.
        masses: ``(njoints,)`` mass of each joint's body [kg].
        levers: ``(njoints, 3)`` its centre of mass in the joint's frame [m].
        mass: The robot's total mass [kg].
    """

    def __init__(self, model: pin.Model) -> None:
        self.model = model
        self.nq, self.nv, self.njoints = model.nq, model.nv, model.njoints
        #: the kernel's joint tables (its arguments after ``q`` and ``v``)
        self.joint_tables, self.unsupported, unit_slices = read_joints(model)
        self.compiled = core.has("Tree") and not self.unsupported
        self.masses = np.array([inertia.mass for inertia in model.inertias], dtype=float)
        self.levers = np.array([inertia.lever for inertia in model.inertias], dtype=float)
        self.mass = float(self.masses.sum())
        self.unit_slices = tuple(slice(a, b) for a, b in unit_slices)
        #: ``(k, 2)`` the ``(start, stop)`` of each slice of unit norm (the kernels' argument)
        self.unit_bounds = np.array(unit_slices, dtype=np.int64).reshape(-1, 2)
        self._unit_index = np.array([i for a, b in unit_slices for i in range(a, b)], dtype=int)
        self._unit_groups = np.repeat(
            np.arange(len(unit_slices)), [b - a for a, b in unit_slices]
        ).astype(int)
        self._lock = threading.Lock()
        #: ``(rows, parents, placements)`` of the frames computed at every tick (``rows``: frame
        #: id -> row in the kernel's frame output); replaced (never mutated) on growth
        self.frame_tables: tuple[dict[int, int], np.ndarray, np.ndarray] = (
            {},
            np.zeros(0, dtype=np.int64),
            np.zeros((0, 12)),
        )
        #: the compiled core's tables (C++), rebuilt with the frame table; None: Pinocchio
        self.core_tree = self._core_tree(*self.frame_tables[1:])
        self._frame_columns: dict[int, np.ndarray] = {}
        self._names: dict[str, int] = {}
        #: frame name -> its row in the kernel's frame output (rows never move once given)
        self.name_rows: dict[str, int] = {}

    def frame_id(self, name: str) -> int:
        """Frame id of ``name`` (``"world"`` is 0), resolved once and computed every tick after.

        Raises:
            FrameNotFoundError: Unknown name (with the closest names).
        """
        frame_id = self._names.get(name)
        if frame_id is None:
            frame_id = resolve_frame(self.model, name)
            self.require([frame_id])
            self.name_rows[name] = self.frame_tables[0][frame_id]
            self._names[name] = frame_id
        return frame_id

    def require(self, frame_ids: Iterable[int]) -> None:
        """Have the kernel compute these frames' placements at every tick (declaration time)."""
        with self._lock:
            rows, parents, floats = self.frame_tables
            new = [int(f) for f in frame_ids if int(f) not in rows]
            if not new:
                return
            rows = dict(rows)
            for f in dict.fromkeys(new):
                rows[f] = len(rows)
            frames = [self.model.frames[f] for f in rows]
            parents = np.array([frame.parentJoint for frame in frames], dtype=np.int64)
            floats = np.array([placement_row(frame.placement) for frame in frames])
            floats = floats.reshape(-1, 12)
            # the core's tree first: a reader that gets the new rows gets a tree with them
            self.core_tree = self._core_tree(parents, floats)
            self.frame_tables = (rows, parents, floats)

    def _core_tree(self, parents: np.ndarray, floats: np.ndarray) -> object | None:
        """The compiled core's ``Tree`` for this frame table, or None."""
        if not self.compiled:
            return None
        return CORE.Tree(*self.joint_tables, parents, floats, self.unit_bounds)

    def frame_columns(self, frame_id: int) -> np.ndarray:
        """Velocity indices that move frame ``frame_id`` (its parent joint's support)."""
        columns = self._frame_columns.get(frame_id)
        if columns is None:
            model = self.model
            joints = [model.joints[j] for j in model.supports[model.frames[frame_id].parentJoint]]
            columns = np.array([i for j in joints[1:] for i in range(j.idx_v, j.idx_v + j.nv)], int)
            self._frame_columns[frame_id] = columns
        return columns

    def core_pass(
        self, q: np.ndarray, v: np.ndarray | None = None
    ) -> tuple[np.ndarray, int, dict[int, int]] | None:
        """The core's pass at checked ``q`` (and ``v``): ``(buffer, its frames, rows)``, or None.

        ``buffer``: the joint placements, the world Jacobian, the frames' placements, then
        (with ``v``) their velocities; ``rows``: frame id -> row, the buffer's first rows.
        """
        rows = self.frame_tables[0]  # before the tree: its frame table may have grown since
        core_tree = self.core_tree
        if core_tree is None:
            return None
        return core_tree.compute(q, v), core_tree.nf, rows

    def check_configuration(self, q: np.ndarray) -> np.ndarray:
        """``q`` ``(model.nq,)`` as float64, its shape, values and unit norms checked.

        Quaternions and (cos, sin) pairs within 1e-3 of unit norm are normalised (in a copy).

        Raises:
            InvalidInputError: Wrong shape, NaN or inf, or a quaternion far from unit norm.
        """
        if not (isinstance(q, np.ndarray) and q.dtype == np.float64):
            q = as_float_array(q, "Configuration q", f"an array of {self.nq} real numbers")
        if q.shape != (self.nq,):
            raise InvalidInputError(
                f"Configuration q has shape {q.shape}; model {self.model.name!r} needs "
                f"({self.nq},) (model.nq)."
            )
        if _UNIT_NORM_ERROR is not None:  # finiteness and unit norms in one compiled pass
            error = _UNIT_NORM_ERROR(q, self.unit_bounds)
            if 0.0 <= error <= 1e-12:
                return q
        if not np.isfinite(q).all():
            bad = np.flatnonzero(~np.isfinite(q)).tolist()
            raise InvalidInputError(f"Configuration q has NaN or inf at indices {bad}.")
        if self.unit_slices:
            values = q[self._unit_index]
            norms = np.sqrt(np.bincount(self._unit_groups, weights=values * values))
            error = np.abs(norms - 1.0)
            if error.max() > 1e-12:
                if error.max() > 1e-3:
                    s = self.unit_slices[int(np.argmax(error))]
                    kind = "(cos, sin) pair" if s.stop - s.start == 2 else "quaternion"
                    raise InvalidInputError(
                        f"Configuration q[{s.start}:{s.stop}] is a {kind} of norm "
                        f"{norms[int(np.argmax(error))]:.6g}; it must have unit norm (see "
                        "pinocchio.normalize)."
                    )
                q = q.copy()  # integration drift: use the exact unit quaternion
                q[self._unit_index] = values / norms[self._unit_groups]
        return q

    def check_velocity(self, v: np.ndarray) -> np.ndarray:
        """Return ``v`` as a float array after checking its shape and values.

        Raises:
            InvalidInputError: Wrong shape, NaN or inf.
        """
        if not (isinstance(v, np.ndarray) and v.dtype == np.float64):
            v = as_float_array(v, "Velocity v", f"an array of {self.nv} real numbers")
        if v.shape != (self.nv,):
            raise InvalidInputError(
                f"Velocity v has shape {v.shape}; model {self.model.name!r} needs ({self.nv},) "
                "(model.nv)."
            )
        if not finite(v):
            raise InvalidInputError("Velocity v has NaN or inf entries.")
        return v

    def __repr__(self) -> str:
        backend = "compiled" if self.compiled else "pinocchio"
        return (
            f"KinematicTree(model={self.model.name!r}, njoints={self.njoints}, nv={self.nv}, "
            f"backend={backend!r}, frames per tick={len(self.frame_tables[0])})"
        )


_TREES_LOCK = threading.Lock()


def tree_of(robot: object) -> KinematicTree:
    """Return the `KinematicTree` of a robot, built on first use and kept in its caches.

    Raises:
        InvalidInputError: ``robot`` is not a [`Robot`][].
    """
    caches = getattr(robot, "caches", None)
    tree = caches.get("kinematic_tree") if isinstance(caches, dict) else None
    if tree is not None:  # a robot checked when its tree was built
        return tree
    if not isinstance(caches, dict) or not isinstance(getattr(robot, "model", None), pin.Model):
        raise InvalidInputError(
            f"robot must be a va.Robot (from va.load_robot), got {type(robot).__name__}."
        )
    with _TREES_LOCK:
        tree = caches.get("kinematic_tree")
        if tree is None:
            tree = caches["kinematic_tree"] = KinematicTree(robot.model)
    return tree
