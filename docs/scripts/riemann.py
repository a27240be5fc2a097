"""Exact solution of the Riemann problem for an ideal gas (Toro, chapter 4), as in
mpmice-algorithm.md section 11.4. Used by sod_plot.py; the C++ validation test has
its own copy of the same formulas (tests/validation/exact_riemann.hpp)."""
import math


def star_state(rl, ul, pl, rr, ur, pr, gamma):
    """Pressure and velocity in the star region."""
    def f(p, rk, pk):
        ck = math.sqrt(gamma * pk / rk)
        if p > pk:  # shock
            a = 2.0 / ((gamma + 1.0) * rk)
            b = (gamma - 1.0) / (gamma + 1.0) * pk
            return (p - pk) * math.sqrt(a / (p + b))
        return 2.0 * ck / (gamma - 1.0) * ((p / pk) ** ((gamma - 1.0) / (2.0 * gamma)) - 1.0)

    lo, hi = 1e-12, 10.0 * max(pl, pr)
    for _ in range(200):  # bisection: f_L + f_R + du is increasing in p
        mid = 0.5 * (lo + hi)
        if f(mid, rl, pl) + f(mid, rr, pr) + ur - ul > 0:
            hi = mid
        else:
            lo = mid
    p = 0.5 * (lo + hi)
    u = 0.5 * (ul + ur) + 0.5 * (f(p, rr, pr) - f(p, rl, pl))
    return p, u


def sample(x, t, x0, rl, ul, pl, rr, ur, pr, gamma):
    """(density, velocity, pressure) at x, t."""
    p, u = star_state(rl, ul, pl, rr, ur, pr, gamma)
    g = gamma
    s = (x - x0) / t
    if s <= u:  # left of the contact
        cl = math.sqrt(g * pl / rl)
        if p > pl:
            sl = ul - cl * math.sqrt((g + 1) / (2 * g) * p / pl + (g - 1) / (2 * g))
            if s < sl:
                return rl, ul, pl
            return rl * ((p / pl + (g - 1) / (g + 1)) / ((g - 1) / (g + 1) * p / pl + 1)), u, p
        head = ul - cl
        cstar = cl * (p / pl) ** ((g - 1) / (2 * g))
        tail = u - cstar
        if s < head:
            return rl, ul, pl
        if s > tail:
            return rl * (p / pl) ** (1 / g), u, p
        uf = 2 / (g + 1) * (cl + (g - 1) / 2 * ul + s)
        c = 2 / (g + 1) * (cl + (g - 1) / 2 * (ul - s))
        return rl * (c / cl) ** (2 / (g - 1)), uf, pl * (c / cl) ** (2 * g / (g - 1))
    cr = math.sqrt(g * pr / rr)
    if p > pr:
        sr = ur + cr * math.sqrt((g + 1) / (2 * g) * p / pr + (g - 1) / (2 * g))
        if s > sr:
            return rr, ur, pr
        return rr * ((p / pr + (g - 1) / (g + 1)) / ((g - 1) / (g + 1) * p / pr + 1)), u, p
    head = ur + cr
    cstar = cr * (p / pr) ** ((g - 1) / (2 * g))
    tail = u + cstar
    if s > head:
        return rr, ur, pr
    if s < tail:
        return rr * (p / pr) ** (1 / g), u, p
    uf = 2 / (g + 1) * (-cr + (g - 1) / 2 * ur + s)
    c = 2 / (g + 1) * (cr - (g - 1) / 2 * (ur - s))
    return rr * (c / cr) ** (2 / (g - 1)), uf, pr * (c / cr) ** (2 * g / (g - 1))
