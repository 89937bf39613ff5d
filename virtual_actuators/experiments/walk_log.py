"""A recorded walking run (`WalkLog`): channels, states, metadata, ``.npz`` storage.

The standard channels, their units and the metadata keys are described on the "Command line"
page.
"""

from __future__ import annotations

import json
import os
from collections.abc import Iterable, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from virtual_actuators.exceptions import InvalidInputError, closest_names

#: Version of the ``.npz`` layout, and the prefix of its entries that hold metadata arrays.
NPZ_FORMAT = 1
META_ARRAY_PREFIX = "meta_array__"


#: The float channels recorded by the walking demos (the discrete ``state`` is always recorded).
STANDARD_CHANNELS: tuple[str, ...] = tuple(
    "time x z z_world pitch xdot x_setpoint z_setpoint pitch_setpoint xdot_setpoint fx fz m_pitch "
    "global_slope fallen".split()
)

STATE_CHANNEL = "state"


def unknown_name(name: object, valid: Sequence[str], what: str) -> InvalidInputError:
    """The error for a name that is not one of ``valid`` (naming it and the valid ones)."""
    listed = ", ".join(repr(v) for v in valid)
    hint = closest_names(str(name), valid, n=3)
    did_you_mean = f" Did you mean {', '.join(repr(h) for h in hint)}?" if hint else ""
    return InvalidInputError(f"Unknown {what} {name!r}; valid {what}s: {listed}.{did_you_mean}")


def check_names(names: Iterable[object], what: str) -> tuple[str, ...]:
    """``names`` as a tuple of non-empty unique strings.

    Raises:
        InvalidInputError: Naming the first bad name.
    """
    out: list[str] = []
    for name in names:
        if not isinstance(name, str) or not name:
            raise InvalidInputError(f"{what}: every name must be a non-empty str, got {name!r}.")
        if name in out:
            raise InvalidInputError(f"{what}: {name!r} is given twice.")
        out.append(name)
    return tuple(out)


def default_step_states(state_names: Iterable[str]) -> tuple[str, ...]:
    """Guess the single-support states from their names.

    A name counts when it contains ``single``, or ``support`` but neither ``double`` nor a final
    ``2`` (the seed's buffer states "Left Support 2" follow a step, they do not start one).
    """
    out = []
    for name in state_names:
        low = name.lower()
        if "single" in low or (
            "support" in low and "double" not in low and not low.rstrip().endswith("2")
        ):
            out.append(name)
    return tuple(out)


def resolve_step_states(
    state_names: Sequence[str],
    metadata: dict,
    step_states: Iterable[str] | None = None,
    key: str = "step_states",
) -> tuple[str, ...]:
    """The step states: ``step_states``, else ``metadata[key]``, else the guess from the names.

    ``key`` is ``"step_states"`` (guessed by `default_step_states`) or
    ``"double_support_states"`` (guessed as the names that contain ``double``).

    Raises:
        InvalidInputError: If a given name is not a state of the log (the message names it and
            lists the valid ones).
    """
    source = key
    if step_states is None:
        step_states = metadata.get(key)
        source = f"metadata[{key!r}]"
    if step_states is None:
        if key == "step_states":
            return default_step_states(state_names)
        return tuple(s for s in state_names if "double" in s.lower())
    if isinstance(step_states, str):
        step_states = (step_states,)
    names = tuple(str(s) for s in step_states)
    for name in names:
        if name not in state_names:
            listed = ", ".join(repr(s) for s in state_names) or "none"
            raise InvalidInputError(
                f"{source}: {name!r} is not a state of the log; valid states: {listed}."
            )
    return names


@dataclass(eq=False)
class WalkLog:
    """A recorded run: one float array per channel, the discrete state, and metadata.

    Build one with `Recorder.to_log` or `load_npz`, or from whole arrays.

    Attributes:
        data: Channel name -> ``(n,)`` float64 array; ``"time"`` [s] is required, finite and
            non-decreasing.
        state: ``(n,)`` int64 index into ``state_names`` per tick; -1 when unknown.
        state_names: Names of the discrete states.
        metadata: Run description (standard keys on the "Command line" page).
    """

    data: dict[str, np.ndarray]
    state: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=np.int64))
    state_names: tuple[str, ...] = ()
    metadata: dict[str, Any] = field(default_factory=dict)

    def __post_init__(self) -> None:
        if not isinstance(self.data, Mapping):
            raise InvalidInputError(f"data must be a mapping of channel arrays, got {self.data!r}.")
        names = check_names(self.data.keys(), "channels")
        if STATE_CHANNEL in names:
            raise InvalidInputError("data: 'state' is not a float channel; pass state=... instead.")
        if "time" not in names:
            given = ", ".join(repr(n) for n in names)
            raise InvalidInputError(f"data: a 'time' channel is required; channels given: {given}.")
        data: dict[str, np.ndarray] = {}
        for name in names:
            try:
                array = data[name] = np.array(self.data[name], dtype=np.float64)
            except (TypeError, ValueError) as err:
                raise InvalidInputError(f"channel {name!r}: not numeric ({err}).") from None
            if array.ndim != 1:
                raise InvalidInputError(
                    f"channel {name!r}: expected a 1-D array, shape {array.shape}."
                )
            n = len(data[names[0]])
            if len(array) != n:
                raise InvalidInputError(
                    f"channel {name!r}: {len(array)} samples, but {names[0]!r} has {n}."
                )
        time = data["time"]
        if not np.all(np.isfinite(time)):
            raise InvalidInputError(f"channel 'time': non-finite value at tick {_first_bad(time)}.")
        if n > 1 and np.any(np.diff(time) < 0):
            bad = int(np.argmax(np.diff(time) < 0)) + 1
            raise InvalidInputError(f"channel 'time': decreases at tick {bad} ({time[bad]!r} s).")
        self.data = data
        self.state_names = check_names(self.state_names, "state_names")
        state = np.asarray(self.state)
        if state.size == 0 and n > 0:
            state = np.full(n, -1, dtype=np.int64)
        if state.ndim != 1 or state.shape[0] != n:
            raise InvalidInputError(f"state: expected shape ({n},), got {state.shape}.")
        if not np.issubdtype(state.dtype, np.integer) and not (
            np.all(np.isfinite(state)) and np.all(state == np.round(state))
        ):
            raise InvalidInputError("state: values must be integers (indices into state_names).")
        state = state.astype(np.int64)
        bad = (state < -1) | (state >= len(self.state_names))
        if self.state_names and np.any(bad):
            i = int(np.argmax(bad))
            raise InvalidInputError(
                f"state: {int(state[i])} at tick {i} is not an index into state_names "
                f"(0..{len(self.state_names) - 1}, or -1 for unknown)."
            )
        self.state = state
        if not isinstance(self.metadata, Mapping):
            raise InvalidInputError(f"metadata must be a dict, got {type(self.metadata).__name__}.")
        self.metadata = dict(self.metadata)

    def __len__(self) -> int:
        return int(self.data["time"].shape[0])

    def __contains__(self, name: object) -> bool:
        return name == STATE_CHANNEL or name in self.data

    def __getitem__(self, name: str) -> np.ndarray:
        return self.channel(name)

    def __repr__(self) -> str:
        span = f"{self.time[0]:.3f}..{self.time[-1]:.3f} s" if len(self) else "empty"
        return (
            f"WalkLog({len(self)} ticks, {span}, channels={list(self.channels)}, "
            f"states={list(self.state_names)})"
        )

    @property
    def channels(self) -> tuple[str, ...]:
        """Names of the float channels, in order (``state`` is not among them)."""
        return tuple(self.data)

    @property
    def time(self) -> np.ndarray:
        """``(n,)`` time of each tick [s]."""
        return self.data["time"]

    def channel(self, name: str) -> np.ndarray:
        """The ``(n,)`` array of channel ``name`` (``"state"``: the state indices).

        Raises:
            InvalidInputError: If the log has no such channel (the message lists the valid ones).
        """
        if name == STATE_CHANNEL:
            return self.state
        try:
            return self.data[name]
        except (KeyError, TypeError):
            raise unknown_name(name, (*self.data, STATE_CHANNEL), "channel") from None

    def has(self, name: str) -> bool:
        """Whether channel ``name`` exists and holds at least one finite value."""
        if name == STATE_CHANNEL:
            return bool(np.any(self.state >= 0))
        array = self.data.get(name)
        return array is not None and bool(np.any(np.isfinite(array)))

    def state_index(self, name: str) -> int:
        """The index of state ``name`` in `state_names`.

        Raises:
            InvalidInputError: If there is no such state (the message lists the valid ones).
        """
        try:
            return self.state_names.index(name)
        except ValueError:
            raise unknown_name(name, self.state_names, "state") from None

    def window(self, start: float | None = None, stop: float | None = None) -> WalkLog:
        """The ticks with ``start <= time <= stop`` [s] as a new log (None: unbounded).

        Raises:
            InvalidInputError: A bound that is not a finite number, ``start > stop``, or a
                window that holds no tick (the message gives the log's time span).
        """
        from ..vocabulary.arguments import check_number

        time = self.data["time"]
        low = -np.inf if start is None else check_number(start, "window start [s]")
        high = np.inf if stop is None else check_number(stop, "window stop [s]")
        if low > high:
            raise InvalidInputError(f"window: start {low} s is after stop {high} s.")
        keep = (time >= low) & (time <= high)
        if not np.any(keep):
            span = f"{time[0]:.3f}..{time[-1]:.3f} s" if len(time) else "empty"
            raise InvalidInputError(
                f"window {low:g}:{high:g} s holds no tick; the log covers {span}."
            )
        return WalkLog(
            data={name: values[keep] for name, values in self.data.items()},
            state=self.state[keep],
            state_names=self.state_names,
            metadata=dict(self.metadata),
        )

    def entries(self, states: Iterable[str]) -> np.ndarray:
        """``(k,)`` ticks at which the state changes into one of ``states`` (never tick 0).

        Raises:
            InvalidInputError: If a name is not a state of this log.
        """
        indices = [self.state_index(s) for s in states]
        if len(self) < 2 or not indices:
            return np.zeros(0, dtype=np.int64)
        s = self.state
        changed = s[1:] != s[:-1]
        into = np.isin(s[1:], np.asarray(indices, dtype=np.int64))
        return np.flatnonzero(changed & into) + 1

    @property
    def terrain_points(self) -> np.ndarray | None:
        """``(n, 2)`` terrain ``(x, z)`` vertices from ``metadata["terrain_points"]``, or None.

        Raises:
            InvalidInputError: If the metadata entry is not an ``(n >= 2, 2)`` finite array.
        """
        points, what = self.metadata.get("terrain_points"), "metadata['terrain_points']"
        if points is None:
            return None
        try:
            array = np.asarray(points, dtype=np.float64)
        except (TypeError, ValueError):
            raise InvalidInputError(
                f"{what}: expected an (n, 2) array of (x, z), got {points!r}."
            ) from None
        if array.ndim != 2 or array.shape[1] != 2 or array.shape[0] < 2:
            raise InvalidInputError(
                f"{what}: expected an (n >= 2, 2) array of (x, z), got {array.shape}."
            )
        if not np.all(np.isfinite(array)):
            raise InvalidInputError(f"{what}: non-finite value in row {_first_bad(array) // 2}.")
        return array

    def save_npz(self, path: str | os.PathLike[str]) -> Path:
        """Write the log to ``path`` (as given, parents created) as a compressed ``.npz``.

        NumPy arrays in the metadata are stored as arrays; the rest must be JSON-able (tuples and
        sets come back as lists). Readable without pickle.

        Returns:
            The path written.

        Raises:
            InvalidInputError: If a metadata value cannot be stored (the message names its key).
        """
        path = Path(path)
        arrays: dict[str, np.ndarray] = {}
        plain: dict[str, Any] = {}
        for key, value in self.metadata.items():
            if not isinstance(key, str):
                raise InvalidInputError(f"metadata: keys must be str, got {key!r}.")
            if isinstance(value, np.ndarray):
                if value.dtype == object:
                    raise InvalidInputError(f"metadata[{key!r}]: object arrays cannot be saved.")
                arrays[META_ARRAY_PREFIX + key] = value
                continue
            try:
                json.dumps(value, default=_json_default)
            except (TypeError, ValueError) as err:
                raise InvalidInputError(f"metadata[{key!r}]: cannot be saved ({err}).") from None
            plain[key] = value
        names = tuple(self.data)
        matrix = np.column_stack(list(self.data.values()))  # (0, channels) for no tick
        path.parent.mkdir(parents=True, exist_ok=True)
        with path.open("wb") as f:
            np.savez_compressed(
                f,
                format=np.asarray(NPZ_FORMAT),
                channels=np.asarray(names, dtype=str),
                data=matrix,
                state=self.state,
                state_names=np.asarray(self.state_names, dtype=str),
                metadata_json=np.asarray(json.dumps(plain, default=_json_default)),
                **arrays,
            )
        return path

    @classmethod
    def load_npz(cls, path: str | os.PathLike[str]) -> WalkLog:
        """Read a log written by `save_npz`.

        Raises:
            InvalidInputError: If the file is not a walk log.
        """
        path = Path(path)
        with np.load(path, allow_pickle=False) as npz:
            missing = [k for k in ("channels", "data", "state") if k not in npz.files]
            if missing:
                raise InvalidInputError(f"{path}: not a walk log (no {', '.join(missing)}).")
            names = [str(n) for n in npz["channels"]]
            matrix = npz["data"]
            metadata = json.loads(str(npz["metadata_json"])) if "metadata_json" in npz else {}
            for key in npz.files:
                if key.startswith(META_ARRAY_PREFIX):
                    metadata[key.removeprefix(META_ARRAY_PREFIX)] = npz[key]
            state_names = tuple(str(s) for s in npz["state_names"]) if "state_names" in npz else ()
            state = npz["state"]
        if matrix.ndim != 2 or matrix.shape[1] != len(names):
            raise InvalidInputError(
                f"{path}: 'data' has shape {matrix.shape}, expected (n, {len(names)})."
            )
        data = {n: np.ascontiguousarray(matrix[:, j]) for j, n in enumerate(names)}
        return cls(data, state, state_names, metadata)


def _first_bad(array: np.ndarray) -> int:
    return int(np.argmax(~np.isfinite(array)))


def _json_default(value: Any) -> Any:
    """Convert NumPy values, sets and paths for `json.dumps`."""
    if isinstance(value, np.generic):
        return value.item()
    if isinstance(value, np.ndarray):
        return value.tolist()
    if isinstance(value, set | frozenset):
        return sorted(value, key=str)
    if isinstance(value, os.PathLike):
        return os.fspath(value)
    raise TypeError(f"{type(value).__name__} is not JSON serialisable")
