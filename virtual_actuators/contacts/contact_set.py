"""The contacts of one parallel actuator as declared (kinds, normals): a frozen `ContactSet`.

`declare` builds it, every argument checked. The QP and the controller's yield policy read the
same rows from it (`ContactSet.rows`); `CompiledMargins` are the tables of the core's evaluation
of them.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import NamedTuple

import numpy as np

from ..exceptions import ConstraintError, InvalidInputError
from ..vocabulary.arguments import as_float_array, check_name, check_number, describe
from ..vocabulary.axes import AXES
from . import flat, point
from .constraint import Constraint, force_entries, reaction_index

#: ``normals[reaction]`` value: the contact normal is the reaction frame's own z axis.
FRAME = "frame"
#: ``normals`` value: every contact's normal is its reaction frame's z axis.
FRAMES = "frames"


class Normals(NamedTuple):
    """The contact normals of ``p`` reactions, as declared."""

    #: ``(p, 3)`` unit normals in the world (world z unless declared; ignored where ``frame``)
    world: np.ndarray
    #: ``(p,)`` whether each normal is its reaction frame's z axis (read every tick)
    frame: np.ndarray


def parse_normals(
    normals: Mapping[str, Sequence[float] | str] | str | None, reactions: Sequence[str]
) -> Normals:
    """The contact normals: world z by default, a world vector or ``"frame"`` by reaction.

    Args:
        normals: None (world z), ``"frames"`` (every reaction frame's z axis) or a mapping by
            reaction frame of a nonzero world 3-vector (normalised) or ``"frame"``.
        reactions: The reaction frames' names.

    Raises:
        InvalidInputError: Another string, a zero or non-finite vector, an unknown reaction.
    """
    world = np.tile([0.0, 0.0, 1.0], (len(reactions), 1))
    frame = np.zeros(len(reactions), dtype=bool)
    if isinstance(normals, str):
        if normals != FRAMES:
            raise InvalidInputError(
                f"normals must be {FRAMES!r} (every reaction frame's z axis) or a mapping "
                f"by reaction frame, got {normals!r}."
            )
        normals = dict.fromkeys(reactions, FRAME)
    elif normals is not None and not isinstance(normals, Mapping):
        raise InvalidInputError(
            f"normals must be None, {FRAMES!r} or a mapping by reaction frame, got {normals!r}."
        )
    for name, normal in dict(normals or {}).items():
        index = reaction_index(name, reactions, "normals")
        if isinstance(normal, str):
            if normal != FRAME:
                raise InvalidInputError(
                    f"normals[{name!r}] must be {FRAME!r} (the frame's z axis) or a nonzero "
                    f"3-vector (world frame), got {normal!r}."
                )
            frame[index] = True
            continue
        valid = f"a nonzero 3-vector (world frame) or {FRAME!r}"
        vector = as_float_array(normal, f"normals[{name!r}]", valid).reshape(-1)
        size = float(np.linalg.norm(vector)) if vector.shape == (3,) else 0.0
        if not size or not np.isfinite(size):
            raise InvalidInputError(
                f"normals[{name!r}] must be a nonzero 3-vector (world frame) or {FRAME!r}, "
                f"got {normal!r}."
            )
        world[index] = vector / size
    return Normals(world, frame)


#: the contact kinds, by the name ``contact=`` gives them (docs/contributing.md: adding a kind)
KINDS = {"point": point, "flat": flat}


def parse_contacts(contact: str | Mapping[str, str], reactions: Sequence[str]) -> tuple[str, ...]:
    """Each reaction's contact kind, ``"point"`` or ``"flat"``, from one kind or a dict by name.

    Raises:
        ConstraintError: Neither a string nor a mapping, an unknown kind, or a key that is not
            a name or not a reaction frame.
    """
    if isinstance(contact, str):
        if contact not in KINDS:
            raise ConstraintError(
                f"contact must be one of {list(KINDS)} or a dict; got {contact!r}."
            )
        return (contact,) * len(reactions)
    if not isinstance(contact, Mapping):
        raise ConstraintError(
            "contact must be 'point', 'flat' or a dict {reaction_frame: 'point' | 'flat'}, "
            f"got {describe(contact)}."
        )
    for name in contact:
        check_name(name, "contact: a key (a reaction frame name)", ConstraintError)
    unknown = set(contact) - set(reactions)
    if unknown:
        raise ConstraintError(
            f"contact names {sorted(unknown)} which are not reaction frames; "
            f"reactions are {list(reactions)}."
        )
    out = []
    for name in reactions:
        kind = contact.get(name, "point")
        if kind not in KINDS:
            raise ConstraintError(f"contact[{name!r}] must be one of {list(KINDS)}, got {kind!r}.")
        out.append(kind)
    return tuple(out)


def ball_axes(kind: str, rotation_axes: np.ndarray) -> np.ndarray:
    """The selected rotational axes (0-2) about which a contact of ``kind`` transmits no moment."""
    return KINDS[kind].ball_axes(rotation_axes)


@dataclass(frozen=True, slots=True)
class ContactSet:
    """The contacts of one parallel actuator's chains, declared once (see `declare`).

    Attributes:
        reactions: The reaction frames' names, one contact each.
        axes: The actuator's axes (the columns of a chain's force).
        kinds: ``"point"`` or ``"flat"`` per reaction (`KINDS`).
        normals: The contact normals (world z unless declared).
        friction: The pyramid's ``mu`` at every contact, or None for no faces.
        min_normal: Least normal force of every contact [N].
        soles: ``{reaction index: (half_length, half_width)}`` of the flat contacts' soles.
        minima: ``{axis index: minimum}``: every chain's share on that axis ``>= minimum``.
        cone: Whether each contact has pyramid rows (a normal row or faces).
        normal_row: Whether the pyramid starts with ``n . f >= min_normal`` (not with faces and
            no least normal force).
        names: The rows' names, in the order `rows` builds them.
        lows: The rows' lower bounds (no upper bound).
    """

    reactions: tuple[str, ...]
    axes: tuple[str, ...]
    kinds: tuple[str, ...]
    normals: Normals
    friction: float | None
    min_normal: float
    soles: Mapping[int, tuple[float, float]]
    minima: Mapping[int, float]
    cone: bool
    normal_row: bool
    names: tuple[str, ...]
    lows: np.ndarray

    @property
    def contact(self) -> dict[str, str]:
        """The kinds by reaction frame (what ``contact=`` declares)."""
        return dict(zip(self.reactions, self.kinds, strict=True))

    @property
    def sole_rows(self) -> bool:
        """Whether the soles give rows (they need moment axes)."""
        return flat.active(self.soles, self.axes)

    def normals_at(self, rotation_a: np.ndarray) -> np.ndarray:
        """``(p, 3)`` contact normals in the world; the frames' z axes from ``rotation_a``."""
        if not self.normals.frame.any():
            return self.normals.world
        normals = self.normals.world.copy()
        normals[self.normals.frame] = rotation_a[self.normals.frame, :, 2]
        return normals

    def rows(
        self, rotation_o: np.ndarray, rotation_a: np.ndarray, offsets_o: np.ndarray | None = None
    ) -> Constraint:
        """``lows <= G x`` over ``x = forces.ravel()``: the minima, the pyramids, then the soles.

        Args:
            rotation_o: ``(3, 3)`` {O}'s rotation in the world.
            rotation_a: ``(p, 3, 3)`` the reaction frames' rotations in the world.
            offsets_o: ``(p, 3)`` from each reaction frame's origin to {B}'s, in {O} (soles).
        """
        p, n = len(self.reactions), len(self.axes)
        blocks = []
        for axis in self.minima:
            block = np.zeros((p, p, n))
            block[np.arange(p), np.arange(p), axis] = 1.0  # chain c's share on the axis
            blocks.append(block.reshape(p, p * n))
        force_axes, components = force_entries(self.axes)
        if self.cone:
            normals_world = self.normals_at(rotation_a)
            stacked = point.pyramid(
                normals_world, normals_world @ rotation_o, rotation_o, self.friction,
                self.normal_row,
            )  # fmt: skip
            chains = np.arange(p)[:, None, None]
            cone = np.zeros((p, stacked.shape[1], p * n))
            columns = chains * n + np.asarray(force_axes, dtype=int)[None, None, :]
            cone[chains, np.arange(stacked.shape[1])[None, :, None], columns] = stacked[
                :, :, components
            ]
            blocks.append(cone.reshape(-1, p * n))
        if self.sole_rows:
            blocks.append(
                flat.block(self.soles, self.friction, rotation_o, rotation_a, offsets_o, self.axes)
            )
        G = np.vstack(blocks) if blocks else np.zeros((0, p * n))  # no row: no block, no low
        return Constraint(G, self.lows, np.full(len(self.lows), np.inf), self.names)

    def tables(self) -> dict[str, np.ndarray]:
        """The declaration's tables for the compiled QP matrices (normals, pyramid, soles)."""
        friction = -1.0 if self.friction is None else self.friction
        return {
            "normals_world": self.normals.world,
            "frame_normals": self.normals.frame.astype(np.int64),
            "cone": np.array([friction, self.min_normal, self.normal_row]),
            "soles": flat.table(self.soles, len(self.reactions)),
        }

    def compiled(self) -> CompiledMargins | None:
        """The core's margins' tables (None with sole rows: build `rows` then)."""
        if self.sole_rows:
            return None
        points = point.parameters(
            self.friction, self.min_normal, self.normals.frame, self.normals.world
        )
        return CompiledMargins(
            points if self.cone else points[:0],
            np.array([AXES.index(a) for a in self.axes], dtype=np.int64),
            np.array(list(self.minima), dtype=np.int64),
            self.lows,
        )


class CompiledMargins(NamedTuple):
    """A `ContactSet`'s tables for the core's margins (see `ContactSet.compiled`)."""

    #: ``(p, k)`` the contacts' `point.parameters` rows (no row: no pyramid)
    points: np.ndarray
    #: ``(n,)`` the component (0-5) of each axis
    axis_rows: np.ndarray
    #: the axes with a unilateral minimum
    minima_axes: np.ndarray
    #: the rows' lower bounds
    lows: np.ndarray


def declare(
    reactions: Sequence[str],
    axes: Sequence[str],
    contact: str | Mapping[str, str] = "point",
    friction: float | None = None,
    min_normal: float = 0.0,
    normals: Mapping[str, Sequence[float] | str] | str | Normals | None = None,
    soles: Mapping[str, Sequence[float]] | None = None,
    minima: Mapping[int, float] | None = None,
) -> ContactSet:
    """The `ContactSet` of ``reactions``' contacts, every argument checked.

    Args:
        reactions: The reaction frames' names.
        axes: The actuator's axes.
        contact: ``"point"``, ``"flat"`` or a dict by reaction (`parse_contacts`).
        friction: Friction coefficient ``mu`` (> 0) of every contact's pyramid, or None.
        min_normal: Least normal force (>= 0) of every contact [N].
        normals: None (world z), ``"frames"``, a mapping by reaction (`parse_normals`) or
            normals already parsed.
        soles: ``(half_length, half_width)`` [m] of flat contacts, by reaction frame.
        minima: ``{axis index: minimum}`` of every chain's share (``unilateral``).

    Raises:
        ConstraintError: A bad ``contact``.
        InvalidInputError: Bad ``friction``, ``min_normal``, ``normals`` or ``soles``.
    """
    if friction is not None:
        friction = check_number(friction, "friction", positive=True)
    min_normal = check_number(min_normal, "min_normal [N]", minimum=0.0)
    reactions, axes = tuple(reactions), tuple(axes)
    kinds = parse_contacts(contact, reactions)
    if not isinstance(normals, Normals):
        normals = parse_normals(normals, reactions)
    soles = flat.parse_soles(soles, reactions, kinds)
    minima = dict(minima or {})
    cone = any(a in axes for a in AXES[:3]) and (
        friction is not None or min_normal > 0.0 or bool(soles)
    )
    normal_row = cone and point.normal_row(friction, min_normal)
    names: list[str] = []
    lows: list[float] = []
    for axis, minimum in minima.items():
        names += [f"{reaction}: {axes[axis]} >= {minimum:g}" for reaction in reactions]
        lows += [minimum] * len(reactions)
    if cone:
        for reaction in reactions:
            rows = point.names(reaction, friction, min_normal, normal_row)
            names += rows
            lows += [min_normal] * normal_row + [0.0] * (len(rows) - normal_row)
    sole_names = flat.declared_names(soles, reactions, friction, axes)
    names += sole_names
    lows += [0.0] * len(sole_names)
    return ContactSet(
        reactions, axes, kinds, normals, friction, min_normal, soles, minima, cone, normal_row,
        tuple(names), np.array(lows, dtype=float),
    )  # fmt: skip
