"""Blind slope walking (VMC section 6): Spring Flamingo over unknown slopes."""

from .parameters import FlamingoParameters
from .walker import FlamingoWalker

__all__ = ["FlamingoParameters", "FlamingoWalker"]
