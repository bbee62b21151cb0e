"""Habitat's ``habitat_sim.metadata``: ``MetadataMediator`` and the scene datasets (defined
in :mod:`engine.templates.metadata`)."""

from engine.templates.metadata import (
    DEFAULT_DATASET,
    DatasetManagers,
    MetadataMediator,
)

__all__ = [
    "DEFAULT_DATASET",
    "DatasetManagers",
    "MetadataMediator",
]
