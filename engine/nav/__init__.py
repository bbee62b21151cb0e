"""Navigation: Habitat's ``habitat_sim.nav`` (the navmesh classes, the PathFinder face,
the greedy geodesic follower)."""

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
