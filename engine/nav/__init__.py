"""Navigation: Habitat's ``habitat_sim.nav`` on the ``navmesh`` library.

The navmesh classes (``PathFinder``, ``NavMeshSettings``, ``ShortestPath``,
``MultiGoalShortestPath``, ``HitRecord``) and the greedy follower are importable from here.
What is here, in reading order:

1. :mod:`~engine.nav.pathfinder`: the simulator's ``PathFinder``, points as ``mn.Vector3``;
2. :mod:`~engine.nav.greedy_geodesic_follower`: ``GreedyGeodesicFollower``, the agent's
   actions fitted to the geodesic shortest path;
3. :mod:`~engine.nav.follower_poses`: the follower's scratch poses (the agent's controls on a
   node, or their arithmetic);
4. :mod:`~engine.nav.follower_probe`: its candidate steps scored in one batch.

May import: ``navmesh``, ``engine.agent`` (controls and the agent), ``engine.scene``,
``engine.mn``, ``engine.errors``. The simulator builds on this folder.
"""

from engine.nav.greedy_geodesic_follower import (
    GreedyFollowerCodes,
    GreedyGeodesicFollower,
    HitRecord,
    MultiGoalShortestPath,
    NavMeshSettings,
    PathFinder,
    ShortestPath,
)

__all__ = [
    "GreedyFollowerCodes",
    "GreedyGeodesicFollower",
    "HitRecord",
    "MultiGoalShortestPath",
    "NavMeshSettings",
    "PathFinder",
    "ShortestPath",
]
