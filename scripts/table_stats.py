"""Statistics shared by the table scripts (stdlib only): the Wilson 95 % interval of a rate,
a mean with its 1.96-standard-error half width, and a lenient number reader."""

import math


def wilson(k: int, n: int) -> tuple[float, float]:
    """The Wilson score 95 % interval of k successes in n trials (NaN for n = 0)."""
    if n == 0:
        return (math.nan, math.nan)
    z = 1.96
    p = k / n
    centre = (p + z * z / (2 * n)) / (1 + z * z / n)
    half = z * math.sqrt(p * (1 - p) / n + z * z / (4 * n * n)) / (1 + z * z / n)
    return (centre - half, centre + half)


def mean_ci(xs: list[float]) -> tuple[float, float]:
    """The mean of the numbers (NaN left out) and 1.96 standard errors (NaN below two)."""
    xs = [x for x in xs if not math.isnan(x)]
    if not xs:
        return (math.nan, math.nan)
    m = sum(xs) / len(xs)
    if len(xs) < 2:
        return (m, math.nan)
    var = sum((x - m) ** 2 for x in xs) / (len(xs) - 1)
    return (m, 1.96 * math.sqrt(var / len(xs)))


def num(s) -> float:
    """A float, or NaN for an empty or non-numeric cell."""
    try:
        return float(s)
    except (TypeError, ValueError):
        return math.nan
