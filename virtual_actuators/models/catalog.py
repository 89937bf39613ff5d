"""Find robots by name or common name: the project's robot folders, example-robot-data, or a path.

The order in which names are resolved is on the "Robots" reference page.
"""

from __future__ import annotations

import functools
import importlib.metadata
import os
import sysconfig
import xml.etree.ElementTree as ET
from collections.abc import Mapping
from pathlib import Path
from types import MappingProxyType
from typing import NamedTuple

from virtual_actuators.exceptions import InvalidInputError, RobotNotFoundError, closest_names

#: The repository's top-level folder of robot descriptions.
robots_dir: Path = Path(__file__).resolve().parents[2] / "robots"

#: Environment variable with extra robot folders (separated by ``os.pathsep``), searched first.
ROBOTS_PATH_ENV = "VIRTUAL_ACTUATORS_ROBOTS"

#: Names of example-robot-data URDFs whose stem is shipped twice: (description folder, stem).
_DUPLICATE_NAMES = {
    ("anymal_b_simple_description", "anymal"): "anymal",
    ("anymal_c_simple_description", "anymal"): "anymal_c",
}

_PATH_SUFFIXES = (".urdf", ".xml", ".xacro")

#: Common name -> example-robot-data file stem (the choices: the "Robots" reference page): the
#: variant ``example_robot_data.load`` picks; never shadowing a file stem, and a local robot
#: named like an alias wins over it.
ALIASES: Mapping[str, str] = MappingProxyType(
    {
        # PAL Robotics TALOS (example_robot_data.load names)
        "talos": "talos_reduced",
        "talos_box": "talos_reduced_box",
        "talos_full": "talos_full_v2",
        "talos_full_box": "talos_full_v2_box",
        "talos_arm": "talos_left_arm",
        # Universal Robots arms
        "ur3_limited": "ur3_joint_limited_robot",
        "ur5": "ur5_robot",
        "ur5_limited": "ur5_joint_limited_robot",
        "ur10": "ur10_robot",
        "ur10_limited": "ur10_joint_limited_robot",
        # legged robots
        "hyq": "hyq_no_sensors",
        "solo8": "solo",
        "anymal_b": "anymal",
        "anymal_kinova": "anymal-kinova",
        "b1_z1": "b1-z1",
        "g1": "g1_29dof_rev_1_0",
        "g1_with_hand": "g1_29dof_with_hand_rev_1_0",
        "alexander": "alexander_v1.lowerBodyOnly",
        "alex": "alex_nub_hands",
        # arms and hands
        "franka": "panda",
        "franka_panda": "panda",
        "xarm": "xarm7",
        "so_arm_100": "so100",
        "so_arm_101": "so101",
        "allegro": "allegro_right_hand",
        "allegro_hand": "allegro_right_hand",
        "asr_twodof": "TwoDofs",
        # flying robots
        "hector": "quadrotor_base",
        "quadrotor": "quadrotor_base",
        "borinot": "borinot_flying_arm_2",
        "hextilt": "hextilt_flying_arm_5",
    }
)


def list_robots(include_aliases: bool = False) -> list[str]:
    """The sorted robot names [`load_robot`][] accepts without a path.

    The generated ``millipede``, the robots of `local_dirs` and every loadable example-robot-data
    URDF (its empty xacro stubs left out); with ``include_aliases``, the `aliases` too.
    """
    names = {"millipede", *example_robot_data().robots, *_local_names()}
    if include_aliases:
        names.update(aliases())
    return sorted(names)


def aliases() -> dict[str, str]:
    """``{alias: name}`` of the `ALIASES` shipped by example-robot-data and not shadowed."""
    index = example_robot_data()
    shadowing = {"millipede", *index.robots, *index.broken, *_local_names()}
    return {
        alias: target
        for alias, target in ALIASES.items()
        if target in index.robots and alias not in shadowing
    }


def suggest_robots(name: str) -> str:
    """A sentence naming the known robots closest to ``name`` (names and aliases).

    For instance ``"Closest robots: 'talos' (talos_reduced), 'tiago'."``, or, when nothing is
    close, ``"Known robots: ..."`` followed by how to list them all.
    """
    targets = aliases()
    names = list_robots()
    matches = closest_names(name, [*names, *targets])
    if matches:
        shown = [f"{m!r} ({targets[m]})" if m in targets else repr(m) for m in matches]
        return f"Closest robots: {', '.join(shown)}."
    more = f" and {len(names) - 12} more" if len(names) > 12 else ""
    return (
        f"Known robots: {', '.join(repr(n) for n in names[:12])}{more} "
        "(virtual_actuators.list_robots(include_aliases=True) lists them with their aliases)."
    )


class _Index(NamedTuple):
    """The URDF files shipped by example-robot-data."""

    share: Path | None
    robots: Mapping[str, Path]
    broken: Mapping[str, str]


@functools.cache
def example_robot_data() -> _Index:
    """Scan example-robot-data's robots folder once.

    Returns:
        The ``share`` folder that holds ``example-robot-data/robots`` (None without the
        package), the loadable URDF files by robot name, and why each other name cannot load.
    """
    try:
        distribution = importlib.metadata.distribution("example-robot-data")
        folder = Path(str(distribution.locate_file("cmeel.prefix/share/example-robot-data/robots")))
    except importlib.metadata.PackageNotFoundError:
        folder = None
    if folder is None or not (folder := folder.resolve()).is_dir():
        return _Index(None, MappingProxyType({}), MappingProxyType({}))

    robots: dict[str, Path] = {}
    broken: dict[str, str] = {}
    for urdf in sorted(folder.rglob("*.urdf")):
        description = urdf.relative_to(folder).parts[0]
        name = _DUPLICATE_NAMES.get((description, urdf.stem), urdf.stem)
        if name in robots:
            name = f"{description.removesuffix('_description')}_{urdf.stem}"
        problem = _quick_check(urdf)
        if problem is None:
            robots[name] = urdf
        else:
            broken[name] = problem
    for name in list(broken):
        replacement = robots.get(f"{name}_robot")
        if replacement is not None:
            robots[name] = replacement
            del broken[name]
    return _Index(folder.parents[1], MappingProxyType(robots), MappingProxyType(broken))


def _quick_check(urdf: Path) -> str | None:
    """Why a URDF surely cannot be loaded (no robot name, no link), or None."""
    try:
        for _, element in ET.iterparse(urdf, events=("start",)):
            if element.tag == "robot" and not element.get("name"):
                return "its <robot> element has no name (it is an unexpanded xacro stub)"
            if element.tag == "link":
                return None
    except (ET.ParseError, OSError) as exc:
        return f"it is not readable XML ({exc})"
    return "it declares no <link>"


def local_dirs() -> list[Path]:
    """Folders searched for robots by name.

    ``VIRTUAL_ACTUATORS_ROBOTS`` first, then the source tree's ``robots/``, then
    ``<prefix>/share/virtual_actuators/robots``.
    """
    extra = os.environ.get(ROBOTS_PATH_ENV, "")
    folders = [_expand_user(Path(entry)) for entry in extra.split(os.pathsep) if entry.strip()]
    installed = Path(sysconfig.get_path("data")) / "share" / "virtual_actuators" / "robots"
    return [*folders, robots_dir, installed]


def _is_file(path: Path) -> bool:
    """Whether ``path`` is a file (False when the file system refuses to say)."""
    try:
        return path.is_file()
    except (OSError, ValueError):  # a name too long, a folder that cannot be searched
        return False


def find_local(folder: Path, name: str) -> Path | None:
    """The URDF (or ``__init__.py`` hook) of robot ``name`` in ``folder``, or None."""
    if not name or name.startswith((".", "_")):
        return None
    candidates = (
        folder / f"{name}.urdf",
        folder / name / f"{name}.urdf",
        folder / name / "urdf" / f"{name}.urdf",
        folder / name / "robots" / f"{name}.urdf",
        folder / name / "__init__.py",
    )
    return next((path for path in candidates if _is_file(path)), None)


def _local_names() -> set[str]:
    """Names of the robots in the `local_dirs` (none in a folder that cannot be listed)."""
    names = set()
    for folder in local_dirs():
        try:
            entries = list(folder.iterdir()) if folder.is_dir() else []
        except (OSError, ValueError):  # a name too long, a folder that cannot be read
            continue
        stems = (entry.name if entry.is_dir() else entry.stem for entry in entries)
        names.update(name for name in stems if find_local(folder, name) is not None)
    return names


def shown_name(name_or_path: object) -> str:
    """The repr of a name or path for messages, shortened to about 80 characters."""
    if isinstance(name_or_path, os.PathLike):
        name_or_path = os.fspath(name_or_path)
    text = repr(name_or_path)
    if len(text) <= 80:
        return text
    return f"{text[:77]}... ({len(name_or_path)} characters)"


def _expand_user(path: Path, name_or_path: object = None) -> Path:
    """``path`` with ``~user`` expanded; an unknown user: kept, or not found for a load_robot."""
    try:
        return path.expanduser()
    except RuntimeError as exc:  # ~nosuchuser, or no HOME and no password entry
        if name_or_path is None:
            return path
        raise RobotNotFoundError(
            f"load_robot(name_or_path={shown_name(name_or_path)}): no URDF file there, "
            f"{path.parts[0]!r} names no known home folder ({exc}). Pass a robot name or the "
            "path of an existing URDF file."
        ) from None


def as_path(name_or_path: object) -> Path | None:
    """The path meant by ``name_or_path``, or None if it is a robot name.

    Raises:
        InvalidInputError: If ``name_or_path`` is neither a string nor a path, or is empty.
        RobotNotFoundError: If it starts with ``~user`` and that user (or the home folder) is
            unknown.
    """
    if isinstance(name_or_path, os.PathLike):
        text = os.fspath(name_or_path)
        if not isinstance(text, str):
            raise InvalidInputError(
                "load_robot(name_or_path=...) needs a str path, got a path of "
                f"{type(text).__name__}."
            )
        return _expand_user(Path(text), name_or_path)
    if not isinstance(name_or_path, str):
        raise InvalidInputError(
            f"load_robot() needs a robot name or a path to a URDF file, got {name_or_path!r}."
        )
    text = name_or_path.strip()
    if not text:
        raise InvalidInputError("load_robot() needs a robot name or a path, got an empty string.")
    separators = {"/", os.sep, os.altsep} - {None}
    if (
        any(separator in text for separator in separators)
        or text.startswith("~")
        or Path(text).suffix.lower() in _PATH_SUFFIXES
    ):
        return _expand_user(Path(text), name_or_path)
    return None


def package_dirs_for(urdf: Path) -> list[str]:
    """Folders ``package://`` URIs of a URDF may refer to (its, two above, example-robot-data's)."""
    share = example_robot_data().share
    folders = (urdf.parent, *urdf.parent.parents[:2], *([share] if share else []))
    return list(dict.fromkeys(str(folder) for folder in folders))


def urdf_in_folder(folder: Path) -> Path:
    """The one URDF that a folder given as a path stands for.

    Raises:
        RobotNotFoundError: If the folder holds no URDF file, or several and none is named
            after the folder.
    """
    for candidate in (
        folder / f"{folder.name}.urdf",
        folder / "urdf" / f"{folder.name}.urdf",
        folder / "robots" / f"{folder.name}.urdf",
    ):
        if candidate.is_file():
            return candidate
    found = sorted(folder.glob("*.urdf")) or sorted(folder.glob("*/*.urdf"))
    if len(found) == 1:
        return found[0]
    if not found:
        raise RobotNotFoundError(f"The folder {folder} holds no URDF file.")
    listed = ", ".join(str(path.relative_to(folder)) for path in found[:10])
    raise RobotNotFoundError(
        f"The folder {folder} holds several URDF files ({listed}): pass the file's path."
    )


def is_curated(path: Path) -> bool:
    """Whether ``path`` (resolved) is one of the URDF files shipped by example-robot-data."""
    share = example_robot_data().share
    return share is not None and path.is_relative_to(share / "example-robot-data" / "robots")
