"""The evacuation environment's task: episodes that end when the mission is decided (or go on
through the hunt), the scenario's reward table ``[env.reward]`` with its team and per-agent
terms, and its errors at their place in the file."""
import numpy as np
import pytest

import vitro
from vitro.env import REWARD_KEYS, parallel_env


@pytest.fixture
def task(root):
    return str(root / "scenarios/evacuation_env.toml")


def with_env_table(root, tmp_path, table):
    """evacuation.toml with ``table`` appended and its data paths made absolute."""
    text = (root / "scenarios/evacuation.toml").read_text()
    text = text.replace('"../data/', f'"{root}/data/') + "\n" + table
    path = tmp_path / "scenario.toml"
    path.write_text(text)
    return str(path)


def test_the_reward_table_is_read_from_the_scenario(task, root):
    e = parallel_env(task)
    assert set(e.reward_weights) == set(REWARD_KEYS)
    assert e.reward_weights["cover_s"] == 0.01 and e.reward_weights["detection"] == 0.0
    assert e.hunt is False
    # A scenario without the table: the table's defaults.
    d = parallel_env(str(root / "scenarios/evacuation.toml"))
    assert d.reward_weights == {"success": 10.0, "vip_down": -10.0, "casualty": -5.0,
                                "detection": 1.0, "uncovered_s": -0.01, "cover_s": 0.0,
                                "down": 0.0}
    # The constructor's weights replace the scenario's.
    o = parallel_env(task, reward={"detection": 2.5}, hunt=True)
    assert o.reward_weights["detection"] == 2.5 and o.reward_weights["cover_s"] == 0.01
    assert o.hunt is True


def test_a_bad_reward_table_is_reported_at_its_line_and_column(root, tmp_path):
    path = with_env_table(root, tmp_path, "[env.reward]\nsucess = 1.0\n")
    with pytest.raises(vitro.InputError) as bad:
        parallel_env(path)
    lines = len((root / "scenarios/evacuation.toml").read_text().splitlines())
    assert f"scenario.toml:{lines + 3}:1" in str(bad.value)
    assert "unknown field `sucess`" in str(bad.value)
    path = with_env_table(root, tmp_path, "[env.reward]\ncover_s = nan\n")
    with pytest.raises(vitro.InputError, match="a finite reward weight"):
        parallel_env(path)
    with pytest.raises(vitro.InputError, match="reward 'cover'"):
        parallel_env(str(root / "scenarios/evacuation.toml"), reward={"cover": 1.0})


def play(e, seed, policy):
    obs, _ = e.reset(seed=seed)
    totals = {a: 0.0 for a in e.possible_agents}
    last = None
    while e.agents:
        obs, rewards, terms, truncs, _ = e.step({a: policy(a, obs[a]) for a in e.agents})
        for a, r in rewards.items():
            totals[a] += r
        last = (terms, truncs)
    return totals, last


def test_the_episode_ends_when_the_mission_is_decided_unless_the_hunt_goes_on(root):
    scenario = str(root / "scenarios/evacuation.toml")  # no [env] table: hunt = false
    e = parallel_env(scenario, decision_s=30, until=900.0)
    _, (terms, truncs) = play(e, 0, lambda a, o: 0)
    assert e.metrics()["success"], "the VIP is out"
    assert all(terms.values()) and not any(truncs.values())
    decided_at = e._sim.now()
    assert decided_at == e.metrics()["time_to_extraction_s"], "the step stops then"
    h = parallel_env(scenario, decision_s=30, until=900.0, hunt=True)
    _, (terms, truncs) = play(h, 0, lambda a, o: 0)
    assert h._sim.now() == 900.0, "the hunt goes on after the mission is decided"
    assert all(truncs.values()) and not any(terms.values())


def test_cover_is_credited_to_the_covering_unit(root):
    """Only the aircraft near the team earn the per-agent cover term, each its own: a Vidar
    flies ahead along the route the team takes, the Skeldar stays over the start the team
    leaves; the UGV never covers (it is no aircraft)."""
    scenario = str(root / "scenarios/evacuation.toml")
    team_free = {k: 0.0 for k in REWARD_KEYS}
    e = parallel_env(scenario, until=120.0, decision_s=10, reward={**team_free, "cover_s": 1.0})
    policy = {"mdars": 0, "vidar-1": 2, "vidar-2": len(e.targets), "skeldar": 0}
    totals, _ = play(e, 3, lambda a, o: policy[a])
    assert totals["mdars"] == 0.0
    assert totals["vidar-1"] >= 60.0, totals
    assert totals["vidar-1"] > totals["skeldar"] + 20, totals
    # The rewards are the seconds of cover the referee credited to each unit.
    assert [totals[a] for a in e.possible_agents] == e._sim.cover_s()


def test_the_mission_ignores_the_env_table(root, tmp_path):
    plain = with_env_table(root, tmp_path, "")
    text = open(plain).read()
    other = tmp_path / "with_env.toml"
    other.write_text(text + "\n[env]\nhunt = true\n\n[env.reward]\ncover_s = 0.5\n")
    a = vitro.run(plain, until=120)
    b = vitro.run(str(other), until=120)
    assert a["trace_hash"] == b["trace_hash"]
