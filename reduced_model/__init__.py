"""Reduced Timoshenko-beam model of the twisted shrouded blade (paper Sect. 2.1).

numpy/scipy/numba only: importing it never loads DOLFINx or gmsh.
"""
