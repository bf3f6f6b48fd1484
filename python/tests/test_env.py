"""The PettingZoo environment of the evacuation: PettingZoo's own API tests, the AEC
wrapper, reproducible resets, and observations from the unit's own sensors only."""
import numpy as np
import pytest
from pettingzoo.test import api_test, parallel_api_test

import vitro
from vitro.env import env, parallel_env

UNTIL = 400.0


@pytest.fixture
def scenario(root):
    return str(root / "scenarios/evacuation.toml")


def test_parallel_api_test_passes(scenario):
    parallel_api_test(parallel_env(scenario, until=UNTIL, decision_s=20), num_cycles=40)


def test_the_aec_wrapper_passes_the_aec_api_test(scenario):
    api_test(env(scenario, until=150.0, decision_s=30), num_cycles=10)


def rollout(e, seed, policy):
    obs, _ = e.reset(seed=seed)
    trail = []
    while e.agents:
        actions = {a: policy(a, obs[a]) for a in e.agents}
        obs, rewards, terms, truncs, _ = e.step(actions)
        trail.append((sorted(rewards.items()), {a: o["position"].tolist() for a, o in obs.items()}))
    return trail, e.trace_hash


def test_reset_with_a_seed_is_reproducible(scenario):
    e = parallel_env(scenario, until=300.0)
    n = e.action_space(e.possible_agents[0]).n
    go = lambda a, o: (e.possible_agents.index(a) * 3) % n  # noqa: E731
    first = rollout(e, 11, go)
    assert rollout(e, 11, go) == first
    assert rollout(parallel_env(scenario, until=300.0), 11, go) == first
    assert rollout(e, 12, go)[1] != first[1], "another seed, another run"


def test_actions_move_the_units_and_reach_the_targets(scenario):
    e = parallel_env(scenario, until=600.0, units=["mdars", "vidar-1"])
    assert e.possible_agents == ["mdars", "vidar-1"]
    obs, _ = e.reset(seed=3)
    start = {a: obs[a]["position"].copy() for a in e.agents}
    target = 2  # the end of the first leg out
    arrived = set()
    for _ in range(20):
        if not e.agents:
            break
        obs, _, _, _, _ = e.step({a: target for a in e.agents})
        arrived |= {a for a in obs if obs[a]["arrived"]}
        for a in obs:
            assert obs[a]["goal"] == target
    assert arrived == {"mdars", "vidar-1"}
    goal = np.asarray(e.targets[target - 1][:2])
    for a in ("mdars", "vidar-1"):
        assert np.linalg.norm(obs[a]["position"] - start[a]) > 50
        assert np.linalg.norm(obs[a]["position"] - goal) < 60, (a, obs[a]["position"], goal)


def test_observations_hold_only_sensed_contacts(scenario):
    e = parallel_env(scenario, until=900.0, units=["mdars"])
    obs, _ = e.reset(seed=42)
    saw = heard = 0
    while e.agents:
        obs, _, _, _, _ = e.step({"mdars": 0})
        for o in obs.values():
            saw += int(o["seen"][:, 0].sum())
            heard += int(o["heard"][:, 0].sum())
            # Contacts are within the sensors' reach of the unit or came by radio.
            near = o["seen"][o["seen"][:, 0] == 1]
            assert (np.hypot(near[:, 1], near[:, 2]) <= 1000).all()
    assert heard > 0, "the team's contact reports reach the unit by radio"


def test_bad_arguments_raise_input_errors(scenario, root):
    with pytest.raises(vitro.InputError, match="cannot be driven from outside"):
        parallel_env(scenario, units=["truck"])
    with pytest.raises(vitro.InputError, match="the environment runs evacuation scenarios"):
        parallel_env(str(root / "scenarios/demo.toml"))
    e = parallel_env(scenario, until=100.0)
    e.reset(seed=1)
    with pytest.raises(vitro.InputError, match="action 999"):
        e.step({a: 999 for a in e.agents})
