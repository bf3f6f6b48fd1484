"""Evaluates a random, an always-hold and a scripted policy on the evacuation environment
over paired seeds and prints their mean returns and success rates with 95 % intervals.

    pip install ./python
    python python/examples/evaluate_policies.py [--episodes 100] [--fidelity interpolated]

An episode's return is the sum over the driven units of their rewards (the scenario's
``[env.reward]``), summed over the episode. Every policy plays the same seeds, so the
differences to random are paired. The scripted policy uses only the briefing and what each
unit senses (``scripted_policy``).
"""
import argparse
from pathlib import Path

import numpy as np

from vitro.env import parallel_env

ROOT = Path(__file__).resolve().parents[2]


def scripted_policy(env):
    """Briefed places, the route and each unit's own sensors, no peeking: the helicopters
    escort the truck (the Vidars hover over the route junction nearest to where each last saw
    it and over the next one ahead; the Skeldar over the nearest), the UGV sweeps the route
    ahead, one target further each time it arrives. Before a unit has seen the truck it takes
    it to be at the start."""
    n = len(env.targets)
    ids = {name: i for i, name, _ in env.members}
    truck = ids.get("truck")
    points = np.asarray(env.targets, dtype=np.float64)[:, :2]
    memory = {}

    def nearest(xy):
        return int(np.argmin(np.hypot(points[:, 0] - xy[0], points[:, 1] - xy[1])))

    def act(agent, obs):
        if not obs["active"]:
            return 0
        if obs["time"][0] == 0:
            memory[agent] = points[env.places["start"] - 1]
        seen = obs["seen"]
        for row in seen[seen[:, 0] == 1]:
            if int(row[4]) == truck:
                memory[agent] = obs["position"] + row[1:3]
        near = nearest(memory.get(agent, points[env.places["start"] - 1]))
        if agent == "mdars":
            goal = int(obs["goal"])
            if goal == 0:
                return 1 + near
            if obs["arrived"]:
                return 1 + goal % n  # the next target along the route, then round again
            return goal
        ahead = agent.endswith("-2")
        return 1 + min(near + int(ahead), n - 1)

    return act


def random_policy(seed):
    """Uniform over the actions the mask allows (each is obeyed)."""
    rng = np.random.default_rng(seed)
    return lambda agent, obs: int(rng.choice(np.flatnonzero(obs["action_mask"])))


def hold_policy(agent, obs):
    """Every unit holds where it is."""
    return 0


def episode_return(env, policy, seed):
    """One episode from ``reset(seed=seed)``: the return summed over the agents (team terms
    once per agent) and the referee's metrics at the end."""
    obs, _ = env.reset(seed=seed)
    total = 0.0
    while env.agents:
        actions = {a: policy(a, obs[a]) for a in env.agents}
        obs, rewards, _, _, _ = env.step(actions)
        total += sum(rewards.values())
    return total, env.metrics()


def interval(x):
    """Mean and the half-width of its 95 % interval (normal approximation)."""
    x = np.asarray(x, dtype=np.float64)
    half = 1.96 * x.std(ddof=1) / np.sqrt(len(x)) if len(x) > 1 else float("nan")
    return float(x.mean()), float(half)


def evaluate(env, policies, seeds, verbose=False):
    """Every policy on the same seeds (paired): ``{name: (returns, successes)}``."""
    out = {}
    for name, policy in policies.items():
        returns, successes = [], []
        for seed in seeds:
            r, m = episode_return(env, policy, seed)
            returns.append(r)
            successes.append(float(m["success"]))
            if verbose:
                print(f"  {name} seed {seed}: return {r:8.2f}  (success {m['success']}, "
                      f"casualties {m['casualties']}, uncovered {m['time_uncovered_s']:.0f} s, "
                      f"trace {env.trace_hash})")
        out[name] = (np.asarray(returns), np.asarray(successes))
    return out


def print_table(results, baseline="random"):
    """Mean return and success with 95 % intervals, and each policy minus the baseline on
    the same seeds."""
    n = len(next(iter(results.values()))[0])
    print(f"{'policy':10s} {'return':>16s} {'success':>14s} {'minus ' + baseline:>18s}   (n = {n})")
    for name, (r, s) in results.items():
        m, h = interval(r)
        sm, sh = interval(s)
        if name != baseline and baseline in results:
            dm, dh = interval(r - results[baseline][0])
            diff = f"{dm:+8.2f} ± {dh:6.2f}"
        else:
            diff = ""
        print(f"{name:10s} {m:8.2f} ± {h:6.2f} {sm:6.2f} ± {sh:5.2f} {diff:>18s}")


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--scenario", default=str(ROOT / "scenarios/evacuation_env.toml"))
    p.add_argument("--fidelity", default=None, help="discrete | interpolated | physical")
    p.add_argument("--episodes", type=int, default=10, help="paired seeds")
    p.add_argument("--until", type=float, default=None)
    p.add_argument("--seed", type=int, default=1000, help="the first seed")
    p.add_argument("--verbose", action="store_true")
    args = p.parse_args()
    env = parallel_env(args.scenario, fidelity=args.fidelity, until=args.until)
    print(f"agents {env.possible_agents}, {len(env.targets)} targets, "
          f"action space {env.action_space(env.possible_agents[0])}, "
          f"reward {env.reward_weights}")
    seeds = list(range(args.seed, args.seed + args.episodes))
    policies = {
        "random": random_policy(args.seed),
        "hold": hold_policy,
        "scripted": scripted_policy(env),
    }
    print_table(evaluate(env, policies, seeds, args.verbose))


if __name__ == "__main__":
    main()
