"""Every contact kind in ``contacts.KINDS``: its numpy rows and an oracle agree.

A kind's rows of one contact are built here from its module's kernels (``point.pyramid``,
``flat.rows``: what ``ContactSet.rows`` stacks). For each kind, on random frames, {O} rotations,
offsets, axes and declarations, the rows' margins on a random wrench equal an oracle written
here by hand from the kind's physics (a kind without rows and an oracle fails
:func:`test_every_kind_has_an_oracle`). The compiled core's rows of the same kinds
are checked against these numpy rows in ``test_core_parity_qp.py`` (the margins) and
``test_qp_paths.py`` (the QP's matrices, points and soles).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
import pinocchio as pin
import pytest

from virtual_actuators.contacts import flat, point
from virtual_actuators.contacts.constraint import Constraint, force_entries
from virtual_actuators.contacts.contact_set import KINDS

SPATIAL = ("x", "y", "z", "rx", "ry", "rz")
AXES_SETS = [SPATIAL, ("x", "z", "ry"), ("z", "rx", "ry"), ("x", "y", "z")]


class Contact(NamedTuple):
    """One contact as declared, what its rows read."""

    #: the reaction frame's name (the rows' names)
    reaction: str
    #: friction coefficient ``mu``, or None for no pyramid faces
    friction: float | None
    #: least normal force [N]
    min_normal: float
    #: ``(3,)`` unit contact normal in the world (unless ``frame_normal``)
    normal: np.ndarray
    #: whether the normal is the reaction frame's z axis, read every tick
    frame_normal: bool
    #: ``(half_length, half_width)`` [m] of a flat contact's sole
    sole: tuple[float, float]


def _world_wrench(wrench: np.ndarray, axes, rotation_o: np.ndarray) -> tuple[np.ndarray, ...]:
    """The chain's force and moment in the world (an axis left out is a zero entry in {O})."""
    full = np.zeros(6)
    for value, axis in zip(wrench, axes, strict=True):
        full[SPATIAL.index(axis)] = value
    return rotation_o @ full[:3], rotation_o @ full[3:]


def _point_oracle(contact, frame_world, rotation_o, offset_o, axes, wrench):
    """``n.f - min`` (when a least normal force is asked, or without friction) and the faces
    ``mu n.f -+ t.f`` about the normal, tangents from the world x axis (y near x)."""
    force, _ = _world_wrench(wrench, axes, rotation_o)
    normal = frame_world[:, 2] if contact.frame_normal else contact.normal
    margins = []
    if contact.friction is None or contact.min_normal > 0.0:
        margins.append(normal @ force - contact.min_normal)
    if contact.friction is not None:
        helper = np.array([1.0, 0.0, 0.0]) if abs(normal[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
        t1 = np.cross(normal, helper)
        t1 /= np.linalg.norm(t1)
        t2 = np.cross(normal, t1)
        mu_n = contact.friction * (normal @ force)
        margins += [mu_n - t1 @ force, mu_n + t1 @ force, mu_n - t2 @ force, mu_n + t2 @ force]
    return np.array(margins)


def _flat_oracle(contact, frame_world, rotation_o, offset_o, axes, wrench):
    """The centre of pressure inside the sole and the bounded yaw moment, in the sole's frame."""
    force, moment_b = _world_wrench(wrench, axes, rotation_o)
    moment = moment_b + np.cross(rotation_o @ offset_o, force)  # about the sole's origin
    f_local, m_local = frame_world.T @ force, frame_world.T @ moment
    half_length, half_width = contact.sole
    mu = 0.0 if contact.friction is None else contact.friction
    halves = (half_width, half_length, mu * min(half_length, half_width))
    return np.array([h * f_local[2] + s * m for h, m in zip(halves, m_local, strict=True)
                     for s in (-1.0, 1.0)])  # fmt: skip


ORACLES = {"point": _point_oracle, "flat": _flat_oracle}


def _point_rows(contact, frame_world, rotation_o, offset_o, axes) -> Constraint:
    """The contact's pyramid rows ``>= lows`` over its chain's force (``n`` entries, in {O})."""
    normal = frame_world[:, 2] if contact.frame_normal else np.asarray(contact.normal, float)
    with_normal = point.normal_row(contact.friction, contact.min_normal)
    vectors = point.pyramid(
        normal[None], (normal @ rotation_o)[None], rotation_o, contact.friction, with_normal
    )[0]
    positions, components = force_entries(axes)
    G = np.zeros((len(vectors), len(axes)))
    G[:, positions] = vectors[:, components]
    lows = np.zeros(len(vectors))
    lows[:with_normal] = contact.min_normal
    names = point.names(contact.reaction, contact.friction, contact.min_normal, with_normal)
    return Constraint(G, lows, np.full(len(lows), np.inf), names)


def _flat_rows(contact, frame_world, rotation_o, offset_o, axes) -> Constraint:
    """The sole's six rows ``>= 0`` over its chain's wrench (``n`` entries, in {O})."""
    frame_o, entries = rotation_o.T @ frame_world, flat.entries(axes, 0, 1)
    G = flat.rows(contact.sole, contact.friction, frame_o, offset_o, entries)
    names = flat.names(contact.reaction, contact.sole, contact.friction)
    return Constraint(G, np.zeros(6), np.full(6, np.inf), names)


#: each kind's rows of one contact, and the most rows one contact has
ROWS = {"point": (_point_rows, 5), "flat": (_flat_rows, 6)}


def test_every_kind_has_an_oracle():
    assert set(KINDS) == set(ORACLES) == set(ROWS)
    for module in KINDS.values():
        assert hasattr(module, "ball_axes"), f"{module.__name__} lacks ball_axes"


def _contact(rng: np.random.Generator) -> Contact:
    normal = rng.normal(size=3) if rng.uniform() < 0.5 else np.array([0.0, 0.0, 1.0])
    return Contact(
        "foot",
        None if rng.uniform() < 0.25 else float(rng.uniform(0.2, 1.2)),
        0.0 if rng.uniform() < 0.4 else float(rng.uniform(0.0, 30.0)),
        normal / np.linalg.norm(normal),
        bool(rng.uniform() < 0.4),
        (float(rng.uniform(0.02, 0.2)), float(rng.uniform(0.02, 0.2))),
    )


@pytest.mark.parametrize("kind", sorted(KINDS))
@pytest.mark.parametrize("seed", range(6))
def test_numpy_rows_equal_the_oracle(kind, seed):
    (build, most), oracle = ROWS[kind], ORACLES[kind]
    rng = np.random.default_rng(seed)
    for trial in range(20):
        axes = AXES_SETS[trial % len(AXES_SETS)]
        contact = _contact(rng)
        frame_world, rotation_o = pin.SE3.Random().rotation, pin.SE3.Random().rotation
        offset_o = rng.normal(size=3) * 0.3
        rows = build(contact, frame_world, rotation_o, offset_o, axes)
        assert len(rows.names) == len(rows.lows) == rows.G.shape[0] <= most
        wrench = rng.normal(size=len(axes)) * 20.0
        margins = rows.G @ wrench - rows.lows
        expected = oracle(contact, frame_world, rotation_o, offset_o, axes, wrench)
        np.testing.assert_allclose(margins, expected, rtol=0, atol=1e-10)
