"""distribution layer of virtual_actuators."""
