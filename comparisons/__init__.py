"""Studies: one module per scene kind (``study = "<module>"`` in scenes/*.toml).

Importing the package registers the models the studies compare.
"""

import reduced_model  # noqa: F401  (registers "reduced", "full", "extended")
import reference_fe  # noqa: F401  (registers "fe", "fe-reduced")
