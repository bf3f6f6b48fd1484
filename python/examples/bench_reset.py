"""How long `reset()` takes, in CPU time: with the site kept from the last episode (the
same scenario and fidelity again, what a training loop does) and with it built anew (two
environments on two copies of the scenario, reset in turn).

    python python/examples/bench_reset.py [SCENARIO] [--resets N]
"""

import argparse
import shutil
import statistics
import tempfile
import time
from pathlib import Path

from vitro.env import parallel_env


def timed(env, seed):
    t = time.process_time()
    env.reset(seed=seed)
    return time.process_time() - t


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("scenario", nargs="?", default="scenarios/evacuation_env.toml")
    ap.add_argument("--resets", type=int, default=8)
    args = ap.parse_args()
    src = Path(args.scenario).resolve()
    # The copies sit beside the scenario: its relative paths (map, terrain) still resolve.
    with tempfile.TemporaryDirectory(dir=src.parent) as tmp:
        copies = [Path(tmp) / f"{i}.toml" for i in range(2)]
        for c in copies:
            shutil.copy(src, c)
            text = c.read_text().replace('"../', '"../../')
            c.write_text(text)
        t = time.process_time()
        a = parallel_env(str(copies[0]))
        a.reset(seed=0)
        first = time.process_time() - t
        b = parallel_env(str(copies[1]))
        b.reset(seed=0)
        rebuilt = [timed(e, s) for s in range(1, args.resets + 1) for e in (a, b)]
        kept = [timed(a, s) for s in range(100, 100 + args.resets)]
    ms = lambda xs: f"median {1000 * statistics.median(xs):.0f} ms CPU (n={len(xs)})"
    print(f"a new environment and its first reset (the patrol game solved): {1000 * first:.0f} ms CPU")
    print(f"reset, site built anew: {ms(rebuilt)}")
    print(f"reset, site kept:       {ms(kept)}")


if __name__ == "__main__":
    main()
