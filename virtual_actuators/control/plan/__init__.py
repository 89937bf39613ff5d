"""The compiled machine: a StateMachine and a Controller lowered into the core, one call a tick.

`compiled.compile_machine` lowers a [`MachineController`][virtual_actuators.MachineController]
(`lower`: events, hooks and components traced into `builder`'s ops, the attachments' tables)
into the core's ``PlanMachine``, whose tick runs the kinematics, the machine, the attachments,
the sums and the clip; what cannot be lowered runs as a Python piece of that tick.
"""
