"""declaration layer of virtual_actuators."""
