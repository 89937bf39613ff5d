"""The documentation site renders offline and as written: no raw roles, math drawn, figures whole.

- No reStructuredText role (``:class:`Snapshot` ``, ``:py:meth:...``) in a docstring of the package
  or a page: mkdocstrings reads Markdown, so a role would show as raw text.
- The built site (``mkdocs build --strict``, the ``docs`` extra) shows no raw role on any page,
  has its formulas as MathML (drawn by the browser, no script), loads no script, stylesheet or
  font from the network, draws docstring examples as code, and has the Simulation reference
  page. Its build refuses a page with a role. (Built once per session, ~20 s: marked slow.)
- Every label of the figures in docs/img lies inside its figure and clear of the other labels,
  as headless Chromium lays them out.

Without mkdocs (or Chromium) these are skipped, except under CI (``CI`` set), where they fail.
"""

from __future__ import annotations

import ast
import html
import json
import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
DOCS = ROOT / "docs"
# any role: ``:name:`` or ``:domain:name:`` right before a backtick (one or two)
ROLE_SOURCE = re.compile(r":(?:[A-Za-z]+:)?[A-Za-z][\w-]*:`")
# the same as Markdown renders it (an inline code span) or leaves it
ROLE_HTML = re.compile(r":(?:[A-Za-z]+:)?[A-Za-z][\w-]*:(?:<code[ >]|`)")
# code shown on purpose (a role quoted as an example in ``...`` or a block) is not a raw role
CODE_SOURCE = re.compile(r"(?<!:)``.+?``|^\s*```.*?^\s*```", re.DOTALL | re.MULTILINE)
CODE_HTML = re.compile(r"<pre\b.*?</pre>|(<code\b[^>]*>).*?</code>", re.DOTALL)


def roles_in_source(text: str) -> list[str]:
    return [m.group(0) for m in ROLE_SOURCE.finditer(CODE_SOURCE.sub("", text))]


def roles_in_html(text: str) -> list[str]:
    prose = CODE_HTML.sub(lambda m: m.group(1) or "", text)  # keeps ``:role:<code>``
    return [prose[m.start() : m.start() + 50] for m in ROLE_HTML.finditer(prose)]


def need(module: str):
    if os.environ.get("CI"):
        return __import__(module)
    return pytest.importorskip(module, reason=f"{module} (the docs extra) is not installed")


def docstrings(path: Path):
    tree = ast.parse(path.read_text(encoding="utf-8"))
    for node in ast.walk(tree):
        if (
            isinstance(node, ast.Expr)
            and isinstance(node.value, ast.Constant)
            and isinstance(node.value.value, str)
        ):
            yield node.lineno, node.value.value


def test_the_role_patterns_catch_every_form():
    forms = [
        ":class:`~virtual_actuators.Snapshot`", ":func:`run`", ":meth:`Controller.compute`",
        ":attr:`x`", ":mod:`virtual_actuators.events`", ":data:`AXES`", ":py:class:`Robot`",
        ":exc:`ValueError`", ":obj:`x`", ":ref:`label`", ":meth:`Viewer.show <a.b.show>`",
        ":class:``Robot``",
    ]
    assert all(roles_in_source(f"A {form} here.") for form in forms)
    for form in forms:
        rendered = re.sub(r"``?([^`]+)``?", r"<code>\1</code>", form)
        assert roles_in_html(f"<p>A {rendered} here.</p>") and roles_in_html(form), form
    prose = [
        "Returns: the value", "``q[:3]``", "a ratio 1:2", "[`Snapshot`][]",
        "see [`run`][virtual_actuators.run]", "http://localhost:7000/static/",
        "a role is written ``:class:`Snapshot` ``", "```rst\n:class:`Snapshot`\n```",
    ]
    assert not any(roles_in_source(text) for text in prose)
    shown = ["<code>:class:`Snapshot`</code>", "<pre><code>:func:`run`</code></pre>"]
    assert not any(roles_in_html(text) for text in shown + prose[:-2])


def test_docstrings_and_pages_have_no_rest_roles():
    found = [
        f"{path.relative_to(ROOT)}:{line}: {role}"
        for path in sorted((ROOT / "virtual_actuators").rglob("*.py"))
        for line, text in docstrings(path)
        for role in roles_in_source(text)
    ]
    found += [
        f"{path.relative_to(ROOT)}: {role}"
        for path in sorted(DOCS.rglob("*.md"))
        for role in roles_in_source(path.read_text(encoding="utf-8"))
    ]
    assert found == [], (
        "reStructuredText roles show as raw text on the site; write "
        "[`Name`][package.Name] (or run `PYTHONPATH=. python tools/rewrite_roles.py`):\n"
        + "\n".join(found)
    )


def mkdocs_build(config: Path, site: Path) -> subprocess.CompletedProcess:
    env = dict(os.environ, PYTHONPATH=str(ROOT), NO_MKDOCS_2_WARNING="1")
    return subprocess.run(
        [sys.executable, "-m", "mkdocs", "build", "--strict", "-f", str(config), "-d", str(site)],
        cwd=config.parent, env=env, capture_output=True, text=True, timeout=600,
    )


def small_site(tmp_path: Path, page: str) -> subprocess.CompletedProcess:
    """Build a one-page site with this site's hooks and math extension."""
    need("mkdocs")
    need("latex2mathml")
    (tmp_path / "docs").mkdir()
    (tmp_path / "docs" / "index.md").write_text(page, encoding="utf-8")
    config = tmp_path / "mkdocs.yml"
    config.write_text(
        "site_name: t\nmarkdown_extensions:\n  - pymdownx.arithmatex:\n      generic: true\n"
        f"hooks:\n  - {ROOT / 'tools' / 'docs_hooks.py'}\n",
        encoding="utf-8",
    )
    return mkdocs_build(config, tmp_path / "site")


def test_the_build_refuses_a_page_with_a_raw_role(tmp_path):
    result = small_site(tmp_path, "# Page\n\nUse :class:`~pkg.Snapshot` here.\n")
    assert result.returncode != 0
    assert "raw reStructuredText roles" in result.stderr and "index.md" in result.stderr


def test_the_build_draws_math_as_mathml(tmp_path):
    result = small_site(tmp_path, "# Page\n\n$$ \\tau = J^T F $$\n\nand \\(x_1^2\\) inline.\n")
    assert result.returncode == 0, result.stderr
    page = (tmp_path / "site" / "index.html").read_text(encoding="utf-8")
    assert '<math xmlns="http://www.w3.org/1998/Math/MathML" display="block">' in page
    assert "<msup><mi>J</mi><mi>T</mi></msup>" in page
    assert '<math xmlns="http://www.w3.org/1998/Math/MathML" display="inline">' in page
    assert "<msubsup><mi>x</mi><mn>1</mn><mn>2</mn></msubsup>" in page
    assert "arithmatex" not in page and "\\tau" not in page


@pytest.fixture(scope="module")
def site(tmp_path_factory) -> Path:
    need("mkdocs")
    need("latex2mathml")
    site = tmp_path_factory.mktemp("site")
    result = mkdocs_build(ROOT / "mkdocs.yml", site)
    assert result.returncode == 0, result.stderr[-4000:]
    return site


@pytest.mark.slow
def test_no_page_shows_a_raw_role(site):
    pages = sorted(site.rglob("*.html"))
    assert len(pages) > 20
    found = [
        f"{page.relative_to(site)}: {html.unescape(role)!r}"
        for page in pages
        for role in roles_in_html(page.read_text(encoding="utf-8"))
    ]
    assert found == []


@pytest.mark.slow
def test_the_concepts_formula_is_mathml(site):
    page = (site / "concepts" / "index.html").read_text(encoding="utf-8")
    formula = re.search(r'<math [^>]*display="block">.*?</math>', page, re.DOTALL)
    assert formula is not None
    assert "<msup><mi>J</mi><mi>T</mi></msup>" in formula.group(0)
    assert "&#x003C4;" in formula.group(0) or "τ" in formula.group(0)  # tau
    assert "\\tau" not in page  # no TeX left as text
    assert not [p for p in site.rglob("*.html") if 'class="arithmatex"' in p.read_text("utf-8")]


@pytest.mark.slow
def test_pages_load_nothing_from_the_network(site):
    remote = re.compile(r"""<(?:script|link|img|iframe)\b[^>]*\b(?:src|href)=["'](?:https?:)?//""")
    found = [
        f"{page.relative_to(site)}: {m.group(0)}"
        for page in sorted(site.rglob("*.html"))
        for m in remote.finditer(page.read_text(encoding="utf-8"))
    ]
    assert found == []


@pytest.mark.slow
def test_the_simulation_reference_documents_the_simulator(site):
    page = (site / "reference" / "simulation" / "index.html").read_text(encoding="utf-8")
    for member in ("push", "reset", "step", "on_ground", "in_contact", "contact_switches",
                   "contact_force", "contact_forces", "touching_terrain"):
        assert f'id="virtual_actuators.simulation.Simulator.{member}"' in page, member
    assert 'id="virtual_actuators.simulation.Terrain"' in page
    nav = (site / "index.html").read_text(encoding="utf-8")
    assert "reference/simulation/" in nav


@pytest.mark.slow
def test_docstring_examples_are_code(site):
    # doctest lines read as Markdown become quotes within quotes (">>>"), run together
    nested = [
        str(page.relative_to(site))
        for page in sorted(site.rglob("*.html"))
        if re.search(r"<blockquote>\s*<blockquote>", page.read_text(encoding="utf-8"))
    ]
    assert nested == []
    page = (site / "reference" / "simulation" / "index.html").read_text(encoding="utf-8")
    example = re.search(r"<pre.*?</pre>", page[page.index("Examples:") :], re.DOTALL)
    assert example is not None and "&gt;&gt;&gt;" in example.group(0)
    assert "spring_turkey" in example.group(0)


SVG_LAYOUT = """<!doctype html><html><body>{svg}<pre id="layout"></pre><script>
const svg = document.querySelector("svg"), box = svg.viewBox.baseVal;
const labels = [...svg.querySelectorAll("text")].map(t => {{
  const b = t.getBBox(); return [t.textContent, b.x, b.y, b.width, b.height]; }});
document.getElementById("layout").textContent =
  JSON.stringify({{view: [box.x, box.y, box.width, box.height], labels}});
</script></body></html>"""


def svg_layout(svg: Path, tmp_path: Path, chromium: str) -> dict:
    """The figure's view box and each label's box, as Chromium lays them out."""
    page = tmp_path / f"{svg.stem}.html"
    page.write_text(SVG_LAYOUT.format(svg=svg.read_text(encoding="utf-8")), encoding="utf-8")
    out = subprocess.run(
        [chromium, "--headless", "--no-sandbox", "--disable-gpu", "--virtual-time-budget=2000",
         "--dump-dom", page.as_uri()],
        capture_output=True, text=True, timeout=120,
    ).stdout
    match = re.search(r'<pre id="layout">(.*?)</pre>', out, re.DOTALL)
    assert match is not None, out[-2000:]
    return json.loads(html.unescape(match.group(1)))


def overlap(a: list, b: list) -> bool:
    return a[1] < b[1] + b[3] and b[1] < a[1] + a[3] and a[2] < b[2] + b[4] and b[2] < a[2] + a[4]


@pytest.mark.slow
@pytest.mark.parametrize("svg", sorted(DOCS.rglob("*.svg")), ids=lambda p: p.name)
def test_figure_labels_are_inside_and_apart(svg, tmp_path):
    chromium = shutil.which("chromium") or shutil.which("chromium-browser")
    if chromium is None:
        if os.environ.get("CI"):
            pytest.fail("CI must provide Debian's chromium", pytrace=False)
        pytest.skip("chromium is not installed")
    layout = svg_layout(svg, tmp_path, chromium)
    x0, y0, width, height = layout["view"]
    labels = layout["labels"]
    assert labels and all(label[3] > 0 for label in labels)
    margin = 2.0  # [px] of the view box
    outside = [
        label[0] for label in labels
        if label[1] < x0 + margin or label[2] < y0 + margin
        or label[1] + label[3] > x0 + width - margin or label[2] + label[4] > y0 + height - margin
    ]
    assert outside == [], f"{svg.name}: labels cut by the figure's edge: {outside}"
    clashes = [
        (a[0], b[0]) for i, a in enumerate(labels) for b in labels[i + 1 :] if overlap(a, b)
    ]
    assert clashes == [], f"{svg.name}: labels drawn over each other: {clashes}"
