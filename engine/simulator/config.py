"""The simulator's configuration (Habitat's ``SimulatorConfiguration`` and ``Configuration``)
and its seeded random source ``sim.random`` (Habitat's ``Random``).

``Simulator(Configuration(sim_cfg, [agent_cfg]))`` is built from these (see
:mod:`engine.simulator.simulator`); both configuration classes are fixed-field dataclasses, so a
misspelt field name raises ``AttributeError`` as Habitat's C++ structs do. Import them from
``engine`` (``habitat_sim.SimulatorConfiguration``) or ``engine.simulator.simulator``.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from engine.agent import AgentConfiguration
from engine.core.fixed_fields import FixedFields
from engine.gfx import NO_LIGHT_KEY
from navmesh import NavMeshSettings

__all__ = ["Configuration", "Random", "SimulatorConfiguration"]


@dataclass
class SimulatorConfiguration(FixedFields):
    """Habitat's ``SimulatorConfiguration`` (``scene_id = "NONE"`` is an empty world).

    Fixed fields: a misspelt name raises ``AttributeError`` naming the closest field. The
    fields after ``load_semantic_mesh`` are Habitat's renderer and dataset switches, stored
    so that Habitat code setting them runs; rigidsim's software renderer ignores them.
    """

    scene_id: str = "NONE"
    scene_dataset_config_file: str = "default"
    enable_physics: bool = True
    physics_config_file: str = ""
    allow_sliding: bool = True
    random_seed: int = 0
    navmesh_settings: NavMeshSettings | None = None
    scene_light_setup: str = NO_LIGHT_KEY
    default_agent_id: int = 0
    load_semantic_mesh: bool = False
    gpu_device_id: int = 0
    default_camera_uuid: str = "rgba_camera"
    compress_textures: bool = False
    create_renderer: bool = True
    frustum_culling: bool = True
    enable_hbao: bool = False
    override_scene_light_defaults: bool = False
    force_separate_semantic_scene_graph: bool = False
    requires_textures: bool = True
    leave_context_with_background_renderer: bool = False
    use_semantic_textures: bool = False
    enable_gfx_replay_save: bool = False
    pbr_image_based_lighting: bool = False


@dataclass
class Configuration(FixedFields):
    """A simulator configuration and the agents' configurations (fixed fields)."""

    sim_cfg: SimulatorConfiguration = field(default_factory=SimulatorConfiguration)
    agents: list[AgentConfiguration] = field(default_factory=lambda: [AgentConfiguration()])
    metadata_mediator: Any = (
        None  # an engine.templates.metadata.MetadataMediator, or None: a new one
    )
    enable_batch_renderer: bool = False


class Random:
    """Habitat's ``sim.random``: a seeded source of uniform and normal numbers."""

    def __init__(self, seed: int = 0) -> None:
        self.seed(seed)

    def seed(self, new_seed: int) -> None:
        self._rng = np.random.default_rng(int(new_seed) & 0xFFFFFFFF)

    def uniform_float(self, a: float = 0.0, b: float = 1.0) -> float:
        return float(self._rng.uniform(a, b))

    def uniform_float_01(self) -> float:
        return float(self._rng.uniform(0.0, 1.0))

    def uniform_int(self, a: int = 0, b: int = 2**31 - 1) -> int:
        return int(self._rng.integers(a, b))

    def normal_float_01(self) -> float:
        return float(self._rng.normal())
