"""Evaluates a random and a scripted policy on the evacuation environment and prints their
mean returns (the team reward summed over an episode, averaged over episodes).

    pip install ./python
    python python/examples/evaluate_policies.py [--episodes 3] [--until 900]

The scripted policy uses only the briefing and what each unit senses: helicopters wait over
the places where the team will be (the safehouse; the start, then the extraction point),
the UGV and the Skeldar sweep the route.
"""
import argparse
from pathlib import Path

import numpy as np

from vitro.env import parallel_env

ROOT = Path(__file__).resolve().parents[2]


def scripted_policy(env):
    """Briefed places and the route, no peeking: one helicopter waits over the safehouse
    (where the team spends longest, fetching the VIP on foot), another over the start and,
    after the first ten minutes, over the extraction point; the rest (the UGV, the Skeldar)
    sweep the route ahead, one target further each time they arrive."""
    n = len(env.targets)
    p = env.places
    sweepers = [a for a in env.possible_agents if a not in ("vidar-1", "vidar-2")]

    def act(agent, obs):
        if not obs["active"]:
            return 0
        if agent == "vidar-1":
            return p["safehouse"]
        if agent == "vidar-2":
            return p["start"] if obs["time"][0] < 600 else p["extraction"]
        goal = int(obs["goal"])
        if goal == 0:
            return 1 + sweepers.index(agent) % n
        if obs["arrived"]:
            return 1 + goal % n  # the next target along the route, then round again
        return goal

    return act


def evaluate(env, policy, episodes, seed0):
    returns = []
    for k in range(episodes):
        obs, _ = env.reset(seed=seed0 + k)
        total = 0.0
        while env.agents:
            actions = {a: policy(a, obs[a]) for a in env.agents}
            obs, rewards, _, _, _ = env.step(actions)
            total += next(iter(rewards.values()), 0.0)
        m = env.metrics()
        print(f"  episode {k}: return {total:8.2f}  (detected {m['adversaries_detected']}, "
              f"uncovered {m['time_uncovered_s']:.0f} s, casualties {m['casualties']}, "
              f"success {m['success']}, trace {env.trace_hash})")
        returns.append(total)
    return float(np.mean(returns))


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--scenario", default=str(ROOT / "scenarios/evacuation.toml"))
    p.add_argument("--episodes", type=int, default=3)
    p.add_argument("--until", type=float, default=900.0)
    p.add_argument("--seed", type=int, default=100)
    args = p.parse_args()
    env = parallel_env(args.scenario, until=args.until)
    print(f"agents {env.possible_agents}, {len(env.targets)} targets, "
          f"action space {env.action_space(env.possible_agents[0])}")
    rng = np.random.default_rng(args.seed)
    print("random policy:")
    # Uniform over the actions the mask allows (each is obeyed).
    r = evaluate(env, lambda a, o: int(rng.choice(np.flatnonzero(o["action_mask"]))),
                 args.episodes, args.seed)
    print("scripted policy:")
    s = evaluate(env, scripted_policy(env), args.episodes, args.seed)
    print(f"mean return over {args.episodes} episodes: random {r:.2f}, scripted {s:.2f}")


if __name__ == "__main__":
    main()
