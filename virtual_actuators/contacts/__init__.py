"""Contacts: what each kind of contact demands of the forces, as rows ``lows <= G x <= uppers``."""

from .constraint import Constraint, TorqueLimits
from .contact_set import ContactSet, declare

__all__ = ["Constraint", "ContactSet", "TorqueLimits", "declare"]
