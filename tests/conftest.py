"""Shared test set-up: the models come from the registry, where the installed builders declare them."""
