"""tools/fuzz/fuzz_oracles.py - what the fuzzer checks on the STEP/DIR edges, as pure functions.

Inputs are plain lists (cycles of the 16 MHz CPU), so the self-test (fuzz_selftest.py) can feed
them synthetic traces. The bounds come from the documented guarantees, not from the firmware:

- docs/stepper-engine.md: every step edge of the planner is within 1 tick of its plan (the exact
  ramp: of round(F t_n)), and Timer1's compare match falls on that tick; F = 16 MHz for the exact
  ramp (ExactRampStepper, MultiAxisStepper: one tick per CPU cycle), 2 MHz for the lab's ramps.
  An edge on the pin comes after its compare match, never before, by at most STEP_LATE_CYCLES
  (the single-axis bound, also the bench's clean criterion for MultiAxisStepper, docs/multi-axis.md).
- The exact ramp is constant acceleration: the average speed over a step interval t_k is the speed
  at its middle, so two consecutive intervals obey
      |1/t_k+1 - 1/t_k| <= a (t_k + t_k+1) / 2        (equality while accelerating)
  with a the acceleration in force; with each edge within QUANT_TICKS of its plan, an interval is
  off by at most 2 QUANT_TICKS ticks (QUANT_TICKS = 1.5: 1 tick of round(F t_n)), which moves 1/t by at most F 2q / (t (t - 2q)).
- No interval is faster than the largest vmax in force (plus the same quantisation).
- A direction reversal happens from rest: under constant deceleration a to rest the step before
  the turning point is less than one step from it, so the interval ending there covers steps
  within two steps of rest, whose speed is at most sqrt(v0^2 + 2 a 2) (v0: a ramp may start and
  end at v0); the same on the way back. So both intervals next to a DIR change are at most that
  fast. (Not for the S-curve, whose largest acceleration `?` does not give: its `accel=` is the
  average.)
"""
import bisect
import math

F_CPU = 16_000_000
STEP_LATE_CYCLES = 260   # docs/stepper-engine.md / docs/multi-axis.md: an edge at most this late after its match
QUANT_TICKS = 1.5        # docs/stepper-engine.md: every edge within 1 tick of round(F t_n), itself 0.5 tick from F t_n
LAW_TOL = 0.002          # the parameters are float32 (6e-8) and the ramp's constants 1/256 tick: 0.2 % is ample


def edges_with_dir(pins, step, dirp):
    """[(cycle, +1/-1)]: every rising STEP edge with the DIR level just before it (high = +1).
    pins: emulog's {name: [(cycle, level)]}; one linear merge."""
    steps = pins.get(step, [])
    dirs = pins.get(dirp, [])
    out = []
    j, level = 0, 0
    for c, lv in steps:
        while j < len(dirs) and dirs[j][0] < c:
            level = dirs[j][1]
            j += 1
        if lv == 1:
            out.append((c, 1 if level == 1 else -1))
    return out


def positions(edges):
    """[(cycle, position after the edge)] from [(cycle, +-1)], starting at 0"""
    pos, out = 0, []
    for c, d in edges:
        pos += d
        out.append((c, pos))
    return out


def planned_cycles(edge_cycles, own_matches, all_matches, late=STEP_LATE_CYCLES):
    """The compare match each pin edge came from: its own channel's last match at or before it, if
    within `late` cycles, else (an axis stepped by another axis's interrupt, a diagonal) any
    channel's. Returns (planned cycles, problems): an edge with no match within `late` cycles
    before it is a problem (late, or not from a timer match at all)."""
    out, problems = [], []
    io = ia = 0
    last_o = last_a = None
    for c in edge_cycles:
        while io < len(own_matches) and own_matches[io] <= c:
            last_o = own_matches[io]
            io += 1
        while ia < len(all_matches) and all_matches[ia] <= c:
            last_a = all_matches[ia]
            ia += 1
        if last_o is not None and c - last_o <= late:
            out.append(last_o)
        elif last_a is not None and c - last_a <= late:
            out.append(last_a)
        else:
            out.append(c)
            if len(problems) < 3:
                ago = f"{c - last_o} cycles after its channel's last match" if last_o is not None else "no match before"
                problems.append(f"STEP edge at {c / F_CPU:.6f} s: {ago} (bound {late} cycles)")
    return out, problems


class Params:
    """The parameters in force over time for one axis: events of accepted `set`s, after the initial
    values: (cycle, key, value), or (earliest, latest, key, value) when the sketch read the line at
    some moment between the two (a flood's line arrives long before the sketch takes it: its reply
    is the latest). max_over(key, a, b): the largest value in force at any time in [a, b] (a set
    takes effect at the next plan, so the old one stays in force until then, and a set read at an
    unknown moment may have come before or after a: taking the largest of both is the honest bound;
    until 2026-12-06 a set was in force from its earliest moment, and a flood's `set x vmax 123`,
    arrived at 0.40 s and answered at 5.38 s, made a move planned at 1.55 s at up to 17,804 steps/s a
    finding: make fuzz seed 10)."""

    def __init__(self, initial, events=()):
        self.initial = dict(initial)
        # in the order the sketch answered them (the order it read them)
        self.events = sorted((e if len(e) == 4 else (e[0],) + tuple(e) for e in events), key=lambda e: (e[1], e[0]))

    def max_over(self, key, a, b):
        v = self.initial.get(key, 0.0)
        best = None
        for c0, c1, k, val in self.events:
            if k != key:
                continue
            if c1 <= a:
                v = val  # in force by a, surely
            elif c0 <= b:
                best = val if best is None else max(best, val)  # maybe in force within [a, b]
        return v if best is None else max(v, best)


def split_runs(times, dirs, split_after):
    """Runs of consecutive edges between rests: a new run after every index in split_after (the
    edge where a move ended: DONE, halt) and at every DIR change. Yields lists of indices."""
    run = []
    for i in range(len(times)):
        if run and (dirs[i] != dirs[i - 1] or (i - 1) in split_after):
            yield run
            run = []
        run.append(i)
    if run:
        yield run


LATE_MIN_CYCLES = 28  # the least a late edge is off its plan (2 us = 32 cycles, less 2 ticks of quantisation)
LATE_RUN_MAX = 8      # the longest run of consecutive late edges recognised (make fuzz at 100,000 steps/s: 4)
LATE_FIT_EDGES = 3    # edges on time fitted on each side of a run


def _quadratic(points):
    """least squares y = c0 + c1 x + c2 x^2 through [(x, y)] (a few points, small x): (c0, c1, c2)"""
    s = [sum(x ** k for x, _ in points) for k in range(5)]
    a = [[s[0], s[1], s[2], sum(y for _, y in points)],
         [s[1], s[2], s[3], sum(y * x for x, y in points)],
         [s[2], s[3], s[4], sum(y * x * x for x, y in points)]]
    for i in range(3):
        p = max(range(i, 3), key=lambda r: abs(a[r][i]))
        a[i], a[p] = a[p], a[i]
        for r in range(3):
            if r != i:
                f = a[r][i] / a[i][i]
                a[r] = [u - f * v for u, v in zip(a[r], a[i])]
    return tuple(a[i][3] / a[i][i] for i in range(3))


def undo_late_edges(times, runs, late=STEP_LATE_CYCLES, tick_cycles=1, moved=None):
    """The planned times of late edges. An edge armed when its time had passed fires 2 us later
    (docs/stepper-engine.md, `late=`), so its compare match is not its planned time; the edge after
    it is armed from the plan again (the timeline is not moved), on time, or, when the interrupt
    that made the late edge ends after that edge's time too, late as well, less so (a run of late
    edges: make fuzz at 70,000-100,000 steps/s found runs of 2 to 4, each displaced less than the one
    before). So: a run of L consecutive edges (1 <= L <= LATE_RUN_MAX), each
    displaced by d (LATE_MIN_CYCLES <= d <= `late`) from the smooth curve through the edges on time
    around it (a ramp's edge times are smooth in the step number: a quadratic through
    LATE_FIT_EDGES edges before the run and up to as many after, each within 3 QUANT_TICKS of it),
    is put back on that curve. A real change of speed moves every later edge too, so no curve
    passes through the edges before and after it, and it is left as it is.
    moved: a list that gets the indices of the edges put back."""
    t = list(times)
    tol = 3 * QUANT_TICKS * tick_cycles
    n_fit = LATE_FIT_EDGES
    for r in runs:
        k = n_fit
        while k < len(r) - 1:
            # first the trend of the two intervals before: is edge k that far behind it at all?
            p1 = t[r[k - 1]] - t[r[k - 2]]
            if (t[r[k]] - t[r[k - 1]]) - (2 * p1 - (t[r[k - 2]] - t[r[k - 3]])) < LATE_MIN_CYCLES - 2 * tol:
                k += 1
                continue
            hit = None
            for length in range(1, LATE_RUN_MAX + 1):
                after = min(n_fit, len(r) - k - length)
                if after < 1:
                    break
                ref = t[r[k - 1]]
                xs = list(range(-n_fit, 0)) + list(range(length, length + after))
                c0, c1, c2 = _quadratic([(x, t[r[k + x]] - ref) for x in xs])

                def curve(x):
                    return ref + c0 + c1 * x + c2 * x * x
                if any(abs(t[r[k + x]] - curve(x)) > tol for x in xs):
                    continue
                if tick_cycles > 1 and abs(2 * c2 - ((t[r[k - 1]] - t[r[k - 2]]) - (t[r[k - 2]] - t[r[k - 3]]))) > 2 * tol:
                    # the lab ramps' intervals may change in stairs (SCurveStepper's table repeats each
                    # period 4 times): a quadratic then fits a stair's edges within tol but bends more
                    # than the intervals before the run change, which a late edge on a ramp does not
                    # (make test's fuzz seed 1 saw a stair of +343 cycles at 227 steps/s as a late run)
                    continue
                ds = [t[r[k + i]] - curve(i) for i in range(length)]
                if not LATE_MIN_CYCLES <= ds[0] <= late:
                    break   # the first edge is not late on this curve: no run starts here
                if tick_cycles > 1 and any(ds[i + 1] > ds[i] + tol for i in range(length - 1)):
                    break   # a run of late edges is displaced less and less; a stair's fit is not
                if all(LATE_MIN_CYCLES <= d <= late for d in ds):
                    hit = [int(round(curve(i))) for i in range(length)]
                    break
            if hit:
                for i, p in enumerate(hit):
                    t[r[k + i]] = p
                    if moved is not None:
                        moved.append(r[k + i])
                k += len(hit) + 1
            else:
                k += 1
    return t


def speed_law(times, dirs, split_after, params, tick_cycles, exact, label, limit=3, reversals=True, plans=(),
              pins=None, positions=None):
    """The speed-continuity oracle on planned edge times (cycles). Returns (problems, pairs
    checked, worst fraction of the allowance used, reversals checked).
    plans: when plans were made: cycles, or (line arrived, reply) pairs, or (line arrived, reply,
    position where the plan starts: the `from` of its `OK`). A run of edges belongs to the plan made
    before it started (a reversal is planned with the target that caused it), and that plan has the
    parameters in force then: the values in force are taken from that plan's time on, not from the
    run's first edge (a `set` after the plan is "from the next plan"). A plan that starts at a
    position is the run's only once the axis has been there since its reply: the queue ahead may
    hold an earlier plan's reversal and the run after it (a lab ramp's new target takes over after
    the queued lead: LeibRampStepper, `make fuzz` seed 8, a reversal planned before a lower `set vmax`
    began its run 80 ms after the next target's `OK`, whose `from` lay 600 steps into that run).
    positions: the position after each edge (the same length as times), for that test.
    exact: apply the constant-acceleration law between consecutive intervals (exact ramp); every
    ramp gets the vmax bound and the reversal bound.
    pins: the edges on the STEP pin (cycles, one per time): a late edge, put back on its plan, must
    still be on the pin within STEP_LATE_CYCLES after that plan (docs/stepper-engine.md: a late edge
    is within the bound), not only after its own (late) compare match."""
    problems = []
    pairs = 0
    worst = 0.0
    q = 2 * QUANT_TICKS * tick_cycles   # cycles an interval may be off
    check_reversals, reversals = reversals, 0

    def quant(t):
        return F_CPU * q / (t * (t - q)) if t > q else float("inf")

    runs = list(split_runs(times, dirs, split_after))
    moved = []
    times = undo_late_edges(times, runs, tick_cycles=tick_cycles, moved=moved)
    if pins is not None:
        for i in moved:
            if pins[i] - times[i] > STEP_LATE_CYCLES and len(problems) < limit:
                problems.append(f"{label}: a late edge on the pin at {pins[i] / F_CPU:.6f} s, {pins[i] - times[i]} "
                                f"cycles after its plan (bound {STEP_LATE_CYCLES})")
    # a plan: (the line arrived, its reply[, the position it starts at]): the sketch made it in
    # between (lines are taken in order)
    plans = sorted(((p, p, None) if isinstance(p, (int, float)) else (tuple(p) + (None,))[:3]) for p in plans)

    def started(plan, i):
        """whether the axis had been at the plan's start position between its reply and edge i (the
        run's first edge): there when answered, or an edge since then brought it there"""
        a, e, at = plan
        if at is None or positions is None:
            return True
        k = bisect.bisect_right(times, e)
        if (positions[k - 1] if k else 0) == at:
            return True
        return any(positions[j] == at for j in range(k, i))

    def since(c, i=None):
        """the time from which the parameters of the run starting at cycle c (edge i) are in force: the
        run's plan is the last one made before c, which is the last one answered before c (whose start
        position the axis had reached) or a later one (arrived before c, answered after it); the
        earliest of these is the honest bound"""
        sure = [p for p in plans if p[1] <= c and (i is None or started(p, i))]
        if sure:
            return sure[-1][0]
        maybe = [a for a, e, _ in plans if a <= c < e]
        return maybe[0] if maybe else c

    for r in runs:
        r_from = since(times[r[0]], r[0])
        for k in range(1, len(r)):
            i0, i1 = r[k - 1], r[k]
            t = times[i1] - times[i0]
            if t <= 0:
                problems.append(f"{label}: two STEP edges on one tick at {times[i1] / F_CPU:.6f} s")
                continue
            v = F_CPU / t
            vmax = params.max_over("vmax", r_from, times[i1])
            if v > vmax * (1 + LAW_TOL) + quant(t) and len(problems) < limit:
                problems.append(f"{label}: {v:.0f} steps/s at {times[i1] / F_CPU:.6f} s (interval {t} cycles), "
                                f"above the largest vmax in force {vmax:g}")
            if exact and k >= 2:
                ta = times[r[k - 1]] - times[r[k - 2]]
                if ta <= 0:
                    continue
                va = F_CPU / ta
                a = params.max_over("accel", r_from, times[i1])
                allowed = a * (ta + t) / 2 / F_CPU * (1 + LAW_TOL) + quant(ta) + quant(t)
                jump = abs(v - va)
                pairs += 1
                if allowed > 0:
                    worst = max(worst, jump / allowed)
                if jump > allowed and len(problems) < limit:
                    problems.append(f"{label}: speed {va:.1f} -> {v:.1f} steps/s in one step at "
                                    f"{times[i1] / F_CPU:.6f} s (intervals {ta} -> {t} cycles; the law allows "
                                    f"{allowed:.1f} at accel {a:g})")
    # reversals: the last interval before a DIR change and the first after it
    for r0, r1 in zip(runs, runs[1:]):
        if not check_reversals or dirs[r0[-1]] == dirs[r1[0]] or r0[-1] in split_after or len(r0) < 2 or len(r1) < 2:
            continue   # not a turn of one motion: a move ended (DONE, halt) and a new one started
        reversals += 1
        a = params.max_over("accel", since(times[r0[0]], r0[0]), times[r1[-1]])
        v0 = params.max_over("v0", since(times[r0[0]], r0[0]), times[r1[-1]])
        bound = math.sqrt(v0 * v0 + 4 * a)
        for ia, ib in ((r0[-2], r0[-1]), (r1[0], r1[1])):
            t = times[ib] - times[ia]
            v = F_CPU / t if t > 0 else float("inf")
            if v > bound * (1 + LAW_TOL) + quant(t) and len(problems) < limit:
                problems.append(f"{label}: reverses at {times[r0[-1]] / F_CPU:.6f} s at {v:.0f} steps/s, faster "
                                f"than two steps from rest ({bound:.0f} at v0 {v0:g}, accel {a:g})")
                break
    return problems, pairs, worst, reversals


def done_splits(pos_after, done_events):
    """Indices of the edges where a move ended: for each (cycle, position) of a DONE, the last edge
    before that cycle that left the axis at that position."""
    out = set()
    k = 0
    for c, p in sorted(done_events):
        while k < len(pos_after) and pos_after[k][0] < c:
            k += 1
        for i in range(k - 1, -1, -1):
            if pos_after[i][1] == p:
                out.add(i)
                break
            if c - pos_after[i][0] > 5 * F_CPU:   # not within 5 s before: no edge of that move
                break
    return out


def position_seen(pos_after, cycle, p, span_cycles):
    """True if the axis was at p at some moment in [cycle - span, cycle] (the DONE line reaches the
    host up to a transmit buffer after the move ended)."""
    lo = cycle - span_cycles
    # binary search for the last edge at or before lo
    a, b = 0, len(pos_after)
    while a < b:
        m = (a + b) // 2
        if pos_after[m][0] <= lo:
            a = m + 1
        else:
            b = m
    at_lo = pos_after[a - 1][1] if a else 0
    if at_lo == p:
        return True
    i = a
    while i < len(pos_after) and pos_after[i][0] <= cycle:
        if pos_after[i][1] == p:
            return True
        i += 1
    return False


def position_at(pos_after, cycle):
    a, b = 0, len(pos_after)
    while a < b:
        m = (a + b) // 2
        if pos_after[m][0] <= cycle:
            a = m + 1
        else:
            b = m
    return pos_after[a - 1][1] if a else 0


def status_problems(fields, label):
    """`underruns=` of a `?` reply: 0 within the sketch's limits (docs/stepper-engine.md). `late=`
    counts edges fired 2 us after their time, which the documented bound allows (a few near
    max_sps); every edge is checked against its compare match instead (planned_cycles)."""
    out = []
    for k in ("underruns",):
        if k in fields and fields[k] != "0":
            out.append(f"{label}: `?` says {k}={fields[k]} (0 within the sketch's limits)")
    return out
