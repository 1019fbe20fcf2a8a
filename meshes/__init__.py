"""Parametric gmsh model of the twisted blade with its shroud, cached on disk."""
