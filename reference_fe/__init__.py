"""3D solid FE reference of the shrouded blade on DOLFINx 0.11 (PETSc/SLEPc)."""
