"""The command line: options and parser (``options``), what each command runs (``commands``)."""
