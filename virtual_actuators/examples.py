"""The seeds' worked examples, reproduced: ``python -m virtual_actuators example NAME``.

``hexapod-tripod`` (VAC section 3, eq. 26), ``millipede`` (VAC 2.5.1), ``single-leg`` (VMC 4.1,
eq. 5-7) and ``double-support`` (VMC 4.2, eq. 8-14); each returns an `Example` and, with
``verbose``, prints a report.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import pinocchio as pin

import virtual_actuators as va

GRAVITY = 9.81  # [m/s^2]


def _sets_line(sol: va.Solution) -> str:
    return "  ".join(f"{k} {len(v)}" for k, v in sol.sets.items())


@dataclass(repr=False)
class Example:
    """What a worked example built and computed.

    Attributes:
        name: The example's CLI name.
        robot: The robot it loaded.
        actuator: The parallel actuator it declared.
        q: The configuration it solved at.
        solution: The distribution.
        details: The example's own figures (set sizes, comparisons, closed forms).
    """

    name: str
    robot: va.Robot
    actuator: va.ParallelVirtualActuator
    q: np.ndarray
    solution: va.Solution
    details: dict[str, Any] = field(default_factory=dict)

    def __repr__(self) -> str:
        return (
            f"Example({self.name!r}, robot={self.robot.name!r}, method={self.solution.method!r}, "
            f"details={sorted(self.details)})"
        )


def hexapod_tripod(verbose: bool = True) -> Example:
    """VAC section 3: the hexapod on tripod legs 1, 3, 5 with the design constraints of eq. 26."""
    robot = va.load_robot("hexapod")
    q = robot.neutral()
    feet = ["foot_1", "foot_3", "foot_5"]  # the seed's legs 1, 2, 3 of the support tripod
    design = [
        va.Equal((feet[2], "x"), (feet[1], "x")),  # f_x3 = f_x2
        va.Equal((feet[2], "y"), (feet[1], "y")),  # f_y3 = f_y2
        va.Linear({(feet[0], "y"): 1.0, (feet[1], "y"): -2.0}),  # f_y1 = 2 f_y2
    ]
    body = va.ParallelVirtualActuator(
        robot, action="body", reactions=feet, reference="world", contact="point", design=design
    )
    mass = pin.computeTotalMass(robot.model)
    wrench = np.array([3.0, 1.5, mass * GRAVITY, 0.05, -0.1, 0.2])  # [N, N m]
    sol = body.solve(q, wrench)
    dense = body.solve(q, wrench, method="dense")
    details = {
        "sizes": body.sizes(),
        "dense_difference": float(np.abs(sol.forces - dense.forces).max()),
        "systems": sol.systems,
    }
    if verbose:
        print(f"{robot}, mass {mass:.3f} kg, standing on legs 1, 3, 5")
        print(f"constants: {body.sizes()}   (seed eq. 25: n=6, p=3, l=3, d=3, r=3)")
        print(f"method: {sol.method}   sets: {_sets_line(sol)}   systems solved: {sol.systems}")
        for key, labels in sol.sets.items():
            print(f"  {key}: " + ", ".join(f"{r}.{a}" for r, a in labels))
        print("\nforces on the body [N, N m]:\n" + sol.table())
        print("\njoint torques [N m]:")
        for leg in (1, 3, 5):
            names = [f"hip1_{leg}", f"hip2_{leg}", f"knee_{leg}"]
            values = [sol.tau[robot.model.joints[robot.model.getJointId(n)].idx_v] for n in names]
            print("  " + "  ".join(f"{n:>8} {v:8.4f}" for n, v in zip(names, values, strict=True)))
        print(f"\npartitioned vs dense eq. 10-11: max |dF| = {details['dense_difference']:.2e}")
    return Example("hexapod-tripod", robot, body, q, sol, details)


def millipede(legs: int = 100, verbose: bool = True) -> Example:
    """VAC 2.5.1: the millipede's set sizes, solved without and with r design constraints."""
    robot = va.millipede(legs=legs)
    q = robot.neutral()
    feet = [f"foot_{i}" for i in range(1, legs + 1)]
    body = va.ParallelVirtualActuator(robot, "body", feet, reference="body")
    mass = pin.computeTotalMass(robot.model)
    wrench = np.array([2.0, 0.0, mass * GRAVITY, 0.1, 0.3, 0.2])
    sol = body.solve(q, wrench)
    # r generic design constraints: seeded random linear relations between neighbouring legs'
    # x and z forces (structured patterns make the 6 x 6 MFS system singular)
    r = body.sizes()["r"]
    rng = np.random.default_rng(1996)
    design = []
    for i in range(1, legs):
        for _ in range(2):
            if len(design) < r:
                c = rng.uniform(0.5, 1.5, 4) * rng.choice([-1.0, 1.0], 4)
                labels = [(feet[i - 1], "x"), (feet[i - 1], "z"), (feet[i], "x"), (feet[i], "z")]
                design.append(va.Linear(dict(zip(labels, c, strict=True))))
    square = va.ParallelVirtualActuator(robot, "body", feet, reference="body", design=design)
    sol_square = square.solve(q, wrench)
    dense = square.solve(q, wrench, method="dense")
    scale = max(1.0, float(np.abs(dense.forces).max()))
    details = {
        "sizes": body.sizes(),
        "square": sol_square,
        "design": len(design),
        "dense_difference": float(np.abs(sol_square.forces - dense.forces).max()) / scale,
    }
    if verbose:
        print(f"{robot}, {legs} legs, mass {mass:.2f} kg")
        print(f"constants: {body.sizes()}   (seed: n=6, p=100, l=4, d=2, r=194)")
        print(f"no design constraint: {sol.method}, sets {_sets_line(sol)}")
        print(
            f"{len(design)} design constraints: {sol_square.method}, "
            f"sets {_sets_line(sol_square)}, systems {sol_square.systems}"
        )
        print(f"partitioned vs dense (relative): {details['dense_difference']:.1e}")
        print("\nfirst legs' forces (no design constraint) [N, N m]:")
        print("\n".join(sol.table().splitlines()[:7]))
    return Example("millipede", robot, body, q, sol, details)


def _flamingo_leg(robot: va.Robot, q: np.ndarray, side: str) -> tuple[float, float, float, float]:
    """Return (a, k, L1, L2): ankle and knee angles, shin and thigh lengths of one leg."""
    model = robot.model
    data = pin.Data(model)
    pin.framesForwardKinematics(model, data, q)
    hip, knee, ankle = (model.getJointId(f"{side}_{part}") for part in ("hip", "knee", "ankle"))
    hip_xz, knee_xz, ankle_xz = (data.oMi[j].translation[[0, 2]] for j in (hip, knee, ankle))
    shin, thigh = (float(np.linalg.norm(d)) for d in (knee_xz - ankle_xz, hip_xz - knee_xz))
    return float(q[model.joints[ankle].idx_q]), float(q[model.joints[knee].idx_q]), shin, thigh


def single_leg_closed_form(a: float, k: float, l1: float, l2: float, fz: float, fry: float):
    """VMC eq. 5-7 for our sign convention (joints about +y, x forward, z up).

    Body (hip) relative to the ankle: ``x = -L1 s_a - L2 s_{a+k}``, ``z = L1 c_a + L2 c_{a+k}``,
    pitch ``-(a + k + h)``. With the ankle limp (``tau_a = 0``), ``f_x`` follows, and::

        tau_k = -L1 L2 s_k / C * f_z - L1 c_a / C * f_ry,   tau_h = -f_ry,
        C = L1 c_a + L2 c_{a+k}

    Returns:
        ``(f_x, tau_k, tau_h)``.
    """
    c = l1 * np.cos(a) + l2 * np.cos(a + k)
    s = l1 * np.sin(a) + l2 * np.sin(a + k)
    fx = -(s * fz + fry) / c
    tau_k = -l1 * l2 * np.sin(k) / c * fz - l1 * np.cos(a) / c * fry
    return fx, tau_k, -fry


def single_leg(verbose: bool = True) -> Example:
    """VMC 4.1: one leg with a limp ankle; z and pitch set, x follows; the straight knee."""
    robot = va.load_robot("spring_flamingo")
    q = robot.neutral()
    leg = va.ParallelVirtualActuator(
        robot, "body", ["left_foot"], reference="world", axes=("x", "z", "ry"),
        contact="flat", unactuated=["left_ankle"],
    )  # fmt: skip
    fz, fry = 12.0 * GRAVITY, 3.0  # [N], [N m]
    sol = leg.solve(q, np.array([0.0, fz, fry]), free=("x",))
    a, k, l1, l2 = _flamingo_leg(robot, q, "left")
    fx, tau_k, tau_h = single_leg_closed_form(a, k, l1, l2, fz, fry)
    index = {n: robot.model.joints[robot.model.getJointId(n)].idx_v for n in robot.joint_names}
    straight = q.copy()
    straight[robot.model.joints[robot.model.getJointId("left_knee")].idx_q] = 0.0
    try:
        leg.solve(straight, np.array([0.0, fz, fry]), free=("x",))
        straight_outcome = "solved"
    except va.SingularConfigurationError as error:
        straight_outcome = f"SingularConfigurationError: {error}"
    details = {
        "closed_form": {"fx": fx, "tau_knee": tau_k, "tau_hip": tau_h},
        "library": {
            "fx": float(sol.forces[0, 0]),
            "tau_knee": float(sol.tau[index["left_knee"]]),
            "tau_hip": float(sol.tau[index["left_hip"]]),
            "tau_ankle": float(sol.tau[index["left_ankle"]]),
        },
        "straight_knee": straight_outcome,
    }
    if verbose:
        print(f"{robot}: left leg, limp ankle, z and pitch set, x free (VMC eq. 5-7)")
        print(f"a = {a:.4f} rad, k = {k:.4f} rad, L1 = {l1:.3f} m, L2 = {l2:.3f} m")
        print(f"{'':12}{'library':>14}{'closed form':>14}")
        for key in ("fx", "tau_knee", "tau_hip"):
            print(f"{key:12}{details['library'][key]:>14.6f}{details['closed_form'][key]:>14.6f}")
        print(f"{'tau_ankle':12}{details['library']['tau_ankle']:>14.2e}{0.0:>14.6f}")
        print(f"method {sol.method}, sets {_sets_line(sol)}, systems {sol.systems}")
        print(f"\nstraight knee (k = 0): {straight_outcome}")
    return Example("single-leg", robot, leg, q, sol, details)


def double_support_closed_form(legs: dict, fx: float, fz: float, fry: float) -> dict:
    """VMC eq. 8-14 for our sign convention: limp ankles, equal hip torques.

    Equal hip torques give ``f_ry`` split in halves (``tau_h = -f_ry`` per leg); each limp ankle
    gives ``C f_x + S f_z + f_ry/2 = 0`` with ``C = L1 c_a + L2 c_{a+k}``,
    ``S = L1 s_a + L2 s_{a+k}``; with ``f_xl + f_xr = f_x`` and ``f_zl + f_zr = f_z``::

        f_zl = (f_x + S_r f_z / C_r + f_ry/2 (1/C_l + 1/C_r)) / (S_r/C_r - S_l/C_l)

    (singular when both hip-to-ankle lines are parallel), then
    ``tau_k = -L2 c_{a+k} f_x - L2 s_{a+k} f_z - f_ry/2`` per leg.

    Args:
        legs: ``{"left": (a, k, L1, L2), "right": (...)}``.
        fx: Body force along x [N].
        fz: Body force along z [N].
        fry: Body moment about y [N m].

    Returns:
        Per leg ``(f_x, f_z, tau_knee, tau_hip)``.
    """
    cs = {}
    for side, (a, k, l1, l2) in legs.items():
        cs[side] = (l1 * np.cos(a) + l2 * np.cos(a + k), l1 * np.sin(a) + l2 * np.sin(a + k))
    (cl, sl), (cr, sr) = cs["left"], cs["right"]
    half = fry / 2.0
    fzl = (fx + sr * fz / cr + half * (1 / cl + 1 / cr)) / (sr / cr - sl / cl)
    fzr = fz - fzl
    out = {}
    for side, fz_leg in (("left", fzl), ("right", fzr)):
        a, k, l1, l2 = legs[side]
        c, s = cs[side]
        fx_leg = -(s * fz_leg + half) / c
        tau_k = -l2 * np.cos(a + k) * fx_leg - l2 * np.sin(a + k) * fz_leg - half
        out[side] = (fx_leg, fz_leg, tau_k, -half)
    return out


def double_support(verbose: bool = True) -> Example:
    """VMC 4.2: both legs, limp ankles, matched hip torques, against the closed form."""
    robot = va.load_robot("spring_flamingo")
    q = robot.neutral()
    body = va.ParallelVirtualActuator(
        robot, "body", ["left_foot", "right_foot"], reference="world", axes=("x", "z", "ry"),
        contact="flat", unactuated=["left_ankle", "right_ankle"],
        design=[va.EqualTorque("left_hip", "right_hip")],
    )  # fmt: skip
    wrench = np.array([8.0, 12.0 * GRAVITY, 2.0])
    sol = body.solve(q, wrench)
    legs = {side: _flamingo_leg(robot, q, side) for side in ("left", "right")}
    closed = double_support_closed_form(legs, *wrench)
    index = {n: robot.model.joints[robot.model.getJointId(n)].idx_v for n in robot.joint_names}
    library = {
        side: (
            float(sol.force(f"{side}_foot")[0]),
            float(sol.force(f"{side}_foot")[1]),
            float(sol.tau[index[f"{side}_knee"]]),
            float(sol.tau[index[f"{side}_hip"]]),
        )
        for side in ("left", "right")
    }
    details = {"closed_form": closed, "library": library}
    if verbose:
        print(f"{robot}: double support, limp ankles, equal hip torques (VMC eq. 8-14)")
        print(f"{'':18}{'library':>12}{'closed form':>14}")
        for side in ("left", "right"):
            for j, key in enumerate(("f_x", "f_z", "tau_knee", "tau_hip")):
                name = f"{side} {key}"
                print(f"{name:18}{library[side][j]:>12.5f}{closed[side][j]:>14.5f}")
        print(f"method {sol.method}, sets {_sets_line(sol)}, systems {sol.systems}")
    return Example("double-support", robot, body, q, sol, details)


EXAMPLES: dict[str, Callable[..., Example]] = {
    "hexapod-tripod": hexapod_tripod,
    "millipede": millipede,
    "single-leg": single_leg,
    "double-support": double_support,
}
