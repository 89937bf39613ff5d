"""Contacts, one concept: what each kind of contact demands of the forces, as rows.

``constraint.py`` the rows ``lows <= G x <= uppers`` over ``x = forces.ravel()`` (mink's ``Limit``
-> ``Constraint`` pattern); ``declare.py`` the declaration (normals, reactions); one file per kind,
each with its natural-constraint columns (``ball_axes``), row names, numpy rows (the compiled core
has their C++ twins, ``src/core/contact_rows.hpp``): ``point.py`` the friction pyramid and least
normal force, ``flat.py`` the sole (centre of pressure, yaw moment); ``kinds.py`` the kinds by name
and each reaction's kind; ``contact_set.py`` the `ContactSet` of one actuator, declared once by
`declare` and read by the QP and by the controller's yield policy (with its compiled margins);
``torque_limits.py`` the joints' torque limits. The distribution layer stacks the rows into its QP;
contacts take what they need (the torque map, the kinematic state) as arguments and import nothing
from it.
"""

from .constraint import Constraint
from .contact_set import ContactSet, declare
from .torque_limits import TorqueLimits

__all__ = ["Constraint", "ContactSet", "TorqueLimits", "declare"]
