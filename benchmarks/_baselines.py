"""Helpers of ``bench_realtime.py``: timing, machine facts, and the baselines it compares with.

Every baseline here is what a user would write without the library, built on the same Pinocchio
model (or, for ``virtualmodelcontrol``, on that package's own UR5), so that ``bench_realtime.py``
can time it in the same run as the library call it stands beside.
"""

from __future__ import annotations

import ctypes
import itertools
import json
import os
import platform
import resource
import signal
import subprocess
import sys
import time
from collections.abc import Callable, Iterable, Iterator, Sequence
from contextlib import contextmanager
from dataclasses import dataclass, field
from importlib import metadata
from typing import Any

import numpy as np
import pinocchio as pin

# -- timing -------------------------------------------------------------------------------------


def summarize(samples_us: np.ndarray) -> dict[str, float]:
    """Median, p90, min and count of timing samples in microseconds."""
    samples_us = np.asarray(samples_us, dtype=float)
    if samples_us.size == 0:
        return {"median_us": float("nan"), "p90_us": float("nan"), "min_us": float("nan"), "n": 0}
    return {
        "median_us": float(np.median(samples_us)),
        "p90_us": float(np.percentile(samples_us, 90)),
        "min_us": float(samples_us.min()),
        "n": int(samples_us.size),
    }


def measure(
    cases: dict[str, tuple[Callable[[], object], int]],
    rounds: int = 10,
    warmup: int = 20,
) -> dict[str, dict[str, float]]:
    """Time each case ``repeat`` times, interleaved in ``rounds`` blocks so that all cases see the
    same machine noise; returns :func:`summarize` per case."""
    for fn, _ in cases.values():
        for _ in range(warmup):
            fn()
    samples: dict[str, list[np.ndarray]] = {name: [] for name in cases}
    clock = time.perf_counter_ns
    for _ in range(rounds):
        for name, (fn, repeat) in cases.items():
            block = np.empty(max(1, repeat // rounds))
            for i in range(block.size):
                start = clock()
                fn()
                block[i] = clock() - start
            samples[name].append(block)
    return {name: summarize(np.concatenate(blocks) / 1e3) for name, blocks in samples.items()}


def cycling(fn: Callable[..., object], inputs: Sequence[Any]) -> Callable[[], object]:
    """A no-argument call of ``fn`` on the next input, round robin (defeats caching on q)."""
    feed = itertools.cycle(inputs)
    return lambda: fn(*next(feed))


def perturbed(model: pin.Model, q0: np.ndarray, count: int, scale: float, seed: int) -> list:
    """``count`` configurations near ``q0``: ``integrate(q0, u)`` with ``u`` uniform in
    ``[-scale, scale]``."""
    rng = np.random.default_rng(seed)
    return [
        pin.normalize(model, pin.integrate(model, q0, rng.uniform(-scale, scale, model.nv)))
        for _ in range(count)
    ]


# -- machine ------------------------------------------------------------------------------------


def _version(package: str) -> str | None:
    try:
        return metadata.version(package)
    except metadata.PackageNotFoundError:
        return None


def machine_info() -> dict[str, Any]:
    """CPU model, cores and the versions of everything timed."""
    cpu = platform.processor() or platform.machine()
    try:
        with open("/proc/cpuinfo") as stream:
            for line in stream:
                if line.startswith("model name"):
                    cpu = line.split(":", 1)[1].strip()
                    break
    except OSError:
        pass
    try:
        blas = np.show_config(mode="dicts")["Build Dependencies"]["blas"]
        blas = f"{blas['name']} {blas['version']}"
    except Exception:  # older numpy, or an unusual build
        blas = None
    return {
        "cpu": cpu,
        "cores": os.cpu_count(),
        "python": platform.python_version(),
        "numpy": np.__version__,
        "blas": blas,
        "pinocchio": pin.__version__,
        "mujoco": _version("mujoco"),
        "proxsuite": _version("proxsuite"),
        "virtualmodelcontrol": _version("virtualmodelcontrol"),
        "casadi": _version("casadi"),
        "platform": platform.platform(),
        "date": time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime()),
        "load_average": [round(x, 2) for x in os.getloadavg()],
    }


# -- figure 1: the Pinocchio floor --------------------------------------------------------------


class PinocchioFloor:
    """Joint Jacobians, frame placements and the LOCAL_WORLD_ALIGNED Jacobians of some frames:
    the least kinematics any distribution of a body wrench over feet has to compute."""

    def __init__(self, model: pin.Model, frames: Iterable[str]) -> None:
        self.model, self.data = model, pin.Data(model)
        self.frames = [model.getFrameId(name) for name in frames]

    def __call__(self, q: np.ndarray) -> list[np.ndarray]:
        model, data = self.model, self.data
        pin.computeJointJacobians(model, data, q)
        pin.updateFramePlacements(model, data)
        return [pin.getFrameJacobian(model, data, f, pin.LOCAL_WORLD_ALIGNED) for f in self.frames]


# -- figure 2: the foot-force QP ----------------------------------------------------------------


def _skew(r: np.ndarray) -> np.ndarray:
    return np.array([[0.0, -r[2], r[1]], [r[2], 0.0, -r[0]], [-r[1], r[0], 0.0]])


class FootForceQP:
    """Body wrench over point feet as a proxsuite dense QP: ``min ||f||^2`` over three force
    components per foot (base frame), subject to ``sum f = F`` and ``sum r_i x f_i = M``, with
    ``r_i`` the foot's position relative to the base origin in the base frame (Pinocchio's frame
    placements), and optionally a 4-sided friction pyramid per foot about the world's z axis.

    ``mode="init"`` calls ``qp.init`` every tick; ``"update"`` initialises once and then calls
    ``qp.update`` (proxsuite's pattern for a sequence of problems of one size).
    """

    def __init__(
        self,
        model: pin.Model,
        base: str,
        feet: Sequence[str],
        friction: float | None = None,
        mode: str = "update",
        eps_abs: float = 1e-9,
    ) -> None:
        from proxsuite import proxqp

        self.model, self.data = model, pin.Data(model)
        self.base = model.getFrameId(base)
        self.feet = [model.getFrameId(name) for name in feet]
        p = len(self.feet)
        n = 3 * p
        self.H, self.g = np.eye(n), np.zeros(n)
        self.A = np.zeros((6, n))
        self.A[:3] = np.tile(np.eye(3), (1, p))
        self.mode, self.friction = mode, friction
        if friction is None:
            self.C = self.lower = self.upper = None
            n_in = 0
        else:
            n_in = 4 * p
            self.C = np.zeros((n_in, n))
            self.lower, self.upper = np.full(n_in, -np.inf), np.zeros(n_in)
            mu = float(friction)
            self.pyramid = np.array(
                [[1.0, 0.0, -mu], [-1.0, 0.0, -mu], [0.0, 1.0, -mu], [0.0, -1.0, -mu]]
            )
        self.qp = proxqp.dense.QP(n, 6, n_in)
        self.qp.settings.eps_abs = eps_abs
        self.qp.settings.verbose = False
        self._initialised = False

    def build(self, q: np.ndarray) -> None:
        """Kinematics and the constraint matrices at ``q``."""
        model, data = self.model, self.data
        pin.forwardKinematics(model, data, q)
        pin.updateFramePlacements(model, data)
        base = data.oMf[self.base]
        rotation, origin = base.rotation, base.translation
        arms = (np.array([data.oMf[f].translation for f in self.feet]) - origin) @ rotation
        for k, arm in enumerate(arms):
            self.A[3:, 3 * k : 3 * k + 3] = _skew(arm)
        if self.C is not None:
            block = self.pyramid @ rotation  # world-frame pyramid rows on base-frame forces
            for k in range(len(self.feet)):
                self.C[4 * k : 4 * k + 4, 3 * k : 3 * k + 3] = block

    def solve(self, q: np.ndarray, wrench: np.ndarray) -> np.ndarray:
        """Foot forces ``(p, 3)`` in the base frame for ``wrench`` = (F, M) in the base frame."""
        self.build(q)
        args = (self.H, self.g, self.A, wrench, self.C, self.lower, self.upper)
        if self.mode == "init" or not self._initialised:
            self.qp.init(*args)
            self._initialised = True
        else:
            self.qp.update(*args)
        self.qp.solve()
        return self.qp.results.x.reshape(-1, 3)

    def status(self) -> str:
        """The last solve's status."""
        return str(self.qp.results.info.status).rsplit(".", 1)[-1]


# -- figure 3: the dense linear solve -----------------------------------------------------------


def dense_system(n: int, seed: int = 0) -> tuple[np.ndarray, np.ndarray, float]:
    """A random well-conditioned ``n x n`` system (Gaussian / sqrt(n) + 3 I) and its
    condition number."""
    rng = np.random.default_rng(seed)
    matrix = rng.standard_normal((n, n)) / np.sqrt(n) + 3.0 * np.eye(n)
    return matrix, rng.standard_normal(n), float(np.linalg.cond(matrix))


def _openblas() -> list[tuple[Callable[[], int], Callable[[int], None]]]:
    """``(get, set)`` thread-count functions of every OpenBLAS loaded in this process."""
    try:
        with open("/proc/self/maps") as stream:
            paths = {line.split()[-1] for line in stream if "openblas" in line.lower()}
    except OSError:
        return []
    found = []
    for path in sorted(p for p in paths if p.startswith("/")):
        try:
            lib = ctypes.CDLL(path)
        except OSError:
            continue
        for prefix, suffix in itertools.product(("scipy_openblas_", "openblas_"), ("64_", "")):
            get = getattr(lib, f"{prefix}get_num_threads{suffix}", None)
            put = getattr(lib, f"{prefix}set_num_threads{suffix}", None)
            if get is not None and put is not None:
                found.append((get, put))
                break
    return found


@contextmanager
def blas_threads(count: int) -> Iterator[int | None]:
    """Run the block with OpenBLAS limited to ``count`` threads; yields the previous count
    (None when no OpenBLAS is found: then nothing changes)."""
    libraries = _openblas()
    before = [get() for get, _ in libraries]
    for _, put in libraries:
        put(count)
    try:
        yield before[0] if before else None
    finally:
        for (_, put), previous in zip(libraries, before, strict=True):
            put(previous)


# -- figure 5: raw Pinocchio and virtualmodelcontrol on the UR5 ---------------------------------


class RawCartesianSpringDamper:
    """``tau = J^T (K (x0 - x) - D J v)`` on a frame's position, with bare Pinocchio calls."""

    def __init__(self, model: pin.Model, frame: str, stiffness, damping, setpoint) -> None:
        self.model, self.data = model, pin.Data(model)
        self.frame = model.getFrameId(frame)
        self.stiffness, self.damping = np.asarray(stiffness), np.asarray(damping)
        self.setpoint = np.asarray(setpoint, dtype=float)

    def __call__(self, q: np.ndarray, v: np.ndarray, t: float = 0.0) -> np.ndarray:
        model, data = self.model, self.data
        pin.forwardKinematics(model, data, q, v)
        pin.updateFramePlacements(model, data)
        jacobian = pin.computeFrameJacobian(model, data, q, self.frame, pin.LOCAL_WORLD_ALIGNED)[:3]
        position = data.oMf[self.frame].translation
        force = self.stiffness * (self.setpoint - position) - self.damping * (jacobian @ v)
        return jacobian.T @ force


#: virtualmodelcontrol's UR5 (standard DH table) has its base turned by pi about z from the
#: example-robot-data URDF's base_link (same joint angles and signs): x_dh = BASE_TURN @ x_urdf.
BASE_TURN = np.diag([-1.0, -1.0, 1.0])


class VMCCartesianSpringDamper:
    """The same spring-damper in ``virtualmodelcontrol``: a ``LinearSpring`` on the flange point
    minus the set point and a ``LinearDamper`` on the flange point, compiled by CasADi, stepped
    by ``VMCController.step(t, Signals(t, motor_position=q, motor_velocity=v))``.

    Raises:
        ImportError: virtualmodelcontrol (or CasADi) is not installed or does not import.

    """

    def __init__(self, stiffness: float, damping: float, setpoint: np.ndarray) -> None:
        import virtualmodelcontrol as vmc
        from virtualmodelcontrol.robots import ur5

        self.vmc = vmc
        self.setpoint_dh = BASE_TURN @ np.asarray(setpoint, dtype=float)
        arm = ur5.arm()  # Mechanism("ur5", SerialChain.from_dh(DH_D, DH_A, DH_ALPHA, "tool"))
        tip = arm.point("tool")
        law = vmc.Mechanism("cartesian")
        law.add("spring", vmc.LinearSpring(tip - self.setpoint_dh, stiffness))
        law.add("damper", vmc.LinearDamper(tip, damping))
        start = time.perf_counter()
        self.controller = vmc.VMCController(vmc.compile(vmc.VirtualMechanismSystem(arm, law)))
        self.compile_s = time.perf_counter() - start

    def __call__(self, q: np.ndarray, v: np.ndarray, t: float = 0.0) -> np.ndarray:
        meas = self.vmc.Signals(t, motor_position=q, motor_velocity=v)
        return self.controller.step(t, meas)["motor_torque"]

    def tool_position(self, q: np.ndarray) -> np.ndarray:
        """Its flange position at ``q``, in the URDF's base frame [m] (to check the model)."""
        self(q, np.zeros_like(q))
        deflection = self.controller.elements()["cartesian.spring"]["y"]
        return BASE_TURN.T @ (deflection + self.setpoint_dh)


# -- figure 4: children with a memory limit -----------------------------------------------------


def _limit_address_space(limit: int) -> Callable[[], None]:
    def apply() -> None:
        resource.setrlimit(resource.RLIMIT_AS, (limit, limit))

    return apply


def peak_rss_bytes() -> int:
    """This process's peak resident set size (``VmHWM``) [bytes]."""
    try:
        with open("/proc/self/status") as stream:
            for line in stream:
                if line.startswith("VmHWM:"):
                    return int(line.split()[1]) * 1024
    except OSError:
        pass
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024


def run_child(arguments: list[str], timeout: float, memory_limit: int) -> dict[str, Any]:
    """Run ``python <this script> <arguments>`` with an address-space limit; the child prints one
    JSON object on its last stdout line. Never raises: a failure comes back as
    ``{"ok": False, "error": ...}``."""
    script = os.path.join(os.path.dirname(os.path.abspath(__file__)), "bench_realtime.py")
    command = [sys.executable, script, *arguments]
    start = time.perf_counter()
    try:
        done = subprocess.run(
            command,
            capture_output=True,
            text=True,
            timeout=timeout,
            preexec_fn=_limit_address_space(memory_limit),
        )
    except subprocess.TimeoutExpired:
        return {"ok": False, "error": f"timeout after {timeout:g} s", "wall_s": timeout}
    except (OSError, subprocess.SubprocessError) as error:  # could not start it
        return {"ok": False, "error": f"{type(error).__name__}: {error}", "wall_s": 0.0}
    wall = time.perf_counter() - start
    if done.returncode == 0:
        try:
            return {"ok": True, **json.loads(done.stdout.strip().splitlines()[-1]), "wall_s": wall}
        except (IndexError, ValueError) as error:
            return {"ok": False, "error": f"unreadable child output ({error})", "wall_s": wall}
    if done.returncode < 0:
        error = f"killed by {signal.Signals(-done.returncode).name}"
    else:
        lines = [line.strip() for line in done.stderr.splitlines() if line.strip()]
        error = lines[-1] if lines else f"exit code {done.returncode}"
        frames = [line for line in lines if line.startswith("File ")]
        if frames:  # where it failed: the innermost frame of the traceback
            path, _, rest = frames[-1].removeprefix('File "').partition('", ')
            error += f" ({os.path.basename(path)}, {rest})"
    return {"ok": False, "error": error, "returncode": done.returncode, "wall_s": wall}


# -- figure 6: per-tick breakdown of a walk -----------------------------------------------------


class WalkProbe:
    """Wrap public methods of some classes at runtime with ``perf_counter_ns`` accumulators
    (one sample per call); the originals are restored on exit. ``targets`` maps a key to
    ``(class, method name)``."""

    def __init__(self, targets: dict[str, tuple[type, str]], tick: str) -> None:
        self.targets, self.tick = targets, tick
        self.samples: dict[str, list[int]] = {key: [] for key in targets}
        self.tick_ends: list[int] = []
        self._saved: list[tuple[type, str, object, bool]] = []

    def _wrap(self, key: str, function: Callable[..., Any]) -> Callable[..., Any]:
        samples, clock = self.samples[key], time.perf_counter_ns
        ends = self.tick_ends if key == self.tick else None

        def wrapped(*args: Any, **kwargs: Any) -> Any:
            start = clock()
            try:
                return function(*args, **kwargs)
            finally:
                end = clock()
                samples.append(end - start)
                if ends is not None:
                    ends.append(end)

        return wrapped

    def __enter__(self) -> WalkProbe:
        for key, (cls, name) in self.targets.items():
            own = name in cls.__dict__
            self._saved.append((cls, name, cls.__dict__.get(name), own))
            setattr(cls, name, self._wrap(key, getattr(cls, name)))
        return self

    def __exit__(self, *exc: object) -> None:
        for cls, name, original, own in reversed(self._saved):
            if own:
                setattr(cls, name, original)
            else:
                delattr(cls, name)
        self._saved.clear()

    def per_tick(self, key: str) -> np.ndarray:
        """Per-call durations of ``key`` [us]."""
        return np.asarray(self.samples[key], dtype=float) / 1e3

    def tick_totals(self) -> np.ndarray:
        """Loop time per tick, from the end of one ``tick`` call to the end of the next [us]."""
        return np.diff(np.asarray(self.tick_ends, dtype=float)) / 1e3


def timed_walks(name: str, seconds: float, runs: int = 3, **options: Any) -> list[float]:
    """Real-time factors of ``runs`` plain ``run_walk(name, **options)`` calls (nothing
    wrapped), after a short warm-up run (imports, first allocations)."""
    from virtual_actuators.demos import run_walk

    run_walk(name, duration=min(seconds, 0.3), progress=False, **options)
    factors = []
    for _ in range(runs):
        result = run_walk(name, duration=seconds, progress=False, **options)
        factors.append(float(result.simulator.time / result.wall_time))
    return factors


def instrumented_walk(
    name: str, gait_class: type, seconds: float, **options: Any
) -> dict[str, Any]:
    """``run_walk(name, **options)`` with the gait's ``compute``, the state machine's
    ``update``, the controller's ``compute_checked``, the simulator's ``step`` and its contact
    queries wrapped by a :class:`WalkProbe`; returns the real-time factor and the per-tick
    breakdown [us]."""
    import virtual_actuators as va
    from virtual_actuators.control.plan.compiled import CompiledMachine
    from virtual_actuators.demos import run_walk
    from virtual_actuators.simulation import Simulator

    targets = {
        "gait.compute": (gait_class, "compute"),
        "machine.update": (va.StateMachine, "update"),
        "controller.compute": (va.Controller, "compute_checked"),  # compute() calls it too
        "simulator.step": (Simulator, "step"),
        "in_contact": (Simulator, "in_contact"),
        "touching_terrain": (Simulator, "touching_terrain"),
        "contact_switches": (Simulator, "contact_switches"),
    }
    targets["compiled.compute"] = (CompiledMachine, "compute")  # a compiled plan's tick
    with WalkProbe(targets, tick="simulator.step") as probe:
        result = run_walk(name, duration=seconds, progress=False, **options)
    # the loop's ticks; the step after them is va.run's final zero effort, not a tick
    ticks = result.loop.ticks
    total = probe.tick_totals()[: ticks - 1]
    # the warm-up's calls come before the loop's: the last ``ticks`` calls are the loop's
    gait = probe.per_tick("gait.compute")[-ticks:]
    step = probe.per_tick("simulator.step")[:ticks]
    native = probe.per_tick("compiled.compute")[-ticks:]
    if gait.size < ticks <= native.size:  # the loop calls the compiled machine itself
        gait = native
    if native.size and gait.size >= ticks:  # gait.compute runs the compiled machine
        parts = {"total": total, "gait.compute": gait, "  compiled machine": native}
    else:
        parts = {
            "total": total,
            "gait.compute": gait,
            "  machine.update": probe.per_tick("machine.update"),
            "  controller.compute": probe.per_tick("controller.compute"),
        }
    parts["simulator.step"] = step
    parts["rest"] = total - gait[1:] - step[1:]  # tick i: from the end of step i-1 to step i
    breakdown = {}
    for label, values in parts.items():
        mean = float(np.mean(values)) if values.size else float("nan")
        breakdown[label.strip()] = {**summarize(values), "mean_us": mean, "label": label}
    queries = ("in_contact", "touching_terrain", "contact_switches")
    contacts = sum(np.sum(probe.per_tick(k)) for k in queries)
    breakdown["rest"]["contact_queries_mean_us"] = float(contacts / max(ticks, 1))
    simulated, period = float(result.simulator.time), result.simulator.control_period
    return {
        "ticks": ticks,
        "simulated_s": simulated,
        "wall_s": float(result.wall_time),
        "realtime_factor": simulated / result.wall_time,
        "physics_only_factor": 1e6 * period / breakdown["simulator.step"]["mean_us"],
        "fell": bool(result.metrics.fell),
        "per_tick": breakdown,
        "smoothness": result.smoothness.to_dict(),  # issue 35: every tick's efforts
    }


# -- reporting ----------------------------------------------------------------------------------


@dataclass
class Figure:
    """One figure's table rows, raw numbers (JSON), notes printed under the table, and its rows
    of issue 27's table (with the issue's goals)."""

    rows: list[dict[str, Any]]
    raw: dict[str, Any]
    notes: list[str] = field(default_factory=list)
    issue: list[dict[str, Any]] = field(default_factory=list)


def us(stats: dict[str, float]) -> str:
    """``median / p90 us``."""
    return f"{stats['median_us']:.1f} / {stats['p90_us']:.1f} us"


def row(figure, ours, baseline, ratio=None, target="-", met=None) -> dict[str, Any]:
    """One line of the table; ``ratio`` is ours / baseline, ``met`` None when there is no target."""
    return {
        "figure": figure,
        "ours": ours,
        "baseline": baseline,
        "ratio": None if ratio is None or not np.isfinite(ratio) else float(ratio),
        "target": target,
        "met": None if met is None else bool(met),
    }


def ratio_of(ours: dict[str, float], baseline: dict[str, float]) -> float:
    """Ratio of medians."""
    return ours["median_us"] / baseline["median_us"]


def print_rows(rows: list[dict[str, Any]]) -> None:
    """A table: ours | baseline | ratio = ours / baseline | target | met."""
    cells = [
        [
            r["figure"],
            r["ours"],
            r["baseline"],
            "-" if r["ratio"] is None else f"{r['ratio']:.3g}x",
            r["target"],
            "-" if r["met"] is None else ("yes" if r["met"] else "no"),
        ]
        for r in rows
    ]
    head = ["figure", "ours", "baseline", "ratio", "target", "met"]
    widths = [max(len(str(c[i])) for c in [head, *cells]) for i in range(len(head))]
    line = " | ".join(f"{h:<{w}}" for h, w in zip(head, widths, strict=True))
    print(line)
    print("-+-".join("-" * w for w in widths))
    for c in cells:
        print(" | ".join(f"{x:<{w}}" for x, w in zip(c, widths, strict=True)))


def print_table(
    machine: dict[str, Any],
    rows: list[dict[str, Any]],
    notes: list[str],
    issue: list[dict[str, Any]] = (),
) -> None:
    """The machine, the table, issue 27's rows (when any) and the notes."""
    print(
        f"machine: {machine['cpu']}, {machine['cores']} cores; Python {machine['python']}, "
        f"numpy {machine['numpy']}, pinocchio {machine['pinocchio']}, mujoco "
        f"{machine['mujoco']}, proxsuite {machine['proxsuite']}, virtualmodelcontrol "
        f"{machine['virtualmodelcontrol']}; BLAS {machine['blas']}"
    )
    load = ", ".join(f"{x:g}" for x in machine["load_average"])
    print(f"date: {machine['date']}; load average at the start {load}")
    print("times: median / p90 per call; ratio = ours / baseline\n")
    print_rows(rows)
    if issue:
        print("\nissue 27's rows, each beside its same-run baseline (target: the issue's goal)")
        print_rows(issue)
    print()
    for note in notes:
        print(note)
