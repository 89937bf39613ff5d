"""Terrain for the simulations: a piecewise-linear height profile ``z(x)`` along world x.

Also the built-in profiles, and the text form of a terrain (``--terrain`` on the CLI).
"""

from __future__ import annotations

import bisect
import itertools
import math
from collections.abc import Iterable, Sequence

import numpy as np

from virtual_actuators.exceptions import InvalidInputError, suggestion
from virtual_actuators.vocabulary.arguments import check_number

#: Length of the level ground that every built-in profile starts with [m].
LEVEL_START = 2.0

# Built-in profiles: (horizontal length [m], slope [deg]) of the segments after LEVEL_START m
# of level ground starting at x = 0; the height starts at 0.
PROFILES: dict[str, tuple[tuple[float, float], ...]] = {
    name: tuple((length, float(slope)) for length, slope in zip(lengths, slopes, strict=True))
    for name, lengths, slopes in (
        ("profile-one", (1.5, 1.6, 1.5, 1.6, 1.2, 1.6, 1.2, 1.8), (15, 0, -15, 0, 20, 0, -20, 0)),
        (
            "profile-two",
            (1.0, 0.8, 1.2, 0.7, 1.0, 0.6, 1.5, 0.9, 0.8, 1.1, 0.7, 1.3, 0.6, 1.0, 1.2),
            (10, 18, 5, -10, -18, -5, 8, 15, 0, -14, 3, 12, -6, -16, 0),
        ),
        ("rolling", (1.0,) * 12, (5, 10, 5, -5, -10, -5) * 2),
    )
}

#: Names accepted by `Terrain.builtin`.
BUILTIN_NAMES = ("flat", *PROFILES)

#: What a terrain spec may be, for error messages.
VALID_SPECS = (
    f"valid terrains: {', '.join(BUILTIN_NAMES)}, 'flat:HEIGHT', or points 'x:z,x:z,...' "
    "in metres with increasing x (e.g. '0:0,2:0,3:0.27')"
)


#: Default width of the terrain boxes along y in MuJoCo [m].
DEFAULT_WIDTH = 2.0


def _number(text: str) -> float:
    """``float(text)``, NaN when it is not a number."""
    try:
        return float(text)
    except ValueError:
        return math.nan


def _interp(x: float, xs: list[float], zs: list[float]) -> float:
    """``np.interp(x, xs, zs)`` for one float, with numpy's arithmetic (the same bits)."""
    if not x == x:
        return x  # NaN
    if x <= xs[0]:
        return zs[0]
    last = len(xs) - 1
    if x >= xs[last]:
        return zs[last]
    j = bisect.bisect_right(xs, x) - 1  # xs[j] <= x < xs[j + 1]
    if xs[j] == x:
        return zs[j]
    slope = (zs[j + 1] - zs[j]) / (xs[j + 1] - xs[j])
    height = slope * (x - xs[j]) + zs[j]
    if height != height:  # numpy's retry from the other end
        height = slope * (x - xs[j + 1]) + zs[j + 1]
        if height != height and zs[j] == zs[j + 1]:
            height = zs[j]
    return height


def _pair(point: np.ndarray) -> str:
    """A point as ``(x, z)`` with plain floats."""
    return f"({float(point[0])!r}, {float(point[1])!r})"


class Terrain:
    """A piecewise-linear height profile ``z(x)`` [m] along world x, flat outside its points.

    Build one from its points, or with [`flat`][], [`builtin`][] or [`parse`][].

    Attributes:
        name: A label (the built-in name, ``"flat"``, or ``"custom"``).
        width: Width along world y in MuJoCo [m], centred on ``y = 0`` (a plane ignores it).
    """

    def __init__(
        self,
        points: Iterable[Sequence[float]],
        *,
        name: str = "custom",
        width: float = DEFAULT_WIDTH,
    ) -> None:
        """Create a terrain named ``name`` through its points.

        Args:
            points: Points ``(x, z)`` [m], at least one, ``x`` strictly increasing.
            name: A label shown by `__repr__`.
            width: Width along y of the MuJoCo terrain boxes [m], > 0.

        Raises:
            InvalidInputError: If the points are not an ``(n, 2)`` array of finite numbers with
                ``n >= 1`` and strictly increasing ``x``, or ``width`` is not positive.
        """
        try:
            array = np.array(points, dtype=float)
        except (TypeError, ValueError) as exc:
            raise InvalidInputError(
                f"Terrain points must be (x, z) pairs of numbers in metres: {exc}."
            ) from exc
        if array.ndim != 2 or array.shape[1] != 2 or array.shape[0] < 1:
            raise InvalidInputError(
                "Terrain points must be a non-empty list of (x, z) pairs, got an array of "
                f"shape {array.shape}."
            )
        if not np.all(np.isfinite(array)):
            bad = int(np.argwhere(~np.isfinite(array))[0, 0])
            raise InvalidInputError(
                f"Terrain point {bad} {_pair(array[bad])} is not finite: heights and positions "
                "must be finite numbers in metres."
            )
        steps = np.diff(array[:, 0])
        if np.any(steps <= 0.0):
            i = int(np.argmax(steps <= 0.0))
            raise InvalidInputError(
                f"Terrain x positions must be strictly increasing: point {i + 1} "
                f"{_pair(array[i + 1])} does not come after point {i} {_pair(array[i])} "
                "(a vertical step is not a valid profile)."
            )
        width = check_number(width, "Terrain width [m]", positive=True)
        array.setflags(write=False)
        self._points = array
        # plain floats for height() at one number (the control loop's query)
        self._xs, self._zs = array[:, 0].tolist(), array[:, 1].tolist()
        self.name = str(name)
        self.width = width

    @classmethod
    def flat(cls, height: float = 0.0, *, width: float = DEFAULT_WIDTH) -> Terrain:
        """Level ground at ``height`` [m].

        Raises:
            InvalidInputError: If ``height`` is not a finite number.
        """
        return cls([(0.0, height)], name="flat", width=width)

    @classmethod
    def builtin(cls, name: str, *, width: float = DEFAULT_WIDTH) -> Terrain:
        """The built-in profile ``name``, one of [`names`][].

        Raises:
            InvalidInputError: If ``name`` is not a built-in profile (with the closest names).
        """
        if name == "flat":
            return cls.flat(width=width)
        if name not in PROFILES:
            hint = suggestion(str(name), BUILTIN_NAMES, "terrains")
            raise InvalidInputError(f"No built-in terrain named {name!r}. {hint}")
        points = [(0.0, 0.0), (LEVEL_START, 0.0)]
        x, z = LEVEL_START, 0.0
        for length, slope_deg in PROFILES[name]:
            x += length
            z += length * math.tan(math.radians(slope_deg))
            points.append((round(x, 12), z))
        return cls(points, name=name, width=width)

    @staticmethod
    def names() -> tuple[str, ...]:
        """Names of the built-in profiles accepted by [`builtin`][] and [`parse`][]."""
        return BUILTIN_NAMES

    @classmethod
    def parse(cls, spec: str, *, width: float = DEFAULT_WIDTH) -> Terrain:
        """A terrain from a command-line text.

        The forms: ``"flat"``, ``"flat:HEIGHT"`` [m], a built-in name ([`names`][]), or points
        ``"x:z,x:z,..."`` [m] (for example ``"0:0,2:0,3:0.27,4:0.27"``).

        Raises:
            InvalidInputError: If the text is none of these forms (quoting the bad token).
        """
        if not isinstance(spec, str):
            raise InvalidInputError(f"A terrain spec must be a string, got {type(spec).__name__}.")
        text = spec.strip()
        if not text:
            raise InvalidInputError(f"Empty terrain spec; {VALID_SPECS}.")
        if text in BUILTIN_NAMES:
            return cls.builtin(text, width=width)
        if text.startswith("flat:"):
            height = text.removeprefix("flat:").strip()
            value = _number(height)
            if not math.isfinite(value):
                raise InvalidInputError(
                    f"Bad terrain height {height!r} in {spec!r}: 'flat:HEIGHT' needs a finite "
                    f"number of metres; {VALID_SPECS}."
                )
            return cls.flat(value, width=width)
        points = []
        for token in text.split(","):
            parts = token.split(":")
            values = [_number(part) for part in parts] if len(parts) == 2 else []
            if len(values) != 2 or not all(math.isfinite(v) for v in values):
                hint = ""
                if ":" not in token and token.strip():
                    hint = " " + suggestion(token.strip(), BUILTIN_NAMES, "terrains")
                raise InvalidInputError(
                    f"Bad terrain token {token.strip()!r} in {spec!r}: expected a point 'x:z' "
                    f"with two finite numbers in metres; {VALID_SPECS}.{hint}"
                )
            points.append(values)
        return cls(points, name="custom", width=width)

    @property
    def points(self) -> np.ndarray:
        """The profile points ``(n, 2)``: x [m] and z [m] (a copy)."""
        return self._points.copy()

    @property
    def is_flat(self) -> bool:
        """Whether every point has the same height."""
        return bool(np.all(self._points[:, 1] == self._points[0, 1]))

    @property
    def slopes(self) -> np.ndarray:
        """Slope angle of each segment [rad], shape ``(n - 1,)``."""
        steps = np.diff(self._points, axis=0)
        return np.arctan2(steps[:, 1], steps[:, 0])

    def height(self, x: float | np.ndarray) -> float | np.ndarray:
        """Ground height [m] at world ``x`` [m]: a float for a number, else an array like ``x``."""
        if isinstance(x, float):  # one number (np.float64 too): no array round trip
            return _interp(float(x), self._xs, self._zs)
        xs, zs = self._points[:, 0], self._points[:, 1]
        heights = np.interp(np.asarray(x, dtype=float), xs, zs)
        return float(heights) if np.ndim(x) == 0 else heights

    def slope(self, x: float | np.ndarray) -> float | np.ndarray:
        """Slope angle [rad] of the ground at world ``x`` [m], positive uphill towards +x.

        Between two segments, the slope of the one after; level (0) outside the points. A float for
        a number, else an array like ``x``.
        """
        angles = np.concatenate(([0.0], self.slopes, [0.0]))
        index = np.searchsorted(self._points[:, 0], np.asarray(x, dtype=float), side="right")
        result = angles[index]  # index 0 before the points, n after them
        return float(result) if np.ndim(x) == 0 else result

    def segments(self, run: float = 50.0) -> list[tuple[tuple[float, float], tuple[float, float]]]:
        """The ground as segments ``((x0, z0), (x1, z1))``, left to right.

        Args:
            run: Length of the level segments added before and after the points [m].
        """
        points = [(x, z) for x, z in self._points.tolist()]
        (x0, z0), (x1, z1) = points[0], points[-1]
        return list(itertools.pairwise([(x0 - run, z0), *points, (x1 + run, z1)]))

    def __repr__(self) -> str:
        if self.is_flat:
            return f"Terrain.flat(height={self._points[0, 1]:g})"
        xs, zs = self._points[:, 0], self._points[:, 1]
        steepest = math.degrees(float(np.max(np.abs(self.slopes))))
        return (
            f"Terrain({self.name!r}, {len(xs)} points, x {xs[0]:g}..{xs[-1]:g} m, "
            f"z {zs.min():.3g}..{zs.max():.3g} m, steepest {steepest:.3g} deg)"
        )
