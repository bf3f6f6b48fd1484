"""Learning in the evacuation environment: the cross-entropy method over a linear scoring
policy (``python/examples/learn_cem.py``) against uniform random play.

The policy's plumbing runs always. The learning itself takes a few minutes on 2 cores (about
400 episodes: training, then 100 paired evaluation seeds), so it runs when ``VITRO_LEARN=1``.
"""
import multiprocessing as mp
import os
import sys

import numpy as np
import pytest

from vitro.env import parallel_env

sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "examples"))
import learn_cem  # noqa: E402


@pytest.fixture
def task(root):
    return str(root / "scenarios/evacuation_env.toml")


def test_the_linear_policy_takes_only_allowed_actions(task):
    env = parallel_env(task)
    rng = np.random.default_rng(3)
    policy = learn_cem.policy_from(rng.standard_normal(learn_cem.GROUPS * learn_cem.FEATURES), env)
    obs, _ = env.reset(seed=5)
    steps = 0
    while env.agents and steps < 40:
        actions = {a: policy(a, obs[a]) for a in env.agents}
        for a, x in actions.items():
            assert obs[a]["action_mask"][x] == 1, (a, x, obs[a]["action_mask"])
        obs, _, _, _, _ = env.step(actions)
        steps += 1
    assert steps > 0


@pytest.mark.skipif(os.environ.get("VITRO_LEARN") != "1", reason="a few minutes: VITRO_LEARN=1")
def test_the_learned_policy_beats_random_by_three_standard_errors(task):
    rng = np.random.default_rng(0)
    train = [10_000 + i for i in range(3)]
    seeds = [1000 + i for i in range(100)]
    with mp.get_context("spawn").Pool(2, learn_cem._init, (task, "discrete")) as pool:
        weights = learn_cem.cem(pool, 6, 12, 3, train, rng)
        learned = np.asarray(pool.map(learn_cem._play, [("linear", weights, s) for s in seeds]))
        rand = np.asarray(pool.map(learn_cem._play, [("random", s, s) for s in seeds]))
    diff = learned - rand
    se = diff.std(ddof=1) / np.sqrt(len(diff))
    assert diff.mean() >= 3 * se, (diff.mean(), se)
