"""The optional packages a command line needs, checked before anything runs.

A missing one is a usage error (exit 2) naming the package, its extra and the command that
installs it, before any robot is loaded or walk simulated.
"""

from __future__ import annotations

import argparse
from typing import NamedTuple

from .views import wants_viewer


class Need(NamedTuple):
    """An optional package a command needs: its module, the extra that installs it, and why."""

    module: str
    extra: str
    feature: str


def needed_packages(args: argparse.Namespace) -> list[Need]:
    """The optional packages the parsed command line will import, in the order it imports them."""
    walks = args.command == "sweep" or (args.command == "demo" and args.name != "stand")
    needs = []
    if walks:
        needs.append(Need("mujoco", "sim", "MuJoCo simulation (the walks and sweeps)"))
        if not args.quiet:
            needs.append(Need("tqdm", "sim", "The progress bar (--quiet runs without it)"))
    if getattr(args, "plot", None):
        needs.append(Need("matplotlib", "plots", "The plot (--plot)"))
    if wants_viewer(args):
        needs.append(Need("meshcat", "viz", "The MeshCat viewer (--viz, --record)"))
    engine = getattr(args, "engine", None)
    if engine == "dask":
        engine_dask = "The Dask engine (--engine dask)"
        needs += [Need(name, "dask", engine_dask) for name in ("dask", "distributed")]
    elif engine == "ray":
        needs.append(Need("ray", "ray", "The Ray engine (--engine ray)"))
    return needs


def check_installed(args: argparse.Namespace, parser: argparse.ArgumentParser) -> None:
    """Import every optional package the command needs, or fail with a usage error.

    Raises:
        SystemExit: With code 2 and a message naming the missing package, its extra and the
            command that installs it (`import_optional`).
    """
    from ..exceptions import MissingDependencyError, import_optional

    for need in needed_packages(args):
        try:
            import_optional(need.module, need.extra, need.feature)
        except MissingDependencyError as error:
            parser.error(str(error))
