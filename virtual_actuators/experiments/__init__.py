"""Experiments: record runs, summarise them in metrics, and plot them (above the controller).

`Recorder` logs channels of a walking run into a
`WalkLog`;
`compute_metrics` summarises it and
`plot_walk` draws it (matplotlib).
"""
