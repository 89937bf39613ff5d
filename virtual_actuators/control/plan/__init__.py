"""The compiled machine: a StateMachine and a Controller lowered into the core, one call a tick."""
