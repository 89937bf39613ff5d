"""The partitioned solve (VAC eq. 10-11 by Constrained and Redundant Force Sets).

``reference.py`` is the numpy solver, ``least_norm.py`` its least-squares minimum norm,
``dense.py`` the dense oracle, ``compiled.py``, ``buffer_solve.py`` and the ``kernel*.py``
modules the compiled per-tick path, ``numeric.py`` the numpy path's scaling and typed errors.
"""
