"""Reduced Timoshenko-beam model of the twisted shrouded blade (paper Sect. 2.1).

numpy/scipy/numba only: importing it never loads DOLFINx or gmsh (gmsh is
imported by reduced_model.step_slices only when a STEP file is cut). Importing
the package registers its models with the core:

* ``full``: the Galerkin beam, 5 fields x N shape functions (5N DOF), 6N with reduced.torsion;
* ``reduced``: its free-interface reduction to ``reduced.nr`` modes;
* ``extended``: the reduced beam with the twist field and the rigid shroud
  (``reduced.torsion = true``, ``reduced.shroud = "rigid"`` whatever the
  parameters say): the beam that matches the solid (reduced_model.beam).

Each also offers ``at_speed(params) -> (rpm -> StructuralSystem)`` for
continuation in speed (shroud.core.continuation).
"""
