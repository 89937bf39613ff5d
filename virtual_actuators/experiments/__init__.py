"""Experiments: record runs, summarise them in metrics, and plot them (above the controller).

:class:`~virtual_actuators.experiments.recorder.Recorder` logs channels of a walking run into a
:class:`~virtual_actuators.experiments.walk_log.WalkLog`;
:func:`~virtual_actuators.experiments.metrics.compute_metrics` summarises it and
:func:`~virtual_actuators.experiments.plots.plot_walk` draws it (matplotlib).
"""
