"""Gymnasium/PettingZoo semantics of the evacuation environment at the discrete level:
PettingZoo's seed, max-cycles and state tests, action masks that every action obeys,
observations a learner can use, seeding of resets without a seed, and pickling."""
import functools
import multiprocessing
import pickle
import types

import numpy as np
import pytest
from pettingzoo.test import max_cycles_test, parallel_api_test
from pettingzoo.test.seed_test import parallel_seed_test, seed_test
from pettingzoo.test.state_test import test_state as state_test

from vitro.env import env, parallel_env


@pytest.fixture
def scenario(root):
    return str(root / "scenarios/evacuation.toml")


def test_seed_tests_pass(scenario):
    # seed=42: the runs built with the environment serve the tests' resets to 42.
    make = functools.partial(parallel_env, scenario, seed=42, until=90.0, decision_s=30)
    parallel_seed_test(make, num_cycles=3)
    seed_test(functools.partial(env, scenario, seed=42, until=60.0, decision_s=30), num_cycles=2)


def test_max_cycles_test_passes(scenario):
    mod = types.SimpleNamespace(
        parallel_env=functools.partial(parallel_env, scenario, until=900.0, decision_s=10),
        env=functools.partial(env, scenario, until=900.0, decision_s=10),
    )
    max_cycles_test(mod)


def test_flat_observations_pass_the_api_tests(scenario):
    e = parallel_env(scenario, seed=3, until=90.0, decision_s=30, flat=True)
    parallel_api_test(e, num_cycles=3)
    obs, infos = e.reset(seed=3)
    for a, o in obs.items():
        assert o.dtype == np.float32 and o.shape == e.observation_space(a).shape
        assert e.observation_space(a).contains(o)
        assert o[e.flat_fields["time"]][0] == 0.0
        assert infos[a]["action_mask"].dtype == np.int8


def test_spaces_are_float32(scenario):
    e = parallel_env(scenario, until=60.0)
    space = e.observation_space(e.possible_agents[0])
    for name, s in space.spaces.items():
        if hasattr(s, "dtype") and name != "action_mask" and s.shape != ():
            assert s.dtype == np.float32, name
    assert space["action_mask"].dtype == np.int8
    assert e.state_space.dtype == np.float32


def test_state_is_the_referees_ground_truth(scenario):
    state_test(env(scenario, seed=0, until=60.0, decision_s=30), 2)
    e = parallel_env(scenario, seed=5, until=60.0, decision_s=30)
    e.reset(seed=5)
    s = e.state()
    assert e.state_space.contains(s)
    assert s[0] == 0.0
    rows = s[1:].reshape(-1, 4)
    assert len(rows) == len(e.members)
    red = [i for i, (_, _, side) in enumerate(e.members) if side == 2]
    assert red, "the scenario has adversaries"
    # The ground truth holds every adversary's place, which no observation needs to.
    assert all(rows[i, 3] in (0.0, 1.0) for i in red)
    e.step({a: 0 for a in e.agents})
    assert e.state()[0] > 0
    assert "state" not in e.observation_space(e.possible_agents[0]).spaces


def episode(e, seed=None, steps=2):
    obs, _ = e.reset(seed=seed)
    out = [e.episode_seed]
    for _ in range(steps):
        if not e.agents:
            break
        obs, rewards, _, _, _ = e.step({a: 1 for a in e.agents})
        out.append((sorted(rewards.items()), {a: o["position"].tolist() for a, o in obs.items()}))
    return out, e.trace_hash


def test_reset_without_a_seed_continues_the_generator(scenario):
    # Without any seed: the environment's seed first, then its generator.
    e = parallel_env(scenario, seed=7, until=60.0, decision_s=30)
    first, second, third = episode(e), episode(e), episode(e)
    assert first[0][0] == 7
    assert len({first[1], second[1], third[1]}) == 3, "a new episode each time"
    # reset(seed=7) seeds the generator the same way: the same sequence follows.
    f = parallel_env(scenario, until=60.0, decision_s=30)
    assert [episode(f, seed=7), episode(f)] == [first, second]


def test_pickle_round_trip_rebuilds_the_environment(scenario):
    e = parallel_env(scenario, seed=9, until=60.0, decision_s=30, units=["mdars", "vidar-1"])
    episode(e)
    copy = pickle.loads(pickle.dumps(e))
    assert copy.possible_agents == ["mdars", "vidar-1"]
    assert copy.decision_s == 30 and copy.until == 60.0
    # The seed generator travels: the next seedless episode is the same in both.
    assert episode(copy) == episode(e)


def _rollout_in_a_subprocess(blob):
    e = pickle.loads(blob)
    return episode(e, seed=4)


def test_a_pickled_environment_runs_in_another_process(scenario):
    e = parallel_env(scenario, seed=4, until=60.0, decision_s=30)
    here = episode(e, seed=4)
    ctx = multiprocessing.get_context("spawn")
    with ctx.Pool(1) as pool:
        there = pool.apply(_rollout_in_a_subprocess, (pickle.dumps(e),))
    assert there == here


def test_supersuit_concat_vec_envs_with_two_processes(scenario):
    ss = pytest.importorskip("supersuit")
    e = parallel_env(scenario, until=90.0, decision_s=30, flat=True)
    e = ss.black_death_v3(e)
    vec = ss.pettingzoo_env_to_vec_env_v1(e)
    vec = ss.concat_vec_envs_v1(vec, 2, num_cpus=2, base_class="gymnasium")
    obs, _ = vec.reset(seed=1)
    n = len(e.possible_agents)
    assert obs.shape == (2 * n, e.observation_space(e.possible_agents[0]).shape[0])
    for _ in range(3):
        actions = np.zeros(2 * len(e.possible_agents), dtype=np.int64)
        obs, rewards, terms, truncs, _ = vec.step(actions)
    assert np.isfinite(rewards).all()
    vec.close()


def test_every_action_is_obeyed_or_masked(scenario):
    """Random actions drawn under the mask: the actuators refuse none of them, and a UGV
    under way is allowed only the action it carries out."""
    e = parallel_env(scenario, until=900.0, decision_s=10)
    rng = np.random.default_rng(0)
    obs, infos = e.reset(seed=21)
    saw_masked = False
    while e.agents:
        actions = {}
        for a in e.agents:
            mask = obs[a]["action_mask"]
            assert mask.any()
            if not mask.all():
                saw_masked = True
                assert mask.sum() == 1 and mask[obs[a]["goal"]] == 1
            actions[a] = int(rng.choice(np.flatnonzero(mask)))
        obs, _, _, _, infos = e.step(actions)
        for a, info in infos.items():
            assert info["refused"] == 0, (a, info)
    assert saw_masked, "the UGV drove somewhere under the mask"


def test_heard_rows_name_the_sender_and_expire(scenario):
    e = parallel_env(scenario, until=900.0, decision_s=20)
    obs, _ = e.reset(seed=42)
    ids = {i for i, _, _ in e.members}
    heard_any = seen_any = False
    while e.agents:
        obs, _, _, _, _ = e.step({a: 0 for a in e.agents})
        for a, o in obs.items():
            me = e.agent_ids[a]
            h = o["heard"][o["heard"][:, 0] == 1]
            heard_any |= len(h) > 0
            assert (h[:, 4] >= 0).all() and (h[:, 4] <= e.stale_s).all(), "no stale row"
            assert (h[:, 5] != me).all(), "no echo of its own reports"
            assert set(h[:, 5].astype(int)) <= ids and set(h[:, 6].astype(int)) <= ids
            assert (h[:, 3] == 2).all(), "units report what they take for red"
            assert list(h[:, 4]) == sorted(h[:, 4]), "most recent first"
            s = o["seen"][o["seen"][:, 0] == 1]
            seen_any |= len(s) > 0
            assert set(s[:, 4].astype(int)) <= ids - {me}
    assert heard_any and seen_any
