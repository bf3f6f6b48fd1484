"""A PettingZoo environment of the evacuation mission.

The agents are the blue units driven from outside (``vitro_evac::external``): by default
the UGV and the helicopters of the scenario (``mdars``, ``vidar-1``, ``vidar-2``,
``skeldar`` in ``scenarios/evacuation.toml``); the truck, the troopers, the VIP and the
fixed-wing scout keep their own controllers. Everything else of the mission runs as in
``vitro run``.

**Observations** (a ``gymnasium.spaces.Dict`` per agent) hold only what the unit's own
sensors and the radio gave it, never ground truth (that is :meth:`EvacuationEnv.state`).
Positions are world metres (x east, y north); ``K`` is ``max_contacts``; ids are the
mission's entity ids (``env.members`` names them; an agent's own id is
``env.agent_ids[agent]``), as numbers:

- ``position``: ``Box(2,)`` its own position from its GPS (``Myself`` sensor);
- ``active``: ``Discrete(2)``: 1 while its own condition sensor says it is active;
- ``goal``: ``Discrete(1 + T)``: 0 none (holding), ``1 + i`` while it goes to target ``i``
  (the last command its actuator took);
- ``arrived``: ``Discrete(2)``: 1 if its actuator reported it at its goal during the last
  step;
- ``seen``: ``Box(K, 5)``: its vision's last look (at most a sensor period old), nearest
  first, one row per sighting ``[1, dx, dy, side, id]``: offset from itself in metres, the
  side its friend-or-foe vision took the body for (0 neutral, 1 blue, 2 red; it may be
  wrong) and who it is; zero rows after the last;
- ``heard``: ``Box(K, 7)``: contact reports heard on the radio from other units (its own
  reports are not echoed), the latest per target, most recent first, ``[1, dx, dy, side,
  age_s, sender, target]``: where the sender saw the target (offset from this unit), the
  side the sender took it for (units report only what they take for red, so 2; friends
  misidentified as red are reported too), seconds since the report arrived, the sender's id
  and the target's id. A report older than the scenario's ``sensors.stale_s`` is dropped;
- ``time``: ``Box(1,)``: simulated seconds since the start (the unit's clock);
- ``action_mask``: ``Box(0, 1, (1 + T,), int8)``: 1 for each action the unit's actuator
  will take now (below).

Every ``Box`` is float32 (the mask int8). The mask is also ``infos[agent]["action_mask"]``.
With ``flat=True`` each observation is instead one ``Box(D,)`` of float32, the fields above
but the mask concatenated in the order listed (``active``, ``arrived`` as 0/1, ``goal``
one-hot; ``env.flat_fields`` gives each field's slice); the mask is then in ``infos`` only
(PettingZoo's other convention). SuperSuit's wrappers need this form.

**Actions**: ``Discrete(1 + T)``: 0 holds (the UGV drives to the junction nearest to it
and stops, a helicopter hovers where it is); ``1 + i`` goes to target ``i`` of the briefing
(the start, the end of every route leg out to the safehouse and back to the extraction
point; the helicopters fly over it at their altitude). ``T`` is ``len(env.targets)``. A
command is carried out at the unit's next sensor look (within a simulated second). Every
action the mask allows is obeyed: a helicopter takes any action at any time; a UGV under
way takes a new goal only once it is there (its actuator refuses a goal on the move), so
while it drives the mask allows only the action it is carrying out (repeating it changes
nothing); a unit that is down has only 0. A masked action is not carried out and counts in
``infos[agent]["refused"]``.

**Time**: a step leaves the commands and runs the mission event by event for at most
``decision_s`` simulated seconds; it stops earlier, after the second in which a driven unit
reached its goal or saw a hostile it had not seen before, or (unless ``hunt``) the mission
was decided.

**The task**: ``scenarios/evacuation_env.toml`` is the evacuation made hard enough that the
driven units decide the outcome (20 quick red troopers whose every shot hits, no fixed-wing
scout: the team is covered only where the driven helicopters are). Its difficulty knobs are
the scenario's keys (``count`` of the red troopers, ``mission.hit_probability``,
``mission.attack_aim_s``, ``channel.loss``, the aircraft); ``scenarios/evacuation.toml``
runs too, but there the escort's own units decide almost every outcome.

**Rewards** come from the referee's measures over the step, weighted by the scenario's
``[env.reward]`` table (read and checked with the scenario: an unknown key or a weight that
is not finite is reported at its file, line and column); the constructor's ``reward``
replaces weights by key; ``env.reward_weights`` holds the weights in force. Team terms go
to every agent alike, per-agent terms to the agent that earned them:

================ ======== ============================================================ =======
key              kind     per                                                          default
================ ======== ============================================================ =======
``success``      team     once, when the VIP reaches the extraction point              10
``vip_down``     team     once, when the VIP is down                                   -10
``casualty``     team     blue person (trooper or VIP) down                            -5
``detection``    team     adversary the blue side reports for the first time           1
``uncovered_s``  team     second some team member has no friendly aircraft within      -0.01
                          ``mission.cover_radius_m`` (until the VIP is out)
``cover_s``      agent    second the agent (an aircraft) is within                     0
                          ``mission.cover_radius_m`` of an active team member (the
                          truck, a trooper, the VIP) until the VIP is out (ground truth,
                          sampled every simulated second)
``down``         agent    once, when the agent goes down                               0
================ ======== ============================================================ =======

(The defaults are those of a scenario without the table; ``evacuation_env.toml`` sets
``detection = 0`` and ``cover_s = 0.01``.)

**Episodes** end (``terminations``) when the mission is decided (the VIP extracted or down:
the step stops in that second), or for one agent when it is down (it then leaves
``env.agents``, as PettingZoo's parallel API has it; SuperSuit's vector environments need a
fixed agent set: wrap with ``supersuit.black_death_v3``). With ``hunt`` (the constructor's,
else the scenario's ``env.hunt``, default false) the episode goes on through the HVT hunt
and ends when the mission is over. Episodes are cut (``truncations``) at the scenario's end
time, at ``until``, or after ``max_cycles`` steps.

**Seeds** (Gymnasium's semantics): ``reset(seed=s)`` builds the run with master seed ``s``
and seeds the environment's own generator with ``s``; ``reset()`` without a seed starts
the next episode with a master seed drawn from that generator, so every episode differs
and the sequence is reproducible from the first seed. The first reset without any seed
uses the ``seed`` given to the environment (else the scenario's), and seeds the generator
with it. The same seed and actions give the same observations, rewards and trace hash.

**State** (for centralised critics): :meth:`EvacuationEnv.state` is the referee's ground
truth, ``state_space`` its ``Box``: the simulated time, then for every entity of the
mission in id order (``env.members``) ``[x, y, z, status]`` (status 0 hidden, 1 active, 2
aboard, 3 down, 4 captured, 5 extracted; a rider at its vehicle's place).

**Pickling**: an environment pickles as its constructor's arguments and its seed
generator; unpickled, it is rebuilt from them (a fresh run, not the episode under way:
call ``reset``), so SuperSuit's ``concat_vec_envs_v1`` and subprocess vector envs work.

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

__all__ = ["parallel_env", "env", "EvacuationEnv", "REWARD_KEYS"]

#: The keys of the reward table (``[env.reward]``): team terms, then per-agent terms.
REWARD_KEYS = ("success", "vip_down", "casualty", "detection", "uncovered_s", "cover_s", "down")


def _metric(metrics, name):
    v = metrics.get(name)
    if v is None:
        return 0.0
    return float(v)


def _rebuild(kwargs, seeds):
    """Unpickles an environment: rebuilt from its constructor's arguments."""
    e = EvacuationEnv(**kwargs)
    if seeds is not None:
        e._seeds = np.random.default_rng()
        e._seeds.bit_generator.state = seeds
    return e


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
        max_cycles=None,
        flat=False,
        hunt=None,
        reward=None,
        render_mode=None,
    ):
        if render_mode is not None:
            raise InputError(f"render_mode {render_mode!r}: the environment renders nothing")
        if not (isinstance(decision_s, (int, float)) and decision_s > 0):
            raise InputError(f"decision_s {decision_s!r}: expected a positive number")
        if not (isinstance(max_contacts, int) and max_contacts > 0):
            raise InputError(f"max_contacts {max_contacts!r}: expected a positive integer")
        if max_cycles is not None and not (
            isinstance(max_cycles, int) and not isinstance(max_cycles, bool) and max_cycles > 0
        ):
            raise InputError(f"max_cycles {max_cycles!r}: expected a positive integer")
        if hunt is not None and not isinstance(hunt, bool):
            raise InputError(f"hunt {hunt!r}: expected True or False")
        reward = dict(reward or {})
        for key, w in reward.items():
            if key not in REWARD_KEYS:
                raise InputError(f"reward {key!r}: expected one of {', '.join(REWARD_KEYS)}")
            if not (isinstance(w, (int, float)) and not isinstance(w, bool) and np.isfinite(w)):
                raise InputError(f"reward {key} = {w!r}: expected a finite number")
        self._kwargs = dict(
            scenario_path=os.fspath(scenario_path),
            seed=seed,
            fidelity=fidelity,
            units=None if units is None else list(units),
            decision_s=decision_s,
            until=until,
            max_contacts=max_contacts,
            max_cycles=max_cycles,
            flat=bool(flat),
            hunt=hunt,
            reward=reward or None,
        )
        self.scenario_path = os.fspath(scenario_path)
        self.fidelity = fidelity
        self.units = None if units is None else list(units)
        self.decision_s = float(decision_s)
        self.until = None if until is None else float(until)
        self.max_contacts = max_contacts
        self.max_cycles = max_cycles
        self.flat = bool(flat)
        self.render_mode = None
        self._first_seed = seed
        self._seeds = None
        self._cycles = 0
        self._sim = self._build(seed)
        #: True while ``_sim`` is as built (never stepped): a reset to its seed reuses it.
        self._fresh = True
        settings = json.loads(self._sim.env_settings())
        #: Whether an episode goes on through the HVT hunt once the mission is decided (the
        #: constructor's ``hunt``, else the scenario's ``env.hunt``).
        self.hunt = settings["hunt"] if hunt is None else hunt
        #: The reward's weights: the scenario's ``[env.reward]`` table (its defaults for the
        #: keys it leaves out), then the constructor's ``reward`` overrides.
        self.reward_weights = {**settings["reward"], **{k: float(w) for k, w in reward.items()}}
        self.possible_agents = list(self._sim.agents())
        self.agents = []
        #: The targets' world points (x, y, z), in action order (action 1 + i is target i).
        self.targets = list(self._sim.targets())
        #: The actions that go to the briefed places: ``{"start": a, "safehouse": b,
        #: "extraction": c}``.
        self.places = {
            name: 1 + i for name, i in zip(("start", "safehouse", "extraction"), self._sim.places())
        }
        #: The mission's entities in id order: ``(id, name, side)`` (side 0 neutral, 1
        #: blue, 2 red): the ids in ``seen`` and ``heard`` rows, the rows of ``state()``.
        self.members = [tuple(m) for m in self._sim.members()]
        #: Each agent's own entity id.
        self.agent_ids = {name: i for i, name, _ in self.members if name in self.possible_agents}
        #: The scenario's ``sensors.stale_s``: the oldest ``heard`` report kept, seconds.
        self.stale_s = self._sim.stale_s()
        k, big = max_contacts, np.float32(np.inf)
        n = len(self.targets)
        fields = {
            "position": spaces.Box(-big, big, shape=(2,), dtype=np.float32),
            "active": spaces.Discrete(2),
            "goal": spaces.Discrete(1 + n),
            "arrived": spaces.Discrete(2),
            "seen": spaces.Box(-big, big, shape=(k, 5), dtype=np.float32),
            "heard": spaces.Box(-big, big, shape=(k, 7), dtype=np.float32),
            "time": spaces.Box(np.float32(0), big, shape=(1,), dtype=np.float32),
        }
        mask = spaces.Box(0, 1, shape=(1 + n,), dtype=np.int8)
        sizes = {"position": 2, "active": 1, "goal": 1 + n, "arrived": 1, "seen": 5 * k,
                 "heard": 7 * k, "time": 1}
        #: With ``flat=True``: each field's slice of the flat observation.
        self.flat_fields, at = {}, 0
        for name, size in sizes.items():
            self.flat_fields[name] = slice(at, at + size)
            at += size
        if self.flat:
            self._obs_space = spaces.Box(-big, big, shape=(at,), dtype=np.float32)
        else:
            self._obs_space = spaces.Dict({**fields, "action_mask": mask})
        self._act_space = spaces.Discrete(1 + n)
        self.observation_spaces = {a: self._obs_space for a in self.possible_agents}
        self.action_spaces = {a: self._act_space for a in self.possible_agents}
        #: The referee's ground truth's space (see :meth:`state`).
        self.state_space = spaces.Box(
            -big, big, shape=(1 + 4 * len(self.members),), dtype=np.float32
        )
        self._last = {}

    def __reduce__(self):
        seeds = None if self._seeds is None else self._seeds.bit_generator.state
        return (_rebuild, (dict(self._kwargs), seeds))

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

    @property
    def episode_seed(self):
        """The master seed of the episode under way."""
        return self._sim.seed()

    def metrics(self):
        """The referee's metrics so far (for evaluation; never part of an observation)."""
        return json.loads(self._sim.metrics())

    def state(self):
        """The referee's ground truth now (never part of an observation), a float32 vector
        of ``state_space``: the simulated time, then ``[x, y, z, status]`` for every entity
        of ``env.members`` (see the module's doc)."""
        rows = np.asarray(self._sim.state(), dtype=np.float32).reshape(-1)
        return np.concatenate([np.asarray([self._sim.now()], dtype=np.float32), rows])

    def _mask(self, k, goal):
        n = self._act_space.n
        if not k["active"]:
            mask = np.zeros(n, dtype=np.int8)
            mask[0] = 1
        elif k["under_way"]:
            mask = np.zeros(n, dtype=np.int8)
            mask[goal] = 1
        else:
            mask = np.ones(n, dtype=np.int8)
        return mask

    def _observe(self, agent):
        k = json.loads(self._sim.knowledge(agent))
        pos = k["pos"] or [0.0, 0.0]
        seen = np.zeros((self.max_contacts, 5), dtype=np.float32)
        for i, (who, x, y, side) in enumerate(k["seen"][: self.max_contacts]):
            seen[i] = (1.0, x - pos[0], y - pos[1], side, who)
        heard = np.zeros((self.max_contacts, 7), dtype=np.float32)
        latest = sorted(k["heard"], key=lambda h: (h[4], h[0]))[: self.max_contacts]
        for i, (target, x, y, side, age, sender) in enumerate(latest):
            heard[i] = (1.0, x - pos[0], y - pos[1], side, age, sender, target)
        goal = 0 if k["goal"] is None else 1 + int(k["goal"])
        fields = {
            "position": np.asarray(pos, dtype=np.float32),
            "active": int(bool(k["active"])),
            "goal": goal,
            "arrived": int(bool(k["arrived"])),
            "seen": seen,
            "heard": heard,
            "time": np.asarray([self._sim.now()], dtype=np.float32),
        }
        mask = self._mask(k, goal)
        if self.flat:
            one_hot = np.zeros(self._act_space.n, dtype=np.float32)
            one_hot[goal] = 1.0
            parts = {
                **fields,
                "active": [fields["active"]],
                "goal": one_hot,
                "arrived": [fields["arrived"]],
                "seen": seen.reshape(-1),
                "heard": heard.reshape(-1),
            }
            # In the order of flat_fields, the one place the layout is written.
            flat = np.concatenate([parts[name] for name in self.flat_fields]).astype(np.float32)
            return flat, k, mask
        return {**fields, "action_mask": mask}, k, mask

    def _info(self, k, mask):
        return {"sim_time_s": self._sim.now(), "refused": k["refused"], "action_mask": mask}

    def reset(self, seed=None, options=None):
        if seed is not None:
            self._seeds = np.random.default_rng(seed)
            episode_seed = int(seed)
        elif self._seeds is not None:
            episode_seed = int(self._seeds.integers(0, 2**63))
        else:
            episode_seed = self._first_seed
        same = episode_seed is None or episode_seed == self._sim.seed()
        if not (self._fresh and same):
            self._sim = self._build(episode_seed)
            self._fresh = True
        if self._seeds is None:
            self._seeds = np.random.default_rng(self._sim.seed())
        self._cycles = 0
        self.agents = list(self.possible_agents)
        self._last = self.metrics()
        self._cover = dict(zip(self.possible_agents, self._sim.cover_s()))
        observations, infos = {}, {}
        for a in self.agents:
            observations[a], k, mask = self._observe(a)
            infos[a] = self._info(k, mask)
        return observations, infos

    def _team_reward(self, metrics):
        """The team terms over the last step (the referee's metrics then and now)."""
        w, last = self.reward_weights, self._last
        r = w["detection"] * (_metric(metrics, "adversaries_detected") -
                              _metric(last, "adversaries_detected"))
        r += w["uncovered_s"] * (_metric(metrics, "time_uncovered_s") -
                                 _metric(last, "time_uncovered_s"))
        r += w["casualty"] * (_metric(metrics, "casualties") - _metric(last, "casualties"))
        for name in ("success", "vip_down"):
            if metrics.get(name) and not last.get(name):
                r += w[name]
        return r

    def step(self, actions):
        if not self.agents:
            raise InputError("step() after the episode ended: call reset()")
        self._fresh = False
        for agent, action in actions.items():
            if agent in self.agents:
                self._sim.command(agent, int(action))
        going = self._sim.advance(self.decision_s, True, not self.hunt)
        self._cycles += 1
        metrics = self.metrics()
        team = self._team_reward(metrics)
        self._last = metrics
        cover = dict(zip(self.possible_agents, self._sim.cover_s()))
        out_of_time = self._sim.now() >= self._sim.end()
        out_of_cycles = self.max_cycles is not None and self._cycles >= self.max_cycles
        over = (not going and not out_of_time) or (not self.hunt and self._sim.decided())
        w = self.reward_weights
        observations, rewards, terminations, truncations, infos = {}, {}, {}, {}, {}
        for a in self.agents:
            observations[a], k, mask = self._observe(a)
            rewards[a] = team + w["cover_s"] * (cover[a] - self._cover[a])
            if not k["active"]:
                rewards[a] += w["down"]
            terminations[a] = over or not k["active"]
            truncations[a] = not terminations[a] and (out_of_time or out_of_cycles or not going)
            infos[a] = self._info(k, mask)
        self._cover = cover
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
    episode at this simulated time), ``max_contacts`` (rows of ``seen`` and ``heard``),
    ``max_cycles`` (truncate the episode after this many steps), ``flat`` (one flat
    float32 ``Box`` per agent beside its action mask), ``hunt`` (go on through the HVT hunt
    once the mission is decided; default the scenario's ``env.hunt``), ``reward`` (weights
    by key of ``[env.reward]`` that replace the scenario's).
    """
    return EvacuationEnv(scenario_path, seed=seed, fidelity=fidelity, **kwargs)


def env(scenario_path, seed=None, fidelity=None, **kwargs):
    """The same environment as a PettingZoo ``AECEnv`` (``parallel_to_aec``)."""
    return parallel_to_aec(parallel_env(scenario_path, seed=seed, fidelity=fidelity, **kwargs))
