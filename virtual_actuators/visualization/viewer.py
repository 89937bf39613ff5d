"""The MeshCat viewer: a robot, its virtual actuators and what the controller does with them.

:class:`Viewer` draws, at a configuration ``q``:

- the robot (its URDF visuals, or a skeleton built from its kinematic tree);
- for a virtual actuator: triads at its action, reaction and reference frames; the requested
  wrench on the action frame as a force arrow and a double-headed moment arrow (lengths
  ``force_scale`` metres per newton and ``moment_scale`` metres per newton-metre, along the
  force and the moment axis in the world); each chain's share at its reaction frame (its force
  and its moment about the reaction frame's origin, on the actuator's rotational axes); and the
  produced wrench when it differs from the request (orange when adjusted on free axes or
  scaled to keep the feet on the ground, red when the request was inadmissible);
- for a controller's output: every active attachment as above, its components (springs as
  coils and dampers as a cylinder and rod, from their reaction-side anchor to the action frame,
  spring set points as small spheres), joint effort gauges (a sphere whose radius is
  ``|tau| / limit`` of a shell, orange or violet by sign, the shell red when saturated), support
  feet and the gait's state name;
- a legend of the colours and scales.

Wrenches of a :class:`~virtual_actuators.Solution` are expressed along the reference frame's
axes with moments about the action frame's origin; the viewer turns them into the world with its
own forward kinematics at ``q``. Objects not drawn in a frame are hidden, so a state machine
switching attachments leaves no stale arrows.
"""

from __future__ import annotations

import math
import time as wallclock
from collections.abc import Callable, Iterable

import meshcat
import meshcat.geometry as mg
import numpy as np
import pinocchio as pin
from meshcat.commands import SetProperty

from ..distribution.solution import Solution
from ..exceptions import InvalidInputError
from ..robots.robot import Robot
from ..vocabulary.frames import AXES, resolve_frame
from .bodies import RobotBodies, typical_link_length
from .geometry import (
    Cone,
    arrow_matrices,
    coil_mesh,
    frame_on_plane,
    material,
    span_matrix,
    terrain_boxes,
    text_object,
    translation,
    triad_parts,
)
from .legend import PALETTE, Palette, legend_entries, legend_html, legend_text
from .recording import AnimationRecording
from .scene import Scene
from .windows import ForwardingWindow, LiveWindow, SceneWindow

#: Roles of the frames drawn as triads, with their length relative to a typical link.
TRIAD_LENGTHS = {"action": 0.5, "reaction": 0.3, "reference": 0.65, "frame": 0.4}

_CAMERA_SIDE = np.array([0.0, -1.0, 0.25])
_CAMERA_ISO = np.array([0.8, -1.0, 0.55])


def _cross(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """3-vector cross product (``np.cross`` costs ten times more on 3-vectors)."""
    return np.array(
        [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]
    )


def _safe(name: str) -> str:
    return str(name).replace("/", "_") or "_"


def _positive(value: float, what: str) -> float:
    if not (isinstance(value, (int, float)) and math.isfinite(value) and value > 0):
        raise InvalidInputError(f"{what} must be a positive number, got {value!r}.")
    return float(value)


class Viewer:
    """Show a robot and its virtual actuators in MeshCat.

    Args:
        robot: The robot.
        window: Where to send the scene: None starts a MeshCat server (or connects to
            ``zmq_url``) and prints its URL; a
            :class:`~virtual_actuators.visualization.CommandRecorder` or
            :class:`~virtual_actuators.visualization.OfflineWindow` draws without any server;
            any object with ``send(command)`` (MeshCat's ``ViewerWindow``) is forwarded to.
        open: Open the URL in a web browser.
        force_scale: Arrow length per newton [m/N].
        moment_scale: Arrow length per newton-metre [m/(N m)].
        effort_reference: Effort drawn as a full gauge at joints without an effort limit in
            the URDF [N m or N].
        zmq_url: URL of a running ``meshcat-server`` to use instead of starting one.
        prefix: MeshCat node under which everything is drawn (re-created empty).
        geometry: ``"auto"`` (URDF visuals when the URDF has some, else a skeleton), ``"urdf"``
            or ``"skeleton"``.
        camera: ``"auto"`` (from the side for a robot moving in the x-z plane, else from the
            front-left), ``"side"``, ``"iso"`` or None (MeshCat's default).
        follow: Keep a travelling robot at the centre of the view, the legend beside it
            (default: when the robot can travel, i.e. a floating base or a prismatic first
            joint).
        legend: Draw the legend in the scene.
        rate_hz: Live updates per wall-clock second of :meth:`maybe_show` and
            :meth:`tick_callback`.
        palette: Colours.

    Raises:
        InvalidInputError: ``robot`` is not a :class:`~virtual_actuators.Robot`, a scale or the
            rate is not a positive number, ``geometry`` or ``camera`` is unknown, or ``window``
            has no ``send`` method.
        RobotDescriptionError: ``geometry="urdf"`` for a robot without visual geometry.
        VirtualActuatorError: The MeshCat server cannot be started or reached.

    """

    def __init__(
        self,
        robot: Robot,
        *,
        window: object | None = None,
        open: bool = False,
        force_scale: float = 0.01,
        moment_scale: float = 0.05,
        effort_reference: float = 10.0,
        zmq_url: str | None = None,
        prefix: str = "virtual_actuators",
        geometry: str = "auto",
        camera: str | None = "auto",
        follow: bool | None = None,
        legend: bool = True,
        rate_hz: float = 30.0,
        palette: Palette = PALETTE,
    ) -> None:
        if not isinstance(robot, Robot):
            raise InvalidInputError(f"Viewer needs a virtual_actuators.Robot, got {robot!r}.")
        self.force_scale = _positive(force_scale, "force_scale")
        self.moment_scale = _positive(moment_scale, "moment_scale")
        self.effort_reference = _positive(effort_reference, "effort_reference")
        self.rate_hz = _positive(rate_hz, "rate_hz")
        if camera not in ("auto", "side", "iso", None):
            raise InvalidInputError(
                f"camera must be 'auto', 'side', 'iso' or None, got {camera!r}."
            )
        if not isinstance(prefix, str) or not prefix.strip("/"):
            raise InvalidInputError(f"prefix must be a non-empty node name, got {prefix!r}.")
        self.robot = robot
        self.palette = palette
        self.model = robot.model
        self.data = pin.Data(self.model)
        self.bodies = RobotBodies(robot, geometry, typical_link_length(self.model))

        started = window is None
        if window is None:
            window = LiveWindow(zmq_url)
        elif not isinstance(window, SceneWindow):
            window = ForwardingWindow(window)
        self.window: SceneWindow = window
        self.vis = meshcat.Visualizer(window=window)
        self.scene = Scene(self.vis, prefix)

        self._frame_ids: dict[tuple[str, str], int] = {}
        self._axis_index: dict[tuple[str, ...], tuple[np.ndarray, np.ndarray, np.ndarray]] = {}
        self._last_live = -math.inf
        self._recording: AnimationRecording | None = None
        self._last_recording: AnimationRecording | None = None
        self._record_start = 0.0
        self._next_record = -math.inf

        q0 = robot.neutral()
        pin.forwardKinematics(self.model, self.data, q0)
        pin.updateFramePlacements(self.model, self.data)
        self._sizes(camera, follow)
        self._effort_joints = self._actuated_joints(q0)

        self.scene.node("").delete()
        self.scene.set_property("/Background", "top_color", [0.98, 0.98, 0.98])
        self.scene.set_property("/Background", "bottom_color", [0.78, 0.8, 0.84])
        self.bodies.create(self.scene, "robot")
        self._setup_camera()
        if legend:
            self._draw_legend()
        self.show(q0)
        if started:
            print(f"MeshCat viewer of {robot.name}: {self.url}")
        if open:
            self.window.open()

    # -- set-up ------------------------------------------------------------------------------

    def _sizes(self, camera: str | None, follow: bool | None) -> None:
        model, data = self.model, self.data
        points = np.array([f.translation for f in data.oMf] + [m.translation for m in data.oMi])
        low, high = points.min(axis=0), points.max(axis=0)
        self.extent = max(0.3, float(np.linalg.norm(high - low)))
        self.detail = min(typical_link_length(model), 0.5 * self.extent)
        self._target0 = (low + high) / 2.0
        floating = model.njoints > 1 and model.joints[1].shortname() == "JointModelFreeFlyer"
        self._ground = float(low[2]) if floating else 0.0  # feet of a free robot, else z = 0
        self._centroid0 = self._centroid()
        d = self.detail
        self.sizes = {
            "shaft": max(1e-3, 0.035 * d),
            "head_length": 0.2 * d,
            "head_radius": max(2.5e-3, 0.085 * d),
            "triad_radius": max(8e-4, 0.018 * d),
            "effort": 0.16 * d,
            "support": 0.14 * d,
            "coil": 0.09 * d,
            "damper": 0.07 * d,
            "setpoint": 0.07 * d,
        }
        planar = self._planar()
        self.planar = planar
        mode = camera if camera != "auto" else ("side" if planar else "iso")
        self._camera_mode = mode
        direction = _CAMERA_SIDE if mode == "side" else _CAMERA_ISO
        self._view = direction / np.linalg.norm(direction)  # from the target to the camera
        first = model.joints[1].shortname() if model.njoints > 1 else ""
        travels = first == "JointModelFreeFlyer" or first.startswith("JointModelP")
        self.follow = travels if follow is None else bool(follow)

    def _planar(self) -> bool:
        """Whether every joint moves in the x-z plane (rotations about y, translations in x-z)."""
        model, data = self.model, self.data
        if model.njoints <= 1:
            return False
        pin.computeJointJacobians(model, data, pin.neutral(model))
        for j in range(1, model.njoints):
            joint = model.joints[j]
            if joint.nv != 1:
                return False
            column = pin.getJointJacobian(model, data, j, pin.LOCAL_WORLD_ALIGNED)[:, joint.idx_v]
            linear, angular = column[:3], column[3:]
            if np.linalg.norm(angular) > 1e-9:
                if abs(abs(angular[1]) - np.linalg.norm(angular)) > 1e-6:
                    return False
            elif abs(linear[1]) > 1e-6:
                return False
        return True

    def _actuated_joints(
        self, q0: np.ndarray
    ) -> list[tuple[str, int, int, float | None, np.ndarray]]:
        """``(name, joint id, velocity index, limit or None, local axis)`` per 1-dof joint."""
        model, data = self.model, self.data
        pin.computeJointJacobians(model, data, q0)
        out = []
        passive = set(self.robot.passive_joints)
        for j in range(1, model.njoints):
            joint = model.joints[j]
            name = model.names[j]
            if joint.nv != 1 or name in passive:
                continue
            column = pin.getJointJacobian(model, data, j, pin.LOCAL)[:, joint.idx_v]
            axis = column[3:] if np.linalg.norm(column[3:]) > 1e-9 else column[:3]
            axis = axis / max(np.linalg.norm(axis), 1e-12)
            limit = float(model.effortLimit[joint.idx_v])
            limit = limit if math.isfinite(limit) and 0 < limit < 1e300 else None
            out.append((name, j, joint.idx_v, limit, axis))
        pin.forwardKinematics(model, data, q0)
        pin.updateFramePlacements(model, data)
        return out

    def _centroid(self) -> np.ndarray:
        return (
            np.mean([m.translation for m in self.data.oMi[1:]], axis=0)
            if len(self.data.oMi) > 1
            else np.zeros(3)
        )

    def _setup_camera(self) -> None:
        """Centre the scene on the robot, replace MeshCat's grid, place the camera.

        MeshCat's orbit controls look at the world origin and cannot be retargeted (MeshCat
        0.3.2), so the viewer's whole node is shifted to put the robot's centre there (and keeps
        shifting with a travelling robot, see ``follow``). MeshCat's grid and axes, which would
        no longer lie on the robot's ground, are replaced by a grid inside the viewer's node.
        """
        scene = self.scene
        scene.place("", translation(-self._target0))
        self._hud_rotation = frame_on_plane(np.array([self._view[0], self._view[1], 0.0]))
        scene.place("hud", translation(self._target0))
        scene.set_property("/Grid", "visible", False)
        scene.set_property("/Axes", "visible", False)
        # short segments: some renderers (SwiftShader) drop a whole line that passes behind
        # the camera, and the camera stands inside the grid
        half, step = 10.0, 0.5
        ticks = np.arange(-half, half + step / 2, step)
        starts, ends = np.meshgrid(ticks, ticks[:-1], indexing="ij")
        starts, ends = starts.ravel(), ends.ravel()
        along_y = np.stack((starts, ends, starts, ends + step), axis=1)
        along_x = np.stack((ends, starts, ends + step, starts), axis=1)
        points = np.vstack((along_y, along_x)).reshape(-1, 2) + self._target0[:2]
        vertices = np.column_stack((points, np.full(len(points), self._ground))).T
        scene.create(
            "ground/grid",
            mg.LineSegments(
                mg.PointsGeometry(vertices.astype(np.float32)),
                mg.LineBasicMaterial(color=0x9A9A9A),
            ),
        )
        if self._camera_mode is None:
            return
        distance = max(0.8, 1.5 * self.extent)
        offset = self._view * distance  # from the robot's centre to the camera, world axes
        local = [float(offset[0]), float(offset[2]), float(-offset[1])]  # three.js is y-up
        scene.set_property("/Cameras/default/rotated/<object>", "position", local)

    def _hud_matrix(self, offset_right: float, offset_up: float) -> np.ndarray:
        rotation = getattr(self, "_hud_rotation", np.eye(3))
        matrix = np.eye(4)
        matrix[:3, :3] = rotation
        matrix[:3, 3] = rotation[:, 0] * offset_right + rotation[:, 1] * offset_up
        return matrix

    def _draw_legend(self) -> None:
        entries = self.legend_entries()
        size = min(1.5, max(0.35, 0.75 * self.extent))
        spacing = 0.105 * size
        left = -(0.6 * self.extent + 0.5 * size)
        top = 0.5 * self.extent
        for k, (color, text) in enumerate(entries):
            up = top - k * spacing
            name = f"hud/legend/line_{k:02d}"
            self.scene.create(name, text_object(text, size, font_size=24))
            self.scene.place(name, self._hud_matrix(left, up))
            if color is not None:
                swatch = f"hud/legend/swatch_{k:02d}"
                self.scene.create(swatch, mg.Box([0.06 * size] * 3), material(color))
                self.scene.place(swatch, self._hud_matrix(left - 0.56 * size, up))

    # -- public helpers ----------------------------------------------------------------------

    @property
    def url(self) -> str | None:
        """URL of the live viewer (None without a server)."""
        return self.window.web_url

    @property
    def recording(self) -> bool:
        """Whether frames are being recorded."""
        return self._recording is not None

    def legend_entries(self) -> list[tuple[int | None, str]]:
        """The legend as ``(colour or None, text)`` pairs."""
        return legend_entries(
            self.palette, self.force_scale, self.moment_scale, self.effort_reference
        )

    def legend(self) -> str:
        """The legend as plain text (colours as ``#RRGGBB``)."""
        return legend_text(self.legend_entries())

    def set_terrain(self, terrain: object, width: float | None = None, run: float = 30.0) -> None:
        """Draw a planar ground profile (a :class:`~virtual_actuators.simulation.Terrain`).

        Args:
            terrain: A terrain (its ``segments(run)``) or an ``(n, 2)`` array of ``(x, z)``
                points [m].
            width: Extent of the ground along y [m] (default: the terrain's ``width``, else
                1 m).
            run: Level ground drawn before the first and after the last point [m].

        Raises:
            InvalidInputError: The points are not an ``(n, 2)`` finite array.

        """
        if width is None:
            width = float(getattr(terrain, "width", 1.0))
        if hasattr(terrain, "segments"):
            segments = terrain.segments(run)
        else:
            points = np.asarray(terrain, dtype=float)
            if points.ndim != 2 or points.shape[1] != 2 or not np.all(np.isfinite(points)):
                raise InvalidInputError(
                    f"terrain must be a Terrain or (n, 2) finite (x, z) points, got {terrain!r}."
                )
            first, last = points[0], points[-1]
            segments = [((first[0] - run, first[1]), tuple(first))]
            segments += [(tuple(a), tuple(b)) for a, b in zip(points[:-1], points[1:], strict=True)]
            segments += [(tuple(last), (last[0] + run, last[1]))]
        self.scene.remove("terrain")
        for k, (lengths, matrix) in enumerate(terrain_boxes(segments, width)):
            name = f"terrain/slab_{k:03d}"
            self.scene.create(name, mg.Box(lengths.tolist()), material(0xB0A58C))
            self.scene.place(name, matrix)
        self.scene.set_property("ground", "visible", False)  # the terrain replaces the grid
        if self.window.live:
            self.scene.sync()

    # -- drawing -----------------------------------------------------------------------------

    def show(
        self,
        q: np.ndarray,
        solution: Solution | None = None,
        *,
        actuator: object | None = None,
        wrench: np.ndarray | None = None,
        controller: object | None = None,
        output: object | None = None,
        state: object | None = None,
        support: Iterable[str] = (),
        time: float | None = None,
    ) -> None:
        """Draw one frame and send it (and record it while recording).

        Args:
            q: Configuration ``(model.nq,)``.
            solution: A :class:`~virtual_actuators.Solution` of ``actuator``.
            actuator: The :class:`~virtual_actuators.ParallelVirtualActuator` or
                :class:`~virtual_actuators.VirtualActuator` to draw (any object with
                ``action``, ``reference``, ``axes`` and ``reactions`` or ``reaction``).
            wrench: Requested wrench on the actuator's axes, when there is no ``solution``
                (a serial actuator's wrench).
            controller: A :class:`~virtual_actuators.Controller` (with ``output``).
            output: Its :class:`~virtual_actuators.ControlOutput` of this tick.
            state: The gait's current :class:`~virtual_actuators.State` (its name is shown and
                its support feet highlighted) or a state name.
            support: More support frames to highlight.
            time: Time of the frame [s] for recordings (default: one frame per call at the
                recording's fps).

        Raises:
            InvalidInputError: Bad ``q``, ``wrench``, a solution without its actuator or of
                another actuator, an output without its controller or naming unknown
                attachments.
            FrameNotFoundError: A frame (action, reaction, reference, support) is not in the
                viewer's robot.

        """
        self._draw(q, solution, actuator, wrench, controller, output, state, support)
        self._publish(self.window.live, self._recording is not None, time)

    def due(self, time: float | None = None) -> tuple[bool, bool]:
        """Whether a live update and a recorded frame are due (cheap: two comparisons).

        Args:
            time: Simulated time [s] (recordings are paced by it), or None for wall time.

        Returns:
            ``(live, record)``.

        """
        live = (
            self.window.live
            and wallclock.perf_counter() - self._last_live >= 1.0 / self.rate_hz
            and not getattr(self.window, "congested", False)  # a lagging server: skip frames
        )
        record = False
        if self._recording is not None:
            now = (wallclock.perf_counter() - self._record_start) if time is None else time
            record = now >= self._next_record - 1e-9
        return live, record

    def maybe_show(
        self,
        q: np.ndarray,
        solution: Solution | None = None,
        *,
        actuator: object | None = None,
        wrench: np.ndarray | None = None,
        controller: object | None = None,
        output: object | None = None,
        state: object | None = None,
        support: Iterable[str] = (),
        time: float | None = None,
    ) -> bool:
        """:meth:`show`, only when a live update (``rate_hz``) or a recorded frame is due.

        Costs two clock readings when nothing is due, so it can be called at every control
        tick. The arguments are those of :meth:`show`; ``time`` (simulated time) paces the
        recording.

        Returns:
            Whether a frame was drawn.

        Raises:
            InvalidInputError: See :meth:`show`.
            FrameNotFoundError: See :meth:`show`.

        """
        live, record = self.due(time)
        if not (live or record):
            return False
        self._draw(q, solution, actuator, wrench, controller, output, state, support)
        self._publish(live, record, time)
        return True

    def _publish(self, live: bool, record: bool, time: float | None) -> None:
        """Send the drawn frame to the live window and/or add it to the recording."""
        if live:
            self.scene.sync()
            self._last_live = wallclock.perf_counter()
        if record and self._recording is not None:
            self._record(time)

    def tick_callback(self, realtime: bool = False, terrain: bool = True) -> TickUpdater:
        """An ``on_tick(simulator, gait)`` for :func:`~virtual_actuators.demos.run_walk`.

        Args:
            realtime: Sleep so that simulated time does not run ahead of wall-clock time.
            terrain: Draw the simulator's terrain at the first tick.

        Returns:
            The callable (a :class:`TickUpdater`).

        """
        return TickUpdater(self, realtime=realtime, terrain=terrain)

    def _draw(self, q, solution, actuator, wrench, controller, output, state, support) -> None:
        q = self._check_q(q)
        model, data = self.model, self.data
        pin.forwardKinematics(model, data, q)
        pin.updateFramePlacements(model, data)
        scene = self.scene
        for part, matrix in zip(self.bodies.parts, self.bodies.matrices(data), strict=True):
            scene.place(f"robot/{part.name}", matrix)
        if self.follow:  # keep the robot at the centre of the view (see _setup_camera)
            centre = self._target0 + self._centroid() - self._centroid0
            centre[2] = self._target0[2]
            scene.place("", translation(-centre))
            scene.place("hud", translation(centre))

        tau, saturated = None, None
        if solution is not None or actuator is not None:
            if actuator is None:
                raise InvalidInputError(
                    "show(solution=...) needs actuator=: the solution does not name its action "
                    "and reference frames."
                )
            self._draw_actuator_request("actuator", actuator, solution, wrench)
            if solution is not None:
                tau = solution.tau
        elif wrench is not None:
            raise InvalidInputError("show(wrench=...) needs actuator=.")
        if output is not None or controller is not None:
            if controller is None or output is None:
                raise InvalidInputError("show() needs both controller= and output= (or neither).")
            self._draw_output(controller, output)
            tau, saturated = output.tau, output.saturated
        if tau is not None:
            self._draw_efforts(np.asarray(tau, dtype=float), saturated)

        frames = list(support)
        if state is not None:
            name = state if isinstance(state, str) else getattr(state, "name", None)
            if not isinstance(name, str):
                raise InvalidInputError(f"state must be a State or a state name, got {state!r}.")
            if not isinstance(state, str):
                frames = [*getattr(state, "support", ()), *frames]
            self._draw_state(name)
        for frame in dict.fromkeys(frames):
            self._draw_support(frame)
        scene.end_frame()

    def _check_q(self, q: np.ndarray) -> np.ndarray:
        try:
            q = np.asarray(q, dtype=float)
        except (TypeError, ValueError):
            raise InvalidInputError(
                f"q must be an array of {self.model.nq} numbers, got {q!r}."
            ) from None
        if q.shape != (self.model.nq,):
            raise InvalidInputError(
                f"q has shape {q.shape}; the robot {self.robot.name!r} needs ({self.model.nq},)."
            )
        if not np.all(np.isfinite(q)):
            raise InvalidInputError(f"q has NaN or inf entries: {q}.")
        return q

    def _frame(self, name: str, role: str) -> int:
        key = (name, role)
        frame_id = self._frame_ids.get(key)
        if frame_id is None:
            frame_id = self._frame_ids[key] = resolve_frame(self.model, name, role)
        return frame_id

    def _split(self, axes: tuple[str, ...], values: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Force and moment 3-vectors (reference axes) of a wrench on ``axes``."""
        index = self._axis_index.get(axes)
        if index is None:
            rows = np.array([AXES.index(a) for a in axes], dtype=int)
            rotational = np.zeros(3)
            rotational[[r - 3 for r in rows if r >= 3]] = 1.0
            index = self._axis_index[axes] = (rows, rotational, np.array([r < 3 for r in rows]))
        full = np.zeros(6)
        full[index[0]] = values
        return full[:3], full[3:]

    def _rotational_mask(self, axes: tuple[str, ...]) -> np.ndarray:
        self._split(axes, np.zeros(len(axes)))
        return self._axis_index[axes][1]

    # arrows, triads -------------------------------------------------------------------------

    def _arrow(self, name: str, origin, vector, color: int, heads: int, thin: float = 1.0) -> bool:
        head_length = self.sizes["head_length"] * thin
        matrices = arrow_matrices(origin, vector, head_length, heads)
        if matrices is None:
            return False
        scene = self.scene
        if not scene.has(f"{name}/shaft"):
            mat = material(color)
            scene.create(f"{name}/shaft", mg.Cylinder(1.0, self.sizes["shaft"] * thin), mat)
            for k in range(heads):
                scene.create(
                    f"{name}/head{k}", Cone(head_length, self.sizes["head_radius"] * thin), mat
                )
            scene.declare(name)
        scene.use(name)
        scene.place(f"{name}/shaft", matrices[0])
        for k in range(heads):
            scene.place(f"{name}/head{k}", matrices[k + 1])
        return True

    def _wrench(
        self,
        name: str,
        origin: np.ndarray,
        rotation: np.ndarray,
        axes: tuple[str, ...],
        values: np.ndarray,
        colors: tuple[int, int],
        thin: float = 1.0,
    ) -> None:
        force, moment = self._split(axes, values)
        self._arrow(
            f"{name}/force", origin, rotation @ force * self.force_scale, colors[0], 1, thin
        )
        self._arrow(
            f"{name}/moment", origin, rotation @ moment * self.moment_scale, colors[1], 2, thin
        )

    def _triad(self, role: str, frame: str) -> None:
        frame_id = self._frame(frame, role)
        name = f"frames/{role}/{_safe(frame)}"
        scene = self.scene
        if not scene.has(f"{name}/x"):
            length = TRIAD_LENGTHS[role] * self.detail
            for axis, geometry, color in triad_parts(length, self.sizes["triad_radius"]):
                scene.create(f"{name}/{axis}", geometry, material(color))
            scene.declare(name)
        scene.use(name)
        scene.place(name, self.data.oMf[frame_id].homogeneous)

    # actuators ------------------------------------------------------------------------------

    @staticmethod
    def _reactions_of(actuator: object) -> tuple[str, ...]:
        reactions = getattr(actuator, "reactions", None)
        if reactions is None:
            reaction = getattr(actuator, "reaction", None)
            if reaction is None:
                raise InvalidInputError(
                    f"actuator {actuator!r} has neither reactions nor reaction frames."
                )
            return (reaction,)
        return (reactions,) if isinstance(reactions, str) else tuple(reactions)

    def _draw_actuator_request(self, key: str, actuator, solution, wrench) -> None:
        for attribute in ("action", "reference", "axes"):
            if not hasattr(actuator, attribute):
                raise InvalidInputError(
                    f"actuator must be a virtual actuator (with action, reference and axes), "
                    f"got {actuator!r}."
                )
        axes = tuple(actuator.axes)
        reactions = self._reactions_of(actuator)
        if solution is not None:
            if not isinstance(solution, Solution):
                raise InvalidInputError(f"solution must be a Solution, got {solution!r}.")
            if tuple(solution.reactions) != reactions or tuple(solution.axes) != axes:
                raise InvalidInputError(
                    f"The solution (reactions {solution.reactions}, axes {solution.axes}) is not "
                    f"one of this actuator's (reactions {reactions}, axes {axes})."
                )
            self._draw_actuator(
                key,
                actuator,
                solution.requested,
                solution.wrench,
                solution.forces,
                not solution.admissible,
            )
            return
        if wrench is None:
            self._draw_actuator(key, actuator, None, None, None, False)
            return
        wrench = np.asarray(wrench, dtype=float)
        if wrench.shape != (len(axes),) or not np.all(np.isfinite(wrench)):
            raise InvalidInputError(
                f"wrench must be {len(axes)} finite numbers on the axes {axes}, got {wrench}."
            )
        forces = wrench[None, :] if len(reactions) == 1 else None
        self._draw_actuator(key, actuator, wrench, wrench, forces, False)

    def _draw_actuator(
        self,
        key: str,
        actuator: object,
        requested: np.ndarray | None,
        produced: np.ndarray | None,
        forces: np.ndarray | None,
        inadmissible: bool,
    ) -> None:
        data, palette = self.data, self.palette
        axes = tuple(actuator.axes)
        reactions = self._reactions_of(actuator)
        action_id = self._frame(actuator.action, "action")
        reference_id = self._frame(actuator.reference, "reference")
        reaction_ids = [self._frame(r, "reaction") for r in reactions]
        self._triad("action", actuator.action)
        self._triad("reference", actuator.reference)
        for reaction in reactions:
            self._triad("reaction", reaction)
        if requested is None:
            return
        origin = data.oMf[action_id].translation
        rotation = data.oMf[reference_id].rotation
        name = f"wrench/{_safe(key)}"
        self._wrench(
            f"{name}/requested",
            origin,
            rotation,
            axes,
            requested,
            (palette.requested_force, palette.requested_moment),
        )
        if produced is not None:
            scale = max(1.0, float(np.max(np.abs(requested))))
            if inadmissible or not np.allclose(produced, requested, rtol=0.0, atol=1e-6 * scale):
                kind, color = (
                    ("inadmissible", palette.inadmissible)
                    if inadmissible
                    else ("produced", palette.produced)
                )
                self._wrench(f"{name}/{kind}", origin, rotation, axes, produced, (color, color))
        if forces is None:
            return
        mask = self._rotational_mask(axes)
        for reaction, reaction_id, share in zip(reactions, reaction_ids, forces, strict=True):
            force, moment = self._split(axes, share)
            force_w = rotation @ force
            at = data.oMf[reaction_id].translation
            moment_w = rotation @ moment + _cross(origin - at, force_w)  # about the reaction
            moment_w = rotation @ (mask * (rotation.T @ moment_w))  # on the actuator's axes
            share_name = f"{name}/share/{_safe(reaction)}"
            self._arrow(
                f"{share_name}/force",
                at,
                force_w * self.force_scale,
                palette.share_force,
                1,
                0.75,
            )
            self._arrow(
                f"{share_name}/moment",
                at,
                moment_w * self.moment_scale,
                palette.share_moment,
                2,
                0.75,
            )

    def _draw_output(self, controller: object, output: object) -> None:
        attachments = getattr(controller, "attachments", None)
        if attachments is None:
            raise InvalidInputError(f"controller must be a Controller, got {controller!r}.")
        for name in getattr(output, "active", ()):
            if name not in attachments:
                raise InvalidInputError(
                    f"The output names attachment {name!r}, which the controller does not have "
                    f"({list(attachments)})."
                )
            if name in output.failed or name not in output.wrenches:
                continue
            attachment = attachments[name]
            solution = output.solutions.get(name)
            actuator = attachment.actuator
            requested = np.asarray(output.wrenches[name], dtype=float)
            produced = np.asarray(output.produced.get(name, requested), dtype=float)
            if solution is not None:
                forces, inadmissible = solution.forces, not solution.admissible
            else:  # a serial actuator: one chain carries the whole wrench
                forces, inadmissible = produced[None, :], False
            self._draw_actuator(name, actuator, requested, produced, forces, inadmissible)
            self._draw_components(name, attachment)

    # components -----------------------------------------------------------------------------

    def _span(
        self, name: str, start, end, geometry_factory: Callable[[], object], color: int
    ) -> bool:
        matrix = span_matrix(start, end)
        if matrix is None:
            return False
        if not self.scene.has(name):
            self.scene.create(name, geometry_factory(), material(color))
            self.scene.declare(name)
        self.scene.use(name)
        self.scene.place(name, matrix)
        return True

    def _draw_components(self, key: str, attachment: object) -> None:
        sensor = attachment.sensor
        data, palette, sizes = self.data, self.palette, self.sizes
        action = data.oMf[self._frame(sensor.action, "action")].translation
        reaction = data.oMf[self._frame(sensor.reaction, "reaction")].translation
        rotation = data.oMf[self._frame(sensor.reference, "reference")].rotation
        for index, component in enumerate(attachment.components):
            axes = tuple(component.axes)
            picks = [(i, "xyz".index(a)) for i, a in enumerate(axes) if a in ("x", "y", "z")]
            if not picks:
                continue  # rotational components show through the moment arrows
            columns = [i for i, _ in picks]
            directions = rotation[:, [k for _, k in picks]]  # (3, t) world directions
            relative = directions.T @ (action - reaction)  # sensor reading on these axes [m]
            anchor = action - directions @ relative
            stiffness = self._parameter(component, "stiffness", len(axes))[columns]
            damping = self._parameter(component, "damping", len(axes))[columns]
            setpoint = getattr(component, "setpoint", None)
            target = None
            if setpoint is not None and np.shape(setpoint) == (len(axes),):
                target = action + directions @ (
                    np.asarray(setpoint, dtype=float)[columns] - relative
                )
            spring, damper = bool(np.any(stiffness > 0)), bool(np.any(damping > 0))
            if damper and not spring and target is not None:
                anchor = target  # a damper's other end moves with its set point (the bunny)
            name = f"components/{_safe(key)}/{index}"
            offset = np.zeros(3)
            if spring and damper:
                side = _cross(action - anchor, self._view)
                norm = np.linalg.norm(side)
                if norm > 1e-9:
                    offset = side / norm * 1.3 * sizes["coil"]
            if spring:
                self._span(
                    f"{name}/spring",
                    anchor + offset,
                    action + offset,
                    lambda: coil_mesh(radius=sizes["coil"]),
                    palette.spring,
                )
                if target is not None:
                    marker = f"{name}/setpoint"
                    if not self.scene.has(marker):
                        self.scene.create(
                            marker, mg.Sphere(sizes["setpoint"]), material(palette.setpoint)
                        )
                        self.scene.declare(marker)
                    self.scene.use(marker)
                    self.scene.place(marker, translation(target))
            if damper:
                start, end = anchor - offset, action - offset
                self._span(
                    f"{name}/damper_housing",
                    start,
                    start + 0.6 * (end - start),
                    lambda: mg.Cylinder(1.0, sizes["damper"]),
                    palette.damper,
                )
                self._span(
                    f"{name}/damper_rod",
                    start + 0.45 * (end - start),
                    end,
                    lambda: mg.Cylinder(1.0, 0.35 * sizes["damper"]),
                    palette.damper,
                )

    @staticmethod
    def _parameter(component: object, attribute: str, size: int) -> np.ndarray:
        value = getattr(component, attribute, None)
        if value is None:
            return np.zeros(size)
        array = np.asarray(value, dtype=float)
        if array.shape != (size,):
            array = np.full(size, float(array.reshape(-1)[0]) if array.size else 0.0)
        return array

    # efforts, support, state ----------------------------------------------------------------

    def _draw_efforts(self, tau: np.ndarray, saturated: np.ndarray | None) -> None:
        if tau.shape != (self.model.nv,):
            raise InvalidInputError(f"tau has shape {tau.shape}, expected ({self.model.nv},).")
        scene, data, palette = self.scene, self.data, self.palette
        radius = self.sizes["effort"]
        for joint, joint_id, index, limit, axis in self._effort_joints:
            value = float(tau[index])
            node = f"efforts/{_safe(joint)}"
            if not scene.has(f"{node}/positive/ball"):
                scene.create(
                    f"{node}/positive/ball", mg.Sphere(1.0), material(palette.effort_positive)
                )
                scene.create(
                    f"{node}/negative/ball", mg.Sphere(1.0), material(palette.effort_negative)
                )
                scene.create(
                    f"{node}/shell/ball",
                    mg.Sphere(radius),
                    material(palette.effort_limit, 0.22, depthWrite=False),
                )
                scene.create(
                    f"{node}/saturated/ball",
                    mg.Sphere(1.12 * radius),
                    material(palette.saturated, 0.5, depthWrite=False),
                )
                for part in ("", "/positive", "/negative", "/shell", "/saturated"):
                    scene.declare(node + part)
            placement = data.oMi[joint_id]
            direction = placement.rotation @ axis
            if direction @ self._view < 0:
                direction = -direction  # put the gauge on the camera's side of the joint
            centre = placement.translation + direction * 1.2 * radius
            reference = limit if limit is not None else self.effort_reference
            fraction = min(1.0, abs(value) / reference)
            if saturated is not None:
                is_saturated = bool(saturated[index])
            else:
                is_saturated = limit is not None and abs(value) > limit * (1.0 + 1e-9)
            scene.use(node)
            scene.use(f"{node}/shell")
            scene.place(f"{node}/shell/ball", translation(centre))
            if fraction > 1e-6:
                sign = "positive" if value > 0 else "negative"
                scene.use(f"{node}/{sign}")
                scene.place(f"{node}/{sign}/ball", translation(centre, fraction * radius))
            if is_saturated:
                scene.use(f"{node}/saturated")
                scene.place(f"{node}/saturated/ball", translation(centre))

    def _draw_support(self, frame: str) -> None:
        frame_id = self._frame(frame, "support")
        name = f"support/{_safe(frame)}"
        if not self.scene.has(name):
            self.scene.create(
                name,
                mg.Sphere(self.sizes["support"]),
                material(self.palette.support, 0.45, depthWrite=False),
            )
            self.scene.declare(name)
        self.scene.use(name)
        self.scene.place(name, translation(self.data.oMf[frame_id].translation))

    def _draw_state(self, state: str) -> None:
        name = f"hud/state/{_safe(state)}"
        if not self.scene.has(name):
            size = min(2.0, max(0.4, 0.8 * self.extent))
            self.scene.create(name, text_object(state, size, font_size=30))
            self.scene.declare(name)
            right, up = 0.45 * self.extent, 0.7 * self.extent + 0.12 * size  # beside the arrows
            self.scene.place(name, self._hud_matrix(right, up))
        self.scene.use(name)

    # recording --------------------------------------------------------------------------------

    def start_recording(self, fps: float = 30.0) -> None:
        """Record every following :meth:`show` (and due :meth:`maybe_show`) as animation frames.

        Args:
            fps: Frames per second of :meth:`maybe_show` / :meth:`tick_callback` (paced by the
                frames' ``time``, e.g. simulated time), and of :meth:`show` calls without a
                time.

        Raises:
            InvalidInputError: ``fps`` is not a positive number.

        """
        self._recording = AnimationRecording(fps)
        self._record_start = wallclock.perf_counter()
        self._next_record = -math.inf

    def stop_recording(self) -> AnimationRecording | None:
        """Stop recording; return the recording (None if none was running)."""
        recording, self._recording = self._recording, None
        self._last_recording = recording
        return recording

    def _record(self, time: float | None) -> None:
        recording = self._recording
        if time is None:
            time = recording.times[-1] + 1.0 / recording.fps if recording.times else 0.0
        time = float(time)
        if recording.times and time <= recording.times[-1]:
            return  # the same instant again (a paused simulation): keep the first frame
        recording.add(time, dict(self.scene.matrices), dict(self.scene.visible))
        self._next_record = time + 1.0 / recording.fps

    def static_html(self, title: str | None = None) -> str:
        """A standalone HTML page of the scene, animated with the recording if there is one.

        Returns:
            The page (MeshCat's viewer inlined: it opens offline).

        """
        self.scene.sync()
        recording = self._recording or self._last_recording
        # the page has the legend as HTML over the view: hide the one drawn in the scene
        extra: list[object] = [SetProperty("visible", False, self.scene.node("hud/legend").path)]
        if recording is not None and recording.frames >= 2:
            extra.append(recording.command(self.scene.path))
        title = title or f"virtual_actuators: {self.robot.name}"
        overlay = legend_html(self.legend_entries(), title)
        return self.window.static_html(extra, title=title, overlay=overlay)

    def save_html(self, path: str, title: str | None = None) -> str:
        """Write :meth:`static_html` to ``path`` (the whole recorded run, if any).

        Args:
            path: File to write (``.html``).
            title: Page title.

        Returns:
            The path written.

        Raises:
            InvalidInputError: The folder of ``path`` does not exist.

        """
        from pathlib import Path

        target = Path(path).expanduser()
        if not target.parent.is_dir():
            raise InvalidInputError(f"Cannot write {str(path)!r}: its folder does not exist.")
        target.write_text(self.static_html(title), encoding="utf-8")
        return str(target)

    # life cycle -------------------------------------------------------------------------------

    def flush(self, timeout: float | None = 10.0) -> bool:
        """Wait until the live viewer received everything sent (True if it did in time)."""
        return self.window.flush(timeout)

    def close(self) -> None:
        """Stop the sender and the MeshCat server this viewer started."""
        self.window.close()

    def __repr__(self) -> str:
        recording = f", recording {self._recording.frames} frames" if self._recording else ""
        return (
            f"Viewer(robot={self.robot.name!r}, url={self.url!r}, geometry={self.bodies.kind!r}, "
            f"force_scale={self.force_scale:g} m/N, moment_scale={self.moment_scale:g} m/(N m)"
            f"{recording})"
        )


class TickUpdater:
    """``on_tick(simulator, gait)`` adapter: throttled live updates and recorded frames.

    Called after every physics step by :func:`~virtual_actuators.demos.run_walk`; does nothing
    (two clock readings) unless a live update (the viewer's ``rate_hz``, wall clock) or a
    recorded frame (the recording's fps, simulated time) is due. Then it draws the simulator's
    configuration with the gait's controller, its last output and its current state.

    Args:
        viewer: The viewer.
        realtime: Sleep so that simulated time does not run ahead of wall-clock time.
        terrain: Draw the simulator's terrain at the first tick.

    """

    def __init__(self, viewer: Viewer, realtime: bool = False, terrain: bool = True) -> None:
        self.viewer = viewer
        self.realtime = realtime
        self.terrain = terrain
        self.updates = 0
        self._start: float | None = None
        self._sim_start = 0.0

    def __call__(self, simulator: object, gait: object) -> None:
        """Update the viewer if due (see the class documentation)."""
        viewer = self.viewer
        sim_time = simulator.time
        if self._start is None:
            self._start, self._sim_start = wallclock.perf_counter(), sim_time
            if self.terrain and getattr(simulator, "terrain", None) is not None:
                viewer.set_terrain(simulator.terrain)
        if self.realtime:
            ahead = (sim_time - self._sim_start) - (wallclock.perf_counter() - self._start)
            if ahead > 0.005:
                wallclock.sleep(ahead)
        live, record = viewer.due(sim_time)
        if not (live or record):
            return
        machine = getattr(gait, "machine", None)
        viewer._draw(
            simulator.q,
            None,
            None,
            None,
            gait.controller if gait.last is not None else None,
            gait.last,
            machine.current if machine is not None else None,
            (),
        )
        viewer._publish(live, record, sim_time)
        self.updates += 1

    def __repr__(self) -> str:
        return (
            f"TickUpdater({self.viewer.robot.name!r}, realtime={self.realtime}, "
            f"updates={self.updates})"
        )
