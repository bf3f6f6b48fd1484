"""Vitro from Python: scenario runs, experiment suites, and a PettingZoo environment.

>>> import vitro
>>> report = vitro.run("scenarios/evacuation.toml", seed=42)      # doctest: +SKIP
>>> report["trace_hash"], report["success"]                      # doctest: +SKIP

- :func:`run` runs a scenario of any registered mission and returns the report of
  ``vitro run --json`` (the same trace hash);
- :func:`batch` makes an experiment's runs into a result directory (as ``vitro batch``);
- :func:`load_results` reads a result directory's tables into a pandas DataFrame;
- :mod:`vitro.env` holds the PettingZoo environment of the evacuation mission.
"""

import json as _json
import os as _os
from pathlib import Path as _Path

from . import _vitro
from .errors import InputError, RunError, VitroError

__all__ = ["run", "batch", "load_results", "kinds", "VitroError", "InputError", "RunError"]


def _seed(seed):
    if seed is None:
        return None
    if isinstance(seed, bool) or not isinstance(seed, int) or not 0 <= seed < 2**64:
        raise InputError(f"seed {seed!r}: expected an integer in [0, 2^64)")
    return seed


def kinds():
    """The scenario kinds (missions) this build knows."""
    return list(_vitro.kinds())


def run(scenario_path, seed=None, until=None, fidelity=None, overrides=None):
    """Runs a scenario to its end and returns its report as a dict.

    The report is that of ``vitro run SCENARIO --json`` with the same arguments: the
    mission's metrics, ``scenario``, ``seed``, ``events``, ``sim_time_s``, ``trace_hash``
    and the wall-clock figures. The same scenario and seed give the same ``trace_hash`` as
    the command.

    :param scenario_path: a scenario file (its ``kind`` names the mission).
    :param seed: master seed (default: the scenario's).
    :param until: simulated seconds to run at most.
    :param fidelity: ``"discrete"``, ``"interpolated"`` or ``"physical"`` (mission scenarios).
    :param overrides: ``{"channel.loss": 0.2, "entity.4.count": 3}``: scenario keys set as an
        experiment's parameters would be (the scenario must hold each key).
    :raises InputError: a bad scenario (the message names file, line and column) or argument.
    :raises RunError: the run could not be set up or broke.
    """
    ov = None
    if overrides is not None:
        ov = _json.dumps([[str(k), v] for k, v in dict(overrides).items()])
    until = None if until is None else float(until)
    text = _vitro.run(_os.fspath(scenario_path), _seed(seed), until, fidelity, ov)
    return _json.loads(text)


def batch(experiment_path, out, jobs=None, shard=None, resume=False):
    """Makes an experiment's runs into the result directory ``out``, as ``vitro batch``.

    Writes ``runs.jsonl``, ``manifest.json`` and the summary and series tables (CSV and
    Parquet); read them with :func:`load_results`. Inside a task of a Slurm job array (or a
    Kubernetes Indexed Job) without ``shard``, makes that task's shard, as the command does.

    :param jobs: runs at once (default: the number of CPUs).
    :param shard: ``"I/N"``: only the runs whose number k has k mod N = I.
    :param resume: complete the runs missing from ``out``.
    :returns: a dict: ``experiment``, ``out``, ``planned``, ``ran``, ``skipped``, ``wall_s``,
        ``tables``.
    :raises InputError: a bad experiment (file, line, column) or argument.
    :raises RunError: runs failed (named in the message; the tables are written) or the
        results could not be written.
    """
    if jobs is not None and (isinstance(jobs, bool) or not isinstance(jobs, int) or jobs < 1):
        raise InputError(f"jobs {jobs!r}: expected a positive integer")
    text = _vitro.batch(_os.fspath(experiment_path), _os.fspath(out), jobs, shard, bool(resume))
    return _json.loads(text)


def load_results(directory, table="summary"):
    """A result directory's table as a pandas DataFrame.

    :param table: ``"summary"`` (one row per run: run, point, replicate, seed, the varied
        parameters, the kept metrics, status, error, wall_s) or ``"series"`` (run, t_s and
        one column per series metric).
    :raises InputError: no such table in the directory.
    """
    import pandas as pd

    if table not in ("summary", "series"):
        raise InputError(f"table {table!r}: expected 'summary' or 'series'")
    path = _Path(directory) / f"{table}.parquet"
    if not path.is_file():
        raise InputError(f"{path}: no such table (is {directory} a vitro batch result directory?)")
    return pd.read_parquet(path)
