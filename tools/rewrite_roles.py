"""Rewrite the reStructuredText roles of the package's docstrings as mkdocstrings cross-references.

The API reference (docs/reference) renders docstrings as Markdown, where a Sphinx role such as
``:class:`~virtual_actuators.Snapshot``` shows as raw text (and the site's build refuses it:
tools/docs_hooks.py). This script rewrites each role found in a docstring of
``virtual_actuators/`` (nothing else in the file is touched):

- to a cross-reference ``[`Snapshot`][virtual_actuators.Snapshot]`` when the object it names is
  rendered in the site (its identifier is in the built site's ``objects.inv``), with the anchor
  the site uses (the public path, ``virtual_actuators.Snapshot``, rather than the module it is
  defined in);
- to plain code, ``Snapshot``, when it is not rendered (a private module, numpy, MuJoCo...).

The name is resolved the way Python would from the docstring's place (its class, its module's
own names and imports, then the package), then by a unique match of its dotted tail in the
package (Sphinx's ``.name`` search). The text shown is the role's: its explicit title
(``Title <target>``), the last component with ``~``, else the target as written. A line the
rewrite makes longer than 100 characters is wrapped at a space outside code and links, its
continuation indented as the docstring's structure needs (Google-style section items by 4).

It is idempotent (a second run finds no role) and deterministic (the same sources and docs give
the same text). Run it from the repository root, with the ``docs`` extra installed:

    PYTHONPATH=. python tools/rewrite_roles.py            # rewrite in place, list what it did
    PYTHONPATH=. python tools/rewrite_roles.py --check    # exit 1 if a docstring has a role

It builds the site once (about 15 s, without the hook that refuses roles) to know what is
rendered; ``--inventory site/objects.inv`` reuses a built site's inventory instead.
"""

from __future__ import annotations

import argparse
import ast
import logging
import os
import re
import sys
import tempfile
import zlib
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
PACKAGE = "virtual_actuators"
MAX_LINE = 100
# a role, its body possibly split over lines (backslash continuations included)
ROLE = re.compile(r":(?:py:)?(?P<role>[a-z]+):`(?P<body>[^`]+)`")
# Google-style sections whose entries are items: a continuation line must be indented deeper
ITEM_SECTIONS = {
    "Args", "Arguments", "Parameters", "Params", "Attributes", "Raises", "Exceptions",
    "Returns", "Return", "Yields", "Yield", "Warns", "Other Parameters", "Keyword Args",
    "Keyword Arguments", "Receives", "Functions", "Classes", "Modules",
}
LIST_ITEM = re.compile(r"(?:[-*+]|\d+\.) ")


# -- what the site renders -----------------------------------------------------------------------


def read_inventory(path: Path) -> dict[str, str]:
    """Map each identifier of a Sphinx inventory (objects.inv) to the anchor it links to."""
    data = path.read_bytes()
    body = zlib.decompress(data.split(b"\n", 4)[4]).decode()
    anchors = {}
    for line in body.splitlines():
        name, _domain, _priority, uri, *_ = line.split(" ")
        anchor = uri.split("#", 1)[1] if "#" in uri else ""
        anchors[name] = name if anchor in ("", "$") else anchor
    return anchors


def build_inventory() -> dict[str, str]:
    """Build the site into a temporary folder (hooks off) and read its inventory."""
    from mkdocs.commands.build import build
    from mkdocs.config import load_config

    logging.getLogger("mkdocs").setLevel(logging.ERROR)
    os.chdir(ROOT)  # mkdocs.yml's paths (the griffe extension, the package) are the root's
    with tempfile.TemporaryDirectory() as site:
        config = load_config(
            str(ROOT / "mkdocs.yml"), site_dir=site, hooks=[], strict=False
        )
        build(config)
        return read_inventory(Path(site) / "objects.inv")


# -- resolving a name ------------------------------------------------------------------------------


class Resolver:
    """Resolve role targets to objects of the package, with griffe (static analysis)."""

    def __init__(self) -> None:
        import griffe

        self.package = griffe.load(PACKAGE, search_paths=[str(ROOT)], resolve_aliases=False)
        self._tails: dict[str, set[str]] | None = None

    def get(self, path: str):
        """The object at a dotted path (through aliases), or None."""
        if path == PACKAGE:
            return self.package
        if not path.startswith(PACKAGE + "."):
            return None
        obj = self.package
        for part in path[len(PACKAGE) + 1 :].split("."):
            obj = self.member(obj, part)
            if obj is None:
                return None
        return obj

    def member(self, obj, name: str):
        """A member of ``obj`` (inherited ones included for classes), or None."""
        try:
            return (obj.all_members if obj.is_class else obj.members).get(name)
        except Exception:  # an alias to an external or cyclic target
            return None

    def paths(self, obj) -> list[str]:
        """``obj``'s path and, if it is an alias, its target's paths."""
        out = [obj.path]
        try:
            target = obj.final_target if obj.is_alias else obj
            out.append(target.path)
        except Exception:  # an alias to something outside the package (numpy...)
            if obj.is_alias:
                out.append(obj.target_path)
        return out

    def scopes(self, context: str) -> Iterator:
        """The docstring's owner and its parents, innermost first."""
        obj = self.get(context)
        while obj is None and "." in context:
            context = context.rsplit(".", 1)[0]
            obj = self.get(context)
        while obj is not None:
            yield obj
            obj = obj.parent

    def scoped(self, name: str, context: str) -> str | None:
        """The path mkdocstrings' scoped cross-references give ``name`` in a docstring, or None.

        The same rule as theirs (``scoped_crossrefs``): the first component resolved by griffe
        from the docstring's object outwards, the rest appended.
        """
        head, _, rest = name.partition(".")
        try:
            path = next(self.scopes(context)).resolve(head)
        except Exception:  # not a name in scope
            return None
        return f"{path}.{rest}" if rest else path

    def by_tail(self, tail: str) -> set[str]:
        """Definition paths of the package's objects known by a path ending with ``.tail``."""
        if self._tails is None:
            self._tails = {}
            for obj in self._walk(self.package):
                defined = self.paths(obj)[-1]
                if not defined.startswith(PACKAGE + "."):
                    continue  # an import from outside the package
                parts = obj.path.split(".")
                for k in range(1, len(parts)):
                    self._tails.setdefault(".".join(parts[k:]), set()).add(defined)
        return self._tails.get(tail, set())

    def _walk(self, obj) -> Iterator:
        """Every member of ``obj``, aliases (imports) included, modules and classes recursed."""
        for member in obj.members.values():
            yield member
            if not member.is_alias and (member.is_module or member.is_class):
                yield from self._walk(member)

    def resolve(self, target: str, context: str, relative: bool) -> list[str]:
        """Paths (alias path first, then definition) that ``target`` names from ``context``."""
        if target == PACKAGE or target.startswith(PACKAGE + "."):
            obj = self.get(target)
            return [target, *self.paths(obj)] if obj is not None else [target]
        head, _, rest = target.partition(".")
        if relative:  # Sphinx's ``.name``: the docstring's module, its package, then anywhere
            module = next(scope for scope in self.scopes(context) if scope.is_module)
            for base in (module, module.parent):
                obj = self.get(f"{base.path}.{target}") if base is not None else None
                if obj is not None:
                    return self.paths(obj)
        else:
            for scope in self.scopes(context):
                obj = self.member(scope, head)
                for part in rest.split(".") if rest else ():
                    obj = self.member(obj, part) if obj is not None else None
                if obj is not None:
                    return self.paths(obj)
        found = self.by_tail(target)
        if len(found) == 1:
            return self.paths(self.get(found.pop()))
        return []


# -- rewriting -------------------------------------------------------------------------------------


@dataclass
class Rewrite:
    """What one role became."""

    file: str
    line: int
    role: str
    text: str


def split_body(body: str) -> tuple[str | None, str]:
    """``(explicit title or None, target)`` of a role's body, line breaks removed."""
    body = re.sub(r"\\\n\s*|\n\s*", "", body).strip()
    match = re.fullmatch(r"(?P<title>.+?)\s*<(?P<target>[^<>]+)>", body)
    if match:
        return match["title"], match["target"].strip()
    return None, body


def replacement(
    body: str, context: str, resolver: Resolver, anchors: dict[str, str]
) -> str:
    """The Markdown that replaces one role: a cross-reference or plain code."""
    title, target = split_body(body)
    target = target.lstrip("!")
    short = target.startswith("~")
    target = target.lstrip("~")
    relative = target.startswith(".")
    target = target.lstrip(".").removesuffix("()")
    if title is None:
        title = target.rsplit(".", 1)[-1] if short else target
    for path in resolver.resolve(target, context, relative):
        if path in anchors:
            if anchors.get(resolver.scoped(title, context) or "") == anchors[path]:
                return f"[`{title}`][]"  # mkdocstrings resolves the title from the docstring
            return f"[`{title}`][{anchors[path]}]"
    return f"`{title}`"


def docstrings(tree: ast.Module, module: str) -> Iterator[tuple[ast.Constant, str]]:
    """Every string statement (docstrings, attribute docstrings) with its owner's path."""

    def visit(node: ast.AST, owner: str) -> Iterator[tuple[ast.Constant, str]]:
        for child in ast.iter_child_nodes(node):
            if isinstance(child, (ast.ClassDef, ast.FunctionDef, ast.AsyncFunctionDef)):
                yield from visit(child, f"{owner}.{child.name}")
            elif (
                isinstance(child, ast.Expr)
                and isinstance(child.value, ast.Constant)
                and isinstance(child.value.value, str)
            ):
                yield child.value, owner
            else:
                yield from visit(child, owner)

    yield from visit(tree, module)


def module_name(path: Path) -> str:
    """The dotted module name of a source file of the package."""
    parts = list(path.relative_to(ROOT).with_suffix("").parts)
    if parts[-1] == "__init__":
        parts.pop()
    return ".".join(parts)


def continuation_indent(lines: list[str], k: int, first: int) -> int:
    """The indentation a wrapped piece of ``lines[k]`` needs, from the docstring's structure."""
    line = lines[k]
    indent = len(line) - len(line.lstrip(" "))
    text = line.strip()
    for j in range(k - 1, first - 1, -1):
        above = lines[j]
        if above.strip() and len(above) - len(above.lstrip(" ")) < indent:
            if above.strip().rstrip(":") in ITEM_SECTIONS and above.strip().endswith(":"):
                return indent + 4
            break
    marker = LIST_ITEM.match(text)
    return indent + len(marker.group(0)) if marker else indent


def protected(line: str) -> list[tuple[int, int]]:
    """Spans of ``line`` not to break: code spans and links."""
    spans = []
    for match in re.finditer(r"\[`[^`]*`\]\[[^\]]*\]|`[^`]*`|\[[^\]]*\]\[[^\]]*\]", line):
        spans.append(match.span())
    return spans


def unlink(line: str) -> str:
    """``line`` with its last cross-references made plain code until it fits, if it can."""
    links = list(re.finditer(r"\[(?P<title>`[^`]*`)\]\[[^\]]*\]", line))
    while len(line) > MAX_LINE and links:
        link = links.pop()
        line = line[: link.start()] + link["title"] + line[link.end() :]
    return line


def wrap(line: str, indent: int) -> list[str]:
    """``line`` broken at spaces outside code and links, so that each piece fits."""
    out = []
    while len(line) > MAX_LINE:
        spans = protected(line)
        start = len(line) - len(line.lstrip(" "))
        breaks = [
            i for i in range(start + 1, MAX_LINE + 1)
            if line[i] == " " and not any(a < i < b for a, b in spans)
        ]
        if not breaks:
            break
        cut = breaks[-1]
        out.append(line[:cut].rstrip())
        line = " " * indent + line[cut:].lstrip()
    out.append(line)
    return out


def rewrite_file(
    path: Path, resolver: Resolver, anchors: dict[str, str], log: list[Rewrite]
) -> str | None:
    """The file's new text, or None when none of its docstrings has a role."""
    source = path.read_text(encoding="utf-8")
    if not ROLE.search(source):
        return None
    raw = source.encode("utf-8")
    starts = [0]
    for line in raw.splitlines(keepends=True):
        starts.append(starts[-1] + len(line))
    module = module_name(path)
    edits = []
    for node, owner in docstrings(ast.parse(source), module):
        begin = starts[node.lineno - 1] + node.col_offset
        end = starts[node.end_lineno - 1] + node.end_col_offset
        text = raw[begin:end].decode("utf-8")
        if not ROLE.search(text):
            continue

        def swap(match: re.Match[str], node=node, owner=owner, text=text) -> str:
            new = replacement(match["body"], owner, resolver, anchors)
            line = node.lineno + text.count("\n", 0, match.start())
            log.append(Rewrite(str(path.relative_to(ROOT)), line, match.group(0), new))
            return new

        edits.append((begin, end, ROLE.sub(swap, text)))
    if not edits:
        return None
    for begin, end, new in sorted(edits, reverse=True):
        raw = raw[:begin] + new.encode("utf-8") + raw[end:]
    return wrap_long_lines(source, raw.decode("utf-8"))


def wrap_long_lines(old: str, new: str) -> str:
    """Wrap the lines of the rewritten docstrings that became longer than the limit."""
    old_lines = set(old.splitlines())
    lines = new.splitlines(keepends=True)
    tree = ast.parse(new)
    spans = [
        (node.lineno - 1, node.end_lineno - 1)
        for node, _ in docstrings(tree, "")
    ]
    out: list[str] = []
    for k, line in enumerate(lines):
        body = line.rstrip("\n")
        inside = next(((a, b) for a, b in spans if a <= k <= b), None)
        if len(body) <= MAX_LINE or body in old_lines or inside is None or ">>>" in body:
            out.append(line)
            continue
        plain = [x.rstrip("\n") for x in lines]
        first = inside[0]
        if k == first:  # a summary is one line (ruff D205): links that do not fit become code
            body = unlink(body)
            out.append(body + "\n")
            continue
        indent = continuation_indent(plain, k, first)
        out.extend(piece + "\n" for piece in wrap(body, indent))
    text = "".join(out)
    return text if new.endswith("\n") else text.rstrip("\n")


def sources() -> list[Path]:
    """The package's Python files, in a fixed order."""
    return sorted((ROOT / PACKAGE).rglob("*.py"))


def find_roles() -> list[str]:
    """``file:line: role`` for every role left in a docstring."""
    found = []
    for path in sources():
        source = path.read_text(encoding="utf-8")
        for node, _ in docstrings(ast.parse(source), ""):
            for match in ROLE.finditer(node.value):
                line = node.lineno + node.value.count("\n", 0, match.start())
                found.append(f"{path.relative_to(ROOT)}:{line}: {match.group(0)}")
    return found


def main(argv: list[str] | None = None) -> int:
    """Rewrite (or, with ``--check``, list) the roles of the package's docstrings."""
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--check", action="store_true", help="list roles left; exit 1 if any")
    parser.add_argument("--inventory", type=Path, help="objects.inv of a built site to use")
    args = parser.parse_args(argv)
    if args.check:
        found = find_roles()
        print("\n".join(found) if found else "no reStructuredText role in the docstrings")
        return 1 if found else 0
    anchors = read_inventory(args.inventory) if args.inventory else build_inventory()
    resolver = Resolver()
    log: list[Rewrite] = []
    changed = 0
    for path in sources():
        text = rewrite_file(path, resolver, anchors, log)
        if text is not None:
            path.write_text(text, encoding="utf-8")
            changed += 1
    links = sum(1 for r in log if r.text.startswith("["))
    for r in log:
        print(f"{r.file}:{r.line}: {r.role!r} -> {r.text}")
    print(
        f"{len(log)} roles in {changed} files: {links} cross-references, "
        f"{len(log) - links} plain code",
        file=sys.stderr,
    )
    left = find_roles()
    if left:
        print("roles left (not in a docstring the script reads):", *left, sep="\n", file=sys.stderr)
    return 1 if left else 0


if __name__ == "__main__":
    sys.exit(main())
