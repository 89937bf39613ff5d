"""Experiments: record runs (`Recorder`), summarise them (`compute_metrics`), plot them."""
