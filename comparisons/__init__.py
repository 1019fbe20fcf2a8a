"""Studies: one module per scene kind (``study = "<module>"`` in scenes/*.toml)."""
