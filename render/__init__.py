"""rigidsim's renderer: a pure-NumPy rasterizer producing Habitat-like sensor images.

A leaf library: it takes plain arrays (meshes, 4x4 poses, a camera) and returns arrays;
it never imports ``engine`` or ``navmesh``. Conventions: Y up, cameras look down their local
-Z with +Y up, meters; depth is z-depth along the camera axis (0 = nothing drawn); image
row 0 is the top.

Pipeline of ``render_frame`` (``render/frame.py``), stage by stage:

1. Vertex stage: mesh-local vertices -> world (``world_from_mesh``) -> camera frame
   (inverse of ``world_from_camera``); ``RenderScene`` caches the static arrays.
2. Frustum culling with vertex outcodes (``cull.vertex_outcodes``,
   ``cull.triangles_in_frustum``); hidden meshes dropped. The surviving triangles are then
   processed in batches of ``RenderSettings.triangle_batch`` through stages 3-6.
3. Optional back-face culling (``cull.front_facing``) and near clipping against z = -near:
   1 or 2 pieces per crossing triangle (``cull.clip_near``).
4. Triangle setup: per triangle, the affine screen functions b_k / z and 1 / z that make
   interpolation perspective-correct (``raster.plane_coefficients``); corners to pixels
   (px = cx + fx x / z, py = cy - fy y / z, ``raster.project_triangles``).
5. Scanline spans: covered pixel runs per row under the top-left fill rule at pixel centers
   (``raster.scanline_spans``).
6. Fragments and depth test: spans expanded in cache-sized chunks, nearest fragment per
   pixel kept with one ``np.minimum.at`` on 64-bit keys (depth bits << 32 | triangle)
   (``raster.depth_test_spans``).
7. Shading setup for the triangles that drew fragments: perspective-correct attribute
   planes of uvs and vertex colors (``resolve.AttributePlanes``), Lambert light factors of
   the lit meshes' light setups (``render.lights``; ``deferred.ShadingInputs.build``).
8. Resolve and deferred shading in bands of rows: per covered pixel the winning triangle
   and its depth (``resolve.resolve_depth``), then base color x vertex colors x bilinear
   texture x light (``shade.shade_pixels``, packed 8-bit kernels of ``packed_rgba``);
   depth and semantic ids written alongside (``deferred.write_band``).

``RenderSettings`` (``render.settings``) sizes the batches, chunks and bands and selects
the fast or the plain kernels: one frozen value per render, the same pixels for all.

Known differences from Habitat's GPU renderer: no mipmaps (distant textures alias), flat
face normals for lighting unless a mesh has vertex normals (Gouraud; no normal maps), no
anti-aliasing, no transparency (drawn pixels are opaque), both faces drawn unless
``cull_back_faces=True``.

``reference`` is the same pipeline written as textbook scalar loops (edge functions,
Sutherland-Hodgman clipping, a float fragment shader), slow, used by the tests to check the
vectorized pipeline: depth and ids exactly, colors within one level of 255.
``render_over_layer`` draws moving meshes over a ``StaticLayer`` (a kept frame of the
static meshes): bit for bit the frame ``render_frame`` gives for all of them, for the cost
of the moving meshes' fragments (a static camera over a static apartment).
``video`` mirrors ``habitat_sim.utils.viz_utils`` (``make_video`` and helpers).
"""

from render.camera import ORTHOGRAPHIC, PINHOLE, Camera, invert_rigid
from render.frame import (
    BACKGROUND_RGBA,
    FrameBuffers,
    StaticLayer,
    render_frame,
    render_over_layer,
)
from render.lights import (
    AMBIENT,
    DEFAULT_LIGHTS,
    DIFFUSE,
    LIGHT_DIRECTIONS,
    Lights,
    face_light_factors,
    lambert_factors,
)
from render.scene import RenderMesh, RenderScene
from render.settings import DEFAULT_SETTINGS, RenderSettings
from render.video import (
    D3_40_COLORS_RGB,
    border_frames_from_overlay,
    depth_to_rgb,
    display_video,
    is_notebook,
    make_video,
    make_video_frame,
    observation_to_image,
    save_video,
    semantic_to_rgb,
)

__all__ = [
    "AMBIENT",
    "DEFAULT_LIGHTS",
    "BACKGROUND_RGBA",
    "Camera",
    "D3_40_COLORS_RGB",
    "DIFFUSE",
    "FrameBuffers",
    "LIGHT_DIRECTIONS",
    "Lights",
    "ORTHOGRAPHIC",
    "PINHOLE",
    "RenderMesh",
    "RenderScene",
    "RenderSettings",
    "DEFAULT_SETTINGS",
    "border_frames_from_overlay",
    "depth_to_rgb",
    "display_video",
    "face_light_factors",
    "lambert_factors",
    "invert_rigid",
    "is_notebook",
    "make_video",
    "make_video_frame",
    "observation_to_image",
    "render_frame",
    "save_video",
    "semantic_to_rgb",
    "StaticLayer",
    "render_over_layer",
]
