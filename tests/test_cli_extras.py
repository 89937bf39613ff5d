"""A core-only install (``pip install .``, no extras): every command that needs an optional
package is a usage error naming the package and its extra, never a traceback; the library's
imports raise the typed :class:`~virtual_actuators.MissingDependencyError`.

The optional packages are made unimportable in a subprocess by a ``sitecustomize`` on a
temporary ``PYTHONPATH`` whose meta-path finder raises :class:`ModuleNotFoundError` for them, as
the import system does for a package that is not installed (nothing is replaced by a stand-in:
the package cannot be imported at all).
"""

from __future__ import annotations

import importlib.util
import json
import os
import re
import subprocess
import sys
import tomllib
from pathlib import Path

import pytest

from virtual_actuators.exceptions import EXTRAS_IN_ALL

pytestmark = pytest.mark.slow  # subprocesses

ROOT = Path(__file__).resolve().parents[1]

#: Every optional package the package imports, and the extra that brings it.
OPTIONAL = {
    "mujoco": "sim",
    "tqdm": "sim",
    "matplotlib": "plots",
    "meshcat": "viz",
    "yourdfpy": "urdf",
    "dask": "dask",
    "distributed": "dask",
    "ray": "ray",
}

#: Makes the modules of BLOCKED unimportable (as if not installed) in every interpreter that
#: has its folder on PYTHONPATH.
SITECUSTOMIZE = """
import importlib.abc
import sys

BLOCKED = {blocked!r}


class NotInstalled(importlib.abc.MetaPathFinder):
    def find_spec(self, name, path=None, target=None):
        if name.split(".")[0] in BLOCKED:
            raise ModuleNotFoundError(f"No module named {{name!r}}", name=name)


sys.meta_path.insert(0, NotInstalled())
"""


#: Optional packages that this environment lacks anyway (the cluster engines, often).
ABSENT = {name for name in OPTIONAL if importlib.util.find_spec(name) is None}


def needs_its_parent(package):
    """Blocking ``distributed`` alone means something only with dask installed."""
    if package == "distributed" and "dask" in ABSENT:
        pytest.skip("dask is not installed: --engine dask already stops at dask")


def run_without(blocked, arguments, tmp_path, code=None):
    """``python -m virtual_actuators ARGUMENTS`` (or ``python -c CODE``) without ``blocked``."""
    site = tmp_path / "site"
    site.mkdir(exist_ok=True)
    (site / "sitecustomize.py").write_text(SITECUSTOMIZE.format(blocked=tuple(blocked)))
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([str(site), str(ROOT)])}
    env["PYTHONWARNINGS"] = "ignore"
    command = ["-c", code] if code is not None else ["-m", "virtual_actuators", *arguments]
    return subprocess.run(
        [sys.executable, *command], capture_output=True, text=True, timeout=300, env=env,
        cwd=tmp_path, stdin=subprocess.DEVNULL, check=False,
    )  # fmt: skip


def assert_names_the_extra(run, package, extra):
    assert run.returncode == 2, (run.returncode, run.stdout[-500:], run.stderr[-3000:])
    assert "Traceback" not in run.stderr, run.stderr
    assert "usage:" in run.stderr, run.stderr
    message = run.stderr.strip().splitlines()[-1]
    assert f"package {package!r}" in message and f"extra [{extra}]" in message, message
    assert re.search(rf'pip install (-e )?"[^"]*\[{extra}\]"', message), message
    assert run.stdout == "", run.stdout  # refused before anything ran


PNG, HTML = "map.png", "run.html"

#: (the one missing package, the command line): every command that needs an optional package.
NEEDS = [
    *[("mujoco", ["demo", *name]) for name in ([], ["flamingo-slopes"], ["hexapod-walk"])],
    *[("mujoco", ["demo", name, "--quiet"]) for name in ("legged", "balance", "turkey-walk")],
    ("mujoco", ["demo", "hexapod-walk", "--terrain", "rolling"]),
    ("mujoco", ["sweep", "turkey-walk"]),
    ("mujoco", ["sweep", "hexapod-walk", "--quiet"]),
    ("tqdm", ["demo"]),
    ("tqdm", ["demo", "balance"]),
    ("tqdm", ["sweep", "turkey-walk"]),
    ("matplotlib", ["demo", "turkey-walk", "--quiet", "--plot", PNG]),
    ("matplotlib", ["demo", "legged", "--quiet", "--plot", PNG]),
    ("matplotlib", ["sweep", "turkey-walk", "--quiet", "--plot", PNG]),
    ("meshcat", ["demo", "turkey-walk", "--quiet", "--viz"]),
    ("meshcat", ["demo", "hexapod-walk", "--quiet", "--record", HTML]),
    ("meshcat", ["demo", "stand", "--viz"]),
    ("meshcat", ["demo", "stand", "--robot", "go2", "--record", HTML]),
    ("meshcat", ["example", "millipede", "--viz"]),
    ("meshcat", ["example", "single-leg", "--record", HTML]),
    ("dask", ["sweep", "turkey-walk", "--quiet", "--engine", "dask"]),
    ("distributed", ["sweep", "turkey-walk", "--quiet", "--engine", "dask"]),
    ("ray", ["sweep", "turkey-walk", "--quiet", "--engine", "ray"]),
]


@pytest.mark.parametrize(
    ("package", "arguments"), NEEDS, ids=[f"{p}: {' '.join(a)}" for p, a in NEEDS]
)
def test_a_missing_package_is_a_usage_error_naming_its_extra(package, arguments, tmp_path):
    needs_its_parent(package)
    run = run_without([package], arguments, tmp_path)
    assert_names_the_extra(run, package, OPTIONAL[package])
    assert sorted(p.name for p in tmp_path.iterdir()) == ["site"]  # no output file either


#: A core-only install: every optional package missing at once. The message names the first
#: the command needs.
CORE_ONLY = [
    (["demo"], "mujoco"),
    (["demo", "hexapod-walk"], "mujoco"),
    (["sweep", "turkey-walk"], "mujoco"),
    (["sweep", "flamingo-slopes", "--quiet", "--engine", "ray", "--plot", PNG], "matplotlib"),
    (["demo", "stand", "--viz"], "meshcat"),
    (["example", "hexapod-tripod", "--record", HTML], "meshcat"),
]


@pytest.mark.parametrize(
    ("arguments", "package"), CORE_ONLY, ids=[" ".join(a) for a, _ in CORE_ONLY]
)
def test_core_only_commands_that_need_an_extra_say_which(arguments, package, tmp_path):
    assert_names_the_extra(run_without(OPTIONAL, arguments, tmp_path), package, OPTIONAL[package])


@pytest.mark.parametrize(
    "arguments",
    [["robots"], ["example", "millipede"], ["demo", "stand", "--robot", "go2"], ["--version"],
     ["--help"], ["demo", "--help"], ["sweep", "--help"]],
    ids=" ".join,
)  # fmt: skip
def test_core_only_commands_that_need_no_extra_run(arguments, tmp_path):
    run = run_without(OPTIONAL, arguments, tmp_path)
    assert run.returncode == 0, run.stderr[-3000:]
    assert "Traceback" not in run.stderr and run.stdout, run.stderr


#: Imports every module of the package, then uses each optional feature: each must work or
#: raise MissingDependencyError naming its package and extra, never another import error.
LIBRARY = r"""
import importlib, json, pkgutil
import virtual_actuators
from virtual_actuators.exceptions import MissingDependencyError

found = []

def attempt(what, call):
    try:
        call()
    except MissingDependencyError as error:
        found.append([what, error.package, error.extra, str(error)])

for info in pkgutil.walk_packages(virtual_actuators.__path__, "virtual_actuators.",
                                  onerror=lambda name: None):
    if not info.name.endswith("__main__"):
        attempt(info.name, lambda: importlib.import_module(info.name))

def plot_map():
    from virtual_actuators.demos.sweep import plot_success_map
    plot_success_map([], "never.png")

def new_figure():
    from virtual_actuators.experiments.plot_panels import new_figure
    new_figure(1.0, 1.0)

def progress():
    from virtual_actuators.experiments.progress import Progress
    Progress(1.0).close()

def engine(name):
    from virtual_actuators.demos.sweep import run_sweep
    run_sweep([], engine=name)

attempt("plot_success_map", plot_map)
attempt("new_figure", new_figure)
attempt("Progress", progress)
attempt("va.viz", lambda: virtual_actuators.viz)
attempt("run_sweep dask", lambda: engine("dask"))
attempt("run_sweep ray", lambda: engine("ray"))
print(json.dumps(found))
"""

#: What each missing package must stop (at least), by the name attempt() gives it.
STOPS = {
    "mujoco": ["virtual_actuators.simulation", "virtual_actuators.experiments.contact_stats",
               "virtual_actuators.gaits.runner"],
    "meshcat": ["virtual_actuators.visualization", "virtual_actuators.viz", "va.viz"],
    "matplotlib": ["plot_success_map", "new_figure"],
    "tqdm": ["Progress"],
    "dask": ["run_sweep dask"],
    "distributed": ["run_sweep dask"],
    "ray": ["run_sweep ray"],
}  # fmt: skip


@pytest.mark.parametrize("package", sorted(OPTIONAL))
def test_the_library_raises_the_typed_error_naming_the_extra(package, tmp_path):
    needs_its_parent(package)
    run = run_without([package], [], tmp_path, code=LIBRARY)
    assert run.returncode == 0, run.stderr[-3000:]  # no other error escaped
    found = json.loads(run.stdout.strip().splitlines()[-1])
    for what, missing, extra, message in found:
        assert missing in {package} | ABSENT and extra == OPTIONAL[missing], (what, message)
        assert f"extra [{extra}]" in message, message
        # the install command, quoted, then the sentence goes on or ends (pip-installed copies
        # name their source folder: `pip install -e "/path[dask]".`)
        assert re.search(rf'\[{extra}\]"(\s|\.|$)', message), message
    stopped = {what for what, missing, *_ in found if missing == package}
    assert set(STOPS.get(package, [])) <= stopped, (package, stopped)
    if package == "yourdfpy":  # optional inside the core: nothing stops
        assert stopped == set(), stopped


def test_extras_in_all_match_the_project():
    project = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))["project"]
    extras = project["optional-dependencies"]
    everything = extras["all"][0]
    assert set(everything[len("virtual_actuators[") : -1].split(",")) == set(EXTRAS_IN_ALL)
    assert set(OPTIONAL.values()) <= set(extras)


#: A distribution's record of where pip installed it from (PEP 610), read by install_command.
INSTALLED = r"""
from virtual_actuators.exceptions import install_command
print(install_command("sim"))
print(install_command("ray"))
"""


def installed(tmp_path, record=None):
    """``install_command`` in a subprocess whose first distribution of the package is one made
    here: with ``direct_url.json`` holding ``record``, or without one (as from an index)."""
    info = tmp_path / "site" / "virtual_actuators-0.1.0.dist-info"
    info.mkdir(parents=True)
    (info / "METADATA").write_text("Metadata-Version: 2.1\nName: virtual_actuators\n"
                                   "Version: 0.1.0\n")  # fmt: skip
    if record is not None:
        (info / "direct_url.json").write_text(json.dumps(record))
    run = run_without([], [], tmp_path, code=INSTALLED)
    assert run.returncode == 0, run.stderr
    return run.stdout.strip().splitlines()


def test_the_install_command_without_a_record_is_for_the_source_folder(tmp_path):
    sim, ray = installed(tmp_path)
    assert sim == 'pip install -e ".[sim]" in the source folder (".[all]" for every extra)'
    assert ray == 'pip install -e ".[ray]" in the source folder'  # [all] does not bring it


@pytest.mark.parametrize(
    ("record", "expected"),
    [
        ({"dir_info": {"editable": True}}, 'pip install -e "{source}[sim]"'),
        ({"dir_info": {}}, 'pip install "{source}[sim]"'),
        ({"archive_info": {}}, 'pip install "{source}[sim]"'),
    ],
    ids=["editable", "folder", "wheel"],
)
def test_the_install_command_names_where_this_copy_came_from(record, expected, tmp_path):
    source = tmp_path / "clone of virtual_actuators"
    source.mkdir()
    sim, ray = installed(tmp_path, {"url": source.as_uri(), **record})
    assert sim == expected.format(source=source) + f' ("{source}[all]" for every extra)'
    assert ray == expected.format(source=source).replace("[sim]", "[ray]")


#: Install instructions that name the package as if it were on an index.
FROM_AN_INDEX = re.compile(r"""pip install\s+(-U\s+)?["']?virtual[_-]actuators\b""")


def test_no_instruction_installs_from_an_index():
    """The package is on no index: README, docs and messages say how to install from a clone."""
    paths = [
        ROOT / "README.md",
        *(ROOT / "docs").rglob("*.md"),
        *(ROOT / "virtual_actuators").rglob("*.py"),
        *(ROOT / "tests").rglob("*.py"),
    ]
    found = []
    for path in paths:
        for number, line in enumerate(path.read_text(encoding="utf-8").splitlines(), 1):
            if FROM_AN_INDEX.search(line) and path.name != Path(__file__).name:
                found.append(f"{path.relative_to(ROOT)}:{number}: {line.strip()}")
    assert found == [], "\n".join(found)
