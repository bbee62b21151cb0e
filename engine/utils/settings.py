"""Habitat's ``habitat_sim.utils.settings``: ``default_sim_settings`` and ``make_cfg``.

The settings dictionary has Habitat's keys and defaults (``scene`` "NONE", 640 x 480 sensors,
``hfov`` 90 degrees, ``sensor_height`` 1.5 m, ``agent_radius`` 0.1 m, a color sensor only,
``seed`` 1, ...). ``make_cfg(settings)`` turns it into a :class:`engine.Configuration`: one
agent whose height is the sensor height, Habitat's default action space (``move_forward``
0.25 m, ``turn_left`` / ``turn_right`` 10 degrees), one camera sensor per ``*_sensor`` key
set to True (pinhole ``color_sensor``, ``depth_sensor``, ``semantic_sensor``; orthographic
``ortho_rgba_sensor``, ``ortho_depth_sensor``, ``ortho_semantic_sensor``), all at
``[0, sensor_height, 0]``, and, with ``default_agent_navmesh``, navmesh settings fitted to
the agent (radius, height, static objects). The wide-angle keys (``fisheye_rgba_sensor``,
``fisheye_depth_sensor``, ``fisheye_semantic_sensor``, ``equirect_*``) add Habitat's
double-sphere fisheye (its "GoPro" lens: ``xi`` -0.27, ``alpha`` 0.57, focal length
``(364.84, 364.86)`` px) and equirectangular sensors (:mod:`engine.sensors.cubemap`).

Use::

    from engine.utils.settings import default_sim_settings, make_cfg
    settings = {**default_sim_settings, "scene": "path/to/apartment.glb", "depth_sensor": True}
    sim = habitat_sim.Simulator(make_cfg(settings))
"""

from __future__ import annotations

from typing import Any

from engine import mn
from engine.agent import ActionSpec, ActuationSpec, AgentConfiguration
from engine.sensors.cameras import CameraSensorSpec, SensorSubType, SensorType
from engine.sensors.cubemap import (
    CubeMapSensorBaseSpec,
    EquirectangularSensorSpec,
    FisheyeSensorDoubleSphereSpec,
)
from engine.simulator.simulator import Configuration, SimulatorConfiguration
from navmesh import NavMeshSettings

__all__ = ["default_sim_settings", "make_cfg"]


default_sim_settings: dict[str, Any] = {
    # a .scene_dataset_config.json, or "default"
    "scene_dataset_config_file": "default",
    # a scene, stage or asset file, or "NONE" for an empty scene
    "scene": "NONE",
    # camera sensors: resolution, horizontal field of view (degrees), far plane (m)
    "width": 640,
    "height": 480,
    "hfov": 90,
    "zfar": 1000.0,
    "clear_color": mn.Color4.from_linear_rgb_int(0),
    # height of the sensors above the agent's root (m), which is also the agent's height
    "sensor_height": 1.5,
    "default_agent": 0,
    "agent_radius": 0.1,
    # which sensors to create
    "color_sensor": True,
    "semantic_sensor": False,
    "depth_sensor": False,
    "ortho_rgba_sensor": False,
    "ortho_depth_sensor": False,
    "ortho_semantic_sensor": False,
    "fisheye_rgba_sensor": False,
    "fisheye_depth_sensor": False,
    "fisheye_semantic_sensor": False,
    "equirect_rgba_sensor": False,
    "equirect_depth_sensor": False,
    "equirect_semantic_sensor": False,
    "seed": 1,
    # a missing physics config file falls back to the defaults with a warning (as Habitat)
    "physics_config_file": "data/default.physics_config.json",
    "enable_physics": True,
    # build a navmesh fitted to the agent, with or without STATIC objects
    "default_agent_navmesh": True,
    "navmesh_include_static_objects": False,
    "enable_hbao": False,
}

#: the sensors make_cfg can add, in its order: uuid (the settings key) -> (type, camera model)
SENSOR_MODELS = {
    "color_sensor": (SensorType.COLOR, SensorSubType.PINHOLE),
    "depth_sensor": (SensorType.DEPTH, SensorSubType.PINHOLE),
    "semantic_sensor": (SensorType.SEMANTIC, SensorSubType.PINHOLE),
    "ortho_rgba_sensor": (SensorType.COLOR, SensorSubType.ORTHOGRAPHIC),
    "ortho_depth_sensor": (SensorType.DEPTH, SensorSubType.ORTHOGRAPHIC),
    "ortho_semantic_sensor": (SensorType.SEMANTIC, SensorSubType.ORTHOGRAPHIC),
    "fisheye_rgba_sensor": (SensorType.COLOR, SensorSubType.FISHEYE),
    "fisheye_depth_sensor": (SensorType.DEPTH, SensorSubType.FISHEYE),
    "fisheye_semantic_sensor": (SensorType.SEMANTIC, SensorSubType.FISHEYE),
    "equirect_rgba_sensor": (SensorType.COLOR, SensorSubType.EQUIRECTANGULAR),
    "equirect_depth_sensor": (SensorType.DEPTH, SensorSubType.EQUIRECTANGULAR),
    "equirect_semantic_sensor": (SensorType.SEMANTIC, SensorSubType.EQUIRECTANGULAR),
}
#: keys make_cfg reads unconditionally (as Habitat's): missing ones raise KeyError
REQUIRED_KEYS = (
    "scene",
    "width",
    "height",
    "sensor_height",
    "hfov",
    "zfar",
    "agent_radius",
    "default_agent_navmesh",
)
#: SimulatorConfiguration attributes copied from the settings key of the same name when present
OPTIONAL_SIM_KEYS = (
    "scene_dataset_config_file",
    "enable_physics",
    "physics_config_file",
    "scene_light_setup",
)


def _lens_spec(
    settings: dict[str, Any], subtype: SensorSubType
) -> CameraSensorSpec | CubeMapSensorBaseSpec:
    """A new spec of the camera model ``subtype`` with the model's own settings: the pinhole
    field of view and the far plane, or Habitat's fisheye lens (``create_fisheye_spec``)."""
    if subtype is SensorSubType.FISHEYE:
        fisheye = FisheyeSensorDoubleSphereSpec()
        fisheye.xi, fisheye.alpha = -0.27, 0.57  # the GoPro lens of Usenko et al. 2018, Table 3
        fisheye.focal_length = [364.84, 364.86]
        return fisheye
    if subtype is SensorSubType.EQUIRECTANGULAR:
        return EquirectangularSensorSpec()
    camera = CameraSensorSpec()
    camera.sensor_subtype = subtype
    camera.far = float(settings["zfar"])
    if subtype is SensorSubType.PINHOLE:
        camera.hfov = float(settings["hfov"])
    return camera


def _sensor_spec(settings: dict[str, Any], uuid: str) -> CameraSensorSpec | CubeMapSensorBaseSpec:
    """The spec of sensor ``uuid`` (a key of :data:`SENSOR_MODELS`), as Habitat's make_cfg
    builds it: the settings' resolution, at ``[0, sensor_height, 0]``, color sensors with
    the clear color, the others with one channel."""
    sensor_type, subtype = SENSOR_MODELS[uuid]
    spec = _lens_spec(settings, subtype)
    spec.uuid, spec.sensor_type = uuid, sensor_type
    spec.resolution = [int(settings["height"]), int(settings["width"])]
    spec.position = [0.0, float(settings["sensor_height"]), 0.0]
    if sensor_type is SensorType.COLOR:
        spec.clear_color = settings["clear_color"]
    else:
        spec.channels = 1
    return spec


def make_cfg(settings: dict[str, Any]) -> Configuration:
    """A :class:`Configuration` from a settings dict (Habitat's ``make_cfg``).

    Keys missing from ``settings`` that Habitat reads unconditionally raise ``KeyError``
    naming the key (start from ``{**default_sim_settings, ...}``).
    """
    missing = [key for key in REQUIRED_KEYS if key not in settings]
    if missing:
        raise KeyError(f"make_cfg: settings lack {missing}; start from default_sim_settings")
    sim_cfg = SimulatorConfiguration()
    sim_cfg.scene_id = settings["scene"]
    for key in OPTIONAL_SIM_KEYS:
        if key in settings:
            setattr(sim_cfg, key, settings[key])
    sim_cfg.frustum_culling = bool(settings.get("frustum_culling", False))
    sim_cfg.enable_hbao = bool(settings.get("enable_hbao", False))
    sim_cfg.gpu_device_id = 0
    if "seed" in settings:
        sim_cfg.random_seed = int(settings["seed"])
    if "default_agent" in settings:
        sim_cfg.default_agent_id = int(settings["default_agent"])

    agent_cfg = AgentConfiguration()
    agent_cfg.height = float(settings["sensor_height"])
    agent_cfg.radius = float(settings["agent_radius"])
    agent_cfg.sensor_specifications = [
        _sensor_spec(settings, uuid) for uuid in SENSOR_MODELS if settings.get(uuid, False)
    ]
    agent_cfg.action_space = {
        "move_forward": ActionSpec("move_forward", ActuationSpec(amount=0.25)),
        "turn_left": ActionSpec("turn_left", ActuationSpec(amount=10.0)),
        "turn_right": ActionSpec("turn_right", ActuationSpec(amount=10.0)),
    }
    if settings["default_agent_navmesh"]:
        navmesh_settings = NavMeshSettings()
        navmesh_settings.set_defaults()
        navmesh_settings.agent_radius = agent_cfg.radius
        navmesh_settings.agent_height = agent_cfg.height
        navmesh_settings.include_static_objects = bool(
            settings.get("navmesh_include_static_objects", False)
        )
        sim_cfg.navmesh_settings = navmesh_settings
    return Configuration(sim_cfg, [agent_cfg])
