"""Sensors and the bridge from the scene graph to ``render``.

Habitat's ``habitat_sim.sensors`` package (``engine.sensors.sensor_wrapper``) and the camera
sensor names (``CameraSensorSpec``, ``CameraSensor``, ``SensorType`` ...) are importable from
here; Habitat's ``habitat_sim.sensor`` module is the face ``engine.sensor``. What is here,
in reading order:

1. :mod:`~engine.sensors.sensor_specs`: what a sensor is asked to be, checked up front;
2. :mod:`~engine.sensors.render_camera`: a camera's matrices (``RenderCamera``);
3. :mod:`~engine.sensors.cameras`: pinhole and orthographic camera sensors on scene nodes;
4. :mod:`~engine.sensors.cubemap`: fisheye and equirectangular sensors (six cube faces);
5. :mod:`~engine.sensors.factory`: ``SensorFactory``, sensors attached to nodes;
6. :mod:`~engine.sensors.sensor_wrapper`: ``sim.sensors[uuid]``, Habitat's wrapper;
7. :mod:`~engine.sensors.scene_render`: the scene graph to render jobs and observations;
8. :mod:`~engine.sensors.render_scheduler`, :mod:`~engine.sensors.frame_sharing`: where
   and when the camera groups render (threads, the render worker, a shared frame);
9. :mod:`~engine.sensors.async_render`: render this frame while physics steps the next;
10. :mod:`~engine.sensors.debug_lines`, :mod:`~engine.sensors.line_overlay`: debug lines
    drawn into the color frames;
11. :mod:`~engine.sensors.observations`: the observations dict (uuid -> frame), whose missing
    key names the uuids there are;
12. :mod:`~engine.sensors.replay`: Habitat's replay renderer and gfx-replay names,
    placeholders (rigidsim has neither) that raise ``NotImplementedError`` when used.

May import: ``render``, ``engine.scene``, ``engine.core``, ``engine.mn`` and the small
Habitat modules (``geo``, ``errors``). Never physics, agents or the simulator.
"""

from engine.sensors.cameras import (
    CameraSensor,
    CameraSensorSpec,
    SemanticSensorTarget,
    Sensor,
    SensorSpec,
    SensorSubType,
    SensorType,
    VisualSensorSpec,
    euler_xyz_matrix,
)

__all__ = [
    "CameraSensor",
    "CameraSensorSpec",
    "SemanticSensorTarget",
    "Sensor",
    "SensorSpec",
    "SensorSubType",
    "SensorType",
    "VisualSensorSpec",
    "euler_xyz_matrix",
]
