"""The filter-shaped move's closed form, written here from its definition (docs/smooth-move.md,
lib/src/smooth_move.h's header) independently of lib/: the velocity command u(t), piecewise
constant, through two moving averages of lengths tau1 = vmax/accel and tau2 = accel/jerk; a change
of the command by c at time s adds c P(t - s) to the position,
  P(t) = [r(t) - r(t - tau1) - r(t - tau2) + r(t - tau1 - tau2)] / (tau1 tau2),  r(x) = max(x, 0)^3 / 6.
A move of R steps from rest: a rectangle of height h and length T, h T = R (h = vmax, T = R/vmax,
unless vmax (tau1 - tau2) < R < vmax (tau1 + tau2): then T = tau1 + tau2, h = R/T). A stop at time s:
the command goes to 0 at s. A new target at s: the command from s on is the rectangle of that rule
for R = target - where a stop at s would come to rest. Step n comes when the position reaches n
(seconds, in the move's frame: steps from its start, in its direction); numpy, float64."""
import numpy as np


class Law:
    def __init__(self, vmax, accel, jerk):
        self.vmax = float(vmax)
        self.tau1 = vmax / accel
        self.tau2 = accel / jerk
        self.chg = []  # (s, c): the command changes by c (steps/s) at time s

    def rect(self, R):
        """the rectangle (h, T) for a distance R >= 0"""
        t1, t2, v = self.tau1, self.tau2, self.vmax
        if R >= v * (t1 + t2) or R <= v * (t1 - t2):
            return v, R / v
        return R / (t1 + t2), t1 + t2

    def start(self, R):
        h, T = self.rect(R)
        self.chg = [(0.0, h), (T, -h)]

    def command_at(self, s):
        return sum(c for t, c in self.chg if t <= s)

    def _cut(self, s):
        """the changes before s, and the command dropped to 0 at s"""
        kept = [(t, c) for t, c in self.chg if t <= s]
        u = sum(c for _, c in kept)
        if u != 0:
            kept.append((s, -u))
        return kept, u

    def rest_if_stopped(self, s):
        kept, _ = self._cut(s)
        return -sum(c * t for t, c in kept)

    def stop(self, s):
        self.chg, _ = self._cut(s)

    def retarget(self, s, R_total):
        """new target R_total (frame) at s: False if behind the rest point of a stop at s"""
        p_stop = self.rest_if_stopped(s)
        R = R_total - p_stop
        if R < 0:
            return False
        kept = [(t, c) for t, c in self.chg if t <= s]
        u = sum(c for _, c in kept)
        h, T = self.rect(R)
        self.chg = kept + [(s, h - u), (s + T, -h)]
        return True

    def final(self):
        return -sum(c * t for t, c in self.chg)

    def t_final(self):
        return max(t for t, _ in self.chg) + self.tau1 + self.tau2

    def pos(self, t):
        t = np.asarray(t, dtype=float)
        t1, t2 = self.tau1, self.tau2
        out = np.zeros_like(t)
        for s, c in self.chg:
            x = t - s
            r = lambda y: np.maximum(y, 0.0) ** 3 / 6.0
            out += c * (r(x) - r(x - t1) - r(x - t2) + r(x - t1 - t2)) / (t1 * t2)
        return out

    def times(self, n):
        """t when the position reaches each n (array of step numbers, 0 < n <= final): bisection; the
        final position itself is reached at t_final, where the law comes to rest (its velocity,
        acceleration and jerk all 0 there, the position is flat to the third order: a bisection on
        pos() in float64 would place that step up to some 10 us early)"""
        n = np.asarray(n, dtype=float)
        lo = np.zeros_like(n)
        hi = np.full_like(n, self.t_final())
        for _ in range(64):
            mid = (lo + hi) / 2
            below = self.pos(mid) < n
            lo = np.where(below, mid, lo)
            hi = np.where(below, hi, mid)
        return np.where(np.abs(n - self.final()) < 1e-9, self.t_final(), (lo + hi) / 2)
