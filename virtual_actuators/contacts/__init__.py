"""Contacts: what each kind of contact demands of the forces, as rows ``lows <= G x <= uppers``."""

from .constraint import Constraint
from .contact_set import ContactSet, declare
from .torque_limits import TorqueLimits

__all__ = ["Constraint", "ContactSet", "TorqueLimits", "declare"]
