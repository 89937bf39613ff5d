"""Contact queries of a simulation: which frames touch the terrain, and with what force.

The robot-terrain contacts are scanned once per physics state, keyed by
``(data.time, data.ncon)``; the answers derived from them are cached with that scan.
"""

from __future__ import annotations

import ctypes
import functools
from collections.abc import Sequence
from pathlib import Path

import mujoco
import numpy as np

from virtual_actuators.core import CORE
from virtual_actuators.exceptions import FrameNotFoundError
from virtual_actuators.simulation.model import MujocoModel

#: Roles of a geom in the contact scan (0: neither; a terrain geom is never the robot's).
_TERRAIN, _ROBOT = 1, 2


def contact_view(model: mujoco.MjModel, data: mujoco.MjData, roles: list[int]) -> object | None:
    """The compiled core's view of ``data``'s contact list, or None (the scans run in Python).

    None without a core, without MuJoCo's headers in it, or with another MuJoCo version.
    """
    version = getattr(CORE, "MJ_VERSION", 0)
    if not version or version != mujoco.mj_version():
        return None
    return CORE.ContactView(
        model._address, data._address, version, np.array(roles, dtype=np.int64), _contact_force()
    )


@functools.cache
def _contact_force() -> int:
    """The address of the running MuJoCo library's ``mj_contactForce`` (0 if not found)."""
    folder = Path(mujoco.__file__).parent
    for path in sorted(folder.glob("libmujoco*")):
        try:
            library = ctypes.CDLL(str(path))
            return int(ctypes.cast(library.mj_contactForce, ctypes.c_void_p).value or 0)
        except (OSError, AttributeError):
            continue
    return 0


class ContactQueries:
    """Terrain-contact queries by frame name, a base of [`Simulator`][].

    The subclass sets ``mujoco_model``, ``model`` and ``data``, then calls
    `_init_contact_queries`.
    """

    mujoco_model: MujocoModel
    model: mujoco.MjModel
    data: mujoco.MjData

    def _init_contact_queries(self) -> None:
        """Empty the caches (once, at construction)."""
        self._force = np.zeros(6)
        self._owned_geoms: dict[str, frozenset[int]] = {}
        self._force_rows: dict[tuple[str, ...], dict[int, list[int]]] = {}  # contact_forces
        self._contacts: list[tuple[int, int, float]] = []
        self._contacts_time: tuple[float, int] | None = None  # (time, ncon) of _contacts
        self._switch_sets: dict[tuple[str, ...], tuple] = {}  # contact_switches, by frames
        self._touched: tuple[int, ...] = ()
        mm = self.mujoco_model  # per geom id: a terrain geom, a robot geom or neither
        self._geom_roles = [
            _TERRAIN if geom in mm.terrain_geoms else _ROBOT if geom in mm.geom_frames else 0
            for geom in range(self.model.ngeom)
        ]
        #: the core's view of the contact list (None: the Python scan) and its output rows
        self._contact_view = contact_view(self.model, self.data, self._geom_roles)
        self._contact_rows = np.zeros((64, 3), dtype=np.int64)
        self._force_rows_out = np.zeros((64, 4))

    def _frame_geoms(self, frame: str) -> frozenset[int]:
        """The robot geoms of ``frame``, or of its body when it owns none (cached); checked."""
        geoms = self._owned_geoms.get(frame) if isinstance(frame, str) else None
        if geoms is None:
            mm = self.mujoco_model
            mm.check_frame(frame)
            owned = mm.frame_geoms.get(frame, ())
            if not owned:
                body = mm.frame_body(frame)
                owned = [g for g in mm.geom_frames if int(self.model.geom_bodyid[g]) == body]
            geoms = self._owned_geoms[frame] = frozenset(owned)
        return geoms

    def _terrain_contacts(self) -> list[tuple[int, int, float]]:
        """``(index in data.contact, robot geom, sign)`` per robot-terrain contact, once a state.

        ``sign`` is +1 when the robot geom is the second (MuJoCo's force acts on it), else -1.
        """
        key = (self.data.time, self.data.ncon)
        if self._contacts_time != key:
            self._contacts = self._scan_contacts()
            self._touched = tuple([hit[1] for hit in self._contacts])  # robot geoms touching
            self._contacts_time = key
        return self._contacts

    def _scan_contacts(self) -> list[tuple[int, int, float]]:
        """The robot-terrain contacts of MuJoCo's list that are not excluded."""
        view = self._contact_view
        if view is not None:  # the same rows, read in place by the core
            rows = self._contact_rows
            if rows.shape[0] < view.ncon:
                rows = self._contact_rows = np.zeros((2 * view.ncon, 3), dtype=np.int64)
            count = view.scan(rows)
            return [(i, geom, float(sign)) for i, geom, sign in rows[:count].tolist()]
        roles = self._geom_roles
        contacts = self.data.contact
        hits = []
        rows = zip(contacts.geom.tolist(), contacts.exclude.tolist(), strict=True)
        for i, ((g1, g2), exclude) in enumerate(rows):
            if exclude == 0:
                first, second = roles[g1], roles[g2]
                if first == _TERRAIN and second == _ROBOT:
                    hits.append((i, g2, 1.0))
                elif first == _ROBOT and second == _TERRAIN:
                    hits.append((i, g1, -1.0))
        return hits

    def in_contact(self, frame: str) -> bool:
        """Whether a geom of ``frame`` touches the terrain.

        A frame's geoms are those of `MujocoModel.frame_geoms` (a heel frame owns its heel sphere).

        Raises:
            FrameNotFoundError: If the robot has no such frame (with the closest names).
        """
        self._terrain_contacts()
        return not self._frame_geoms(frame).isdisjoint(self._touched)

    def contact_switches(self, frames: Sequence[str]) -> dict[str, bool]:
        """``{frame: in contact}`` for several frames, in one pass (as [`in_contact`][]).

        Raises:
            FrameNotFoundError: If a frame is not the robot's (with the closest names).
        """
        key = frames if frames.__class__ is tuple else tuple(frames)
        try:
            entry = self._switch_sets.get(key)
        except TypeError:  # an unhashable entry: _frame_geoms names it below
            entry = None
        if entry is None:  # per geom, bit k set when it belongs to frame k; answers by mask
            py_bits = [0] * self.model.ngeom
            for k, frame in enumerate(key):
                for geom in self._frame_geoms(frame):
                    py_bits[geom] |= 1 << k
            fits = self._contact_view is not None and len(key) < 63
            entry = (np.array(py_bits, dtype=np.int64) if fits else None, py_bits, {})
            if len(self._switch_sets) >= 64:
                self._switch_sets.clear()
            self._switch_sets[key] = entry  # the frames are names: _frame_geoms checked them
        bits, py_bits, answers = entry
        if bits is not None:  # one compiled pass over MuJoCo's contact list
            mask = self._contact_view.touch_mask(bits)
        else:
            self._terrain_contacts()
            mask = 0
            for geom in self._touched:
                mask |= py_bits[geom]
        out = answers.get(mask)  # the same frames touching: the same answers
        if out is None:
            if len(answers) >= 256:
                answers.clear()
            out = answers[mask] = {frame: bool(mask >> k & 1) for k, frame in enumerate(key)}
        return dict(out)

    def contact_force(self, frame: str) -> np.ndarray:
        """Total force of the terrain on a frame's geoms, world axes [N], shape ``(3,)``.

        A frame without geometry (a sole frame) reads the geometry of its link.

        Raises:
            FrameNotFoundError: If the robot has no such frame (with the closest names), or
                neither the frame nor its link has geometry.
        """
        return self.contact_forces((frame,))[0]

    def contact_forces(self, frames: Sequence[str]) -> np.ndarray:
        """[`contact_force`][] of several frames in one pass: ``(len(frames), 3)`` [N].

        Raises:
            FrameNotFoundError: If the robot has no such frame (with the closest names), or
                neither a frame nor its link has geometry.
        """
        key = tuple(frames)
        try:
            rows_of = self._force_rows.get(key)
        except TypeError:  # an unhashable entry: _frame_geoms names it below
            rows_of = None
        if rows_of is None:  # geom -> the rows of the frames that own it, once per frame list
            rows_of, mm = {}, self.mujoco_model
            for k, frame in enumerate(key):
                geoms = self._frame_geoms(frame)
                if not geoms:
                    with_geometry = sorted({names[0] for names in mm.geom_frames.values()})
                    raise FrameNotFoundError(
                        f"Frame {frame!r} of robot {mm.robot.name!r} has no collision geometry, "
                        "nor has the link it is attached to: no terrain force can act on it. "
                        f"Frames with geometry: {with_geometry[:12]}"
                        f"{' ...' if len(with_geometry) > 12 else ''}."
                    )
                for geom in geoms:
                    rows_of.setdefault(geom, []).append(k)
            self._force_rows[key] = rows_of  # every entry a known frame name: hashable
        out = np.zeros((len(key), 3))
        data, force = self.data, self._force
        axes_all = data.contact.frame  # (ncon, 9): normal, tangent 1, tangent 2 (rows)
        for i, geom, sign in self._terrain_contacts():
            rows = rows_of.get(geom)
            if rows:
                mujoco.mj_contactForce(self.model, data, i, force)
                world = (force[:3] @ axes_all[i].reshape(3, 3)) * sign  # axes^T f
                for k in rows:
                    out[k] += world
        return out

    def grouped_contact_forces(self, groups: np.ndarray) -> list[list[float]]:
        """The terrain's force on each contact of grouped robot geoms, in the contact's frame.

        Args:
            groups: ``(model.ngeom,)`` int64, each geom's group (-1: none), e.g. its foot.

        Returns:
            Per robot-terrain contact on a grouped geom, in MuJoCo's order:
            ``[group, normal, tangential 1, tangential 2]`` [N].
        """
        view = self._contact_view
        if view is not None:
            out = self._force_rows_out
            if out.shape[0] < view.ncon:
                out = self._force_rows_out = np.zeros((2 * view.ncon, 4))
            count = view.forces(groups, out)
            if count >= 0:
                return out[:count].tolist()
        rows, force = [], self._force
        for i, geom, _ in self._terrain_contacts():
            group = groups[geom]
            if group >= 0:
                mujoco.mj_contactForce(self.model, self.data, i, force)
                rows.append([float(group), *force[:3].tolist()])
        return rows

    def touches_outside(self, allowed: np.ndarray) -> bool:
        """Whether a robot geom outside ``allowed`` touches the terrain.

        Args:
            allowed: ``(model.ngeom,)`` int8 flags, 1 for the geoms allowed to touch.
        """
        view = self._contact_view
        if view is not None:
            return view.touches_outside(allowed)
        self._terrain_contacts()
        return not all(allowed[geom] for geom in self._touched)

    def touching_terrain(self) -> set[str]:
        """Names of the frames whose geoms touch the terrain (each geom's owners)."""
        self._terrain_contacts()
        owners = self.mujoco_model.geom_frames
        return {name for geom in self._touched for name in owners[geom]}
