"""kinematics.py - velocity, acceleration and jerk estimated from step edges alone (the smooth ramp's
emulator checks, test/emu/checks_library.py, and `make bench`'s smooth section): divided differences of
the position over edges, each a positive-weighted mean of the true derivative, so their peak is never
above the law's but by the edges' jitter."""


def divided_differences(t, x, h, order):
    """order-th divided differences of x(t) over nodes order+1 edges about h apart, slid every 2 ms
    (times 1, 2 or 6: velocity, acceleration, jerk); each is a weighted mean of the true derivative
    between its nodes (a B-spline kernel, positive): its peak is never above the law's"""
    import numpy as np
    out = []
    fact = (1.0, 1.0, 2.0, 6.0)[order]
    for tau in np.arange(t[0], t[-1] - order * h, 0.002):
        idx = np.searchsorted(t, tau + h * np.arange(order + 1))
        idx = np.minimum(idx, len(t) - 1)
        if len(set(idx.tolist())) != order + 1:
            continue
        tt, xx = t[idx], x[idx].astype(float)
        for k in range(1, order + 1):  # the divided-difference table
            xx = (xx[1:] - xx[:-1]) / (tt[k:] - tt[:-k])
        out.append((tt[0], fact * xx[0], tt[-1]))
    return out
