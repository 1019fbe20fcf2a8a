"""The models the tests run are those the builder packages register on import."""

import reduced_model  # noqa: F401  (registers "reduced", "full", "extended")
import reference_fe  # noqa: F401  (registers "fe", "fe-reduced"; DOLFINx loads only when built)
