"""3D solid FE reference of the shrouded blade on DOLFINx 0.11 (PETSc/SLEPc).

Its models are declared in ``reference_fe.models`` (entry-point group
``shroud.models``), read by the core's registry without loading DOLFINx:

* ``fe``: the full solid, quadratic cells, one contact element per face node;
  by harmonic balance condensed exactly on its contact coordinates per
  harmonic (reference_fe.harmonic), its Newton started from fe-reduced, its
  Floquet multipliers those of its own orbit with the perturbations on
  fe-reduced's basis (at 1x and 2x the kept modes);
* ``fe-reduced``: its free-interface component-mode-synthesis reduction, which
  also offers one basis for a speed range (``at_speed``, reference_fe.frequency);
* ``shell``: the Reissner-Mindlin shell of the blade's mid-surface with the
  shroud as a plate on its tip (reference_fe.shell, docs/shell.md);
* ``shell-reduced``: its free-interface reduction to ``shell.cms_modes`` modes.
"""
