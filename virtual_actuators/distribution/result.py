"""The result of a parallel virtual actuator's solve, and the numpy paths' shared per-tick tail."""

from __future__ import annotations

import dataclasses
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from ..exceptions import InadmissibleWrenchError
from .linalg import stable_norm
from .tolerances import ROUNDING


def no_sets() -> dict[str, list[tuple[str, str]]]:
    """The ``sets`` of a solution built without a partition: every key, no label."""
    return {"MFS": [], "RFS": [], "CFS": []}


@dataclass(slots=True)
class RawSolution:
    """Solver output before it is wrapped into a [`Solution`][]."""

    forces: np.ndarray
    method: str
    #: MFS / RFS / CFS labels; empty lists for the solvers that build no partition (dense, QP)
    sets: dict[str, list[tuple[str, str]]] = field(default_factory=no_sets)
    #: linear systems inverted at this solve: ``(what, size, how many)``
    systems: tuple[tuple[str, int, int], ...] = ()
    #: the algorithm that produced it (``"dense"`` when the partitioned one could not decide)
    solver: str = "partitioned"
    #: the QP's active inequalities, by name (empty for the other solvers)
    active: tuple[str, ...] = ()


@dataclass(slots=True)
class TickResult:
    """What every solver backend returns for one tick (before [`Solution`][] wraps it).

    Attributes:
        raw: The distribution, its method, partition, systems, solver and active rows.
        tau: ``(nv,)`` joint efforts, zero at limp and passive joints.
        tau_passive: ``(nv,)`` torques of the passive springs.
        produced: ``(n,)`` the wrench produced.
        requested: ``(n,)`` the request (free axes hold the produced value).
        residual: Norm of the prescribed part of the request not produced.
        scale: The larger of the request's and the produced wrench's norms, prescribed axes.
        rounding: The rounding of chain forces that cancel (the path's own estimate).
        compiled: Whether a compiled kernel computed it.
    """

    raw: RawSolution
    tau: np.ndarray
    tau_passive: np.ndarray
    produced: np.ndarray
    requested: np.ndarray
    residual: float
    scale: float
    rounding: float
    compiled: bool = False

    @classmethod
    def from_buffer(
        cls,
        raw: RawSolution,
        out: np.ndarray,
        residual: float,
        scale: float,
        rounding: float,
        compiled: bool = True,
    ) -> TickResult:
        """The tick of a kernel's output buffer ``out`` (views of it).

        ``out``: the forces (``p n``, chain by chain), ``tau`` (``nv``), the springs' torques
        (``nv``), the produced and the requested wrench (``n`` each).
        """
        a, n = raw.forces.size, raw.forces.shape[1]
        nv = (out.shape[0] - a - 2 * n) // 2
        b, c = a + nv, a + 2 * nv
        return cls(raw, out[a:b], out[b:c], out[c : c + n], out[c + n :], residual, scale,
                   rounding, compiled)  # fmt: skip


def close_tick(
    raw: RawSolution,
    wrench: np.ndarray,
    keep: np.ndarray,
    torques: Callable[[np.ndarray], np.ndarray],
    actuated: np.ndarray,
    passive: np.ndarray,
    factor: float = 1.0,
    accuracy: float = 0.0,
) -> TickResult:
    """The tail of a numpy solve: efforts, produced and requested wrenches, residual, norms.

    ``raw``'s forces are scaled by ``factor`` (the power of two the solve's right-hand sides were
    multiplied by; the returned ``raw`` holds them unscaled), ``wrench`` is not; ``torques`` maps
    ``(p, n)`` forces to ``sum_i J_i^T F_i``, ``actuated`` masks the joints that get a torque,
    ``passive`` holds the springs' torques and ``accuracy`` (a solver's own, e.g. the QP's) is
    added to the rounding. The norms are taken on the scaled forces; ``compiled`` is False.
    """
    forces_scaled = raw.forces
    raw = dataclasses.replace(raw, forces=forces_scaled / factor)
    tau = np.where(actuated, torques(raw.forces), 0.0)
    produced_scaled = forces_scaled.sum(axis=0)
    residual = stable_norm((produced_scaled - wrench * factor)[keep]) / factor
    request = stable_norm(wrench[keep])
    output = stable_norm(produced_scaled[keep]) / factor
    rounding = ROUNDING * float(np.abs(forces_scaled).max(initial=0.0)) / factor + accuracy
    produced = produced_scaled / factor
    requested = np.where(keep, wrench, produced)
    scale = max(request, output)
    return TickResult(raw, tau, passive, produced, requested, residual, scale, rounding)


def label(method: str, admissible: bool) -> str:
    """A solve's ``method``: "qp", else "least-squares" if missed, else "pseudo-inverse"."""
    if method == "qp":
        return method
    if not admissible:
        return "least-squares"
    return "pseudo-inverse" if method == "least-squares" else method


def inadmissible(
    wrench: np.ndarray, axes: tuple[str, ...], solution: Solution
) -> InadmissibleWrenchError:
    """The error of ``solve(..., strict=True)`` when ``solution`` missed ``wrench``."""
    return InadmissibleWrenchError(
        f"The wrench {wrench.tolist()} on axes {axes} cannot be produced at this "
        f"configuration: residual {solution.residual:.3g} (produced "
        f"{solution.wrench.round(6).tolist()}).",
        solution,
    )


@dataclass(repr=False, slots=True)
class Solution:
    """A force distribution and the joint efforts that produce it.

    Attributes:
        tau: ``(nv,)`` joint efforts to command [N m or N]; 0 at limp and passive joints.
        forces: ``(p, n)`` each chain's wrench on the action frame {B} (forces along and moments
            about {O}'s axes, moments about {B}'s origin) [N, N m].
        wrench: ``(n,)`` the wrench actually produced on {B}: ``forces.sum(axis=0)``.
        sets: ``{"MFS": [...], "RFS": [...], "CFS": [...]}`` with labels ``(reaction, axis)``.
        residual: Norm of the part of the requested wrench (prescribed axes) not produced.
        method: ``"partitioned"``, ``"pseudo-inverse"``, ``"least-squares"`` or ``"qp"``.
        requested: ``(n,)`` the wrench that was asked for (free axes hold the produced value).
        reactions: Reaction frame names, one per row of ``forces``.
        axes: Axis names, one per column of ``forces``.
        free: Axes left to the solver.
        tau_passive: ``(nv,)`` torques that passive springs contribute at this configuration.
        base_effort: Efforts on a floating base's six coordinates: 0 unless the request needs
            the base to push on the world; these cannot be commanded.
        solver: ``"partitioned"``, ``"dense"`` (the dense reference, where the closed form
            cannot decide) or ``"qp"``.
        systems: Linear systems inverted at this solve, as ``(what, size, count)``, e.g.
            ``(("CFS", 3, 3), ("MFS", 6, 1))`` for the hexapod tripod.
        active: ``method="qp"``: the inequalities active at the answer, by name (e.g.
            ``"FL_FOOT: friction +t1"``, ``"torque FL_KFE <= 2.7"``); empty otherwise.
        compiled: Whether the compiled per-tick kernel computed this.
        tolerance: The residual up to which the request counts as produced: ``tol *
            max(|requested|, |produced|)`` on the prescribed axes plus the chain forces'
            rounding; [`admissible`][] compares ``residual`` with it.
    """

    tau: np.ndarray
    forces: np.ndarray
    wrench: np.ndarray
    sets: dict[str, list[tuple[str, str]]]
    residual: float
    method: str
    requested: np.ndarray
    reactions: tuple[str, ...]
    axes: tuple[str, ...]
    free: tuple[str, ...] = ()
    tau_passive: np.ndarray = field(default_factory=lambda: np.zeros(0))
    base_effort: np.ndarray = field(default_factory=lambda: np.zeros(0))
    solver: str = "partitioned"
    systems: tuple[tuple[str, int, int], ...] = ()
    compiled: bool = False
    active: tuple[str, ...] = ()
    tolerance: float = 0.0

    @classmethod
    def from_tick(
        cls,
        tick: TickResult,
        tol: float,
        reactions: tuple[str, ...],
        axes: tuple[str, ...],
        free: tuple[str, ...],
        floating: bool,
    ) -> Solution:
        """The solution of a backend's ``tick``, labelled by the one admissibility rule.

        ``tol``: ``solve(..., tol=)``; ``floating``: ``base_effort`` is ``tau[:6]``.
        """
        raw, tau = tick.raw, tick.tau
        limit = tol * tick.scale + tick.rounding
        return cls(  # positional (a tick's cost): the fields in declaration order
            tau,
            raw.forces,
            tick.produced,
            raw.sets,
            tick.residual,
            label(raw.method, tick.residual <= limit),
            tick.requested,
            reactions,
            axes,
            free,
            tick.tau_passive,
            tau[:6].copy() if floating else np.zeros(0),
            raw.solver,
            raw.systems,
            tick.compiled,
            raw.active,
            limit,
        )

    @property
    def admissible(self) -> bool:
        """Whether the requested wrench was produced: ``residual <= tolerance``, on every path.

        ``solve(..., strict=True)`` raises exactly when this is False.
        """
        return self.residual <= self.tolerance

    def force(self, reaction: str) -> np.ndarray:
        """Return the ``(n,)`` wrench that the chain ending at ``reaction`` exerts on {B}.

        Raises:
            KeyError: If ``reaction`` is not a reaction frame of the actuator.
        """
        if reaction not in self.reactions:
            raise KeyError(f"{reaction!r} is not a reaction frame; reactions: {self.reactions}")
        return self.forces[self.reactions.index(reaction)]

    def table(self, precision: int = 3) -> str:
        """Return the forces as a text table, one row per chain, plus the total."""
        width = max(10, precision + 8)
        name_width = max(len("produced"), *(len(r) for r in self.reactions))
        head = " " * name_width + "".join(f"{a:>{width}}" for a in self.axes)
        lines = [head]

        def line(label: str, values: np.ndarray) -> str:
            return f"{label:<{name_width}}" + "".join(f"{x:>z{width}.{precision}f}" for x in values)

        lines += [line(name, row) for name, row in zip(self.reactions, self.forces, strict=True)]
        lines.append(line("produced", self.wrench))
        lines.append(line("requested", self.requested))
        return "\n".join(lines)

    def __repr__(self) -> str:
        sizes = ", ".join(f"{k}={len(v)}" for k, v in self.sets.items())
        return (
            f"Solution(method={self.method!r}, solver={self.solver!r}, "
            f"residual={self.residual:.3g}, p={len(self.reactions)}, axes={self.axes}, {sizes})"
        )
