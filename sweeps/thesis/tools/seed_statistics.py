"""Statistics over seeds for the thesis tools, by the rules of sweeps/thesis/README.md ("Verdicts"):
the 95 % Student-t interval of a mean and the paired "holds in every seed or by a one-sided sign
test at 5 %" comparison. The C++ home of the same rules is analysis/summary_statistics and
analysis/thesis_comparison; this is their Python counterpart for the tools that read databases
directly (tools/ik_noise_verdict.py). Python 3 standard library only.
"""
import math


def _incomplete_beta(a, b, x):
    """The regularized incomplete beta I_x(a, b), by its continued fraction (modified Lentz)."""
    if x <= 0.0:
        return 0.0
    if x >= 1.0:
        return 1.0
    if x > (a + 1.0) / (a + b + 2.0):  # the fraction converges fast below the mean only
        return 1.0 - _incomplete_beta(b, a, 1.0 - x)
    log_front = math.lgamma(a + b) - math.lgamma(a) - math.lgamma(b) + a * math.log(x) + b * math.log1p(-x)
    tiny = 1e-300
    c, d = 1.0, 1.0 - (a + b) * x / (a + 1.0)
    d = 1.0 / (d if abs(d) > tiny else tiny)
    fraction = d
    for m in range(1, 500):
        for numerator in (m * (b - m) * x / ((a + 2 * m - 1) * (a + 2 * m)),
                          -(a + m) * (a + b + m) * x / ((a + 2 * m) * (a + 2 * m + 1))):
            d = 1.0 + numerator * d
            d = 1.0 / (d if abs(d) > tiny else tiny)
            c = 1.0 + numerator / c
            c = c if abs(c) > tiny else tiny
            fraction *= c * d
        if abs(c * d - 1.0) < 1e-15:
            break
    return math.exp(log_front) * fraction / a


def _t_upper_tail(x, df):
    """P(T > x) for x >= 0 and Student's t with df degrees of freedom."""
    return 0.5 * _incomplete_beta(df / 2.0, 0.5, df / (df + x * x))


def t_quantile_975(df):
    """t(0.975, df): the x with P(T > x) = 0.025, by bisection."""
    if df < 1:
        raise ValueError("t quantile needs at least 1 degree of freedom")
    low, high = 0.0, 100.0
    for _ in range(60):
        middle = 0.5 * (low + high)
        if _t_upper_tail(middle, df) > 0.025:
            low = middle
        else:
            high = middle
    return 0.5 * (low + high)


def mean_interval(values):
    """(mean, low, high) of the 95 % Student-t interval; low = high = None for fewer than 2 values."""
    n = len(values)
    if n == 0:
        raise ValueError("no values")
    mean = sum(values) / n
    if n < 2:
        return mean, None, None
    s = math.sqrt(sum((v - mean) ** 2 for v in values) / (n - 1))
    half = t_quantile_975(n - 1) * s / math.sqrt(n)
    return mean, mean - half, mean + half


def format_mean_interval(values, spec=".3f"):
    """'mean [low, high] (n)' (or 'mean (1)'), each number formatted by `spec`."""
    mean, low, high = mean_interval(values)
    if low is None:
        return f"{mean:{spec}} ({len(values)})"
    return f"{mean:{spec}} [{low:{spec}}, {high:{spec}}] ({len(values)})"


def sign_test_p(k, n):
    """One-sided P(X >= k) for X ~ Binomial(n, 1/2)."""
    return sum(math.comb(n, i) for i in range(k, n + 1)) / 2.0 ** n


def holds_in_seeds(differences):
    """A paired comparison holds when every difference is > 0 (at least 2 seeds), or when the
    sign test of the k positive of n gives p < 0.05."""
    n = len(differences)
    k = sum(1 for d in differences if d > 0.0)
    if n >= 2 and k == n:
        return True
    return n > 0 and sign_test_p(k, n) < 0.05
