"""kinematics layer of virtual_actuators."""
