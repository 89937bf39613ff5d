"""What the viewer draws in one frame, checked once: `FrameSnapshot`, which overlays read."""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass
from typing import TypedDict

import numpy as np

from ..actuators import ParallelVirtualActuator, VirtualActuator
from ..control import Attachment, Controller, ControlOutput, State
from ..distribution.result import Solution
from ..exceptions import InvalidInputError

#: What the viewer draws as a virtual actuator.
Actuator = VirtualActuator | ParallelVirtualActuator


def reactions_of(actuator: Actuator) -> tuple[str, ...]:
    """The reaction frames of a serial (``reaction``) or parallel (``reactions``) actuator.

    Raises:
        InvalidInputError: The actuator has neither.
    """
    reactions = getattr(actuator, "reactions", None)
    reactions = getattr(actuator, "reaction", None) if reactions is None else reactions
    if reactions is None:
        raise InvalidInputError(f"actuator {actuator!r} has neither reactions nor reaction frames.")
    return (reactions,) if isinstance(reactions, str) else tuple(reactions)


class FrameExtras(TypedDict, total=False):
    """The keyword arguments of `Viewer.show` and `Viewer.maybe_show` (described there)."""

    actuator: Actuator | None
    wrench: np.ndarray | None
    controller: Controller | None
    output: ControlOutput | None
    state: State | str | None
    support: Iterable[str]
    time: float | None


@dataclass(frozen=True, repr=False)
class FrameSnapshot:
    """One frame to draw: a configuration and what acts on the robot in it (made by `build`).

    Attributes:
        q: Configuration ``(model.nq,)``, finite.
        actuator: A virtual actuator to draw, or None.
        solution: A solution of ``actuator`` (its request, distribution and efforts), or None.
        wrench: A wrench requested of ``actuator`` on its axes without a solution, or None.
        controller: The controller whose ``output`` is drawn, or None.
        output: The controller's output of this tick, or None.
        state: Name of the gait's state, or None.
        support: Support frames to highlight (the state's first), without repeats.
        time: Time of the frame for recordings [s], or None.
    """

    q: np.ndarray
    actuator: Actuator | None = None
    solution: Solution | None = None
    wrench: np.ndarray | None = None
    controller: Controller | None = None
    output: ControlOutput | None = None
    state: str | None = None
    support: tuple[str, ...] = ()
    time: float | None = None

    @classmethod
    def build(
        cls,
        nq: int,
        robot_name: str,
        q: np.ndarray,
        solution: Solution | None = None,
        *,
        actuator: Actuator | None = None,
        wrench: np.ndarray | None = None,
        controller: Controller | None = None,
        output: ControlOutput | None = None,
        state: State | str | None = None,
        support: Iterable[str] = (),
        time: float | None = None,
    ) -> FrameSnapshot:
        """Check `Viewer.show`'s arguments for a robot of ``nq`` and ``robot_name``; bundle them.

        Raises:
            InvalidInputError: Bad ``q`` or ``wrench``, a solution or a wrench without its
                actuator or of another actuator, an actuator without action, reference and
                axes, an output without its controller or naming unknown attachments, a state
                that is neither a State nor a name.
        """
        q = _check_q(q, nq, robot_name)
        if solution is not None or actuator is not None:
            if actuator is None:
                raise InvalidInputError(
                    "show(solution=...) needs actuator=: the solution does not name its action "
                    "and reference frames."
                )
            wrench = _check_request(actuator, solution, wrench)
        elif wrench is not None:
            raise InvalidInputError("show(wrench=...) needs actuator=.")
        if output is not None or controller is not None:
            if controller is None or output is None:
                raise InvalidInputError("show() needs both controller= and output= (or neither).")
            _check_output(controller, output)
        frames = list(support)
        name = None
        if state is not None:
            name = state if isinstance(state, str) else getattr(state, "name", None)
            if not isinstance(name, str):
                raise InvalidInputError(f"state must be a State or a state name, got {state!r}.")
            if not isinstance(state, str):
                frames = [*getattr(state, "support", ()), *frames]
        support_frames = tuple(dict.fromkeys(frames))
        return cls(q, actuator, solution, wrench, controller, output, name, support_frames, time)

    @property
    def tau(self) -> np.ndarray | None:
        """Joint efforts to draw: the output's, else the solution's, else None."""
        if self.output is not None:
            return self.output.tau
        return self.solution.tau if self.solution is not None else None

    @property
    def saturated(self) -> np.ndarray | None:
        """The output's saturation flags (None: judged against the effort limits)."""
        return self.output.saturated if self.output is not None else None

    def attachments(self) -> list[tuple[str, Attachment]]:
        """``(name, attachment)`` of the output's active attachments that produced a wrench."""
        if self.output is None or self.controller is None:
            return []
        output, attachments = self.output, self.controller.attachments
        return [
            (name, attachments[name])
            for name in getattr(output, "active", ())
            if name not in output.failed and name in output.wrenches
        ]

    def __repr__(self) -> str:
        actuator, output = self.actuator, self.output
        parts = [
            f"q=({len(self.q)},)",
            actuator is not None and f"actuator={type(actuator).__name__} on {actuator.action!r}",
            self.solution is not None and "solution",
            output is not None and f"active={tuple(getattr(output, 'active', ()))}",
            self.state is not None and f"state={self.state!r}",
            bool(self.support) and f"support={self.support}",
            self.time is not None and f"time={self.time:g}",
        ]
        return f"FrameSnapshot({', '.join(part for part in parts if part)})"


def _check_q(q: np.ndarray, nq: int, robot_name: str) -> np.ndarray:
    """``q`` as a finite float array of shape ``(nq,)`` (else an InvalidInputError)."""
    try:
        q = np.asarray(q, dtype=float)
    except (TypeError, ValueError):
        raise InvalidInputError(f"q must be an array of {nq} numbers, got {q!r}.") from None
    if q.shape != (nq,):
        raise InvalidInputError(f"q has shape {q.shape}; the robot {robot_name!r} needs ({nq},).")
    if not np.all(np.isfinite(q)):
        raise InvalidInputError(f"q has NaN or inf entries: {q}.")
    return q


def _check_request(
    actuator: Actuator, solution: Solution | None, wrench: np.ndarray | None
) -> np.ndarray | None:
    """Check an actuator with its solution or wrench; return the wrench as floats (or None)."""
    if not all(hasattr(actuator, attribute) for attribute in ("action", "reference", "axes")):
        raise InvalidInputError(
            f"actuator must be a virtual actuator (with action, reference and axes), "
            f"got {actuator!r}."
        )
    axes = tuple(actuator.axes)
    reactions = reactions_of(actuator)
    if solution is not None:
        if not isinstance(solution, Solution):
            raise InvalidInputError(f"solution must be a Solution, got {solution!r}.")
        if tuple(solution.reactions) != reactions or tuple(solution.axes) != axes:
            raise InvalidInputError(
                f"The solution (reactions {solution.reactions}, axes {solution.axes}) is not "
                f"one of this actuator's (reactions {reactions}, axes {axes})."
            )
        return None  # the solution's request is drawn, not ``wrench``
    if wrench is None:
        return None
    wrench = np.asarray(wrench, dtype=float)
    if wrench.shape != (len(axes),) or not np.all(np.isfinite(wrench)):
        raise InvalidInputError(
            f"wrench must be {len(axes)} finite numbers on the axes {axes}, got {wrench}."
        )
    return wrench


def _check_output(controller: Controller, output: ControlOutput) -> None:
    """Check that the output's active attachments (and postures) are the controller's."""
    attachments = getattr(controller, "attachments", None)
    if attachments is None:
        raise InvalidInputError(f"controller must be a Controller, got {controller!r}.")
    terms = getattr(controller, "postures", {})
    for name in getattr(output, "active", ()):
        if name not in attachments and name not in terms:
            raise InvalidInputError(
                f"The output names attachment {name!r}, which the controller does not have "
                f"({list(attachments)})."
            )
