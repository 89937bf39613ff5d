"""Common names of the example-robot-data robots, and suggestions for a name that is not known.

Each alias of `ALIASES` picks the variant ``example_robot_data.load`` picks; a file stem is
never shadowed by an alias, and a local robot named like an alias wins over it.
"""

from __future__ import annotations

from collections.abc import Mapping
from types import MappingProxyType

__all__ = ["ALIASES"]

#: Common name -> example-robot-data file stem (the choices: the "Robots" reference page).
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
