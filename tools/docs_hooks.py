r"""MkDocs hooks of this site (``hooks:`` in mkdocs.yml): math drawn at build time, no raw roles.

Math: ``pymdownx.arithmatex`` (generic mode) wraps TeX as ``<span class="arithmatex">\(..\)``
and ``<div class="arithmatex">\[..\]``, which nothing would draw without a script. Each is
replaced here by MathML (``latex2mathml``, in the ``docs`` extra), which browsers draw natively:
the built site needs no script, font or network to show its formulas. TeX that cannot be
converted fails the build, naming the page.

Roles: a reStructuredText role (``:class:`Snapshot```, ``:py:meth:...``) left in a docstring or a
page shows as raw text, since mkdocstrings reads Markdown. The build fails listing every page and
role left; ``tools/rewrite_roles.py`` writes them as mkdocstrings cross-references.
"""

from __future__ import annotations

import html
import re

from latex2mathml.converter import convert
from mkdocs.exceptions import PluginError

# arithmatex's generic output: the TeX, HTML-escaped, between \( \) or \[ \]
_MATH = re.compile(
    r'<(?P<tag>span|div) class="arithmatex">\s*\\(?P<open>[(\[])(?P<tex>.*?)\\[)\]]\s*</(?P=tag)>',
    re.DOTALL,
)
# a role as Markdown renders it (``:role:<code>..``) or leaves it (``:role:`..``)
_ROLE = re.compile(r":(?:[a-z]+:)?[a-z]+:(?:<code>|`)")
# code shown on purpose (a role quoted as an example): blocks dropped, inline code emptied
_CODE = re.compile(r"<pre\b.*?</pre>|(?<=<code>).*?(?=</code>)", re.DOTALL)

_raw_roles: dict[str, list[str]] = {}


def on_pre_build(config) -> None:  # noqa: ARG001 - mkdocs passes the config
    """Forget the roles found by a previous build (``mkdocs serve`` rebuilds)."""
    _raw_roles.clear()


def render_math(content: str, where: str) -> str:
    """Replace every arithmatex wrapper in ``content`` by its MathML.

    Args:
        content: A page's HTML.
        where: The page, for error messages.

    Returns:
        The HTML with ``<math>`` elements in place of the wrappers.

    Raises:
        PluginError: If a formula cannot be converted, or a wrapper is left unconverted.

    """

    def to_mathml(match: re.Match[str]) -> str:
        tex = html.unescape(match["tex"]).strip()
        display = "block" if match["open"] == "[" else "inline"
        try:
            mathml = convert(tex, display=display)
        except Exception as error:  # latex2mathml raises its own and plain exceptions
            raise PluginError(f"{where}: cannot draw the formula {tex!r}: {error}") from error
        return mathml

    content = _MATH.sub(to_mathml, content)
    if 'class="arithmatex"' in content:
        raise PluginError(f"{where}: a formula was left undrawn (unexpected arithmatex output).")
    return content


def on_page_content(html_text: str, page, config, files) -> str:  # noqa: ARG001
    """Draw the page's math and note its raw roles."""
    where = page.file.src_uri
    prose = _CODE.sub("", html_text)
    roles = [prose[m.start() : m.start() + 60] for m in _ROLE.finditer(prose)]
    if roles:
        _raw_roles[where] = roles
    return render_math(html_text, where)


def on_post_build(config) -> None:  # noqa: ARG001
    """Fail the build if a page shows a raw role.

    Raises:
        PluginError: Listing each page and the start of each role found on it.

    """
    if _raw_roles:
        lines = [
            f"  {page}: {len(roles)}, e.g. {' '.join(html.unescape(roles[0]).split())!r}"
            for page, roles in sorted(_raw_roles.items())
        ]
        total = sum(len(roles) for roles in _raw_roles.values())
        raise PluginError(
            f"{total} raw reStructuredText roles on {len(_raw_roles)} pages (write "
            "[`Name`][package.module.Name] cross-references, or run "
            "`PYTHONPATH=. python tools/rewrite_roles.py`):\n" + "\n".join(lines)
        )
