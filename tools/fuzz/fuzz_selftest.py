"""tools/fuzz/fuzz_selftest.py - the fuzz oracles must be able to fail: synthetic traces, good and
bad, through the same functions the campaign uses (fuzz_oracles.py, fuzz_conversation.check).

Good traces come from the closed form of constant acceleration, t_n = sqrt(2 n / a) (rounded to
whole ticks, as the documented planner does within 1 tick), so they are independent of the
firmware; each bad trace carries one of issue 22's faults: a speed jump at a replan (new speed =
old x new accel / old accel), a speed above vmax, a drop to ~95 steps/s in one step, a reversal
at speed, an edge late after its compare match; and conversations in which a damaged flood line
was executed (`OK 6629 -7799999`), lines went unaccounted, or an overrun came only after the
host's next line. run() returns (problems, cases): a problem is an oracle that passed a bad trace
or failed a good one.
"""
import math

import emulog
import fuzz_conversation as fc
import fuzz_oracles as fo

F = fo.F_CPU


def ramp(a, n, v0=0.0, t0=0.0):
    """edge cycles of n steps of constant acceleration a from v0, starting at t0 (s)"""
    out = []
    for k in range(1, n + 1):
        t = (math.sqrt(v0 * v0 + 2 * a * k) - v0) / a
        out.append(int(round((t0 + t) * F)))
    return out


def cruise_then(edges, v, n):
    out = list(edges)
    for _ in range(n):
        out.append(out[-1] + int(round(F / v)))
    return out


def law(times, a, vmax, v0=0.0, dirs=None, splits=(), events=(), plans=(), pins=None, positions=None):
    p = fo.Params({"accel": a, "vmax": vmax, "v0": v0}, events)
    return fo.speed_law(times, dirs or [1] * len(times), set(splits), p, 1, True, "t", plans=plans, pins=pins,
                        positions=positions)


def displaced(edges, at, cycles):
    """edges with edges[at], edges[at + 1], ... later by cycles[0], cycles[1], ... (late edges)"""
    out = list(edges)
    for i, d in enumerate(cycles):
        out[at + i] += d
    return out


def run():
    problems, cases = [], 0

    def expect(name, probs, fail):
        nonlocal cases
        cases += 1
        if bool(probs) != fail:
            problems.append(f"{name}: the oracle {'passed' if fail else 'failed'} it"
                            + (f" ({probs[0]})" if probs else ""))

    # 1. good: accelerate at 50,000 steps/s^2 to 5,000 steps/s, cruise, then a replan at a new
    # accel that keeps the speed (decelerate at 200,000 from 5,000)
    up = ramp(50000, 250)                       # v(250) = sqrt(2 a 250) = 5000
    good = cruise_then(up, 5000, 300)
    t_end = good[-1] / F
    down = [int(round((t_end + (5000 - math.sqrt(max(0.0, 5000 ** 2 - 2 * 200000 * k))) / 200000) * F))
            for k in range(1, 62)]
    good_replan = good + down
    ev = [(good[-50], "accel", 200000.0)]
    expect("constant acceleration, cruise, faster deceleration after set accel",
           law(good_replan, 50000, 5000, events=ev)[0], False)
    # 1b. one late edge (armed past its time, fired 2 us later: 59 cycles late) between edges on
    # time passes; a speed change that moves every later edge still fails
    late_one = list(cruise_then(up, 5000, 300))
    late_one[400] += 59
    expect("one late edge, 59 cycles after its plan, in a cruise at 5,000 steps/s",
           law(late_one, 50000, 5000)[0], False)
    late_run = list(cruise_then(up, 5000, 300))
    for k in range(400, len(late_run)):
        late_run[k] += 59 * (k - 399)           # every later interval 59 cycles longer: a speed drop
    expect("a speed drop that moves every later edge", law(late_run, 50000, 5000)[0], True)
    # 1b'. runs of late edges: the interrupt that fired a late edge ends after the next edge's time
    # too, which then fires late as well, less so (make fuzz seed 23: 80 and 67 cycles at 70,000
    # steps/s; 151, 123, 95 and 67 at 100,000); every later edge is on its plan. The pin: 60 to 143
    # cycles after each late compare match, within 260 of the plan; a pin 270 cycles after its plan,
    # a run displaced past the bound, a run after which the edges stay displaced (a lost interval)
    # and a run longer than LATE_RUN_MAX fail.
    up7 = cruise_then(ramp(1_000_000, 2450), 70000, 600)     # 70,000 steps/s after 2,450 steps
    pair = displaced(up7, 2800, [80, 67])
    expect("two consecutive late edges (80, 67 cycles) in a cruise at 70,000 steps/s",
           law(pair, 1e6, 70000, pins=displaced(pair, 2800, [143, 60]))[0], False)
    up10 = ramp(1_000_000, 5000)                             # accelerating, 100,000 steps/s at the end
    four = displaced(up10, 4500, [151, 123, 95, 67])
    pins4 = [c + 4 for c in four]
    expect("four consecutive late edges (151, 123, 95, 67 cycles) accelerating near 100,000 steps/s",
           law(four, 1e6, 100000, pins=displaced(pins4, 4500, [56] * 4))[0], False)
    expect("a run of late edges, one on the pin 270 cycles after its plan",
           law(four, 1e6, 100000, pins=displaced(pins4, 4500, [115, 56, 56, 56]))[0], True)
    # A table ramp on the lab's 2 MHz tick (8 cycles): SCurveStepper repeats each period 4 times, so
    # its intervals change in stairs (make test's fuzz seed 1: 14,816 cycles x 4, then 14,448 x 4, ...
    # at about 1,100 steps/s); a quadratic fits a stair's edges within the tolerance, but no edge is
    # late: with every pin 4 cycles after its match the oracle must find nothing (the oracle before
    # this case saw a run of late edges there, one 262 cycles after its plan).
    stairs, c = [0], 0
    for period in range(15200, 13000, -368):
        for _ in range(4):
            c += period
            stairs.append(c)
    p8 = fo.Params({"accel": 1e9, "vmax": 5000, "v0": 0.0}, ())
    expect("a table ramp's stairs of 4 equal intervals on 8-cycle ticks, every pin 4 cycles after its match",
           fo.speed_law(stairs, [1] * len(stairs), set(), p8, 8, False, "t", pins=[x + 4 for x in stairs])[0], False)
    expect("two consecutive edges 300 and 272 cycles after their plans (past the bound)",
           law(displaced(up10, 4500, [300, 272]), 1e6, 100000)[0], True)
    lost = displaced(up10, 4500, [151, 123] + [95] * 400)
    expect("two late edges, then every later edge 95 cycles late (a speed change)",
           law(lost, 1e6, 100000)[0], True)
    nine = displaced(up10, 4500, [250 - 25 * i for i in range(fo.LATE_RUN_MAX + 1)])
    expect(f"a run of {fo.LATE_RUN_MAX + 1} late edges (more than LATE_RUN_MAX)", law(nine, 1e6, 100000)[0], True)
    # 1c. a reversal planned with the target that caused it: decelerate to rest and accelerate back
    # at 500,000 steps/s^2; `set accel 50000` arrives after that plan, before the turn ("from the
    # next plan"): the run after the turn keeps 500,000 and passes; the same `set` before the plan
    # makes it too fast for the accel in force and fails
    fast = ramp(500000, 120)
    t_top = fast[-1] / F
    v_top = math.sqrt(2 * 500000 * 120)
    back = [int(round((t_top + (v_top - math.sqrt(max(0.0, v_top ** 2 - 2 * 500000 * k))) / 500000) * F))
            for k in range(1, 121)]
    t_rest = back[-1] / F + 0.0015
    again = ramp(500000, 60, t0=t_rest)
    turn = fast + back + again
    dirs = [1] * (len(fast) + len(back)) + [-1] * len(again)
    plan_at, set_at = fast[10], back[60]
    expect("a reversal planned before a lower `set accel` keeps the accel of its plan",
           law(turn, 500000, 1e6, dirs=dirs, events=[(set_at, "accel", 50000.0)], plans=[0, plan_at])[0], False)
    expect("the same reversal with the lower accel set before its plan",
           law(turn, 500000, 1e6, dirs=dirs, events=[(plan_at - 1, "accel", 50000.0)], plans=[0, plan_at])[0], True)
    # 1c'. a flood's lower `set accel` arrived before the plan of the turn but answered after the turn
    # (the sketch read it at some moment in between): the old accel may still be in force; the same
    # `set` answered before the plan is in force for it and fails
    expect("a lower `set accel` arrived before the turn's plan and answered after the turn",
           law(turn, 500000, 1e6, dirs=dirs, events=[(plan_at - 1, again[-1] + F, "accel", 50000.0)],
               plans=[0, plan_at])[0], False)
    expect("a lower `set accel` arrived and answered before the turn's plan",
           law(turn, 500000, 1e6, dirs=dirs, events=[(plan_at - 2, plan_at - 1, "accel", 50000.0)],
               plans=[0, plan_at])[0], True)
    # 1d. in a flood a later target's line has arrived before the turn but is answered after it (the
    # sketch may read it after the turn): the turn's plan is the earlier one, answered before it
    expect("a line arrived before the turn and answered after it does not replace the turn's plan",
           law(turn, 500000, 1e6, dirs=dirs, events=[(set_at, "accel", 50000.0)],
               plans=[0, (plan_at, plan_at), (set_at + 5, again[-1] + F)])[0], False)
    # 1e. the queue's lead: a later target answered before the turn, whose plan starts (its OK's
    # `from`) 30 steps into the run after the turn (a position the axis passed on its way out, before
    # that answer), does not replace the turn's plan at the turn (make fuzz seed 8, LeibRampStepper);
    # the same target starting at a position the axis reached after its answer and before the turn
    # (235, on the deceleration) is the turn's plan, and its lower accel fails
    pos, q = [], 0
    for d in dirs:
        q += d
        pos.append(q)
    later = (back[95], back[100], pos[len(fast) + len(back) + 29])   # answered past that position
    expect("a later target whose plan starts ahead in the run after the turn does not replace the turn's plan",
           law(turn, 500000, 1e6, dirs=dirs, events=[(set_at, "accel", 50000.0)], plans=[0, plan_at, later],
               positions=pos)[0], False)
    expect("a later target whose plan starts before the turn is the turn's plan (its lower accel fails)",
           law(turn, 500000, 1e6, dirs=dirs, events=[(set_at, "accel", 50000.0)],
               plans=[0, plan_at, later[:2] + (235,)], positions=pos)[0], True)
    # 2. issue 22 item 1: after the replan the interval drops from 200 us to 50 us (4x vmax)
    jump = cruise_then(good, 20000, 50)
    expect("a 4x speed jump at a replan (5,000 -> 20,000 steps/s)",
           law(jump, 50000, 20000, events=[(good[-50], "accel", 200000.0)])[0], True)
    # 3. set accel 1000: the speed falls from 5,000 to ~95 steps/s in one step
    drop = cruise_then(good, 95, 3)
    expect("a drop from 5,000 to 95 steps/s in one step", law(drop, 50000, 5000)[0], True)
    # 4. above vmax: the good ramp against a vmax of 4,000
    expect("5,000 steps/s with vmax 4,000", law(good, 50000, 4000)[0], True)
    # 5. a 1 % faster acceleration than allowed (the law's tolerance is 0.2 % + 2 ticks)
    expect("accelerating 1 % above accel (many steps)", law(ramp(50500, 2000), 50000, 1e9)[0], True)
    # 6. quantisation: each edge within 1 tick of the plan passes
    exact = [(math.sqrt(2 * 50000 * k)) / 50000 * F for k in range(1, 2001)]
    jitter = [int(round(c)) + (1 if i % 3 == 0 else -1 if i % 3 == 1 else 0) for i, c in enumerate(exact)]
    expect("the exact ramp with +-1 tick on round(F t_n)", law(jitter, 50000, 1e9)[0], False)
    jitter3 = [int(round(c)) + (3 if i % 2 else -3) for i, c in enumerate(exact)]
    expect("the exact ramp with +-3 ticks on its edges", law(jitter3, 50000, 1e9)[0], True)
    # 7. reversal: at speed (no deceleration) vs from rest
    back = [good[-1] + (good[-1] - x) for x in reversed(good[:-1])]
    dirs = [1] * len(good) + [-1] * len(back)
    expect("a reversal at 5,000 steps/s", law(good + back, 50000, 5000, dirs=dirs)[0], True)
    rest = ramp(50000, 100)
    mirror = [2 * rest[-1] - x for x in reversed(rest[:-1])]   # decelerate to rest at the last edge
    turn = rest + mirror
    ret = [turn[-1] + x for x in ramp(50000, 100, t0=0)]
    expect("a reversal from rest", law(turn + ret, 50000, 1e9, dirs=[1] * len(turn) + [-1] * len(ret))[0], False)
    # 8. a move that ended (DONE) and a new one from v0: not a jump
    v0ramp = ramp(50000, 100, v0=3000)
    nxt = [v0ramp[-1] + 160000 + x for x in ramp(50000, 100, v0=3000)]
    expect("a new move from v0 after a DONE", law(v0ramp + nxt, 50000, 1e9, v0=3000, splits=[99])[0], False)
    # 9. edges on the pin vs the compare matches
    matches = list(range(1000, 100000, 1000))
    expect("edges 100 cycles after their matches", fo.planned_cycles([m + 100 for m in matches], matches, matches)[1],
           False)
    expect("an edge 300 cycles after its match", fo.planned_cycles([m + (300 if m == 5000 else 100) for m in matches],
                                                                   matches, matches)[1], True)

    # 10. conversations: a flood (the pattern) on a servo sketch, the log as motionemu writes it
    def conv(replies, flood_values, after_query="setpoint=0 position=0 error=0 duty=0 kp=0.02"):
        items = [("line", b"?", b"\r\n", None), ("line", b"100000", b"\r\n", 1)]
        for a_, b_ in flood_values:
            items += [("line", b"?", b"\r\n", 1), ("line", a_.encode(), b"\r\n", 1),
                      ("line", b"?", b"\r\n", 1), ("line", b_.encode(), b"\r\n", 1)]
        items += [("settle", 1000), ("line", b"?", b"\r\n", None)]
        text = ["mark 100 fuzz", "txraw 200 ?\\x0d\\x0a", "rx 300 setpoint=0 position=0 error=0 duty=0 kp=0.02"]
        c = 1000
        for it in items[1:-2]:
            text.append(f"txraw {c} {it[1].decode()}\\x0d\\x0a")
        for r in replies:
            c += 100
            text.append(f"rx {c} {r}")
        text += [f"txraw {c + 5000} ?\\x0d\\x0a"] + ([f"rx {c + 6000} {after_query}"] if after_query else [])
        text += [f"mark {c + 9000} fuzz-end", f"end {c + 9100} done"]
        log = emulog.EmuLog.parse("\n".join(text) + "\n")
        return fc.check(log, "servo", items)

    vals = [("-7777", "9999")] * 3
    good_r = ["OK setpoint=100000", "setpoint=100000 position=0 error=0 duty=0 kp=0.02", "OK setpoint=-7777",
              "ERR input overrun: 10 lines lost"]
    expect("a flood answered or counted exactly (3 replies + 10 lost of 13 lines)",
           conv(good_r, vals, "setpoint=-7777 position=0 error=0 duty=0 kp=0.02").problems, False)
    expect("a flood line that lost bytes executed (OK setpoint=-77799)",
           conv(good_r[:2] + ["OK setpoint=-77799", "ERR input overrun: 10 lines lost"], vals).problems, True)
    expect("a flood with one line neither answered nor counted",
           conv(good_r[:3] + ["ERR input overrun: 9 lines lost"], vals).problems, True)
    expect("the overrun reported only after the host's next line",
           conv(good_r[:3], vals, "ERR input overrun: 10 lines lost").problems, True)
    expect("the `?` after a flood reports a setpoint never sent",
           conv(good_r, vals, "setpoint=77 position=0 error=0 duty=0 kp=0.02").problems, True)
    expect("a `?` with underruns=1", fo.status_problems({"underruns": "1", "late": "0"}, "t"), True)
    expect("a `?` with late=0 underruns=0", fo.status_problems({"underruns": "0", "late": "0"}, "t"), False)
    expect("a `?` with late=3 underruns=0 (edges within the bound)",
           fo.status_problems({"underruns": "0", "late": "3"}, "t"), False)
    return problems, cases


if __name__ == "__main__":
    import sys
    p, n = run()
    for x in p:
        print(x)
    print(f"{n} cases, {len(p)} failures")
    sys.exit(1 if p else 0)
