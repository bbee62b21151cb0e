"""Habitat-style navigation: configure with ``make_cfg``, act with ``sim.step``, follow a path.

The flow of Habitat's "Basics for Navigation" tutorial on rigidsim's demo apartment, with
only the import lines changed: build a configuration from ``default_sim_settings``, place the
agent, take a few discrete actions (each returns the observations and whether the agent
collided), then let the greedy geodesic follower walk to a random goal.

    python examples/navigate.py                 # 256 x 256 sensors, prints what happens
    python examples/navigate.py --video out.mp4 # also writes the walk as a video
    python examples/navigate.py --fast          # small sensors (the test suite's mode)
"""

from __future__ import annotations

import argparse

import numpy as np

import engine as habitat_sim
from engine.demo import demo_data_path
from engine.utils import viz_utils as vut
from engine.utils.settings import default_sim_settings, make_cfg


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--fast", action="store_true", help="64 x 64 sensors")
    parser.add_argument("--video", help="write the follower's walk to this .mp4 file")
    args = parser.parse_args()

    size = 64 if args.fast else 256
    settings = {
        **default_sim_settings,
        "scene": str(demo_data_path() / "scene_datasets/demo/apartment.glb"),
        "width": size,
        "height": size,
        "color_sensor": True,
        "depth_sensor": True,
        "seed": 1,
        "physics_config_file": "",  # Habitat's default physics settings
    }
    with habitat_sim.Simulator(make_cfg(settings)) as sim:
        agent = sim.initialize_agent(0)
        agent.set_state(habitat_sim.AgentState(np.array([-0.6, -1.45, 0.5])))

        for action in ("move_forward", "turn_left", "move_forward", "turn_right"):
            observations = sim.step(action)
            depth = observations["depth_sensor"]
            print(
                f"{action:13s} collided={observations['collided']!s:5s} "
                f"position={np.round(agent.get_state().position, 3)} "
                f"median depth {np.median(depth[depth > 0]):.2f} m"
            )

        sim.pathfinder.seed(4)
        goal = sim.pathfinder.get_random_navigable_point(island_index=0)
        path = habitat_sim.ShortestPath()
        path.requested_start, path.requested_end = agent.get_state().position, goal
        sim.pathfinder.find_path(path)
        print(f"goal {np.round(goal, 2)}: geodesic distance {path.geodesic_distance:.2f} m")

        follower = sim.make_greedy_follower(goal_radius=0.25)
        frames = []
        for action in follower.find_path(goal):
            if action is None:  # the follower's stop
                break
            frames.append(sim.step(action))
        left = float(np.linalg.norm(agent.get_state().position - goal))
        print(f"follower: {len(frames)} actions, {left:.2f} m from the goal")
        if args.video and frames:
            vut.make_video(frames, "color_sensor", "color", args.video, fps=10, open_vid=False)
            print(f"wrote {args.video}")


if __name__ == "__main__":
    main()
