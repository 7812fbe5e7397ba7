"""coord_profile.py - the reference for coordinated moves (issue 13), shared by the motionsim CLI
tests and the emulator checks: s(t), the fraction of a move of d_max master steps covered at time t,
by the closed form of constant acceleration ("uniform acceleration, constant speed and uniform
deceleration", the lab handout) with v0, vmax and a rounded to floats as the Mega holds them.
Computed here in Python, independently of lib/."""
import math
import struct


def f32(x):
    return struct.unpack("f", struct.pack("f", x))[0]


def profile(d_max, v0, vmax, a):
    """(s_at, tt): s(t) in [0, 1] and the move's duration, seconds"""
    v0, vmax, a = f32(v0), f32(vmax), f32(a)
    s_acc = (vmax * vmax - v0 * v0) / (2 * a)
    if 2 * s_acc >= d_max:
        xa, vp = d_max / 2, math.sqrt(v0 * v0 + a * d_max)
    else:
        xa, vp = s_acc, vmax
    ta = (vp - v0) / a
    tt = 2 * ta + (d_max - 2 * xa) / vp

    def s_at(t):
        if t <= 0:
            return 0.0
        if t >= tt:
            return 1.0
        if t <= ta:
            x = v0 * t + a * t * t / 2
        elif t <= tt - ta:
            x = xa + vp * (t - ta)
        else:
            u = tt - t
            x = d_max - (v0 * u + a * u * u / 2)
        return x / d_max
    return s_at, tt
