"""Reading a parallel actuator's declaration once: limp and passive joints, design rows."""

from __future__ import annotations

from collections.abc import Iterable, Mapping, Sequence
from typing import NamedTuple

import numpy as np

from ...exceptions import ConstraintError, InvalidAxisError, InvalidInputError, JointNotFoundError
from ...kinematics.relative import RelativeKinematics
from ...vocabulary.arguments import check_name, check_number, describe
from ...vocabulary.axes import resolve_joint
from ...vocabulary.constraints import DesignConstraint, Equal, EqualTorque, Label, Linear


class DesignRows(NamedTuple):
    """The design constraints as rows."""

    constant_rows: np.ndarray  #: ``(s0, p, n)`` rows over the forces (``Equal``, ``Linear``)
    constant_rhs: np.ndarray  #: ``(s0,)`` their right-hand sides
    torque_pairs: np.ndarray  #: ``(s1, 2)`` velocity indices of ``EqualTorque`` joint pairs
    constant_names: list[str]  #: a readable name per constant row
    torque_names: list[str]  #: a readable name per torque pair


def joint_columns(
    kinematics: RelativeKinematics, reactions: Sequence[str], name: str, role: str
) -> tuple[int, np.ndarray]:
    """A joint's id and velocity columns, checked to lie on a chain.

    Raises:
        JointNotFoundError: An unknown joint, or one on no chain (the message lists them).
    """
    joint_id = resolve_joint(kinematics.model, name, role)
    joint = kinematics.model.joints[joint_id]
    vs = np.arange(joint.idx_v, joint.idx_v + joint.nv)
    on_chains = np.zeros(kinematics.model.nv, dtype=bool)
    on_chains[np.concatenate(kinematics.chain_columns)] = True
    if not np.any(on_chains[vs]):
        chain_joints = sorted(
            {
                kinematics.model.names[j]
                for j in range(1, kinematics.model.njoints)
                if on_chains[kinematics.model.joints[j].idx_v]
            }
        )
        raise JointNotFoundError(
            f"The {role} {name!r} is not on any chain between the action frame and the "
            f"reaction frames {list(reactions)}; joints on the chains: {chain_joints}."
        )
    return joint_id, vs


def check_passive(passive: object) -> dict[str, tuple[float, float]]:
    """``passive`` as ``{joint: (stiffness, rest)}`` with two finite real numbers per joint."""
    if passive is None:
        return {}
    if not isinstance(passive, Mapping):
        raise InvalidInputError(
            "passive must be a dict {joint_name: (stiffness [N m/rad], rest angle [rad])}, got "
            f"{describe(passive)}."
        )
    out: dict[str, tuple[float, float]] = {}
    for name, params in passive.items():
        check_name(name, "passive: a key (a joint name)", JointNotFoundError)
        what = f"passive[{name!r}]"
        if isinstance(params, (str, bytes, Mapping)) or not isinstance(params, Iterable):
            params = (params,)  # reported below as a wrong number of values
        params = tuple(params)
        if len(params) != 2:
            raise ConstraintError(
                f"{what} must be (stiffness, rest_angle), two real numbers, got {params!r}."
            )
        out[name] = tuple(
            check_number(x, f"{what}: {label}", error=ConstraintError)
            for x, label in zip(params, ("stiffness", "rest angle"), strict=True)
        )
    return out


class Spring(NamedTuple):
    """A passive joint's spring, ``tau = -stiffness (angle - rest)``.

    Attributes:
        name: The joint.
        stiffness: [N m/rad or N/m].
        rest: Rest angle or position [rad or m].
        idx_q: The joint's first configuration index.
        continuous: Whether the joint is continuous (its angle is ``(cos, sin)`` at ``idx_q``).
    """

    name: str
    stiffness: float
    rest: float
    idx_q: int
    continuous: bool


def parse_joints(
    kinematics: RelativeKinematics,
    reactions: Sequence[str],
    unactuated: Sequence[str],
    passive: Mapping[str, tuple[float, float]],
) -> tuple[dict[int, str], dict[int, Spring]]:
    """Limp joints ``{v: name}`` and passive springs ``{v: Spring}``.

    ``unactuated`` is a tuple of names, ``passive`` checked by `check_passive`.

    Raises:
        JointNotFoundError: A joint that is unknown or on no chain.
        ConstraintError: A multi-dof passive joint, or one both limp and passive.
    """
    limp: dict[int, str] = {}
    for name in unactuated:
        _, vs = joint_columns(kinematics, reactions, name, "unactuated joint")
        limp.update(dict.fromkeys(vs.tolist(), name))
    springs: dict[int, Spring] = {}
    for name, (stiffness, rest) in passive.items():
        joint_id, vs = joint_columns(kinematics, reactions, name, "passive joint")
        joint = kinematics.model.joints[joint_id]
        if joint.nv != 1 or joint.nq not in (1, 2):
            raise ConstraintError(
                f"passive joint {name!r} has {joint.nv} degrees of freedom; passive springs "
                "need a one-degree-of-freedom joint (revolute, prismatic or continuous)."
            )
        if int(vs[0]) in limp:
            raise ConstraintError(f"joint {name!r} is declared both unactuated and passive.")
        springs[int(vs[0])] = Spring(name, stiffness, rest, joint.idx_q, joint.nq == 2)
    return limp, springs


def label_index(
    label: Label, constraint: DesignConstraint, reactions: Sequence[str], axes: Sequence[str]
) -> tuple[int, int]:
    """``(chain, axis)`` indices of a design label (a pair of str, checked by the constraint).

    Raises:
        ConstraintError: An unknown reaction frame.
        InvalidAxisError: An axis the actuator does not have.
    """
    reaction, axis = label
    if reaction not in reactions:
        raise ConstraintError(
            f"{constraint!r} names {reaction!r}, which is not a reaction frame of this "
            f"actuator; reactions are {list(reactions)}."
        )
    if axis not in axes:
        raise InvalidAxisError(
            f"{constraint!r} names axis {axis!r}, which is not one of this actuator's axes {axes}."
        )
    return reactions.index(reaction), axes.index(axis)


def design_rows(
    design: Sequence[DesignConstraint],
    kinematics: RelativeKinematics,
    reactions: Sequence[str],
    axes: Sequence[str],
) -> DesignRows:
    """The rows of the design constraints: constant rows over the forces, equal-torque pairs.

    Raises:
        ConstraintError: A malformed constraint (self-equality, no coefficient, NaN, a
            multi-dof or repeated joint, an unknown type), or a label naming no reaction.
        InvalidAxisError: A label naming an axis the actuator does not have.
        JointNotFoundError: An EqualTorque joint that is unknown or on no chain.
    """
    p, n = len(reactions), len(axes)
    constant_rows, constant_rhs, torque_pairs = [], [], []
    constant_names, torque_names = [], []
    for constraint in design:
        if isinstance(constraint, (Equal, Linear)):
            row, rhs = np.zeros((p, n)), 0.0
            if isinstance(constraint, Equal):
                (ia, xa), (ib, xb) = (
                    label_index(lbl, constraint, reactions, axes)
                    for lbl in (constraint.a, constraint.b)
                )
                if (ia, xa) == (ib, xb):
                    raise ConstraintError(f"{constraint!r} equates an entry with itself.")
                row[ia, xa] += 1.0
                row[ib, xb] -= 1.0
            else:
                if not constraint.coefficients:
                    raise ConstraintError(f"{constraint!r} has no coefficient.")
                for label, coeff in constraint.coefficients.items():
                    i, x = label_index(label, constraint, reactions, axes)
                    if not np.isfinite(coeff):
                        raise ConstraintError(f"{constraint!r} has a NaN or inf coefficient.")
                    row[i, x] += float(coeff)
                if not np.isfinite(constraint.rhs):
                    raise ConstraintError(f"{constraint!r} has a NaN or inf rhs.")
                rhs = float(constraint.rhs)
            constant_rows.append(row)
            constant_rhs.append(rhs)
            constant_names.append(repr(constraint))
        elif isinstance(constraint, EqualTorque):
            vs = []
            for name in (constraint.joint_a, constraint.joint_b):
                joint_id, v = joint_columns(kinematics, reactions, name, "EqualTorque joint")
                if len(v) != 1:
                    raise ConstraintError(
                        f"{constraint!r}: joint {name!r} has {len(v)} degrees of freedom; "
                        "EqualTorque needs one-degree-of-freedom joints."
                    )
                vs.append(int(v[0]))
            if vs[0] == vs[1]:
                raise ConstraintError(f"{constraint!r} names the same joint twice.")
            torque_pairs.append(vs)
            torque_names.append(repr(constraint))
        else:
            raise ConstraintError(
                f"Unknown design constraint {constraint!r}; use va.Equal, va.Linear or "
                "va.EqualTorque."
            )
    return DesignRows(
        np.array(constant_rows).reshape(-1, p, n),
        np.array(constant_rhs, dtype=float),
        np.array(torque_pairs, dtype=int).reshape(-1, 2),
        constant_names,
        torque_names,
    )
