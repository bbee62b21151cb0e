"""Seeded soak: thousands of mixed API operations on the demo apartment, checked after each.

Operations, drawn with fixed weights from one seeded generator: add an object (cube, sphere,
a 25 cm cone, a 27 cm capsule or one of the tutorial's example objects) above a random
navigable point, remove one, push one against a wall (a horizontal impulse of 1-4 m/s and a
force toward the stage surface a horizontal ray from its center meets within 2 m, both at a
point off its center),
teleport one, set linear / angular velocities (at most 4 m/s, 5 rad/s), apply forces,
torques and impulses (at most 2 m/s of velocity change), change the motion type, turn
velocity control on or off (at most 1 m/s), step the physics by 1/60 s, cast a ray, render
the agent's color and depth sensors at 16 x 16.

After every operation: no NaN or inf in any live body, the manager's object count equals the
soak's own list of live wrappers and the world's live bodies (stage excluded). After every
step: a DYNAMIC object that was put inside the apartment, never made kinematic/static or
driven by kinematic velocity control since, and now lies outside the stage's bounding box
grown by 0.5 m (below the floor or beyond a wall) is *lost*: recorded, then removed. Such an
object whose true shape (its lowest hull vertex in the world) is more than 2 cm below the
stage surface under it (rays cast down onto the stage alone from the object's center, from
above that vertex and from four points 2 cm beside it: the least depth), six steps or more
after it was put inside, has *sunk*: recorded with its depth. At the end every object rests
for 2 s and its final depth is measured the same way.
Memory is the process's resident set size, read after a warm-up (10 % of the operations)
and at the end.

The CI test ``tests/reliability/test_soak.py`` runs 2000 operations; this script runs 10^4
with a progress bar and prints the figures::

    python benchmarks/soak.py [--ops 10000] [--seed 0]
"""

from __future__ import annotations

import argparse
import os
import resource
import sys
import time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
from tqdm import tqdm

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import engine as habitat_sim  # noqa: E402
from engine.demo import demo_data_path  # noqa: E402
from engine.physics import MotionType  # noqa: E402
from engine.physics.core.quaternions import quat_to_matrix  # noqa: E402
from engine.physics.objects.queries import cast_ray_bodies  # noqa: E402
from engine.sensors import CameraSensorSpec, SensorType  # noqa: E402

#: operation -> weight (probability proportional to it)
OPERATIONS = {
    "add": 8,
    "remove": 4,
    "teleport": 6,
    "linear_velocity": 6,
    "angular_velocity": 4,
    "force": 5,
    "torque": 3,
    "impulse": 4,
    "push_wall": 6,
    "motion_type": 4,
    "velocity_control": 4,
    "step": 40,
    "ray": 6,
    "render": 3,
}
MAX_OBJECTS = 24  # an "add" with this many objects removes one instead
MAX_SPEED = 4.0  # m/s
MAX_SPIN = 5.0  # rad/s
LOST_MARGIN = 0.5  # m, outside the stage's bounding box by more than this is lost
SINK_TOLERANCE = 0.02  # m, the lowest hull vertex this far below the stage under it has sunk
SETTLE_STEPS = 6  # steps after being put inside before an object's depth counts
REST_STEPS = 120  # steps of rest at the end before the final depths
#: soak templates of Habitat's default cone and capsule primitives, scaled to 10 cm radii
PRIMITIVES = {
    "soak_cone": "coneSolid_segments_12_halfLen_1.25_rings_1_useTexCoords_false"
    "_useTangents_false_capEnd_true",
    "soak_capsule": "capsule3DSolid_hemiRings_4_cylRings_1_segments_12_halfLen_0.75"
    "_useTexCoords_false_useTangents_false",
}
ALL_TEMPLATES = (
    "cubeSolid", "uvSphereSolid", "soak_cone", "soak_capsule", "cheezit", "banana", "chefcan",
    "mug",
)  # fmt: skip
#: the CI test's lighter mix: cheaper objects, fewer of them, fewer steps
CI_TEMPLATES = ("cubeSolid", "uvSphereSolid", "soak_cone", "soak_capsule", "cheezit")
CI_MAX_OBJECTS = 10
CI_OPERATIONS = {**OPERATIONS, "step": 20}


@dataclass
class SoakReport:
    """What a soak run measured."""

    operations: int
    seed: int
    counts: dict = field(default_factory=dict)  # operation -> times run
    steps: int = 0
    max_objects: int = 0
    #: (operation index, handle, position, the last operations on that object)
    lost: list = field(default_factory=list)
    #: (operation index, handle, depth in m, the last operations on that object)
    sunk: list = field(default_factory=list)
    deepest: float = 0.0  # m, the deepest lowest-vertex depth seen after settling
    final_deepest: float = 0.0  # m, the deepest one after the final rest
    final_by_kind: dict = field(default_factory=dict)  # template -> deepest final depth, m
    rss_after_warmup_mb: float = 0.0
    rss_end_mb: float = 0.0
    peak_rss_mb: float = 0.0
    wall_seconds: float = 0.0
    ray_hits: int = 0

    @property
    def memory_growth_mb(self) -> float:
        return self.rss_end_mb - self.rss_after_warmup_mb

    def summary(self) -> str:
        ops = ", ".join(f"{k} {v}" for k, v in sorted(self.counts.items()))
        return (
            f"{self.operations} operations (seed {self.seed}) in {self.wall_seconds:.1f} s: "
            f"{ops}\n{self.steps} steps, at most {self.max_objects} objects, "
            f"{self.ray_hits} ray hits, no NaN, counts consistent after every operation\n"
            f"lost dynamic objects: {len(self.lost)}"
            + "".join(
                f"\n  op {i}: {h} at {np.round(p, 2).tolist()} after {history}"
                for i, h, p, history in self.lost
            )
            + f"\nsunk (lowest hull vertex > {SINK_TOLERANCE * 100:.0f} cm below the stage "
            f"under it): {len(self.sunk)}, deepest {self.deepest * 100:.2f} cm"
            + "".join(
                f"\n  op {i}: {h} {d * 100:.1f} cm after {history}"
                for i, h, d, history in self.sunk
            )
            + f"\nafter {REST_STEPS} steps of rest: deepest {self.final_deepest * 100:.2f} cm ("
            + ", ".join(f"{k} {v * 100:.2f}" for k, v in sorted(self.final_by_kind.items()))
            + ")"
            + f"\nresident memory: {self.rss_after_warmup_mb:.1f} MB after warm-up, "
            f"{self.rss_end_mb:.1f} MB at the end (growth {self.memory_growth_mb:+.1f} "
            f"MB), peak {self.peak_rss_mb:.1f} MB"
        )


def resident_mb() -> float:
    """Current resident set size in MB (Linux /proc; elsewhere the peak from getrusage)."""
    try:
        pages = int(Path("/proc/self/statm").read_text().split()[1])
        return pages * os.sysconf("SC_PAGE_SIZE") / 2**20
    except (OSError, ValueError, IndexError):
        return peak_mb()


def peak_mb() -> float:
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0


class Soak:
    """The world and the bookkeeping of one soak run (see the module docstring)."""

    def __init__(
        self,
        seed: int,
        data_path: Path | None = None,
        templates: tuple = ALL_TEMPLATES,
        max_objects: int = MAX_OBJECTS,
    ) -> None:
        data = demo_data_path() if data_path is None else Path(data_path)
        cfg = habitat_sim.SimulatorConfiguration()
        cfg.scene_id = str(data / "scene_datasets/demo/apartment.glb")
        specs = []
        for uuid, kind in (("color", SensorType.COLOR), ("depth", SensorType.DEPTH)):
            spec = CameraSensorSpec()
            spec.uuid, spec.sensor_type, spec.resolution = uuid, kind, [16, 16]
            specs.append(spec)
        agent_cfg = habitat_sim.agent.AgentConfiguration()
        agent_cfg.sensor_specifications = specs
        self.sim = habitat_sim.Simulator(habitat_sim.Configuration(cfg, [agent_cfg]))
        library = self.sim.get_object_template_manager()
        library.load_configs(str(data / "objects/example_objects"))
        for name, primitive in PRIMITIVES.items():
            template = library.create_new_template(name)
            template.render_asset_handle = template.collision_asset_handle = primitive
            template.scale = [0.1, 0.1, 0.1]
            library.register_template(template, name)
        self.handles = [library.get_template_handles(name)[0] for name in templates]
        self.max_objects = max_objects
        self.manager = self.sim.get_rigid_object_manager()
        self.world = self.sim.get_physics_world()
        self.rng = np.random.default_rng(seed)
        self.sim.pathfinder.seed(seed)
        low, high = self.sim.pathfinder.get_bounds()
        stage = self.world.bodies
        lo = stage.body_position[0] + stage.body_shape_center[0] - stage.body_shape_half[0]
        hi = stage.body_position[0] + stage.body_shape_center[0] + stage.body_shape_half[0]
        self.box = (np.minimum(lo, low) - LOST_MARGIN, np.maximum(hi, high) + LOST_MARGIN)
        self.objects: dict[int, object] = {}  # our own list of live wrappers
        self.history: dict[int, list] = {}  # object id -> its last operations
        self.picked: int | None = None  # the object the current operation used
        self.tracked: set[int] = set()  # dynamic since put inside: may not leave the stage
        self.steps = 0  # steps run so far
        self.placed: dict[int, int] = {}  # object id -> the step count when put inside
        self.kinds: dict[int, str] = {}  # object id -> its template's short name
        self.depths_checked_at = 0  # the step count at the last depth check

    # -- helpers ------------------------------------------------------------------------
    def _pick(self):
        ids = sorted(self.objects)
        if not ids:
            return None
        self.picked = ids[int(self.rng.integers(len(ids)))]
        return self.objects[self.picked]

    def _inside_point(self) -> np.ndarray:
        point = self.sim.pathfinder.get_random_navigable_point()
        return point + np.array([0.0, self.rng.uniform(0.3, 1.0), 0.0])

    def _vector(self, magnitude: float) -> np.ndarray:
        direction = self.rng.normal(size=3)
        return direction / np.linalg.norm(direction) * self.rng.uniform(0.0, magnitude)

    # -- operations ---------------------------------------------------------------------
    def add(self) -> None:
        if len(self.objects) >= self.max_objects:
            self.remove()
            return
        handle = self.handles[int(self.rng.integers(len(self.handles)))]
        obj = self.manager.add_object_by_template_handle(handle)
        obj.translation = self._inside_point()
        obj.rotation = habitat_sim.mn.to_quaternion(self.rng.normal(size=4))
        self.objects[obj.object_id] = obj
        self.tracked.add(obj.object_id)
        self.placed[obj.object_id] = self.steps
        self.kinds[obj.object_id] = Path(handle).name.split(".")[0]
        self.picked = obj.object_id

    def remove(self) -> None:
        obj = self._pick()
        if obj is not None:
            self._forget(obj.object_id)
            self.manager.remove_object_by_id(obj.object_id)

    def _forget(self, object_id: int) -> None:
        del self.objects[object_id]
        self.tracked.discard(object_id)
        self.history.pop(object_id, None)

    def teleport(self) -> None:
        obj = self._pick()
        if obj is not None:
            obj.translation = self._inside_point()
            self.placed[obj.object_id] = self.steps
            if obj.motion_type == MotionType.DYNAMIC and not self._kinematic_control(obj):
                self.tracked.add(obj.object_id)

    def linear_velocity(self) -> None:
        if (obj := self._pick()) is not None:
            obj.linear_velocity = self._vector(MAX_SPEED)

    def angular_velocity(self) -> None:
        if (obj := self._pick()) is not None:
            obj.angular_velocity = self._vector(MAX_SPIN)

    def force(self) -> None:
        if (obj := self._pick()) is not None:  # at most 2 m/s over one 1/60 s frame
            obj.apply_force(self._vector(120.0 * obj.mass), self._vector(0.05))

    def push_wall(self) -> None:
        """Push a dynamic object toward the wall a horizontal ray from its center meets."""
        obj = self._pick()
        if obj is None or obj.motion_type != MotionType.DYNAMIC:
            return
        angle = self.rng.uniform(0.0, 2.0 * np.pi)
        direction = np.array([np.cos(angle), 0.0, np.sin(angle)])
        center = np.asarray(obj.translation)
        if not cast_ray_bodies(self.world.bodies, [0], center, direction, 2.0):
            return
        offset = self._vector(0.05)
        obj.apply_impulse(direction * self.rng.uniform(1.0, 4.0) * obj.mass, offset)
        obj.apply_force(direction * 120.0 * obj.mass, offset)

    def torque(self) -> None:
        if (obj := self._pick()) is not None:
            obj.apply_torque(self._vector(10.0 * obj.mass * 0.01))

    def impulse(self) -> None:
        if (obj := self._pick()) is not None:
            obj.apply_impulse(self._vector(2.0 * obj.mass), self._vector(0.02))

    def motion_type(self) -> None:
        if (obj := self._pick()) is None:
            return
        choice = self.rng.choice(
            [MotionType.DYNAMIC, MotionType.DYNAMIC, MotionType.KINEMATIC, MotionType.STATIC]
        )
        obj.motion_type = MotionType(int(choice))
        if obj.motion_type != MotionType.DYNAMIC:
            self.tracked.discard(obj.object_id)  # may be left anywhere: re-tracked on teleport

    def velocity_control(self) -> None:
        if (obj := self._pick()) is None:
            return
        control = obj.velocity_control
        on = bool(self.rng.random() < 0.5)
        control.controlling_lin_vel = control.controlling_ang_vel = on
        control.linear_velocity = self._vector(1.0)
        control.angular_velocity = self._vector(1.0)
        control.lin_vel_is_local = bool(self.rng.random() < 0.5)
        if self._kinematic_control(obj):
            self.tracked.discard(obj.object_id)

    @staticmethod
    def _kinematic_control(obj) -> bool:
        control = obj.velocity_control
        return obj.motion_type == MotionType.KINEMATIC and (
            control.controlling_lin_vel or control.controlling_ang_vel
        )

    def step(self) -> None:
        self.sim.step_physics(1.0 / 60.0)
        self.steps += 1

    def ray(self) -> int:
        origin = self._inside_point()
        ray = habitat_sim.geo.Ray(origin, self._vector(1.0) + [0.0, 0.0, 1e-3])
        results = self.sim.cast_ray(ray, 20.0)
        for hit in results.hits:
            if not (np.all(np.isfinite(np.asarray(hit.point))) and hit.ray_distance >= 0):
                raise AssertionError(f"bad ray hit {hit}")
        return len(results.hits)

    def render(self) -> None:
        agent = self.sim.agents[0]
        state = agent.get_state()
        state.position = self.sim.pathfinder.get_random_navigable_point()
        agent.set_state(state)
        observations = self.sim.get_sensor_observations()
        if not np.all(np.isfinite(observations["depth"])):
            raise AssertionError("non-finite depth in a render")

    # -- checks -------------------------------------------------------------------------
    def check(self, op_index: int, report: SoakReport) -> None:
        """No NaN, consistent counts; lost objects are recorded and removed."""
        b, n = self.world.bodies, self.world.bodies.count
        alive = b.body_alive[:n].copy()
        for name in (
            "body_position",
            "body_rotation",
            "body_linear_velocity",
            "body_angular_velocity",
        ):
            if not np.all(np.isfinite(getattr(b, name)[:n][alive])):
                raise AssertionError(f"op {op_index}: non-finite {name}")
        alive[0] = False  # the stage
        counts = (self.manager.get_num_objects(), len(self.objects), int(np.count_nonzero(alive)))
        if len(set(counts)) != 1:
            raise AssertionError(
                f"op {op_index}: inconsistent counts (manager, wrappers, bodies) = {counts}"
            )
        for object_id in sorted(self.tracked):
            obj = self.objects[object_id]
            position = np.asarray(obj.translation)
            if np.all(position >= self.box[0]) and np.all(position <= self.box[1]):
                continue
            speed = float(np.linalg.norm(np.asarray(obj.linear_velocity)))
            history = self.history.get(object_id, [])[-6:] + [f"{speed:.1f} m/s"]
            report.lost.append((op_index, obj.handle, position, history))
            self._forget(object_id)
            self.manager.remove_object_by_id(object_id)
        if self.steps == self.depths_checked_at:
            return  # the depths change only when the world steps
        self.depths_checked_at = self.steps
        awake = self.world.bodies.body_awake
        for object_id in sorted(self.tracked):
            if self.steps - self.placed.get(object_id, 0) < SETTLE_STEPS or not awake[object_id]:
                continue  # settling, or asleep (checked while it came to rest)
            depth = self.depth_below_stage(object_id)
            report.deepest = max(report.deepest, depth)
            if depth > SINK_TOLERANCE:
                history = self.history.get(object_id, [])[-6:]
                report.sunk.append((op_index, self.objects[object_id].handle, depth, history))

    def depth_below_stage(self, object_id: int) -> float:
        """How far (m) the object's lowest hull vertex is below the stage surface under it,
        0 when above: the least depth below rays cast down onto the stage alone from the
        object's center and from above the vertex and four points ``SINK_TOLERANCE`` beside
        it (a vertex touching the side of a step, or a body over a table with a foot on the
        floor, is then not taken for sunk into the step or the table)."""
        b = self.world.bodies
        rotation = quat_to_matrix(b.body_rotation[object_id])
        points = np.concatenate([shape.hull_vertices for shape in b.shapes[object_id]])
        world = points @ rotation.T + b.body_position[object_id]
        lowest = world[np.argmin(world[:, 1])]
        center = b.body_position[object_id]
        tops = [
            np.array([lowest[0] + dx * SINK_TOLERANCE, center[1], lowest[2] + dz * SINK_TOLERANCE])
            for dx, dz in ((0, 0), (1, 0), (-1, 0), (0, 1), (0, -1))
        ] + [center]
        depth = np.inf
        for top in tops:  # the least depth: stop at the first ray that finds none
            hits = cast_ray_bodies(b, [0], top, np.array([0.0, -1.0, 0.0]), 5.0)
            surface = hits[0][2][1] if hits else -np.inf
            depth = min(depth, max(0.0, float(surface - lowest[1])))
            if depth == 0.0:
                break
        return depth

    def rest_depths(self, report: SoakReport) -> None:
        """Step ``REST_STEPS`` times, then record each tracked object's depth by template."""
        for _ in range(REST_STEPS):
            self.step()
        for object_id in sorted(self.tracked):
            depth = self.depth_below_stage(object_id)
            kind = self.kinds[object_id]
            report.final_deepest = max(report.final_deepest, depth)
            report.final_by_kind[kind] = max(report.final_by_kind.get(kind, 0.0), depth)


def run_soak(
    operations: int = 2000,
    seed: int = 0,
    progress: bool = False,
    data_path: Path | None = None,
    templates: tuple = ALL_TEMPLATES,
    max_objects: int = MAX_OBJECTS,
    weights: dict | None = None,
) -> SoakReport:
    """Run ``operations`` seeded operations and return the figures (see the module docstring).

    ``templates`` (template name fragments), ``max_objects`` and ``weights`` (operation ->
    weight, default :data:`OPERATIONS`) choose the mix; the CI test uses the ``CI_*`` ones.
    """
    soak = Soak(seed, data_path, templates, max_objects)
    report = SoakReport(operations, seed)
    table = OPERATIONS if weights is None else weights
    names = list(table)
    weights = np.array([table[name] for name in names], dtype=np.float64)
    draws = soak.rng.choice(len(names), size=operations, p=weights / weights.sum())
    warmup = max(1, operations // 10)
    start = time.perf_counter()
    for op_index, draw in enumerate(tqdm(draws, disable=not progress, desc="soak")):
        name = names[int(draw)]
        soak.picked = None
        result = getattr(soak, name)()
        if soak.picked in soak.objects:
            soak.history.setdefault(soak.picked, []).append(f"{op_index}:{name}")
        report.counts[name] = report.counts.get(name, 0) + 1
        if name == "ray":
            report.ray_hits += result
        if name == "step":
            report.steps += 1
        soak.check(op_index, report)
        report.max_objects = max(report.max_objects, len(soak.objects))
        if op_index + 1 == warmup:
            report.rss_after_warmup_mb = resident_mb()
    report.wall_seconds = time.perf_counter() - start
    soak.rest_depths(report)
    report.rss_end_mb = resident_mb()
    report.peak_rss_mb = peak_mb()
    soak.sim.close()
    return report


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--ops", type=int, default=10_000)
    parser.add_argument("--seed", type=int, default=0)
    args = parser.parse_args()
    report = run_soak(args.ops, args.seed, progress=True)
    print(report.summary())


if __name__ == "__main__":
    main()
