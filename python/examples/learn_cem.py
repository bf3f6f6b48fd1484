"""Learns a policy for the evacuation environment by the cross-entropy method over a linear
scoring policy, and compares it with uniform random play on paired seeds.

    pip install ./python
    python python/examples/learn_cem.py [--fidelity discrete] [--episodes 100] [--workers 2]

The policy scores each action a unit may take (hold, or go to target ``j``) with a linear
function of features of the unit's own observation and briefing, and takes the best allowed
one. Features of target ``j``: how far it is from the unit, how far from where the unit last
saw the truck (or the start, before it has), whether it is the target just ahead of that,
whether it is the unit's current goal, and how far along the route it lies; hold has a bias
of its own. The UGV and the aircraft have a weight vector each (``FEATURES`` weights).

The cross-entropy method (Rubinstein and Kroese, *The Cross-Entropy Method*, 2004): sample a
population of weight vectors from a Gaussian, play each on the same training seeds, refit the
Gaussian to the best (the elite), repeat. Training seeds and evaluation seeds do not overlap.
"""
import argparse
import multiprocessing as mp
from pathlib import Path

import numpy as np

from vitro.env import parallel_env

ROOT = Path(__file__).resolve().parents[2]
FEATURES = 6  # per action: 5 for a target, the hold bias in the last slot
GROUPS = 2  # the UGV, the aircraft


def policy_from(weights, env):
    """The greedy linear policy of ``weights`` (``GROUPS * FEATURES`` numbers) on ``env``."""
    w = np.asarray(weights, dtype=np.float64).reshape(GROUPS, FEATURES)
    points = np.asarray(env.targets, dtype=np.float64)[:, :2]
    n = len(points)
    truck = {name: i for i, name, _ in env.members}.get("truck")
    start = points[env.places["start"] - 1]
    along = np.arange(n) / max(n - 1, 1)
    memory = {}

    def act(agent, obs):
        mask = np.asarray(obs["action_mask"], dtype=bool)
        if mask.sum() <= 1 or not obs["active"]:
            return int(np.flatnonzero(mask)[0]) if mask.any() else 0
        if obs["time"][0] == 0 or agent not in memory:
            memory[agent] = start
        seen = obs["seen"]
        for row in seen[seen[:, 0] == 1]:
            if int(row[4]) == truck:
                memory[agent] = obs["position"] + row[1:3]
        here = np.asarray(obs["position"], dtype=np.float64)
        to_me = np.hypot(*(points - here).T) / 1000.0
        to_truck = np.hypot(*(points - memory[agent]).T) / 1000.0
        ahead = np.zeros(n)
        ahead[min(int(np.argmin(to_truck)) + 1, n - 1)] = 1.0
        goal = np.zeros(n)
        if int(obs["goal"]) > 0:
            goal[int(obs["goal"]) - 1] = 1.0
        g = w[0] if agent == "mdars" else w[1]
        scores = np.empty(n + 1)
        scores[0] = g[5]
        scores[1:] = -g[0] * to_me - g[1] * to_truck + g[2] * ahead + g[3] * goal + g[4] * along
        scores[~mask] = -np.inf
        return int(np.argmax(scores))

    return act


def random_policy(seed):
    """Uniform over the actions the mask allows."""
    rng = np.random.default_rng(seed)
    return lambda agent, obs: int(rng.choice(np.flatnonzero(obs["action_mask"])))


def episode_return(env, policy, seed):
    """The return of one episode from ``reset(seed=seed)``, summed over the agents."""
    obs, _ = env.reset(seed=seed)
    total = 0.0
    while env.agents:
        obs, rewards, _, _, _ = env.step({a: policy(a, obs[a]) for a in env.agents})
        total += sum(rewards.values())
    return total


_ENV = None


def _init(scenario, fidelity):
    global _ENV
    _ENV = parallel_env(scenario, fidelity=fidelity)


def _play(job):
    """``(kind, weights or seed, episode seed)`` -> the episode's return."""
    kind, arg, seed = job
    policy = policy_from(arg, _ENV) if kind == "linear" else random_policy(arg)
    return episode_return(_ENV, policy, seed)


def cem(pool, iterations, population, elite, train_seeds, rng):
    """The cross-entropy method: returns the mean of the last fitted Gaussian."""
    dim = GROUPS * FEATURES
    mean, std = np.zeros(dim), np.ones(dim)
    for it in range(iterations):
        cands = mean + std * rng.standard_normal((population, dim))
        jobs = [("linear", c, s) for c in cands for s in train_seeds]
        returns = np.asarray(pool.map(_play, jobs)).reshape(population, len(train_seeds))
        score = returns.mean(axis=1)
        best = cands[np.argsort(score)[-elite:]]
        mean, std = best.mean(axis=0), best.std(axis=0) + 0.05
        print(f"iteration {it + 1}: population mean {score.mean():7.2f}, best {score.max():7.2f}, "
              f"elite mean {np.sort(score)[-elite:].mean():7.2f}", flush=True)
    return mean


def interval(x):
    """Mean and the half-width of its 95 % interval (normal approximation)."""
    x = np.asarray(x, dtype=np.float64)
    return float(x.mean()), float(1.96 * x.std(ddof=1) / np.sqrt(len(x)))


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--scenario", default=str(ROOT / "scenarios/evacuation_env.toml"))
    p.add_argument("--fidelity", default=None, help="discrete | interpolated | physical")
    p.add_argument("--episodes", type=int, default=100, help="paired evaluation seeds")
    p.add_argument("--iterations", type=int, default=6)
    p.add_argument("--population", type=int, default=12)
    p.add_argument("--elite", type=int, default=3)
    p.add_argument("--train-seeds", type=int, default=3)
    p.add_argument("--workers", type=int, default=2)
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--weights", nargs=GROUPS * FEATURES, type=float, default=None,
                   help="play these weights (as printed after training) instead of training")
    p.add_argument("--transfer", nargs="*", default=[], metavar="LEVEL:EPISODES",
                   help="evaluate the learned weights at other levels too, e.g. interpolated:20")
    args = p.parse_args()
    rng = np.random.default_rng(args.seed)
    train = [10_000 + i for i in range(args.train_seeds)]
    evaluation = [1000 + i for i in range(args.episodes)]
    spawn = mp.get_context("spawn")
    if args.weights:
        weights = np.asarray(args.weights, dtype=np.float64)
    else:
        with spawn.Pool(args.workers, _init, (args.scenario, args.fidelity)) as pool:
            weights = cem(pool, args.iterations, args.population, args.elite, train, rng)
    print("weights:", np.round(weights, 2).tolist())
    levels = [(args.fidelity, args.episodes)] + [
        (level, int(n)) for level, n in (x.split(":") for x in args.transfer)
    ]
    for level, n in levels:
        seeds = evaluation[:n]
        with spawn.Pool(args.workers, _init, (args.scenario, level)) as pool:
            learned = np.asarray(pool.map(_play, [("linear", weights, s) for s in seeds]))
            rand = np.asarray(pool.map(_play, [("random", s, s) for s in seeds]))
        diff = learned - rand
        se = diff.std(ddof=1) / np.sqrt(len(diff))
        print(f"at the {level or 'scenario'} level{'s' if level is None else ''}, {n} paired seeds:")
        for name, x in [("learned", learned), ("random", rand), ("learned - random", diff)]:
            m, h = interval(x)
            print(f"  {name:17s} {m:8.2f} ± {h:6.2f}   (95 % interval)")
        print(f"  learned minus random: {diff.mean() / se:.1f} standard errors")


if __name__ == "__main__":
    main()
