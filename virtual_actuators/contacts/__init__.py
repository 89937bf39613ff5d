"""Contacts, one concept: what each kind of contact demands of the forces, as rows.

``constraint.py`` the rows ``lows <= G x <= uppers`` over ``x = forces.ravel()`` (mink's
``Limit`` -> ``Constraint`` pattern); ``declare.py`` the declaration (kinds, normals); one file
per kind, each with its row names, numpy rows and compiled (njit) rows: ``point.py`` the
friction pyramid and least normal force, ``flat.py`` the sole (centre of pressure, yaw moment);
``kinds.py`` the kinds by name (``KINDS``, ``parse_contacts``, ``ball_axes``);
``kinds.py`` the kinds by name and each reaction's kind; ``torque_limits.py`` the joints'
torque limits. The distribution layer stacks them into its QP;
contacts take what they need (the torque map, the kinematic state) as arguments and import
nothing from it.
"""

from .constraint import Constraint
from .torque_limits import TorqueLimits

__all__ = ["Constraint", "TorqueLimits"]
