"""Griffe extension of the docs: a Google-style ``Example:`` section is read as ``Examples:``.

Griffe reads only ``Examples:`` as doctest examples, drawn as code. Under ``Example:`` (which the
Google style guide and Sphinx's napoleon accept too, and this package's docstrings use) it makes
an admonition, where Markdown turns the ``>>>`` lines into nested quotes run together. Listed in
mkdocs.yml (the python handler's ``extensions``).
"""

from __future__ import annotations

import re
from typing import Any

import griffe

_EXAMPLE = re.compile(r"^(?P<indent>[ \t]*)Example:[ \t]*$", re.MULTILINE)


class ExampleSections(griffe.Extension):
    """Rename each docstring's ``Example:`` section ``Examples:`` as the object is loaded."""

    def on_instance(self, *, obj: griffe.Object, **kwargs: Any) -> None:  # noqa: ARG002
        """Rename the section in ``obj``'s docstring, if it has one."""
        if obj.docstring is not None:
            obj.docstring.value = _EXAMPLE.sub(r"\g<indent>Examples:", obj.docstring.value)
