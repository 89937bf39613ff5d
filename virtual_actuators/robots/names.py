"""Common names of the example-robot-data robots, and suggestions for a name that is not known.

:func:`~virtual_actuators.robots.loader.load_robot` finds a robot by the stem of its URDF file
(``talos_reduced``, ``ur5_robot``, ``hyq_no_sensors``...) and also by the common names of
:data:`ALIASES` (``talos``, ``ur5``, ``hyq``...). Each alias names one file stem; where a robot
ships in several variants the alias picks the one example-robot-data's own Python loader picks
(``example_robot_data.load("talos")``), so a model loaded here matches the one other
Pinocchio tools load by the same name:

- ``talos`` is ``talos_reduced`` (the legs, torso and arms with their grippers, 32 actuated
  joints: the model used for whole-body control); ``talos_full`` is ``talos_full_v2`` (also
  the head and the fingers, 44);
- ``ur3``, ``ur5``, ``ur10`` are the arms without a gripper and with their full joint range
  (``*_robot``); ``*_limited`` the joint-limited variants;
- ``g1`` is the Unitree G1 with 29 degrees of freedom and no hands (``g1_with_hand`` with
  them); ``hyq`` is ``hyq_no_sensors``; ``solo8`` is ``solo``.

A file stem is never shadowed by an alias (``iris`` is ``iris.urdf``, not ``iris_simple``), and a
robot of a local folder (see :mod:`~virtual_actuators.robots.catalog`) named like an alias wins
over the alias.

:func:`closest_names` ranks known names and aliases by edit distance (Damerau-Levenshtein:
insertions, deletions, substitutions and swaps of two neighbouring letters each cost 1; case,
``-`` and ``_`` are ignored), so ``"talso"`` suggests ``talos`` and ``"ur_5"`` suggests
``ur5``.
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from types import MappingProxyType

__all__ = ["ALIASES", "closest_names", "edit_distance"]

#: Common name -> example-robot-data file stem (see the module documentation for the choices).
ALIASES: Mapping[str, str] = MappingProxyType(
    {
        # PAL Robotics TALOS (example_robot_data.load names)
        "talos": "talos_reduced",
        "talos_box": "talos_reduced_box",
        "talos_full": "talos_full_v2",
        "talos_full_box": "talos_full_v2_box",
        "talos_arm": "talos_left_arm",
        # Universal Robots arms
        "ur3_limited": "ur3_joint_limited_robot",
        "ur5": "ur5_robot",
        "ur5_limited": "ur5_joint_limited_robot",
        "ur10": "ur10_robot",
        "ur10_limited": "ur10_joint_limited_robot",
        # legged robots
        "hyq": "hyq_no_sensors",
        "solo8": "solo",
        "anymal_b": "anymal",
        "anymal_kinova": "anymal-kinova",
        "b1_z1": "b1-z1",
        "g1": "g1_29dof_rev_1_0",
        "g1_with_hand": "g1_29dof_with_hand_rev_1_0",
        "alexander": "alexander_v1.lowerBodyOnly",
        "alex": "alex_nub_hands",
        # arms and hands
        "franka": "panda",
        "franka_panda": "panda",
        "xarm": "xarm7",
        "so_arm_100": "so100",
        "so_arm_101": "so101",
        "allegro": "allegro_right_hand",
        "allegro_hand": "allegro_right_hand",
        "asr_twodof": "TwoDofs",
        # flying robots
        "hector": "quadrotor_base",
        "quadrotor": "quadrotor_base",
        "borinot": "borinot_flying_arm_2",
        "hextilt": "hextilt_flying_arm_5",
    }
)


def _key(name: str) -> str:
    """A name as compared by :func:`closest_names`: lower case, without ``-`` and ``_``."""
    return name.lower().replace("-", "").replace("_", "")


def edit_distance(a: str, b: str) -> int:
    """Damerau-Levenshtein distance (optimal string alignment) between two strings.

    Args:
        a: A string.
        b: Another string.

    Returns:
        The least number of insertions, deletions, substitutions and swaps of two neighbouring
        characters that turn ``a`` into ``b``.

    """
    previous2: list[int] = []
    previous = list(range(len(b) + 1))
    for i, char_a in enumerate(a, start=1):
        current = [i] + [0] * len(b)
        for j, char_b in enumerate(b, start=1):
            cost = 0 if char_a == char_b else 1
            current[j] = min(previous[j] + 1, current[j - 1] + 1, previous[j - 1] + cost)
            if i > 1 and j > 1 and char_a == b[j - 2] and a[i - 2] == char_b:
                current[j] = min(current[j], previous2[j - 2] + 1)
        previous2, previous = previous, current
    return previous[-1]


def closest_names(name: str, candidates: Iterable[str], n: int = 5) -> list[str]:
    """The candidates closest to ``name`` by edit distance, best first.

    A candidate is close when its distance is at most half the length of the longer of the two
    (at least 2), or when one name contains the other (``"panda"`` in ``"panda_arm"``). Ties go
    to a candidate that contains ``name`` or is contained in it (``"anymall"`` suggests
    ``anymal`` before ``anymal_c``), then to the one whose length is closest, then
    alphabetically.

    Args:
        name: The name that was not found.
        candidates: Known names.
        n: How many names at most.

    Returns:
        Up to ``n`` names (possibly none).

    """
    wanted = _key(name)
    ranked = []
    for candidate in dict.fromkeys(candidates):
        key = _key(candidate)
        contained = bool(wanted) and bool(key) and (wanted in key or key in wanted)
        close = max(2, max(len(wanted), len(key)) // 2)
        if not contained and abs(len(wanted) - len(key)) > close:
            continue  # the distance is at least the difference in length: too far, not computed
        distance = edit_distance(wanted, key)
        if contained or distance <= close:
            ranked.append((distance, not contained, abs(len(key) - len(wanted)), candidate))
    return [candidate for *_, candidate in sorted(ranked)[:n]]
