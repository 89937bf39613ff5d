"""Progress bars for long runs: simulated seconds of a walk, or finished items of a sweep.

The position is set from the clock (or the count), never accumulated, so it cannot drift.
"""

from __future__ import annotations

import sys

from ..exceptions import import_optional


class Progress:
    """A tqdm bar over a known total, on stderr, redrawn at most ten times a second.

    Args:
        total: Simulated seconds, or items.
        unit: ``"sim s"`` (seconds, one decimal) or an item name (``"walks"``).
        description: Text before the bar.

    Raises:
        MissingDependencyError: tqdm is not installed (the extra ``sim``).
    """

    def __init__(self, total: float, unit: str = "sim s", description: str = "") -> None:
        tqdm = import_optional("tqdm", "sim", "Progress bars").tqdm
        self.total = float(total)
        seconds = unit == "sim s"
        counts = "{n:.1f}/{total:.1f} s" if seconds else "{n:.0f}/{total:.0f} " + unit
        self._bar = tqdm(
            total=self.total,
            desc=description or None,
            unit=unit,
            file=sys.stderr,
            mininterval=0.1,
            leave=True,
            bar_format="{l_bar}{bar}| " + counts + " [{elapsed}<{remaining}]",
        )
        self._closed = False

    def set(self, done: float) -> None:
        """Move the bar to ``done`` (clipped to ``[0, total]``); redraws when due."""
        value = min(max(round(float(done), 6), 0.0), self.total)  # 1.9999999 s is 2 s
        if value != self._bar.n:
            self._bar.n = value
            self._bar.refresh() if self._bar.n >= self.total else self._bar.update(0)

    def close(self, done: float | None = None) -> None:
        """Set the final position (if given) and leave the bar's last line; idempotent."""
        if self._closed:
            return
        if done is not None:
            self._bar.n = min(max(round(float(done), 6), 0.0), self.total)
        self._bar.close()
        self._closed = True

    def __enter__(self) -> Progress:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    def __repr__(self) -> str:
        return f"Progress({self._bar.n:g}/{self.total:g})"
