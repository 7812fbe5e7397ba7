"""The filter-shaped move's closed form, written here from its definition (docs/smooth-move.md,
lib/src/smooth_move.h's header) independently of lib/: the velocity command u(t), piecewise
constant, through two moving averages of lengths tau1 = vmax/accel and tau2 = accel/jerk; a change
of the command by c at time s adds c P(t - s) to the position,
  P(t) = [r(t) - r(t - tau1) - r(t - tau2) + r(t - tau1 - tau2)] / (tau1 tau2),  r(x) = max(x, 0)^3 / 6.
A move of R steps from rest: a rectangle of height h and length T, h T = R (h = vmax, T = R/vmax,
unless vmax (tau1 - tau2) < R < vmax (tau1 + tau2): then T = tau1 + tau2, h = R/T). A stop at time s:
the command goes to 0 at s. A new target at s: the command from s on is the rectangle of that rule
for R = target - where a stop at s would come to rest. When: at s, unless that puts a jerk window
over one still running of the same sign (the jerk would exceed jerk); then at the first end of a
running window from which it stays within jerk (a new target that could only start once the
command is at 0 and the motion has come to rest, or that no such time keeps within jerk: a stop,
then a move from rest, as one behind).
Step n comes when the position reaches n (seconds, in the move's frame: steps from its start, in
its direction); numpy, float64."""
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

    def _cut(self, s, e=None):
        """the changes before s, and the command dropped to 0 at e (default s)"""
        kept = [(t, c) for t, c in self.chg if t <= s]
        u = sum(c for _, c in kept)
        if u != 0:
            kept.append((s if e is None else e, -u))
        return kept, u

    def rest_if_stopped(self, s, e=None):
        kept, _ = self._cut(s, e)
        return -sum(c * t for t, c in kept)

    def jerk_max_after(self, chg, s):
        """the largest |jerk| after s of a change list: +c/(tau1 tau2) over [t, t + tau2), -c/(tau1 tau2)
        over [t + tau1, t + tau1 + tau2) for each change c at t (pieces shorter than 0.1 us not judged:
        windows that meet, a rounding apart)"""
        t1, t2 = self.tau1, self.tau2
        pts = sorted({s} | {t + d for t, _ in chg for d in (0.0, t2, t1, t1 + t2) if t + d > s})
        worst = 0.0
        for a, b in zip(pts, pts[1:] + [pts[-1] + 1.0]):
            if b - a <= 1e-7:
                continue
            m = (a + b) / 2
            j = sum(c * ((0 <= m - t < t2) - (t1 <= m - t < t1 + t2)) for t, c in chg) / (t1 * t2)
            worst = max(worst, abs(j))
        return worst

    def _when(self, s):
        """the times a change given at s may take: s, then the ends of the running windows"""
        t1, t2 = self.tau1, self.tau2
        kept = [(t, c) for t, c in self.chg if t <= s]
        return kept, [s] + sorted({t + d for t, _ in kept for d in (t2, t1, t1 + t2) if t + d > s})

    def stop(self, s):
        kept, when = self._when(s)
        lim = self.vmax / (self.tau1 * self.tau2) * (1 + 1e-6)
        for e in when:
            chg, _ = self._cut(s, e)
            if self.jerk_max_after(chg, s) <= lim:
                self.chg = chg
                return
        self.chg, _ = self._cut(s)

    def retarget(self, s, R_total):
        """new target R_total (frame) at s: False if behind the rest point of a stop at s, if it could
        only start once the motion has come to rest, or if no time keeps the jerk within its limit
        (then: a stop, a move from rest)"""
        kept, when = self._when(s)
        u = sum(c for _, c in kept)
        lim = self.vmax / (self.tau1 * self.tau2) * (1 + 1e-6)
        for k, e in enumerate(when):
            if u == 0 and k > 0 and k == len(when) - 1:
                return False
            R = R_total - self.rest_if_stopped(s, e)
            if R < 0 and R > -1e-9 * max(1.0, abs(R_total)):
                R = 0.0  # the target is the rest point, but for float rounding
            if R < 0:
                if k == 0:
                    return False
                continue
            h, T = self.rect(R) if R > 0 else (0.0, 0.0)
            chg = kept + [(e, h - u)] * (h != u) + [(e + T, -h)] * (h != 0)
            if self.jerk_max_after(chg, s) <= lim:
                self.chg = chg
                return True
        return False  # no time keeps it within jerk: a stop, then a move from rest

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
