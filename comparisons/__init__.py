"""Studies: one module per scene kind (``study = "<module>"`` in scenes/*.toml).

The models they compare come from the core's registry (shroud.core.registry), where the
builder packages declare them.
"""
