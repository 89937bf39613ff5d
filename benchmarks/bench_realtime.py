"""Real-time figures of virtual_actuators, each beside a baseline timed in the same run.

    python benchmarks/bench_realtime.py [--quick] [--json PATH] [--walk-seconds 3]
                                        [--worst-seconds 20] [--only N]

Figures (median and p90 per call after warm-up, in microseconds; ours and its baseline are timed
interleaved, in blocks, over the same round-robin set of configurations):

1. solo12 body ``solve`` vs the Pinocchio floor (joint Jacobians, frame placements, 5 frame
   Jacobians).
2. the same distribution as a proxsuite dense QP (kinematics + matrices + solve), without and
   with 4-sided friction pyramids; the total wrenches are compared. Our ``method="qp"`` beside
   the QP with pyramids, for solo12 and for the hexapod on six feet.
3. millipede (100 legs) ``solve`` vs one dense 600x600 ``np.linalg.solve``.
4. millipede scaling and memory (100, 400 legs solved, 1000 legs declared), one child process
   each, 4 GiB address-space limit, peak RSS from ``VmHWM``.
5. UR5 Cartesian spring-damper through ``va.Controller.compute`` vs raw Pinocchio and vs the
   ``virtualmodelcontrol`` package (torques compared).
6. every registered walk in MuJoCo (``gaits.registry.WALKS``; the legged walk as trots of
   solo12 and go2): real-time factor beside MuJoCo stepping the same robot alone (their
   ratio) and a per-tick breakdown; and, in a row of its own, whether the loop is smooth at the
   tick rate (issue 35, ``effort_smoothness`` of the breakdown's run): the efforts' tick-rate
   oscillation (75th percentile, worst joint) and rms change per tick in percent of the effort
   limits, beside the base rate's alternation (percent of the ticks).
7. worst case: p50, p99, p99.9 and the maximum tick of each walk of figure 6 (``--worst-seconds``
   simulated seconds each, 20 by default) and of 10,000-tick ``va.run`` loops on the UR5 (tool
   tracking) and on go2 standing; the controller's compute (wall and thread CPU time) and the
   whole loop iteration, beside MuJoCo's step in the same ticks; every tick of 1 ms or more is
   listed with what happened in it and replayed, to tell the code's from the machine's
   (definitions in ``_latency.py``).
8. cold start: a new process with Python's bytecode cache empty (``PYTHONPYCACHEPREFIX``, a
   new temporary directory) times ``import virtual_actuators``, the solo12 declaration of
   figure 1, the first ``solve`` and the first ``solve(method="qp")``; and the README's demo
   command is launched the same way, timed until its progress bar first moves. Beside each, the
   same in a new process reading the cache the cold one wrote (``_cold_start.py``). ``--quick``
   runs the warm ones only.
9. the legged state estimator: ``LeggedEstimator.update`` on go2's readings of a 0.8 m/s trot
   (the simulated MEMS sensors) vs the walker's tick on the same walk's states, interleaved.

After the table, the rows of issue 27's table (each beside its same-run baseline and the issue's
goal) are printed again on their own. Figure 2 uses friction 0.7 as the issue does (0.6 before
2026-11-25).
"""

from __future__ import annotations

import argparse
import json
import sys
import time
import traceback
from collections.abc import Callable
from contextlib import nullcontext
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import pinocchio as pin
from _baselines import (
    Figure,
    FootForceQP,
    PinocchioFloor,
    RawCartesianSpringDamper,
    VMCCartesianSpringDamper,
    blas_threads,
    cycling,
    dense_system,
    instrumented_walk,
    machine_info,
    measure,
    peak_rss_bytes,
    perturbed,
    print_table,
    ratio_of,
    row,
    run_child,
    timed_walks,
    us,
)

import virtual_actuators as va

SOLO_FEET = ["FL_FOOT", "FR_FOOT", "HL_FOOT", "HR_FOOT"]
SOLO_WRENCH = np.array([2.0, 1.0, 25.0, 0.1, -0.2, 0.05])  # [N, N m] on base_link, in base_link
MU = 0.7  # friction of figure 2's pyramids and of figure 8's qp solve
UR5_Q = np.array([0.3, -1.2, 1.5, -0.8, -1.2, 0.4])  # [rad], away from singularities
UR5_SETPOINT = np.array([0.35, 0.25, 0.45])  # [m], tool0 in the world
UR5_K, UR5_D = 300.0, 30.0  # [N/m], [N s/m]
GIB, MIB = 1 << 30, 1 << 20


@dataclass
class Settings:
    """Repetitions and limits of one run."""

    repeat: int  # calls per case, fast figures
    repeat_slow: int  # calls per case, millipede and dense solve
    child_repeat: int  # solves per child of figure 4
    walk_seconds: float
    child_timeout: float  # [s]
    rounds: int = 10  # interleaved blocks
    worst_seconds: float = 20.0  # simulated s of each walk of figure 7
    loop_ticks: int = 10_000  # ticks of each va.run loop of figure 7
    cold: bool = True  # figure 8 measures a cold start (False: the warm ones only)


def _fresh(count: int) -> int:
    """How many configurations to cycle through so that no timed call repeats one: a real loop
    never sees the same q twice, so caching on q must not help."""
    return count + 32


# -- figures 1 and 2: solo12 --------------------------------------------------------------------


def _solo12(cfg: Settings):
    robot = va.load_robot("solo12")
    body = va.ParallelVirtualActuator(
        robot, "base_link", SOLO_FEET, reference="base_link", contact="point"
    )
    configs = perturbed(robot.model, robot.neutral(), _fresh(cfg.repeat), 0.02, seed=12)
    solve = cycling(lambda q: body.solve(q, SOLO_WRENCH), [(q,) for q in configs])
    return robot, body, configs, solve


def figure_solo12_floor(cfg: Settings) -> Figure:
    """1. solo12 body solve vs the bare Pinocchio kinematics it needs."""
    robot, body, configs, solve = _solo12(cfg)
    floor = PinocchioFloor(robot.model, ["base_link", *SOLO_FEET])
    floor_call = cycling(floor, [(q,) for q in configs])
    cases = {"solve": (solve, cfg.repeat), "floor": (floor_call, cfg.repeat)}
    stats = measure(cases, cfg.rounds)
    ratio = ratio_of(stats["solve"], stats["floor"])
    ours, base = us(stats["solve"]), us(stats["floor"])
    rows = [
        row("1a solo12 solve vs Pinocchio floor", ours, base, ratio, "<= 10x", ratio <= 10),
        row("1b   (stretch)", ours, base, ratio, "<= 3x", ratio <= 3),
    ]
    method = body.solve(configs[0], SOLO_WRENCH).method
    issue = [row("solo12 solve / Pinocchio Jacobian floor", ours, base, ratio, "<= 3x", ratio <= 3)]
    return Figure(rows, {**stats, "method": method, "configurations": len(configs)}, [], issue)


def figure_solo12_qp(cfg: Settings) -> Figure:
    """2. solo12 body solve vs the proxsuite QP a user would write instead."""
    robot, body, configs, solve = _solo12(cfg)
    qps = {
        f"qp_{kind}_{mode}": FootForceQP(
            robot.model, "base_link", SOLO_FEET, MU if kind == "cone" else None, mode
        )
        for kind in ("plain", "cone")
        for mode in ("init", "update")
    }
    # ours with the contacts as inequalities (method="qp": pyramids mu MU, least normal 0)
    body_qp = va.ParallelVirtualActuator(
        robot, "base_link", SOLO_FEET, reference="base_link", contact="point", friction=MU
    )
    solve_qp = cycling(
        lambda q: body_qp.solve(q, SOLO_WRENCH, method="qp"), [(q,) for q in configs]
    )
    cases = {"solve": (solve, cfg.repeat), "solve_qp": (solve_qp, cfg.repeat)}
    for name, qp in qps.items():
        cases[name] = (cycling(qp.solve, [(q, SOLO_WRENCH) for q in configs]), cfg.repeat)
    stats = measure(cases, cfg.rounds)
    # the QP's total wrench (A f, A from Pinocchio's placements) against ours, at every q
    wrench_diff = dict.fromkeys(qps, 0.0)
    force_diff = requested_diff = 0.0
    ours_in_cone, statuses = True, set()
    for q in configs[:64]:
        sol = body.solve(q, SOLO_WRENCH)
        requested_diff = max(requested_diff, float(np.abs(sol.wrench - SOLO_WRENCH).max()))
        for name, qp in qps.items():
            forces = qp.solve(q, SOLO_WRENCH)
            statuses.add(qp.status())
            produced = qp.A @ forces.ravel()
            wrench_diff[name] = max(wrench_diff[name], float(np.abs(produced - sol.wrench).max()))
            if name == "qp_plain_init":
                force_diff = max(force_diff, float(np.abs(forces - sol.forces[:, :3]).max()))
            if name == "qp_cone_init":
                ours_in_cone &= bool(np.all(qp.C @ sol.forces[:, :3].ravel() <= 1e-9))
    rows = []
    for label, kind, what in (("2a", "plain", "no cone"), ("2b", "cone", f"pyramids mu {MU}")):
        best = min(("init", "update"), key=lambda m: stats[f"qp_{kind}_{m}"]["median_us"])
        base = stats[f"qp_{kind}_{best}"]
        ratio = ratio_of(stats["solve"], base)
        target, met = ("< 1x", ratio < 1) if kind == "plain" else ("(info)", None)
        figure = f"{label} solo12 solve vs proxsuite QP ({what}, {best})"
        rows.append(row(figure, us(stats["solve"]), us(base), ratio, target, met))
    best = min(("init", "update"), key=lambda m: stats[f"qp_cone_{m}"]["median_us"])
    base = stats[f"qp_cone_{best}"]
    ratio = ratio_of(stats["solve_qp"], base)
    figure = f"2d solo12 method='qp' vs proxsuite QP (pyramids mu {MU}, {best})"
    rows.append(row(figure, us(stats["solve_qp"]), us(base), ratio, "<= 2x", ratio <= 2))
    figure = f"solo12 solve(method='qp'), friction {MU:g} / plain ProxQP cone QP ({best})"
    issue = [row(figure, us(stats["solve_qp"]), us(base), ratio, "<= 0.5x", ratio <= 0.5)]
    ratio = ratio_of(stats["solve_qp"], stats["solve"])
    figure = "2e solo12 method='qp' vs our partitioned solve"
    rows.append(row(figure, us(stats["solve_qp"]), us(stats["solve"]), ratio, "(info)", None))
    hexapod_rows, hexapod_raw = _hexapod_qp(cfg)
    rows += hexapod_rows
    worst = max(wrench_diff.values())
    figure = "2c QP total wrench vs ours, max |diff|"
    rows.append(row(figure, f"{worst:.1e}", "-", None, "<= 1e-6", worst <= 1e-6))
    notes = [
        f"2: proxsuite eps_abs 1e-9, statuses {sorted(statuses)}; max |ours - requested| "
        f"{requested_diff:.1e}; max |QP min-norm force - our force| {force_diff:.2e} N "
        f"(ours: {body.solve(configs[0], SOLO_WRENCH).method}); our forces inside the "
        f"mu {MU} pyramids: {'yes' if ours_in_cone else 'no'}"
    ]
    raw = {
        **stats,
        "wrench_max_abs_diff": wrench_diff,
        "force_max_abs_diff": force_diff,
        "ours_requested_max_abs_diff": requested_diff,
        "ours_in_pyramids": ours_in_cone,
        "qp_statuses": sorted(statuses),
        "hexapod": hexapod_raw,
    }
    return Figure(rows, raw, notes, issue)


def _hexapod_qp(cfg: Settings) -> tuple[list, dict]:
    """2f/2g: the hexapod on all six point feet, method='qp' beside the plain proxsuite QP with
    pyramids of the same size and beside our partitioned solve."""
    robot = va.load_robot("hexapod")
    feet = [f"foot_{i}" for i in range(1, 7)]
    wrench = np.array([1.0, 0.5, pin.computeTotalMass(robot.model) * 9.81, 0.05, -0.1, 0.02])
    body = va.ParallelVirtualActuator(robot, "body", feet, reference="body", contact="point")
    body_qp = va.ParallelVirtualActuator(
        robot, "body", feet, reference="body", contact="point", friction=MU
    )
    configs = perturbed(robot.model, robot.neutral(), _fresh(cfg.repeat), 0.02, seed=6)
    plain = FootForceQP(robot.model, "body", feet, MU, "update")
    cases = {
        "hexapod_solve": (cycling(lambda q: body.solve(q, wrench), [(q,) for q in configs]),
                          cfg.repeat),
        "hexapod_solve_qp": (
            cycling(lambda q: body_qp.solve(q, wrench, method="qp"), [(q,) for q in configs]),
            cfg.repeat,
        ),
        "hexapod_qp_cone_update": (cycling(plain.solve, [(q, wrench) for q in configs]),
                                   cfg.repeat),
    }  # fmt: skip
    stats = measure(cases, cfg.rounds)
    diff = 0.0
    for q in configs[:64]:
        ours = body_qp.solve(q, wrench, method="qp")
        forces = plain.solve(q, wrench)
        diff = max(diff, float(np.abs(plain.A @ forces.ravel() - ours.wrench).max()))
    ours, base = stats["hexapod_solve_qp"], stats["hexapod_qp_cone_update"]
    ratio = ratio_of(ours, base)
    rows = [
        row(f"2f hexapod method='qp' vs proxsuite QP (pyramids mu {MU}, update)", us(ours),
            us(base), ratio, "<= 2x", ratio <= 2),
        row("2g hexapod method='qp' vs our partitioned solve", us(ours),
            us(stats["hexapod_solve"]), ratio_of(ours, stats["hexapod_solve"]), "(info)", None),
    ]  # fmt: skip
    return rows, {**stats, "wrench_max_abs_diff": diff, "configurations": len(configs)}


# -- figures 3 and 4: millipede -----------------------------------------------------------------


def _millipede(legs: int):
    robot = va.millipede(legs=legs)
    feet = [f"foot_{i}" for i in range(1, legs + 1)]
    body = va.ParallelVirtualActuator(robot, "body", feet, reference="body")
    wrench = np.array([2.0, 0.0, pin.computeTotalMass(robot.model) * 9.81, 0.1, 0.3, 0.2])
    return robot, body, wrench


def figure_millipede(cfg: Settings) -> Figure:
    """3. millipede (100 legs) solve vs one dense 600x600 linear solve."""
    robot, body, wrench = _millipede(100)
    q0, count = robot.neutral(), _fresh(2 * cfg.repeat_slow)  # two passes below
    configs = [(q,) for q in perturbed(robot.model, q0, count, 0.02, seed=100)]
    matrix, rhs, cond = dense_system(600)
    solve = cycling(lambda q: body.solve(q, wrench), configs)
    # two passes: numpy's BLAS threads as configured, then one thread (on a busy 2-core machine
    # a multithreaded 600x600 solve can be 20x slower); the faster dense solve is the baseline
    passes, default_threads = {}, None
    for threads in ("default", "1"):
        with blas_threads(1) if threads == "1" else nullcontext() as previous:
            cases = {
                "solve": (solve, cfg.repeat_slow),
                "dense_600": (lambda: np.linalg.solve(matrix, rhs), cfg.repeat_slow),
            }
            passes[threads] = measure(cases, cfg.rounds, warmup=3)
        default_threads = previous if threads == "1" else default_threads
    best = min(passes, key=lambda k: passes[k]["dense_600"]["median_us"])
    stats = passes[best]
    ratio = ratio_of(stats["solve"], stats["dense_600"])
    figure = f"3  millipede-100 solve vs dense 600x600 solve ({best} BLAS thr.)"
    ours, base = us(stats["solve"]), us(stats["dense_600"])
    line = row(figure, ours, base, ratio, "<= 0.01x (100x faster)", ratio <= 0.01)
    method = body.solve(configs[0][0], wrench).method
    note = "3: dense 600x600 by BLAS threads: " + ", ".join(
        f"{k}: {p['dense_600']['median_us']:.0f} us (ours {p['solve']['median_us']:.0f} us)"
        for k, p in passes.items()
    )
    note += f"; default = {default_threads} threads; condition number {cond:.1f}"
    raw = {
        **stats,
        "blas_threads": best,
        "default_blas_threads": default_threads,
        "passes": passes,
        "dense_condition": cond,
    }
    return Figure([line], {**raw, "method": method}, [note])


def figure_scaling(cfg: Settings) -> Figure:
    """4. millipede declaration, solve and peak memory at 100, 400 and 1000 legs, in children."""
    limit = 4 * GIB
    children = {"floor": run_child(["--child", "floor"], cfg.child_timeout, limit)}
    for legs, extra in ((100, []), (400, []), (1000, ["--declare-only"])):
        arguments = ["--child", "millipede", "--legs", str(legs), "--repeat", str(cfg.child_repeat)]
        children[legs] = run_child(arguments + extra, cfg.child_timeout, limit)
    floor, c100, c400, c1000 = (children[k] for k in ("floor", 100, 400, 1000))

    def rss(child: dict) -> str:
        return f"{child['peak_rss_bytes'] / MIB:.0f} MiB" if child["ok"] else failed(child)

    def failed(child: dict) -> str:
        return f"failed: {child['error'].split(' (')[0]}"[:60]

    def declared(child: dict) -> str:
        return f"{child['declare_s']:.2f} s" if child["ok"] else failed(child)

    ok = c400["ok"] and floor["ok"]
    ratio = c400["peak_rss_bytes"] / floor["peak_rss_bytes"] if ok else None
    met = c400["ok"] and c400["peak_rss_bytes"] < GIB
    figure = "4a peak RSS, 400 legs vs import-only"
    rows = [row(figure, rss(c400), rss(floor), ratio, "< 1 GiB", met)]
    ok = c100["ok"] and c400["ok"]
    ratio = ratio_of(c400["solve"], c100["solve"]) if ok else None
    ours = us(c400["solve"]) if c400["ok"] else failed(c400)
    base = us(c100["solve"]) if c100["ok"] else failed(c100)
    rows.append(row("4b t(400) / t(100) solve", ours, base, ratio, "<= 4.4", ok and ratio <= 4.4))
    ratio = c1000["declare_s"] / c100["declare_s"] if c1000["ok"] and c100["ok"] else None
    figure = "4c 1000 legs declare vs 100 legs"
    rows.append(row(figure, declared(c1000), declared(c100), ratio, "declares", c1000["ok"]))
    notes = [f"4: children (address space limited to 4 GiB, timeout {cfg.child_timeout:.0f} s):"]
    for key, child in children.items():
        if child["ok"]:
            solve = f", solve {us(child['solve'])}" if "solve" in child else ""
            declare = f", declare {child['declare_s']:.2f} s" if "declare_s" in child else ""
            notes.append(f"   {key!s:>5}: peak RSS {rss(child)}{declare}{solve}")
        else:
            notes.append(f"   {key!s:>5}: FAILED after {child['wall_s']:.1f} s: {child['error']}")
    return Figure(rows, {str(k): v for k, v in children.items()}, notes)


def child_main(args: argparse.Namespace) -> None:
    """Child process of figure 4: print one JSON line."""
    out: dict[str, Any] = {}
    if args.child == "millipede":
        out["legs"] = args.legs
        start = time.perf_counter()
        robot, body, wrench = _millipede(args.legs)
        out["declare_s"] = time.perf_counter() - start
        if not args.declare_only:
            q0, count = robot.neutral(), _fresh(args.repeat)
            configs = [(q,) for q in perturbed(robot.model, q0, count, 0.02, seed=7)]
            solve = cycling(lambda q: body.solve(q, wrench), configs)
            out["solve"] = measure({"solve": (solve, args.repeat)}, rounds=1, warmup=2)["solve"]
    out["peak_rss_bytes"] = peak_rss_bytes()
    print(json.dumps(out))


# -- figure 5: UR5 ------------------------------------------------------------------------------


def figure_ur5(cfg: Settings) -> Figure:
    """5. UR5 Cartesian spring-damper: controller vs raw Pinocchio vs virtualmodelcontrol."""
    robot = va.load_robot("ur5_robot")
    act = va.VirtualActuator(robot, "tool0", "world", "world", ("x", "y", "z"))
    ctrl = va.Controller(robot)
    spring = va.SpringDamper(("x", "y", "z"), stiffness=UR5_K, damping=UR5_D, setpoint=UR5_SETPOINT)
    ctrl.add("ee", act, [spring])
    rng = np.random.default_rng(5)
    count = _fresh(cfg.repeat)
    states = [(UR5_Q + rng.uniform(-0.3, 0.3, 6), rng.uniform(-0.5, 0.5, 6)) for _ in range(count)]
    raw = RawCartesianSpringDamper(robot.model, "tool0", UR5_K, UR5_D, UR5_SETPOINT)
    notes: list[str] = []
    try:
        vmc = VMCCartesianSpringDamper(UR5_K, UR5_D, UR5_SETPOINT)
    except Exception as error:  # not installed, or does not import: skip that baseline only
        vmc = None
        notes.append(f"5: virtualmodelcontrol baseline skipped: {type(error).__name__}: {error}")
        print(notes[-1], flush=True)
    cases = {
        "compute": (cycling(lambda q, v: ctrl.compute(q, v, 0.0), states), cfg.repeat),
        "raw_pinocchio": (cycling(raw, states), cfg.repeat),
    }
    if vmc is not None:
        cases["virtualmodelcontrol"] = (cycling(vmc, states), cfg.repeat)
    stats = measure(cases, cfg.rounds)
    raw_diff = vmc_diff = position_diff = 0.0
    saturated, data, tool = False, pin.Data(robot.model), robot.model.getFrameId("tool0")
    for q, v in states[:64]:
        out = ctrl.compute(q, v, 0.0)
        saturated |= bool(np.any(out.saturated))
        raw_diff = max(raw_diff, float(np.abs(out.tau - raw(q, v)).max()))
        if vmc is not None:
            vmc_diff = max(vmc_diff, float(np.abs(out.tau - vmc(q, v)).max()))
            pin.framesForwardKinematics(robot.model, data, q)
            gap = np.abs(vmc.tool_position(q) - data.oMf[tool].translation).max()
            position_diff = max(position_diff, float(gap))
    ours = us(stats["compute"])
    ratio = ratio_of(stats["compute"], stats["raw_pinocchio"])
    figure = "5a UR5 ctrl.compute vs raw Pinocchio"
    rows = [row(figure, ours, us(stats["raw_pinocchio"]), ratio, "<= 3x", ratio <= 3)]
    figure = "5b UR5 ctrl.compute vs virtualmodelcontrol"
    if vmc is not None:
        ratio = ratio_of(stats["compute"], stats["virtualmodelcontrol"])
        base = us(stats["virtualmodelcontrol"])
        rows.append(row(figure, ours, base, ratio, "< 1x", ratio < 1))
        figure = "5c torques, max |vmc - ours| [N m]"
        rows.append(row(figure, f"{vmc_diff:.1e}", "-", None, "<= 1e-9", vmc_diff <= 1e-9))
        notes.append(
            "5: virtualmodelcontrol's UR5 is its DH table (robots.ur5.arm), base turned by pi "
            f"about z from the URDF's; flange vs tool0 max |position diff| {position_diff:.1e} m "
            "(the URDF writes pi/2 as 1.57079632679); "
            f"CasADi compile {vmc.compile_s:.2f} s (not timed)"
        )
    else:
        rows.append(row(figure, ours, "skipped (not importable)", None, "< 1x", None))
    notes.append(
        f"5: max |raw Pinocchio - ours| {raw_diff:.1e} N m; "
        f"efforts saturated: {'yes' if saturated else 'no'}"
    )
    raw_json = {**stats, "raw_max_abs_diff": raw_diff, "saturated": saturated}
    if vmc is not None:
        raw_json |= {"vmc_max_abs_diff": vmc_diff, "vmc_position_max_abs_diff": position_diff}
    return Figure(rows, raw_json, notes)


# -- figure 6: walks ----------------------------------------------------------------------------


#: The legged walk's trots in figure 6 (robot, speed [m/s]); their target is >= 5x real time.
LEGGED_TROTS = (("solo12", 0.5), ("go2", 0.5))


def _walk_cases() -> list[tuple[str, str, dict, float]]:
    """Figure 6's runs: ``(title, walk, options, target x real time)``, every registered walk
    with its defaults, the legged walk as the trots of :data:`LEGGED_TROTS`."""
    from virtual_actuators.gaits.registry import WALKS

    cases = []
    for name in WALKS:
        if name != "legged":
            cases.append((name, name, {}, 10.0))
            continue
        for robot, speed in LEGGED_TROTS:
            options = {"robot": robot, "gait": "trot", "speed": speed}
            cases.append((f"legged {robot} trot {speed:g} m/s", name, options, 5.0))
    return cases


def figure_walks(cfg: Settings) -> Figure:
    """6. every registered walk: real-time factor and per-tick breakdown (6a, 6b, ...)."""
    from virtual_actuators.gaits import Gait

    rows, raw, notes, issue = [], {}, [], []
    for index, (title, name, options, target) in enumerate(_walk_cases()):
        label = f"6{chr(ord('a') + index)}"
        factors = timed_walks(name, cfg.walk_seconds, runs=3, **options)
        # every gait's compute
        walk = raw[title] = instrumented_walk(name, Gait, cfg.walk_seconds, **options)
        rtf, ceiling = float(np.median(factors)), walk["physics_only_factor"]
        walk["plain_realtime_factors"] = factors
        figure = f"{label} {title} x real time vs MuJoCo alone"
        ours, base = f"{rtf:.2f}x", f"{ceiling:.1f}x"
        rows.append(row(figure, ours, base, rtf / ceiling, f">= {target:g}x", rtf >= target))
        rows.append(_smoothness_row(f"{label}' {title}", walk["smoothness"]))
        if name == "turkey-walk":
            figure = "turkey walk real-time factor / MuJoCo alone stepping the same robot"
            issue.append(row(figure, ours, base, rtf / ceiling, ">= 0.5", rtf / ceiling >= 0.5))
        elif name == "hexapod-walk":
            figure = "hexapod walk x real time (beside MuJoCo alone)"
            issue.append(row(figure, ours, base, rtf / ceiling, ">= 10x", rtf >= 10))
        notes.append(
            f"6: {title}, x real time of 3 plain runs of {cfg.walk_seconds:.2f} simulated s: "
            f"{', '.join(f'{f:.2f}' for f in factors)} (median in the table; the ratio column "
            "is ours / MuJoCo stepping the same robot alone, from the breakdown's run)"
        )
        notes.append(
            f"   breakdown from one run with every part timed (the timers cost time too): "
            f"{walk['ticks']} ticks, {walk['realtime_factor']:.2f}x real time, "
            f"fell: {walk['fell']}"
        )
        notes.append(f"   {'per tick [us]':<22}{'mean':>10}{'median':>10}{'p90':>10}")
        for stats in walk["per_tick"].values():
            notes.append(
                f"   {stats['label']:<22}{stats['mean_us']:>10.1f}"
                f"{stats['median_us']:>10.1f}{stats['p90_us']:>10.1f}"
            )
        contacts = walk["per_tick"]["rest"]["contact_queries_mean_us"]
        notes.append(f"   {'  of rest: contacts':<22}{contacts:>10.1f}")
        step = walk["per_tick"]["simulator.step"]["mean_us"]
        share = step / walk["per_tick"]["total"]["mean_us"]
        notes.append(f"   {'  MuJoCo share':<22}{100 * share:>9.0f}%  (step / total, means)")
    rows.append(_user_machine_row(raw, notes, issue))
    return Figure(rows, raw, notes, issue)


def _user_machine_row(raw: dict, notes: list, issue: list) -> dict:
    """6z: a user's own two-state machine on solo12 (public classes only) under ``va.run``."""
    from _user_machine import user_machine_loop

    run = raw["user machine"] = user_machine_loop()
    ours, base = f"{run['loop_us']:.1f} us/tick", f"{run['mujoco_alone_us']:.1f} us/tick"
    figure = "6z a user's StateMachine on solo12 (va.run) vs MuJoCo alone"
    result = row(figure, ours, base, run["ratio"], ">= 0.5", run["ratio"] >= 0.5)
    issue.append(result)
    notes.append(
        f"6z: the user's machine (benchmarks/_user_machine.py), {run['ticks']} ticks x 3, "
        f"compiled: {run['compiled']}, Python pieces: {run['python_pieces'] or 'none'}; "
        f"loop {', '.join(f'{x:.1f}' for x in run['loops_us'])} us/tick, MuJoCo alone "
        f"{', '.join(f'{x:.1f}' for x in run['alone_us'])} us/tick (alternated)"
    )
    return result


#: Figure 6's smoothness targets (issue 35): oscillation [-] of the limits, alternation [-].
OSCILLATION_MAX, ALTERNATION_MAX = 0.005, 0.01


def _smoothness_row(title: str, smoothness: dict) -> dict:
    """6a', 6b', ...: effort oscillation (worst joint) / change per tick, base rate alternation."""
    oscillation, change = smoothness["oscillation"], smoothness["change_rms"]
    alternation = smoothness["rate_alternation"]
    if oscillation is None:
        return row(f"{title} efforts at the tick rate", "not measured (under 1 s)", "-")
    ours = (
        f"osc {100 * oscillation:.3f} % ({smoothness['oscillation_joint']}), "
        f"change {100 * change:.2f} %/tick"
    )
    base = "-" if alternation is None else f"base rate alternating {100 * alternation:.1f} %"
    met = oscillation < OSCILLATION_MAX and (alternation or 0.0) < ALTERNATION_MAX
    return row(f"{title} efforts at the tick rate", ours, base, None, "osc < 0.5 %, alt < 1 %", met)


# -- figure 7: worst case -----------------------------------------------------------------------


def figure_worst_case(cfg: Settings) -> Figure:
    """7. worst case: p50, p99, p99.9 and max tick of each walk and of two va.run loops."""
    from _latency import RUN_LOOPS, slow_summary, tail_text, walk_ticks

    runs = {}
    for title, name, options, _ in _walk_cases():
        runs[f"{title}, {cfg.worst_seconds:g} s"] = walk_ticks(name, cfg.worst_seconds, **options)
    for title, loop in RUN_LOOPS.items():
        runs[f"{title}, {cfg.loop_ticks} ticks"] = loop(cfg.loop_ticks)
    rows, notes = [], [
        "7: ticks p50 / p99 / p99.9 / max; controller = its compute between reading the state "
        "and writing the efforts (wall clock, and the thread's CPU time: without the time it "
        "was preempted), loop = the whole iteration with MuJoCo's step (see _latency.py); "
        "'CPU, replayed' = the CPU time with the machine's ticks >= 1 ms (fast in a replay: the "
        "same run again up to them, and no collection or ProxQP fallback in them) replaced by "
        "their replay: what a quiet machine gives; baseline = MuJoCo's step "
        "in the same ticks; ratio = max / its max"
    ]
    parts = (("controller", "controller"), ("controller_cpu", "controller, thread CPU time"),
             ("controller_cpu_replayed", "controller, CPU, replayed"), ("loop", "loop"))
    for index, (title, run) in enumerate(runs.items()):
        label, step = f"7{chr(ord('a') + index)}", run["mujoco_step"]
        base = f"MuJoCo {tail_text(step)}"
        for part, what in parts:
            stats = run[part]
            met = stats["max"] < 1000.0
            rows.append(row(f"{label} {title}: {what}", tail_text(stats), base,
                            stats["max"] / step["max"], "max < 1 ms", met))  # fmt: skip
        worst = run["controller_cpu"]
        extra = f", fell: {run['fell']}" if "fell" in run else (
            f", failed ticks {run['failed_ticks']}, overruns of 1 ms {run['overruns_of_1ms']}")
        notes.append(
            f"   {title}: {run['ticks']} ticks{extra}; the controller's CPU max at tick "
            f"{worst['max_at']} (after the first tick {worst['max_after_first']:.0f} us); "
            f"garbage collections (gen 0/1/2) {'/'.join(map(str, run['gc']['collections']))}, "
            f"the longest {run['gc']['longest_pause_us']:.0f} us; inside the controller "
            f"{run['gc']['inside_ticks']}, the longest {run['gc']['longest_inside_us']:.0f} us"
        )  # fmt: skip
        notes.append(f"      {slow_summary(run)}")
    return Figure(rows, runs, notes, list(rows))


# -- figure 8: cold start -----------------------------------------------------------------------

#: Figure 8's steps in a new process: key, what, goal [s].
COLD_STEPS = (
    ("import", "import virtual_actuators", 1.0),
    ("declare", "solo12 body actuator declaration (figure 1's)", 1.0),
    ("first_solve", "first solve", 1.0),
    ("first_qp", f"first solve(method='qp'), friction {MU:g}", 1.0),
    ("second_qp", "second solve(method='qp') (its warm-started path)", 1.0),
)


def _seconds(run: dict | None, key: str, quick: bool) -> str:
    if run is None:
        return "not measured (--quick)" if quick else "-"
    if not run["ok"]:
        return f"failed: {run['error']}"[:60]
    return f"{run[key]:.3f} s"


def figure_cold_start(cfg: Settings) -> Figure:
    """8. cold start: a new process with an empty bytecode cache; the README demo's first tick."""
    import tempfile

    from _cold_start import demo_first_tick, first_calls

    spec = {"feet": SOLO_FEET, "wrench": SOLO_WRENCH.tolist(), "mu": MU}
    timeout = max(cfg.child_timeout, 300.0)
    cold = cold_demo = None
    with tempfile.TemporaryDirectory(prefix="va-pyc-") as calls, \
            tempfile.TemporaryDirectory(prefix="va-pyc-") as demo:  # fmt: skip
        if cfg.cold:  # empty caches, then the same caches again (warm)
            cold, cold_demo = first_calls(calls, spec, timeout), demo_first_tick(demo, timeout)
        else:  # --quick: the bytecode cache where it is (warm after any earlier run)
            calls = demo = None
        warm, warm_demo = first_calls(calls, spec, timeout), demo_first_tick(demo, timeout)
    rows = []
    steps = [(cold, warm, *step) for step in COLD_STEPS]
    steps.append((cold_demo, warm_demo, "first_progress_s",
                  "README demo's first tick after launch (upper bound)", 2.0))  # fmt: skip
    for index, (ours, base, key, what, goal) in enumerate(steps):
        figure = f"8{chr(ord('a') + index)} cold start: {what}"
        ok = ours is not None and ours["ok"] and base["ok"]
        ratio = ours[key] / base[key] if ok else None
        met = ours[key] < goal if ok else (None if ours is None else False)
        ours_text, base_text = _seconds(ours, key, not cfg.cold), _seconds(base, key, False)
        target = f"< {goal:g} s"
        rows.append(row(figure, ours_text, f"warm cache: {base_text}", ratio, target, met))
    notes = [
        "8: new processes (python + PYTHONPATH of this tree), Python's bytecode cache "
        "(PYTHONPYCACHEPREFIX) a new empty directory (cold), then the same directory again (warm)"
        + ("" if cfg.cold else "; --quick: no cold runs, warm = the bytecode cache as it is")
    ]
    for name, run in (("cold", cold), ("warm", warm), ("cold demo", cold_demo),
                      ("warm demo", warm_demo)):  # fmt: skip
        if run is not None and run["ok"]:
            times = ", ".join(f"{k} {v:.3f}" for k, v in run.items() if k not in ("ok",)
                              and isinstance(v, float))  # fmt: skip
            notes.append(f"   {name} [s]: {times}")
        elif run is not None:
            notes.append(f"   {name}: FAILED: {run['error']}")
    raw = {"cold": cold, "warm": warm, "cold_demo": cold_demo, "warm_demo": warm_demo}
    return Figure(rows, raw, notes, list(rows))


# -- figure 9: the state estimator beside the controller's tick ---------------------------------


def _go2_trot_record(ticks: int) -> tuple[list, list]:
    """go2 trotting at 0.8 m/s on the truth: every tick's (q, v, t, contacts) and sensor reading."""
    from virtual_actuators.simulation import SensorModel, Simulator

    robot = va.load_robot("go2")
    walker = va.LeggedWalker(robot, pattern="trot")
    walker.set_command((0.8, 0.0), yaw_rate=0.0)
    simulator = Simulator(robot, sensors=SensorModel(seed=9))
    simulator.reset(simulator.on_ground(walker.initial_configuration()))
    states, readings = [], []
    for _ in range(ticks):
        contacts = simulator.contact_switches(walker.feet)
        state = (simulator.q, simulator.v, simulator.time, contacts)
        tau = walker.compute(*state).tau
        simulator.step(tau, ignore_unactuated=True)
        states.append(state)
        readings.append((simulator.read_sensors(), tau))
    return states, readings


def _in_order(fn: Callable[..., object], inputs: list) -> Callable[[], object]:
    """A no-argument call of ``fn`` on the next input, in order (time must advance)."""
    feed = iter(inputs)
    return lambda: fn(*next(feed))


def figure_estimator(cfg: Settings) -> Figure:
    """9. The legged estimator's update vs the controller's tick, same run (go2 trot)."""
    warmup = 20
    ticks = cfg.repeat + warmup + 8
    states, readings = _go2_trot_record(ticks)
    robot = va.load_robot("go2")
    walker = va.LeggedWalker(robot, pattern="trot")  # replays the recorded walk's states
    walker.set_command((0.8, 0.0), yaw_rate=0.0)
    estimator = va.estimation.LeggedEstimator(robot, feet=walker.feet)
    estimator.reset(states[0][0], states[0][1])
    cases = {
        "update": (_in_order(estimator.update, readings), cfg.repeat),
        "tick": (_in_order(walker.compute, states), cfg.repeat),
    }
    stats = measure(cases, cfg.rounds, warmup=warmup)
    ratio = ratio_of(stats["update"], stats["tick"])
    ours, base = us(stats["update"]), us(stats["tick"])
    figure = "9  go2 estimator update vs the walker's tick"
    rows = [row(figure, ours, base, ratio, "< 0.2x", ratio < 0.2)]
    return Figure(rows, stats, [], [])


# -- main ---------------------------------------------------------------------------------------

FIGURES = {
    "1": figure_solo12_floor,
    "2": figure_solo12_qp,
    "3": figure_millipede,
    "4": figure_scaling,
    "5": figure_ur5,
    "6": figure_walks,
    "7": figure_worst_case,
    "8": figure_cold_start,
    "9": figure_estimator,
}


def main(argv: list[str] | None = None) -> None:
    """Run every figure, print the table, optionally write JSON."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--json", help="write every figure and raw median/p90 to this file")
    parser.add_argument("--quick", action="store_true", help="fewer repetitions (smoke run)")
    parser.add_argument("--walk-seconds", type=float, default=None, help="simulated s (3)")
    parser.add_argument(
        "--worst-seconds", type=float, default=None, help="simulated s of figure 7's walks (20)"
    )
    parser.add_argument("--only", action="append", choices=list(FIGURES), help="figure(s)")
    parser.add_argument("--child", choices=("millipede", "floor"), help=argparse.SUPPRESS)
    parser.add_argument("--legs", type=int, default=100, help=argparse.SUPPRESS)
    parser.add_argument("--repeat", type=int, default=100, help=argparse.SUPPRESS)
    parser.add_argument("--declare-only", action="store_true", help=argparse.SUPPRESS)
    args = parser.parse_args(argv)
    if args.child:
        child_main(args)
        return
    if args.quick:
        cfg = Settings(300, 20, 10, args.walk_seconds or 0.5, 60.0, rounds=5,
                       worst_seconds=args.worst_seconds or 0.5, loop_ticks=500, cold=False)
    else:
        cfg = Settings(3000, 200, 100, args.walk_seconds or 3.0, 300.0,
                       worst_seconds=args.worst_seconds or 20.0)  # fmt: skip
    from tqdm import tqdm

    start = time.perf_counter()
    machine = machine_info()
    rows, notes, raw, issue = [], [], {}, []
    chosen = [key for key in FIGURES if not args.only or key in args.only]
    bar = tqdm(chosen, file=sys.stderr, disable=None, leave=False, desc="figures")
    for key in bar:
        bar.set_postfix_str(FIGURES[key].__doc__.split(".")[1].strip()[:40])
        try:
            figure = FIGURES[key](cfg)
        except Exception as error:  # a figure that breaks is reported, the others still run
            traceback.print_exc(file=sys.stderr)
            message = f"{type(error).__name__}: {error}"
            failed = row(f"{key}  FAILED", message[:70], "-", met=False)
            figure = Figure([failed], {"error": message})
        rows += figure.rows
        notes += figure.notes
        issue += figure.issue
        raw[key] = figure.raw
    bar.close()
    elapsed = time.perf_counter() - start
    print_table(machine, rows, notes, issue)
    print(f"\ntotal wall time {elapsed:.1f} s{' (--quick)' if args.quick else ''}")
    if args.json:
        path = Path(args.json)
        path.parent.mkdir(parents=True, exist_ok=True)
        payload = {
            "machine": machine,
            "settings": cfg.__dict__,
            "quick": args.quick,
            "wall_time_s": elapsed,
            "rows": rows,
            "issue27": issue,
            "figures": raw,
            "notes": notes,
        }
        path.write_text(json.dumps(payload, indent=2, default=float))
        print(f"wrote {path}")


if __name__ == "__main__":
    main()
