"""A PettingZoo environment of the evacuation mission.

The agents are the blue units driven from outside (``vitro_evac::external``): by default
the UGV and the helicopters of the scenario (``mdars``, ``vidar-1``, ``vidar-2``,
``skeldar`` in ``scenarios/evacuation.toml``); the truck, the troopers, the VIP and the
fixed-wing scout keep their own controllers. Everything else of the mission runs as in
``vitro run``.

**Observations** (a ``gymnasium.spaces.Dict`` per agent) hold only what the unit's own
sensors and the radio gave it — never ground truth:

- ``position``: ``Box(2,)`` its own position (GPS), world metres (x east, y north);
- ``active``: ``Discrete(2)``: 1 while it is active;
- ``goal``: ``Discrete(1 + T)``: 0 none, ``1 + i`` while it goes to target ``i``;
- ``arrived``: ``Discrete(2)``: 1 if it reached its goal during the last step;
- ``seen``: ``Box(K, 4)``: its vision's last look, nearest first, one row per sighting
  ``[1, dx, dy, side]`` (offset from itself in metres; side 0 neutral, 1 blue, 2 red as
  the sensor identified it, which may be wrong), zero rows after the last;
- ``heard``: ``Box(K, 5)``: the latest radio contact report per target, most recent first,
  ``[1, dx, dy, side, age_s]``;
- ``time``: ``Box(1,)``: simulated seconds since the start.

**Actions**: ``Discrete(1 + T)``: 0 holds (the UGV stops at the nearest junction, a
helicopter hovers where it is); ``1 + i`` goes to target ``i`` of the briefing (the start,
the end of every route leg out to the safehouse and back to the extraction point; the
helicopters fly over it at their altitude). ``T`` is ``len(env.targets)``. A command is
carried out at the unit's next sensor look (within a simulated second).

**Time**: a step leaves the commands and runs the mission event by event for at most
``decision_s`` simulated seconds; it stops earlier, after the second in which a driven unit
reached its goal or saw a hostile it had not seen before.

**Rewards** (the same team reward for every agent, from the referee's metrics over the
step): ``+1`` per adversary newly detected by the blue side, ``-0.01`` per second the team
was uncovered by a drone, ``-5`` per blue casualty, ``+10`` when the VIP is extracted
(``success``), ``-10`` if the VIP is down.

**Episodes** end (``terminations``) when the mission is decided, or for one agent when it
is down; they are cut (``truncations``) at the scenario's end time or ``until``.
``reset(seed=s)`` builds the run with master seed ``s``: the same seed and actions give the
same observations, rewards and trace hash. Without a seed, the first reset uses the
``seed`` given to the environment (else the scenario's), later ones draw a seed from a
generator seeded by the last explicit seed.

>>> from vitro.env import parallel_env
>>> env = parallel_env("scenarios/evacuation.toml", until=600)   # doctest: +SKIP
>>> obs, infos = env.reset(seed=42)                             # doctest: +SKIP
>>> obs, rewards, terms, truncs, infos = env.step({a: 0 for a in env.agents})  # doctest: +SKIP
"""

import json
import os

import numpy as np
from gymnasium import spaces
from pettingzoo import ParallelEnv
from pettingzoo.utils.conversions import parallel_to_aec

from . import _vitro
from .errors import InputError

__all__ = ["parallel_env", "env", "EvacuationEnv", "REWARDS"]

#: Reward weights: per adversary detected, per second uncovered, per casualty, on success,
#: if the VIP is down.
REWARDS = {
    "adversaries_detected": 1.0,
    "time_uncovered_s": -0.01,
    "casualties": -5.0,
    "success": 10.0,
    "vip_down": -10.0,
}


def _metric(metrics, name):
    v = metrics.get(name)
    if v is None:
        return 0.0
    return float(v)


class EvacuationEnv(ParallelEnv):
    """The evacuation mission as a PettingZoo ``ParallelEnv`` (see the module's doc)."""

    metadata = {"name": "vitro_evacuation_v0", "render_modes": [], "is_parallelizable": True}

    def __init__(
        self,
        scenario_path,
        seed=None,
        fidelity=None,
        units=None,
        decision_s=30.0,
        until=None,
        max_contacts=8,
        render_mode=None,
    ):
        if render_mode is not None:
            raise InputError(f"render_mode {render_mode!r}: the environment renders nothing")
        if not (isinstance(decision_s, (int, float)) and decision_s > 0):
            raise InputError(f"decision_s {decision_s!r}: expected a positive number")
        if not (isinstance(max_contacts, int) and max_contacts > 0):
            raise InputError(f"max_contacts {max_contacts!r}: expected a positive integer")
        self.scenario_path = os.fspath(scenario_path)
        self.fidelity = fidelity
        self.units = None if units is None else list(units)
        self.decision_s = float(decision_s)
        self.until = None if until is None else float(until)
        self.max_contacts = max_contacts
        self.render_mode = None
        self._first_seed = seed
        self._seeds = None
        self._sim = self._build(seed)
        self.possible_agents = list(self._sim.agents())
        self.agents = []
        #: The targets' world points (x, y, z), in action order (action 1 + i is target i).
        self.targets = list(self._sim.targets())
        #: The actions that go to the briefed places: ``{"start": a, "safehouse": b,
        #: "extraction": c}``.
        self.places = {
            name: 1 + i for name, i in zip(("start", "safehouse", "extraction"), self._sim.places())
        }
        k, big = max_contacts, np.float32(np.inf)
        n = len(self.targets)
        self._obs_space = spaces.Dict(
            {
                "position": spaces.Box(-big, big, shape=(2,), dtype=np.float32),
                "active": spaces.Discrete(2),
                "goal": spaces.Discrete(1 + n),
                "arrived": spaces.Discrete(2),
                "seen": spaces.Box(-big, big, shape=(k, 4), dtype=np.float32),
                "heard": spaces.Box(-big, big, shape=(k, 5), dtype=np.float32),
                "time": spaces.Box(np.float32(0), big, shape=(1,), dtype=np.float32),
            }
        )
        self._act_space = spaces.Discrete(1 + n)
        self.observation_spaces = {a: self._obs_space for a in self.possible_agents}
        self.action_spaces = {a: self._act_space for a in self.possible_agents}
        self._last = {}

    def _build(self, seed):
        sim = _vitro.EvacSim(self.scenario_path, seed, self.fidelity, self.units)
        if self.until is not None:
            sim.set_end(self.until)
        return sim

    def observation_space(self, agent):
        return self.observation_spaces[agent]

    def action_space(self, agent):
        return self.action_spaces[agent]

    @property
    def trace_hash(self):
        """The run's trace hash so far (as ``vitro run`` prints it)."""
        return self._sim.trace_hash()

    def metrics(self):
        """The referee's metrics so far (for evaluation; never part of an observation)."""
        return json.loads(self._sim.metrics())

    def _observe(self, agent):
        k = json.loads(self._sim.knowledge(agent))
        pos = k["pos"] or [0.0, 0.0]
        seen = np.zeros((self.max_contacts, 4), dtype=np.float32)
        for i, (_, x, y, side) in enumerate(k["seen"][: self.max_contacts]):
            seen[i] = (1.0, x - pos[0], y - pos[1], side)
        heard = np.zeros((self.max_contacts, 5), dtype=np.float32)
        latest = sorted(k["heard"], key=lambda h: (h[4], h[0]))[: self.max_contacts]
        for i, (_, x, y, side, age) in enumerate(latest):
            heard[i] = (1.0, x - pos[0], y - pos[1], side, age)
        goal = 0 if k["goal"] is None else 1 + int(k["goal"])
        obs = {
            "position": np.asarray(pos, dtype=np.float32),
            "active": int(bool(k["active"])),
            "goal": goal,
            "arrived": int(bool(k["arrived"])),
            "seen": seen,
            "heard": heard,
            "time": np.asarray([self._sim.now()], dtype=np.float32),
        }
        return obs, k

    def reset(self, seed=None, options=None):
        if seed is not None:
            self._seeds = np.random.default_rng(seed)
            episode_seed = int(seed)
        elif self._seeds is not None:
            episode_seed = int(self._seeds.integers(0, 2**63))
        else:
            episode_seed = self._first_seed
        self._sim = self._build(episode_seed)
        self.agents = list(self.possible_agents)
        self._last = self.metrics()
        observations, infos = {}, {}
        for a in self.agents:
            observations[a], k = self._observe(a)
            infos[a] = {"sim_time_s": self._sim.now(), "refused": k["refused"]}
        return observations, infos

    def _reward(self, metrics):
        r = 0.0
        for name in ("adversaries_detected", "time_uncovered_s", "casualties"):
            r += REWARDS[name] * (_metric(metrics, name) - _metric(self._last, name))
        for name in ("success", "vip_down"):
            if metrics.get(name) and not self._last.get(name):
                r += REWARDS[name]
        return r

    def step(self, actions):
        if not self.agents:
            raise InputError("step() after the episode ended: call reset()")
        for agent, action in actions.items():
            if agent in self.agents:
                self._sim.command(agent, int(action))
        going = self._sim.advance(self.decision_s, True)
        metrics = self.metrics()
        reward = self._reward(metrics)
        self._last = metrics
        out_of_time = self._sim.now() >= self._sim.end()
        decided = not going and not out_of_time
        observations, rewards, terminations, truncations, infos = {}, {}, {}, {}, {}
        for a in self.agents:
            observations[a], k = self._observe(a)
            rewards[a] = reward
            terminations[a] = decided or not k["active"]
            truncations[a] = not decided and (out_of_time or not going)
            infos[a] = {"sim_time_s": self._sim.now(), "refused": k["refused"]}
        self.agents = [a for a in self.agents if not (terminations[a] or truncations[a])]
        return observations, rewards, terminations, truncations, infos

    def render(self):
        return None

    def close(self):
        pass


def parallel_env(scenario_path, seed=None, fidelity=None, **kwargs):
    """The evacuation of ``scenario_path`` as a PettingZoo ``ParallelEnv``.

    Keyword arguments: ``units`` (names of the driven units; default every controllable
    one), ``decision_s`` (most simulated seconds per step, default 30), ``until`` (end the
    episode at this simulated time), ``max_contacts`` (rows of ``seen`` and ``heard``).
    """
    return EvacuationEnv(scenario_path, seed=seed, fidelity=fidelity, **kwargs)


def env(scenario_path, seed=None, fidelity=None, **kwargs):
    """The same environment as a PettingZoo ``AECEnv`` (``parallel_to_aec``)."""
    return parallel_to_aec(parallel_env(scenario_path, seed=seed, fidelity=fidelity, **kwargs))
