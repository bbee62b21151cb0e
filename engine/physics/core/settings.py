"""Solver switches and physical constants of the rigid-body world, with units.

Every tunable number of the physics engine lives here, never as a scattered literal, each
with its unit and one line saying what it does.

Names: a :class:`SolverSettings` instance is always called ``settings`` (``world.settings``,
the ``settings`` argument of every stage). Modules that take one import the constants they
use by name (``from .settings import TINY``); the others may refer to them through the
module, ``settings.TINY``. Nothing else (no ``constants``, no ``options``).
The boolean switches mirror box2d-lite's demo toggles (accumulated impulses, warm
starting, position correction) so a student can turn each idea off and watch what breaks.

Conventions (declared once for the whole package): Y up, -Z forward, right handed,
meters / kilograms / seconds, quaternion arrays ``(4,)`` in order ``[x, y, z, w]``.
Contact normals point **from body A to body B** of a pair (A has the lower body index;
the stage, index 0, is always A).
"""

from __future__ import annotations

from dataclasses import dataclass


@dataclass
class SolverSettings:
    """Switches and constants of the sequential-impulse solver.

    Attributes
    ----------
    velocity_iterations : int
        Gauss-Seidel sweeps over all contacts per fixed step (Catto 2005). Range 1..50.
        10 as in Bullet (Habitat's engine) and Jolt; the stage-priority pass
        (``stage_iterations``) keeps the floor winning at this count.
    constraint_iterations : int
        Sweeps of the rigid-constraint solver (:mod:`constraints`) per fixed step: chains
        of Fixed constraints under gravity need more than the contacts (15 keeps a pinned
        cube within 1 mm of its pivot).
    position_iterations : int
        Sweeps of the split-impulse (pseudo velocity) position solve. 0 disables it.
    substeps : int
        Each fixed step is divided into this many solver substeps (>= 1).
    warm_starting : bool
        Start each step from last step's accumulated impulses (matched contact points).
    accumulate_impulses : bool
        Clamp the accumulated impulse (True, Catto) instead of each increment (False).
    position_correction : bool
        Remove penetration with split impulses (pseudo velocities that never enter the
        real velocity, so they add no kinetic energy).
    block_jacobi : bool
        Solve the (up to 4) points of a manifold together as a Jacobi block with mass
        splitting (one NumPy batch per color; the default: fastest, and symmetric, so a
        perfect stack stays perfect) instead of Gauss-Seidel over the point slots (one
        batch per slot; its fixed slot order biases tall stacks into a slow lean).
    block_normal_sweeps : int
        With ``block_jacobi`` and ``accumulate_impulses``: the first this many velocity
        sweeps of a step (0: none) try a block solve of a manifold's touching normal rows,
        ``K d_lambda = -(J V + b)`` with ``K = J M^-1 J^T`` (a smooth pseudo-inverse,
        ``BLOCK_REGULARIZATION``), and keep it only
        where every accumulated normal impulse stays ``>= 0`` (Box2D's block solver, its
        all-points-active case); elsewhere, and in the later sweeps, the mass-split Jacobi
        update.
    overlap_position_iterations : int
        Position sweeps used instead while some contact is deeper than ``DEEP_OVERLAP``
        (bodies created inside each other separate in about a second, not many).
    stage_iterations : int
        Normal-only sweeps over the contacts with the stage (and static or kinematic
        bodies) after each velocity and position solve, so the stage always wins: a light
        body under a heavy one is never pushed into the floor (0 disables it).
    contact_cache : bool
        Skip the narrow phase and the manifold update of a pair whose relative pose moved
        less than ``CONTACT_CACHE_DISTANCE`` since its last query and whose points overlap
        by at most ``SLEEP_MAX_PENETRATION`` (Bullet's persistent manifold idea: its points
        stay attached to the bodies, the solver recomputes their depths from the current
        poses). Off: every pair is queried every step.
    feature_manifolds : bool
        Rebuild every pair's manifold (the stage's included) from this step's contacts, cut
        to four with last step's feature keys winning near-ties and the stage's corner slot
        choice, warm-started from the nearest cached points, a stage row with fewer than
        three fresh points keeping its untaken cached points still touching (True, Box2D
        v3's and Jolt's way: :mod:`keyed_manifolds`), instead of merging the fresh points
        into persistent manifolds (False, the default, Bullet's ``btPersistentManifold``:
        :mod:`manifold_merge`). Pairs with a capsule always merge (:mod:`manifold_rows`).
        Off by default: measured, it cut 16 % of column-10's NumPy operations (0.93x its
        CPU time) and over eight drops of the 100-cube column was as good as the merge, but
        the benchmark's one-drop gates (transient cube-cube overlap, sleeping at 3 s, the
        500-cube floor overlap) read worse (``docs/physics_performance.md``).
    use_vectorized : bool
        Route the collision and solve stages through the batched NumPy code (True) or the
        plain reference path (False): contacts and manifolds one body pair at a time
        (:mod:`reference_contacts`), Jacobians, effective masses, velocity and position
        solves one contact point at a time (:mod:`reference_solver`). Both apply the same
        rules and agree to rounding (1e-9 over 2 s, tested); not bitwise (other sum order).
        The reference is 10-50x slower: it exists to be read and stepped through.
    soft_step : bool
        Solve contacts with Box2D v3's soft step (:mod:`soft_step`; False, the default:
        ``velocity_iterations`` sweeps, then the split-impulse position solve). Per
        substep: the forces' share, a warm start, one soft normal sweep (``contact_hertz``,
        ``contact_damping_ratio``, push-out at most ``contact_push_speed``), the bodies'
        displacement, one relax sweep (normal and friction rows, no bias); then the
        restitution pass. The contacts and manifolds stay those of the step.
    soft_substeps : int
        Substeps of the soft step (>= 1): 2 at the 0.008 s step is a 250 Hz substep, Box2D
        v3's 4 substeps at 60 Hz a 240 Hz one.
    relax_iterations : int
        Relax sweeps per substep of the soft step (>= 1; Box2D v3's ``RELAX_ITERATIONS``).
    contact_hertz : float
        Hz, the soft contacts' stiffness between moving bodies (Box2D v3's 30, at most an
        eighth of the substep rate); a contact with the stage gets twice it.
    contact_damping_ratio : float
        1, the soft contacts' damping ratio (Box2D v3's 10: heavily over-damped).
    contact_push_speed : float
        m/s, the fastest a soft contact pushes overlapping bodies apart (Box2D v3's
        ``contactSpeed``, 3 m/s).
    """

    velocity_iterations: int = 10
    constraint_iterations: int = 15
    position_iterations: int = 2
    substeps: int = 1
    warm_starting: bool = True
    accumulate_impulses: bool = True
    position_correction: bool = True
    block_jacobi: bool = True
    block_normal_sweeps: int = 1
    overlap_position_iterations: int = 6
    stage_iterations: int = 1
    contact_cache: bool = True
    feature_manifolds: bool = False
    use_vectorized: bool = True
    soft_step: bool = False
    soft_substeps: int = 2
    relax_iterations: int = 1
    contact_hertz: float = 30.0
    contact_damping_ratio: float = 10.0
    contact_push_speed: float = 3.0

    @property
    def uses_block_normal(self) -> bool:
        """Whether a step runs the block normal solve: ``block_normal_sweeps > 0`` with
        ``block_jacobi`` and ``accumulate_impulses`` (the block replaces their update)."""
        return self.block_normal_sweeps > 0 and self.block_jacobi and self.accumulate_impulses


# --- contact geometry -------------------------------------------------------------------
#: m, penetration left uncorrected so resting contacts persist from step to step.
PENETRATION_SLOP = 0.004
#: 1, fraction of the penetration beyond the slop removed per step by the position solve.
POSITION_BAUMGARTE = 0.2
#: m, beyond the slop: a contact this deep switches the position solve to
#: ``overlap_position_iterations`` sweeps (bodies created overlapping).
DEEP_OVERLAP = 0.01
#: 1, the Baumgarte fraction of the contacts deeper than ``DEEP_OVERLAP`` (the others keep
#: ``POSITION_BAUMGARTE``, so a falling pile's brief impacts do not disturb its neighbors).
OVERLAP_BAUMGARTE = 0.4
#: m, the soft step (soft_step.py) treats a point as speculative (no softness) only when its
#: separation exceeds this: points resting exactly on a surface (s = 0 give or take
#: round-off) then always take the soft row, whichever way the round-off falls (the two rows
#: differ by the impulse scale, 6 % of the load at 30 Hz).
SOFT_SPECULATIVE_TOLERANCE = 1e-12
#: m/s, upper bound of the position-correction pseudo velocity (no launches).
MAX_CORRECTION_SPEED = 2.0
#: m, a manifold point whose bodies separate by more than this along the normal is dropped.
CONTACT_BREAKING_DISTANCE = 0.02
#: m, a persistent point whose two anchors slide apart more than this tangentially is dropped.
CONTACT_DRIFT_DISTANCE = 0.02
#: m, a new point closer than this to a cached one inherits its impulses (warm start).
CONTACT_MATCH_DISTANCE = 0.02
#: 1, a pair's feature length (match, drift and dedupe distances) is this fraction of the
#: thinner body's smallest dimension, at most ``CONTACT_MATCH_DISTANCE``.
FEATURE_LENGTH_FRACTION = 0.25
#: 1, fraction of a rigid constraint's position / orientation error removed per step
#: (Baumgarte factor; Bullet's default ERP).
CONSTRAINT_BAUMGARTE = 0.2
#: 1, the block normal solve (``SolverSettings.block_normal_sweeps``) inverts a manifold's
#: ``K = J M^-1 J^T`` as ``(K + d I)^-1 K (K + d I)^-1``, ``d`` this times K's largest
#: diagonal entry: ``1 / w`` on an eigenvalue ``w >> d``, 0 on K's null space (a box
#: face's four coplanar points: rank 3, eigenvalues 6, 6, 4 and 0 for a cube in units of
#: 1/m) and small on directions K barely sees (never a huge impulse). A face's common mode
#: is solved to 0.2 %; the Jacobi sweeps after the block sweep take up the rest.
BLOCK_REGULARIZATION = 1e-3
#: 1, the block normal solve is kept while every accumulated normal impulse stays above
#: ``-BLOCK_FEASIBILITY_TOLERANCE`` times its value before the update (round-off: a warm
#: start taken back whole ends at 0 give or take a few ulps), then clamped to ``>= 0``.
BLOCK_FEASIBILITY_TOLERANCE = 1e-9
#: m, polyhedron-polyhedron vertex contacts are kept up to this far outside the other body.
SPECULATIVE_DISTANCE = 0.004
#: m, bodies within this distance of the stage get speculative contacts (Box2D v3 uses 4 x
#: its 5 mm slop): the solver lets a gap g close by at most g / h per step, so a falling
#: body stops exactly on the surface instead of sinking in and being pushed back up.
STAGE_SPECULATIVE_DISTANCE = 0.02
#: m, thickness given to a flat (planar) collision mesh so its hull has a volume.
FLAT_HULL_THICKNESS = 0.01
#: points, the most points a manifold keeps (deepest + largest area, as Bullet does).
MAX_MANIFOLD_POINTS = 4
# m: with mass splitting, only manifold points closer than this count as sharing the load
# (a speculative point 1 cm away carries no impulse, so it must not dilute the others)
SPLIT_TOUCH_DISTANCE = 0.004
#: m, manifold reduction spreads its points over those within this depth of the deepest one
#: (the supporting points); farther, speculative points only fill the slots left over, so a
#: can lying on its side keeps both ends of its bottom line rather than its far sides.
SUPPORT_DEPTH_BAND = 0.004
#: 1 (cosine), a polyhedron face serves as reference face of a contact only if its outward
#: normal is at least this aligned with fcl's contact normal (about 45 degrees).
REFERENCE_FACE_ALIGNMENT = 0.7
#: 1, tangent_basis builds t1 from the world X axis unless ``|n_x|`` reaches this (then Y):
#: just below 1/sqrt(3), so the chosen axis is never nearly parallel to n.
TANGENT_AXIS_SWITCH = 0.57
#: m (or m^2 for areas), manifold choices (deepest point, farthest point, largest area)
#: treat values closer than this as ties, won by the lower slot, so rounding never decides.
TIE_QUANTUM = 1e-9
#: 1 (cosine), a cached stage normal within 60 degrees of a touched triangle's normal
#: decides which side of the triangle is outward (the side the contact began on).
OUTWARD_SIDE_ALIGNMENT = 0.5
#: m, ... and only when its contact point lies within this of the triangle's plane: a normal
#: cached on another surface (a shelf's underside, the back of a 15 mm skirting board) never
#: turns a parallel one over (cached stage points lie on their triangle's plane exactly).
OUTWARD_SIDE_PLANE_DISTANCE = 0.001
#: 1 (cosine), a stage triangle whose normal is within 60 degrees of vertical is a floor
#: (or ceiling): a new contact with a body whose center is above its plane pushes up,
#: whichever way the stage winds it (contact_helpers.new_contact_side).
FLOOR_NORMAL_Y = 0.5
#: 1, a new contact with a wall-like stage triangle takes the side of the body's center
#: when the center is level with the triangle or the plane passes clear of it: farther
#: from it than this fraction of the body's extent along the normal; otherwise (a low face
#: cutting the body near its middle, a thin slab's side) the triangle's front.
STAGE_CENTER_SIDE_FRACTION = 0.25
#: m, a pair whose bodies moved relative to each other by less than this (at any point of
#: B's bounding sphere) since its last narrow-phase query keeps its manifold unchanged.
CONTACT_CACHE_DISTANCE = 0.0005
#: m, a fresh point matching a cached one counts this much deeper when the manifold picks
#: its deepest point (hysteresis: near-ties keep last step's points).
PREFERRED_DEPTH_BONUS = 1e-3
#: 1, and its distances and areas count this fraction larger (10 %).
PREFERRED_SIZE_BONUS = 0.1
#: 1, a hull vertex more than this fraction of the hull's extent below a stage triangle is
#: on the triangle's other side (a thin wall), not in contact with it.
STAGE_BELOW_FRACTION = 0.5
#: 1 (cosine), a hull vertex touching stage triangles turned 45 to 135 degrees from its
#: resting one (a floor and a wall at a corner) also keeps the shallowest of those it
#: has passed (lies behind); a manifold point this far turned from another is a second
#: direction (never merged with it, and the manifold keeps the deepest point of each).
STAGE_CORNER_COSINE = 0.7
#: m, a hull vertex behind its resting stage triangle is pushed out of it to this far in
#: front of it, and a triangle turned from that one holds it up in a corner only while the
#: pushed vertex is still inside its prism: a floor meeting a wall (a vertex pressed a few
#: mm into the wall keeps the floor that ends at the wall's foot), not a convex edge (a
#: skirting board's top and front).
STAGE_CORNER_PUSH = 0.001
#: m, ... a triangle whose prism holds only the pushed vertex (the floor ending at the wall)
#: holds it when it lies at most this far below it, not deeper (below a skirting board's
#: top, behind the board: not lifted onto it).
STAGE_CORNER_REACH = 0.02
#: m, a hull vertex behind a stage triangle rests on it only if the segment to its foot
#: crosses no other stage triangle (collision.stage_crossings); a plane within this of
#: either end of the segment is not crossed (the foot's neighbours share its plane).
STAGE_CROSSING_TOLERANCE = 1e-6
#: 1 (cosine), a stage triangle a hull straddles without a vertex on it (a thin slab's
#: side crossing a body whose vertices rest on the floor) takes fcl's points on it whose
#: normal is within 60 degrees of its own: the way out is through its face, not over its
#: edge (a body overhanging the slab's top beside it).
STAGE_CROSSED_FACE_ALIGNMENT = 0.5
#: 1 (barycentric units), a point this close outside a triangle's edge counts as inside,
#: so a vertex over a shared edge of two triangles is in contact with both.
BARYCENTRIC_TOLERANCE = 1e-9
#: 1, two bodies whose centers are closer than this fraction of the thinner one's smallest
#: dimension count as coincident (created at one point): they are pushed apart along a
#: direction that turns with their ids, so a crowd spawned at one point spreads over a disc.
COINCIDENT_FRACTION = 0.05
#: fcl contacts requested per shape pair.
MAX_FCL_CONTACTS = 32
#: 1 (a cosine), added to every ``|R_ij|`` of the oriented-box separating-axis test
#: (``boxes_separated``): the edge-edge axes of (nearly) parallel edges have a cross
#: product near 0, and the guard keeps round-off from separating boxes along them.
BOX_TEST_PARALLEL_GUARD = 1e-9
#: m, a sphere center closer than this to its nearest stage triangle point has no offset
#: direction: the sphere-triangle contact takes the triangle's normal instead.
SPHERE_CENTER_ON_SURFACE = 1e-9
#: sine of the angle below which two capsule axes count as parallel: capsules lying side
#: by side then touch along a line and get two contacts, the ends of the axes' overlap.
CAPSULE_PARALLEL_SINE = 1e-3

#: m, the stage grid names the triangles within this of a body's AABB: a probe (the shape
#: grown by ``STAGE_SPECULATIVE_DISTANCE`` along each of its own axes, shapes.probe_geometry)
#: reaches at most sqrt(3) times that distance beyond the body, at a rotated box's corner.
STAGE_NEAR_DISTANCE = 3.0**0.5 * STAGE_SPECULATIVE_DISTANCE
#: m, side of the square X-Z cells of the stage's triangle grid (stage_grid.py): about a few
#: bodies wide, so a body's box meets one to four cells.
STAGE_GRID_CELL = 1.0
#: cells, the most the stage grid holds; a larger stage gets coarser cells (doubled).
STAGE_GRID_MAX_CELLS = 1_000_000

# --- broad phase ------------------------------------------------------------------------
#: m, broad-phase AABB inflation of every body (keeps touching pairs found).
AABB_MARGIN = 0.005
#: comparisons, largest (moving bodies x collidable bodies) table the broad phase tests by
#: brute force; above it, sort and sweep (same pairs, O(n log n + overlaps)).
BROAD_PHASE_BRUTE_FORCE = 20_000
#: pairs, fewest candidate pairs for which the oriented-box pre-test pays for its NumPy calls.
MIN_PAIRS_FOR_BOX_TEST = 8

# --- restitution and friction -----------------------------------------------------------
#: m/s, a contact point approaching faster than this is an impact: its impulse is not kept
#: for warm starting (200 m/s stopped in one step must not be re-applied as a launch).
IMPACT_SPEED = 1.0
#: m/s, approach speeds below this do not bounce (kills micro bounces of resting bodies).
RESTITUTION_VELOCITY_THRESHOLD = 0.5

# --- sleeping ---------------------------------------------------------------------------
#: m/s, a body slower than this (and below the angular threshold) counts as resting.
SLEEP_LINEAR_VELOCITY = 0.05
#: rad/s, angular speed threshold for resting.
SLEEP_ANGULAR_VELOCITY = 0.1
#: s, an island sleeps after all its bodies have rested this long.
TIME_TO_SLEEP = 0.5
#: m, a body with a contact deeper than this is still being pushed apart by the position
#: solve (whose pseudo velocities the rest test cannot see), so it does not count as resting.
SLEEP_MAX_PENETRATION = 0.01

# --- numerics ---------------------------------------------------------------------------
#: 1 (unit of whatever it divides), smallest positive divisor: ``x / max(y, TINY)`` guards a
#: division by a length, mass or speed that may be exactly 0.
TINY = 1e-300
#: rad, below this rotation angle ``rotation_quat`` uses the limit ``sin(theta/2) / theta
#: -> 1/2`` (the rotation axis is undefined at zero angle; no 0 / 0).
SMALL_ROTATION_ANGLE = 1e-12
#: m^2 (for a unit ray direction), a triangle whose Moller-Trumbore determinant
#: ``e1 . (d x e2)`` is smaller in magnitude lies parallel to the ray: no hit.
RAY_PARALLEL_DETERMINANT = 1e-14
#: m, added to a body's bounding-sphere radius before a ray marches up to the sphere
#: (``cast_ray``), so round-off never starts the ray inside the body.
RAY_SPHERE_MARGIN = 1e-3
#: m, a hull vertex this close to the hull's center has no outward direction: growing the
#: hull into its speculative probe divides by this instead of its distance.
PROBE_MIN_OFFSET = 1e-12
#: points, a collision point set larger than this gets the hull of a capped sample
#: (hull_sampling.py): every hull pass and every contact step would pay for each vertex.
MAX_HULL_POINTS = 4096
#: points, about how many such a sample keeps (one per occupied cell of a grid).
HULL_SAMPLE_POINTS = 1024
#: m^3, a convex collision hull with no more volume than this is degenerate (refused).
MIN_HULL_VOLUME = 1e-12
#: 1, a point set whose smallest principal extent is at most this fraction of its largest
#: is flat: it gets ``FLAT_HULL_THICKNESS`` before its hull is built.
FLAT_HULL_RATIO = 1e-9
#: m^3, the least hull volume a unit-mass inertia is divided by (density 1 -> per kg).
MIN_INERTIA_VOLUME = 1e-18
#: m, half extent given to a bounding-box collision shape along an axis the mesh is flat in.
MIN_BOX_HALF_EXTENT = 1e-4
#: 1, a pose quaternion whose norm is at most this is degenerate (refused by pose setters).
MIN_QUATERNION_NORM = 1e-12
#: 1, a transformation whose rotation columns are shorter than this is degenerate (refused).
MIN_AXIS_SCALE = 1e-9
#: 1, a transformation whose normalized rotation part R has ``|R^T R - I|`` above this in
#: some entry is a shear, not a rotation (refused).
ORTHOGONALITY_TOLERANCE = 1e-4

# --- robustness -------------------------------------------------------------------------
#: m, the thinnest collision shape an object may have (smallest dimension of its body-frame
#: box); thinner templates are refused when the object is added. Bodies down to 5 mm (and
#: plates down to 1 mm) are tested not to fall through the stage.
MIN_BODY_DIMENSION = 1e-4
#: m/s, linear speeds are clamped to this (keeps a bad impulse from launching a body).
MAX_LINEAR_SPEED = 200.0
#: rad/s, angular speeds are clamped to this.
MAX_ANGULAR_SPEED = 100.0
#: fixed steps, the most a single step_physics call may run (dt / timestep above it raises).
MAX_STEPS_PER_CALL = 100_000
#: m (positions) and m/s or rad/s (velocity-control targets), the largest magnitude of one
#: component: the largest 32-bit float, the type Habitat keeps them in (beyond it they are
#: inf there). Poses and targets beyond it are refused before anything changes; within it the
#: float64 arithmetic on them (squares, the renderer's products) cannot overflow.
MAX_COORDINATE = 3.4028234663852886e38
#: 1, a body moving more than this fraction of its smallest half extent per step is swept
#: against static geometry (continuous collision, sweep.py) so it cannot tunnel through walls.
CCD_MOTION_FRACTION = 0.5
#: sweeps, the most swept tests per fast body and step (one more wall found per sweep).
CCD_SWEEPS = 3
#: rad, the path sweep follows a turning body's vertices along their arcs in chords of at
#: most this turn (a 20 cm reach strays at most 1.5 mm from its arc; 100 rad/s, the speed
#: limit, turns 0.8 rad in a 1/125 s step: 4 chords).
CCD_ARC_ANGLE = 0.25
#: m, a body whose center moved more than this in a step has its center's segment tested
#: against the stage's triangles (sweep.centers_through_stage); resting bodies are skipped
#: (a cone spun against a wall crept in 7-15 mm a step before its center crossed).
CCD_CENTER_TRAVEL = 0.001
#: m, how deep a swept body is left inside the wall it hit, so the next step sees the contact.
CCD_PENETRATION = 0.001
#: 1, ... at most this fraction of the body's smallest half extent (thin bodies stay thin).
CCD_PENETRATION_FRACTION = 0.2
#: m, the least smallest-half-extent the CCD threshold uses (a zero-size body would
#: otherwise count as fast at any speed).
CCD_MIN_RADIUS = 1e-6
#: m, padding of the box swept by a fast body, inside which obstacle triangles are tested.
SWEEP_BOX_PADDING = 1e-6

# --- analytic box-box contacts (box_box.py) -----------------------------------------------
#: 1, a B face axis replaces A's, and an edge-edge axis replaces the best face, only when
#: its separation s beats the face's s_f by ``s > BOX_AXIS_RELATIVE s_f + BOX_AXIS_ABSOLUTE``
#: (box2d-lite's relativeTol / absoluteTol): faces win near-ties, so resting boxes keep
#: face contacts with several points instead of flickering to a single edge point.
BOX_AXIS_RELATIVE = 0.95
#: m, see ``BOX_AXIS_RELATIVE``.
BOX_AXIS_ABSOLUTE = 0.0005
#: 1, ``|a_i x b_j|`` below this: the two edges are parallel and their cross product is no axis.
BOX_PARALLEL_EDGES = 1e-6
#: m, clipping tolerance: a point this close outside a face's rectangle still counts.
BOX_CLIP_TOLERANCE = 1e-7
#: m, clipped points closer than this to an earlier one of the same pair are duplicates.
BOX_DUPLICATE_DISTANCE = 1e-6
#: m, box pairs overlapping deeper than this (created inside each other) take the general
#: polyhedron path (fcl's normal + vertex contacts, tuned for separating spawned piles):
#: the least-overlap axis of such a pair is often vertical and pressed the lowest box of a
#: spawned pile into the floor (measured: 30 cubes at one point, lowest center 0.0896 m
#: analytic, 0.0956 m with this rule; the test asks > 0.09).
BOX_DEEP_OVERLAP = 0.02
