"""The partitioned solve (VAC eq. 10-11 by Constrained and Redundant Force Sets)."""
