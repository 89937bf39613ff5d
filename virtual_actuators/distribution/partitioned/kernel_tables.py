"""The compiled partitioned path's tables: the chain table's columns and the packed arguments."""

from __future__ import annotations

import numpy as np

#: Columns of the per-chain integer table's header: its velocity columns, own constrained
#: joints, ball axes, rank, natural rows, free entries, start of its free entries
K_COLS, C_CON, NB_BALL, RANK, L_ROWS, D_FREE, START = 0, 1, 2, 3, 4, 5, 6
HEADER = 7

#: Entries of :func:`pack_arguments`' integer header: mode, n, p, chain table width, torque
#: rows, plan length, chain columns, velocity indices, constant rows.
PACK_HEADER = 9


def pack_arguments(
    mode: int,
    keep: np.ndarray,
    axis_rows: np.ndarray,
    frame_rows: np.ndarray,
    chain_ints: np.ndarray,
    chain_signs: np.ndarray,
    springs: np.ndarray,
    const_rows: np.ndarray,
    const_rhs: np.ndarray,
    torque_rows: np.ndarray,
    torque_signs: np.ndarray,
    plan: np.ndarray,
    layout: np.ndarray,
) -> tuple[np.ndarray, np.ndarray]:
    """`distribute`'s declaration-time arguments as one integer and one float array, once per mode.

    Args:
        mode: 0 minimum norm, 1 partitioned (square).
        keep: ``(n,)`` 1 for prescribed axes, 0 for free ones.
        axis_rows: ``(n,)`` rows of the selected axes among ``x y z rx ry rz``.
        frame_rows: ``(2 + p,)`` rows of {B}, {O} and each {A_i} in ``frames``.
        chain_ints: ``(p, HEADER + K + C + 3 + L + D)`` per chain: the header (columns, own
            constrained joints, ball axes, rank, natural rows, free entries, start of its free
            entries in the reduced unknowns), then its velocity columns, the positions of its
            constrained joints among them, its ball axes (0-2), its CFS and its free entries.
        chain_signs: ``(p, K)`` +1/-1 of each chain column.
        springs: ``(nv, 5)`` the `spring_table`.
        const_rows: ``(s0, p, n)`` constant design rows.
        const_rhs: ``(s0,)`` their right-hand sides.
        torque_rows: ``(s1, 3)`` torque rows: joint a, joint b (-1: none), kind (0: shared
            limp/passive joint, ahead of the constant rows; 1: equal torques, after them).
        torque_signs: ``(s1, 2, p)`` chain signs at joints a and b.
        plan: ``(m,)`` mode 1: the RFS indices first (``s`` of them), then the MFS.
        layout: ``(4,)`` widths K, C, L, D of the column blocks of ``chain_ints``.
    """
    n, (p, width), s1 = keep.shape[0], chain_ints.shape, torque_rows.shape[0]
    header = [mode, n, p, width, s1, plan.shape[0], chain_signs.shape[1], springs.shape[0]]
    header.append(const_rows.shape[0])
    ints = np.concatenate(
        [
            np.array(header, dtype=np.int64),
            *(
                np.asarray(part, dtype=np.int64).ravel()
                for part in (keep, axis_rows, frame_rows, chain_ints, torque_rows, plan, layout)
            ),
        ]
    )
    floats = np.concatenate(
        [
            np.asarray(part, dtype=np.float64).ravel()
            for part in (chain_signs, springs, const_rows, const_rhs, torque_signs)
        ]
    )
    return ints, floats


__all__ = ["HEADER", "PACK_HEADER", "pack_arguments"]
