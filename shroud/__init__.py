"""Shared core of the shrouded-blade workbench: parameters, the contact law,
the Newmark integrator, signals, scenes and the ``shroud`` command."""
