"""The viewer's constants, each with its unit and one line of purpose.

Colours are packed ``0xRRGGBB`` integers (k3d's convention). Lengths are meters.
"""

from __future__ import annotations

#: object id of the stage, as Habitat numbers it (objects count from 1)
STAGE_OBJECT_ID = 0

# -- contact overlay ----------------------------------------------------------------------------
#: m per N s: drawn normal length per unit of normal impulse (force x fixed step). A 1 kg box
#: resting on 4 points gets 9.8 * 0.008 / 4 = 0.02 N s per point and step: a 0.1 m arrow.
CONTACT_LENGTH_PER_IMPULSE = 5.0
#: m, shortest drawn normal, so that a contact with no impulse yet (just created) still shows
CONTACT_MIN_LENGTH = 0.03
#: m, longest drawn normal, so that a landing impact does not draw across the room
CONTACT_MAX_LENGTH = 0.4
CONTACT_COLOR = 0xE0201B  # red: normal on B, from B towards A, scaled by impulse
CONTACT_POINT_COLOR = 0xFFC000  # amber: the contact point on B
#: m, drawn diameter of a contact point
CONTACT_POINT_SIZE = 0.025

# -- AABB overlay -------------------------------------------------------------------------------
AABB_COLOR = 0x2B8CBE  # blue: world AABB of each object's render mesh
PAIR_COLOR = 0xF28E2B  # orange: centre to centre of two overlapping AABBs (a broad-phase pair)

# -- sleeping islands ---------------------------------------------------------------------------
#: one colour per sleeping island (cycled): cool, desaturated, so that awake objects stand out
ISLAND_COLORS = (0x4E79A7, 0x76B7B2, 0x59A14F, 0xB07AA1, 0x9C755F, 0x8CD17D, 0x499894, 0x86BCB6)

# -- navmesh and path ---------------------------------------------------------------------------
#: one colour per navmesh island (cycled); island 0 is the largest in the grid navmesh
NAVMESH_COLORS = (0x59A14F, 0xEDC948, 0xB07AA1, 0xFF9DA7, 0x9C755F, 0xBAB0AC)
#: m, the navmesh is drawn this far above its surface so that the floor does not hide it
NAVMESH_LIFT = 0.02
NAVMESH_OPACITY = 0.55
PATH_COLOR = 0xD62728  # red polyline of find_path's points
#: m, the path is drawn this far above the navmesh
PATH_LIFT = 0.05

# -- velocity control and agents ----------------------------------------------------------------
#: s, the velocity-control target drawn is the pose integrate_transform reaches after this time
VELOCITY_HORIZON = 1.0
VELOCITY_COLOR = 0x9467BD  # purple: from the object to its velocity-control target
AGENT_COLOR = 0x17BECF  # cyan: agent cylinders and sensor frusta
#: m, distance at which a sensor's frustum is cut for drawing
FRUSTUM_DEPTH = 0.5

# -- lines --------------------------------------------------------------------------------------
#: m, width of the overlay lines (k3d's "thick" shader: screen-facing ribbons this wide)
LINE_WIDTH = 0.006

# -- live server --------------------------------------------------------------------------------
#: the live viewer's page asks for changes this often, ms
POLL_INTERVAL_MS = 200
#: the live server binds here unless asked otherwise: this machine only
DEFAULT_HOST = "127.0.0.1"
