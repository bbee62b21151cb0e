"""``engine.batch.run_batch`` with the serial and process backends.

Contract: episode ``i`` gets ``SeedSequence(batch seed).spawn(n)[i]``'s seed whatever runs
it; results come back in input order; a failing episode or a dying worker process never
loses the others; ``output_dir`` + ``resume=True`` continues an interrupted batch.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from engine.batch import WorkerPool, episode_seed, read_results, run_batch

from .episodes_for_tests import seed_echo, toss_cube

PARAMS = [{"speed": 0.5 + 0.25 * i} for i in range(6)]
GRAVITY_Y = -9.8


def values(results):
    """What must not depend on the backend: index, params, seed, status, value."""
    out = []
    for r in results:
        value = dict(r.value)
        value.pop("pid")
        out.append((r.index, r.params, r.seed, r.status, value))
    return out


@pytest.fixture(scope="module")
def serial_results():
    return run_batch(toss_cube, PARAMS, backend="serial", seed=11, progress=False)


def test_episode_seeds_are_numpys_spawned_sequences():
    children = np.random.SeedSequence(11).spawn(4)
    expected = [int(c.generate_state(1, dtype=np.uint32)[0]) for c in children]
    assert [episode_seed(11, i) for i in range(4)] == expected
    assert len({episode_seed(11, i) for i in range(100)}) == 100


def test_serial_results_are_in_order_and_physical(serial_results):
    assert [r.index for r in serial_results] == list(range(len(PARAMS)))
    for r in serial_results:
        assert r.ok and r.error is None and r.wall_time > 0
        assert r.seed == episode_seed(11, r.index)
        # free flight from the origin, n symplectic Euler steps of h:
        # p_n = n h v0 + g h^2 n (n + 1) / 2
        v, h = np.asarray(r.value["velocity"]), r.value["time_step"]
        n = round(r.value["world_time"] / h)
        assert n * h == pytest.approx(0.1, abs=h)
        expected = n * h * v + np.array([0.0, GRAVITY_Y, 0.0]) * h**2 * n * (n + 1) / 2
        np.testing.assert_allclose(r.value["position"], expected, atol=1e-9)
        speed = np.linalg.norm(v)
        assert speed > 0  # params set the scale of the seeded random velocity
    # different seeds give different episodes
    assert len({tuple(r.value["velocity"]) for r in serial_results}) == len(PARAMS)


@pytest.mark.parametrize("workers", [1, 2])
def test_process_backend_matches_serial(serial_results, workers):
    results = run_batch(
        toss_cube, PARAMS, backend="process", workers=workers, seed=11, progress=False
    )
    assert values(results) == values(serial_results)  # bit for bit
    pids = {r.value["pid"] for r in results}
    assert len(pids) <= workers


def test_a_kept_pool_runs_several_batches_and_survives_a_killed_worker(serial_results):
    with WorkerPool(2) as pool:
        assert pool.start() > 0
        first = run_batch(toss_cube, PARAMS, backend="process", pool=pool, seed=11, progress=False)
        killed = run_batch(
            toss_cube, [{}, {"kill": True}, {}], backend="process", pool=pool, progress=False
        )
        again = run_batch(toss_cube, PARAMS, backend="process", pool=pool, seed=11, progress=False)
    assert values(first) == values(serial_results) == values(again)
    assert [r.status for r in killed] == ["ok", "lost", "ok"]
    with pytest.raises(ValueError, match="pool"):
        run_batch(toss_cube, [{}], backend="serial", pool=WorkerPool(1))
    with pytest.raises(ValueError, match="workers"):
        run_batch(toss_cube, [{}], workers=3, pool=WorkerPool(2))


def test_short_episodes_travel_in_chunks_and_keep_their_order():
    # 0.1 ms episodes: after the first ones, chunks of many episodes per submission
    params = [{"i": i} for i in range(300)]
    results = run_batch(seed_echo, params, backend="process", workers=2, seed=5, progress=False)
    assert [r.index for r in results] == list(range(300))
    assert [r.params for r in results] == params
    assert [r.value for r in results] == [{"i": i, "seed": episode_seed(5, i)} for i in range(300)]
    assert len({r.worker for r in results}) <= 2


def test_a_failing_episode_is_reported_and_the_others_complete():
    params = [{}, {"fail": True}, {}, {}]
    results = run_batch(toss_cube, params, backend="process", workers=2, progress=False)
    assert [r.status for r in results] == ["ok", "failed", "ok", "ok"]
    failed = results[1]
    assert failed.error.startswith("ValueError: episode asked to fail")
    assert "raise ValueError" in failed.traceback and failed.value is None


def test_a_killed_worker_loses_only_its_episode():
    # episode 2 kills its own worker process (SIGKILL) every time it runs
    params = [{"sleep": 0.2}, {}, {"kill": True}, {}, {"sleep": 0.2}, {}]
    results = run_batch(toss_cube, params, backend="process", workers=2, progress=False)
    assert [r.status for r in results] == ["ok", "ok", "lost", "ok", "ok", "ok"]
    assert "BrokenProcessPool" in results[2].error
    assert results[2].value is None and results[2].seed == episode_seed(0, 2)
    # the episodes that went down with the pool ran again and match a clean serial run
    clean = run_batch(
        toss_cube, [{} if "kill" in p else p for p in params], backend="serial", progress=False
    )
    kept = [i for i in range(len(params)) if i != 2]
    assert values([results[i] for i in kept]) == values([clean[i] for i in kept])


def test_results_are_written_as_they_arrive_and_a_batch_resumes(tmp_path: Path):
    out = tmp_path / "batch"
    params = [{"speed": 1.0}, {"speed": 2.0}, {"speed": 3.0}, {"speed": 4.0}]

    calls = []

    def interrupted_at_2(p, seed, episode_dir=None):
        calls.append(p["speed"])
        if p["speed"] == 3.0:
            raise KeyboardInterrupt  # Ctrl-C while episode 2 runs
        return toss_cube(p, seed, episode_dir)

    with pytest.raises(KeyboardInterrupt):
        run_batch(interrupted_at_2, params, backend="serial", output_dir=out, progress=False)
    on_disk = read_results(out)
    assert [r.index for r in on_disk] == [0, 1]
    lines = (out / "results.jsonl").read_text().splitlines()
    assert [json.loads(line)["index"] for line in lines] == [0, 1]
    assert (out / "episodes" / "00001" / "velocity.npy").is_file()

    calls.clear()
    results = run_batch(
        _recorder(calls), params, backend="serial", output_dir=out, resume=True, progress=False
    )
    assert calls == [3.0, 4.0]  # only the episodes that had not finished ran
    assert [r.status for r in results] == ["ok"] * 4
    full = run_batch(toss_cube, params, backend="serial", progress=False)
    for resumed, fresh in zip(results, full, strict=True):
        assert resumed.value["position"] == fresh.value["position"]
    saved = np.load(out / "episodes" / "00003" / "velocity.npy")
    np.testing.assert_array_equal(saved, results[3].value["velocity"])
    # everything ran: resuming again runs nothing
    calls.clear()
    run_batch(
        _recorder(calls), params, backend="serial", output_dir=out, resume=True, progress=False
    )
    assert calls == []


def _recorder(calls):
    def recording_toss(p, seed, episode_dir=None):
        calls.append(p["speed"])
        return toss_cube(p, seed, episode_dir)

    return recording_toss


def test_a_torn_last_line_is_ignored_and_rerun(tmp_path: Path):
    out = tmp_path / "batch"
    params = [{"speed": 1.0}, {"speed": 2.0}]
    run_batch(toss_cube, params, backend="serial", output_dir=out, progress=False)
    path = out / "results.jsonl"
    first, second = path.read_text().splitlines()
    path.write_text(first + "\n" + second[: len(second) // 2])  # killed while writing
    calls = []
    results = run_batch(
        _recorder(calls), params, backend="serial", output_dir=out, resume=True, progress=False
    )
    assert calls == [2.0] and all(r.ok for r in results)
    assert [r.index for r in read_results(out)] == [0, 1]


def test_a_value_json_cannot_hold_fails_its_episode_only(tmp_path: Path):
    def returns_an_object(p, seed):
        return {"thing": object()} if p["bad"] else {"seed": seed}

    results = run_batch(
        returns_an_object,
        [{"bad": False}, {"bad": True}],
        backend="serial",
        output_dir=tmp_path,
        progress=False,
    )
    assert [r.status for r in results] == ["ok", "failed"]
    assert "not JSON serializable" in results[1].error
    assert [r.status for r in read_results(tmp_path)] == ["ok", "failed"]


def test_bad_arguments_are_refused_before_anything_runs(tmp_path: Path):
    with pytest.raises(ValueError, match="backend"):
        run_batch(toss_cube, [{}], backend="threads")
    with pytest.raises(TypeError, match="sequence"):
        run_batch(toss_cube, {"speed": 1.0})
    with pytest.raises(ValueError, match="workers"):
        run_batch(toss_cube, [{}], workers=0)
    with pytest.raises(ValueError, match="seed"):
        run_batch(toss_cube, [{}], seed=-1)
    with pytest.raises(ValueError, match="resume"):
        run_batch(toss_cube, [{}], resume=True)
    with pytest.raises(TypeError, match=r"params\[1\]"):
        run_batch(toss_cube, [{}, {"x": object()}], output_dir=tmp_path / "a")
    assert not (tmp_path / "a").exists()
    out = tmp_path / "b"
    run_batch(toss_cube, [{}], backend="serial", output_dir=out, progress=False)
    with pytest.raises(FileExistsError, match="resume=True"):
        run_batch(toss_cube, [{}], backend="serial", output_dir=out, progress=False)
    with pytest.raises(ValueError, match="params"):
        run_batch(
            toss_cube,
            [{"speed": 9.0}],
            backend="serial",
            output_dir=out,
            resume=True,
            progress=False,
        )
    with pytest.raises(ValueError, match="n_episodes"):
        run_batch(
            toss_cube, [{}, {}], backend="serial", output_dir=out, resume=True, progress=False
        )
