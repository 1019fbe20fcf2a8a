"""The models this application offers: importing a builder package registers its models."""

import reduced_model  # noqa: F401  (registers "reduced", "full", "extended")
import reference_fe  # noqa: F401  (registers "fe", "fe-reduced"; DOLFINx loads only when one is built)
from shroud.core import registry

__all__ = ["registry"]
