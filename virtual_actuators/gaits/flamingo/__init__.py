"""Blind slope walking (VMC section 6): Spring Flamingo over unknown slopes."""

from .walker import FlamingoParameters, FlamingoWalker

__all__ = ["FlamingoParameters", "FlamingoWalker"]
