"""rigidsim's renderer: a pure-NumPy rasterizer producing Habitat-like sensor images.

A leaf library: it takes plain arrays (meshes, 4x4 poses, a camera) and returns arrays;
it never imports ``engine`` or ``navmesh``. Conventions: Y up, cameras look down their local
-Z with +Y up, meters; depth is z-depth along the camera axis (0 = nothing drawn); image
row 0 is the top.

Pipeline of ``render_frame`` (``render/frame.py``), stage by stage:

1. Vertex stage: mesh-local vertices -> world (``world_from_mesh``) -> camera frame
   (inverse of ``world_from_camera``); ``RenderScene`` caches the static arrays.
2. Primitive assembly and culling: triangles fully outside one frustum plane are dropped
   (optionally back faces too) (``raster.frustum_keep_mask``).
3. Near clipping against z = -near: 1 or 2 pieces per crossing triangle (``raster.clip_near``).
4. Triangle setup: per triangle, the affine screen functions b_k / z and 1 / z that make
   interpolation perspective-correct (``raster.plane_coefficients``); corners to pixels
   (``camera.Camera.project``: px = cx + fx x / z, py = cy - fy y / z).
5. Scanline spans: covered pixel runs per row under the top-left fill rule at pixel centers
   (``raster.scanline_spans``).
6. Fragments and depth test: spans expanded in cache-sized chunks, nearest fragment per
   pixel kept with one ``np.minimum.at`` on 64-bit keys (depth bits << 32 | triangle)
   (``raster.depth_test_spans``).
7. Resolve: per covered pixel the winning triangle and its depth (``raster.resolve_depth``).
8. Deferred shading: base color x vertex colors x bilinear texture (perspective-correct
   ``raster.AttributePlanes``) x Lambert light of Habitat's default 4-light setup for lit
   meshes (``shade``); depth and semantic ids written alongside.

``video`` mirrors ``habitat_sim.utils.viz_utils`` (``make_video`` and helpers).
"""

from render.camera import ORTHOGRAPHIC, PINHOLE, Camera, invert_rigid
from render.frame import BACKGROUND_RGBA, FrameBuffers, render_frame
from render.scene import RenderMesh, RenderScene
from render.shade import AMBIENT, DIFFUSE, LIGHT_DIRECTIONS, face_light_factors
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
    "BACKGROUND_RGBA",
    "Camera",
    "D3_40_COLORS_RGB",
    "DIFFUSE",
    "FrameBuffers",
    "LIGHT_DIRECTIONS",
    "ORTHOGRAPHIC",
    "PINHOLE",
    "RenderMesh",
    "RenderScene",
    "border_frames_from_overlay",
    "depth_to_rgb",
    "display_video",
    "face_light_factors",
    "invert_rigid",
    "is_notebook",
    "make_video",
    "make_video_frame",
    "observation_to_image",
    "render_frame",
    "save_video",
    "semantic_to_rgb",
]
