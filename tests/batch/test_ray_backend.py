"""``run_batch(..., backend="ray")``: same results as the other backends, retries of dead
workers, and a simulated two-node cluster on this machine.

A Ray cluster takes 10-30 s to start on two cores, so each test starts one: the first lets
``run_batch`` start (and stop) a local Ray instance itself, the second builds a two-node
cluster with ``ray.cluster_utils.Cluster``. Both listen on loopback only (conftest.py).
Skipped when Ray is not installed (``pip install rigidsim[ray]``).
"""

from __future__ import annotations

from pathlib import Path

import pytest

from engine.batch import episode_seed, run_batch

from .episodes_for_tests import ray_node_id, toss_cube
from .test_batch import PARAMS, values

ray = pytest.importorskip("ray")


def test_ray_matches_serial_and_retries_dead_workers(tmp_path: Path):
    killed_once = tmp_path / "killed_once"
    params = [*PARAMS, {"kill_once": str(killed_once)}, {"fail": True}, {"kill": True}]
    results = run_batch(
        toss_cube, params, backend="ray", workers=2, seed=11, max_retries=1, progress=False
    )
    assert not ray.is_initialized()  # run_batch started a local Ray and shut it down
    # the plain episodes give the serial backend's results bit for bit
    serial = run_batch(toss_cube, PARAMS, backend="serial", seed=11, progress=False)
    assert values(results[: len(PARAMS)]) == values(serial)
    kill_once, fail, kill = results[len(PARAMS) :]
    # the episode that killed its worker the first time ran again and finished
    assert killed_once.is_file() and kill_once.ok
    assert kill_once.seed == episode_seed(11, len(PARAMS))
    # a Python error is reported, not retried
    assert fail.status == "failed" and "ValueError" in fail.error
    # an episode that kills every worker it runs on is lost after max_retries reruns
    assert kill.status == "lost" and "died 2 times" in kill.error


def test_ray_on_a_simulated_two_node_cluster():
    from ray.cluster_utils import Cluster

    # fewer helper processes per node: they start faster on a busy machine
    node_args = {"num_cpus": 1, "include_log_monitor": False}
    cluster = Cluster(
        initialize_head=True, head_node_args={**node_args, "include_dashboard": False}
    )
    try:
        cluster.add_node(**node_args)
        cluster.wait_for_nodes()
        # what a real cluster needs: its address (here given, usually $RAY_ADDRESS)
        results = run_batch(
            ray_node_id,
            [{"sleep": 1.0}] * 4,
            backend="ray",
            ray_address=cluster.address,
            progress=False,
        )
        assert not ray.is_initialized()  # run_batch disconnected again
    finally:
        cluster.shutdown()
    assert all(r.ok for r in results)
    assert [r.value["seed"] for r in results] == [episode_seed(0, i) for i in range(4)]
    # one CPU per node and four 1 s episodes, two at a time: both nodes ran episodes
    assert len({r.value["node"] for r in results}) == 2
