"""Record a walking run one control tick at a time into a `WalkLog`."""

from __future__ import annotations

import copy
from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np

from virtual_actuators.exceptions import InvalidInputError
from virtual_actuators.experiments.walk_log import (
    STANDARD_CHANNELS,
    STATE_CHANNEL,
    WalkLog,
    check_names,
    unknown_name,
)


class Recorder:
    """Collect one row per control tick into a preallocated array that doubles when full.

    Example:
        >>> rec = Recorder(channels=("time", "x", "z"), state_names=("double", "single"),
        ...                metadata={"robot": "spring_turkey"})
        >>> rec.append(time=0.0, x=0.0, z=0.54, state="single")
        >>> rec.append_row([0.001, 0.0005, 0.54], state=1)
        >>> log = rec.to_log()
        >>> log["x"].tolist()
        [0.0, 0.0005]

    Args:
        channels: Float channel names; must include ``"time"`` (``"state"`` is recorded
            separately either way).
        state_names: Names of the discrete states; ``state`` values index into them.
        capacity: Rows allocated up front.
        metadata: Run description, copied.

    Raises:
        InvalidInputError: If a channel or state name is empty or repeated, ``"time"`` is
            missing, or ``capacity`` is not a positive integer.
    """

    __slots__ = (
        "_buffer",
        "_channels",
        "_index",
        "_n",
        "_nchan",
        "_state",
        "_state_index",
        "_state_names",
        "metadata",
    )

    def __init__(
        self,
        channels: Sequence[str] = STANDARD_CHANNELS,
        *,
        state_names: Sequence[str] = (),
        capacity: int = 4096,
        metadata: Mapping[str, Any] | None = None,
    ) -> None:
        if isinstance(channels, str):
            raise InvalidInputError(f"channels: expected a sequence of names, got {channels!r}.")
        names = tuple(c for c in check_names(channels, "channels") if c != STATE_CHANNEL)
        if "time" not in names:
            raise InvalidInputError(
                "channels: 'time' is required; given: " + ", ".join(repr(n) for n in names) + "."
            )
        if isinstance(state_names, str):
            raise InvalidInputError(f"state_names: expected a sequence, got {state_names!r}.")
        if isinstance(capacity, bool) or not isinstance(capacity, int | np.integer) or capacity < 1:
            raise InvalidInputError(f"capacity: expected a positive int, got {capacity!r}.")
        self._channels: tuple[str, ...] = names
        self._nchan = len(names)
        self._index: dict[str, int] = {n: j for j, n in enumerate(names)}
        self._state_names: tuple[str, ...] = check_names(state_names, "state_names")
        self._state_index: dict[str, int] = {n: i for i, n in enumerate(self._state_names)}
        self._buffer = np.full((int(capacity), self._nchan), np.nan)
        self._state = np.full(int(capacity), -1, dtype=np.int64)
        self._n = 0
        #: Run description (standard keys on the "Command line" page); copied by to_log.
        self.metadata: dict[str, Any] = dict(metadata or {})

    def __len__(self) -> int:
        return self._n

    def __repr__(self) -> str:
        return (
            f"Recorder({self._n} rows, capacity {self.capacity}, channels={list(self._channels)})"
        )

    @property
    def channels(self) -> tuple[str, ...]:
        """The float channel names, in row order."""
        return self._channels

    @property
    def state_names(self) -> tuple[str, ...]:
        """The discrete state names."""
        return self._state_names

    @property
    def capacity(self) -> int:
        """Rows currently allocated."""
        return int(self._buffer.shape[0])

    def _next_row(self, state: int | str | None) -> tuple[int, int]:
        """The next row's index (the buffers doubled when full) and its checked state."""
        if state is None:
            state = -1
        elif type(state) is not int or state < -1 or state >= len(self._state_names) > 0:
            state = self._state_value(state)
        n = self._n
        if n == self._buffer.shape[0]:
            self._buffer = np.vstack((self._buffer, np.full((n, self._nchan), np.nan)))
            self._state = np.concatenate((self._state, np.full(n, -1, dtype=np.int64)))
        return n, state

    def _state_value(self, state: int | str) -> int:
        if isinstance(state, str):
            try:
                return self._state_index[state]
            except KeyError:
                raise unknown_name(state, self._state_names, "state") from None
        if isinstance(state, bool) or not isinstance(state, int | np.integer):
            raise InvalidInputError(f"state: expected an int index or a state name, got {state!r}.")
        value = int(state)
        if value < -1 or (self._state_names and value >= len(self._state_names)):
            raise InvalidInputError(
                f"state: {value} is not an index into state_names "
                f"(0..{len(self._state_names) - 1}, or -1 for unknown)."
            )
        return value

    def append(self, state: int | str | None = None, **values: float) -> None:
        """Record one tick: ``rec.append(time=t, x=x, ..., state=i)``; channels left out stay NaN.

        Args:
            state: Index into `state_names` (or the state's name); -1 (unknown) if omitted.
            **values: Channel name -> value.

        Raises:
            InvalidInputError: If a channel or state is unknown (nothing is recorded then).
        """
        n, state = self._next_row(state)
        row = self._buffer[n]
        index = self._index
        try:
            for name, value in values.items():
                row[index[name]] = value
        except KeyError as err:
            row[:] = np.nan
            raise unknown_name(err.args[0], self._channels, "channel") from None
        except (TypeError, ValueError) as err:
            row[:] = np.nan
            raise InvalidInputError(f"channel {name!r}: cannot record {value!r} ({err}).") from None
        self._state[n], self._n = state, n + 1

    def append_row(self, row: Sequence[float] | np.ndarray, state: int | str | None = None) -> None:
        """Record one tick from a full row of values in `channels` order.

        Args:
            row: ``(len(channels),)`` values.
            state: Index into `state_names` (or the state's name); -1 (unknown) if omitted.

        Raises:
            InvalidInputError: If ``row`` has the wrong length or the state is unknown.
        """
        try:
            length = len(row)
        except TypeError:
            length = -1
        if length != self._nchan:
            raise InvalidInputError(
                f"row: expected {self._nchan} values ({', '.join(self._channels)}), got "
                f"{'a scalar' if length < 0 else length}."
            )
        n, state = self._next_row(state)
        try:
            self._buffer[n] = row
        except (TypeError, ValueError) as err:
            self._buffer[n] = np.nan
            raise InvalidInputError(f"row: cannot record {row!r} ({err}).") from None
        self._state[n], self._n = state, n + 1

    def to_log(self) -> WalkLog:
        """The rows recorded so far as a `WalkLog` (copies; recording may go on).

        Raises:
            InvalidInputError: If the recorded ``time`` is not finite and non-decreasing.
        """
        n = self._n
        return WalkLog(
            data={c: self._buffer[:n, j] for j, c in enumerate(self._channels)},  # copied
            state=self._state[:n],  # copied by WalkLog
            state_names=self._state_names,
            metadata=copy.deepcopy(self.metadata),
        )
