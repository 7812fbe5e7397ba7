"""tools/fuzz/motionsim_fuzz.py - fuzz motionsim's command line and input files under ASan+UBSan.

A seeded random.Random makes invocations of build/motionsim-san (motionsim built with
AddressSanitizer and UndefinedBehaviorSanitizer, -fno-sanitize-recover: the first finding aborts):
every subcommand with its options given good, bad and edge values (hexadecimal, nan, inf,
overflow, underflow, negative, empty, very long), options twice, without a value, unknown ones,
stray positional words, `--opt=value`, `-o` into a missing folder or /dev/full; and input files
written for the run: filter --input csv: tables and pid-replay vectors (copies of
test/data/pid_v1 with their JSON set-up), mutated (bytes flipped, dropped, doubled, NUL bytes,
lines dropped or repeated, numbers replaced).

The properties (README, motionsim; docs/motionsim.md):
  - no crash (a signal), no sanitizer report, no hang (RUN_TIMEOUT_S);
  - the exit status is 0, 1 or 2;
  - exit 2 prints exactly one line on stderr, "motionsim ...: <reason>"; exit 1 too.
"""
import os
import random
import shlex
import subprocess
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
PID_DATA = os.path.join(ROOT, "test", "data", "pid_v1")
RUN_TIMEOUT_S = 30

EDGE = ["0", "-0", "1", "-1", "+1", "2", "0.5", "-0.5", "1e3", "1e-3", "0x10", "nan", "inf", "-inf", "1e400", "-1e400",
        "1e-320", "1e-46", "3.5e38", "1e38", "", " ", "abc", "12abc", "1..2", "--1", "2147483647", "2147483648",
        "-2147483648", "-2147483649", "4294967295", "4294967296", "65535", "65536", "1000000", "1000001", "3600",
        "3601", "0.001", "0.0001", "1e-9", "9" * 40, "0." + "0" * 30 + "1", "1,5", "1 2", "\u00e9", "-", "--", "=",
         "1" * 400]

RAMP_ALGOS = ["simplistic", "leib", "exact", "sigmoid", "LEIB", "", "s"]


def num(rng, lo, hi, ints=False):
    """a plausible value (small enough that the run ends quickly) or an edge case"""
    if rng.random() < 0.35:
        return rng.choice(EDGE)
    if ints:
        return str(rng.randint(int(lo), int(hi)))
    return f"{rng.uniform(lo, hi):.{rng.randint(0, 6)}g}"


# option -> value maker; None: a flag. Ranges keep the work of a valid run small (a few thousand rows).
def ramp_opts(rng):
    return {
        "--algo": lambda: rng.choice(RAMP_ALGOS), "--from": lambda: num(rng, -300, 300, True),
        "--to": lambda: num(rng, -300, 300, True), "--v0": lambda: num(rng, 0, 100),
        "--vmax": lambda: num(rng, 1, 5000), "--accel": lambda: num(rng, 1, 100000),
        "--tick-hz": lambda: num(rng, 1000, 16000000), "--len": lambda: num(rng, 2, 2000, True),
        "--fmin": lambda: num(rng, 10, 1000), "--fmax": lambda: num(rng, 1000, 64000),
        "--flex": lambda: num(rng, 0.1, 20), "--timer-hz": lambda: num(rng, 1e5, 1e7),
        "--hold": lambda: num(rng, 1, 10, True), "--integer-ticks": None, "--compare": None, "--queue": None,
        "--commands": lambda: rng.choice(["-", "@tmp", "/nonexistent/dir/c.csv"]),
        "--stop-at": lambda: num(rng, 0, 200, True),
        "--retarget-at": lambda: ",".join(f"{num(rng, 0, 200, True)}:{num(rng, -300, 300, True)}"
                                          for _ in range(rng.randint(1, 3))) if rng.random() < 0.8 else rng.choice(EDGE),
    }


def filter_opts(rng):
    return {
        "--kind": lambda: rng.choice(["ma", "ma2", "exp", "MA", "", "ma3"]), "--tau": lambda: num(rng, 0.01, 20),
        "--tau2": lambda: num(rng, 0.01, 10), "--ts": lambda: rng.choice(["0.01", "0.02", "0.1", "0.005"]) if rng.random() < 0.6 else num(rng, 0.001, 1),
        "--input": lambda: rng.choice([f"step:{num(rng, -1, 6)}", f"step:{num(rng, -1, 6)}:{num(rng, 0, 20)}",
                                       f"square:{num(rng, 0, 5)}:{num(rng, 0.02, 10)}", "csv:@csv", "csv:@csv",
                                       "csv:/nonexistent.csv", "csv:", "step", "square:1", "sine:1", "step:5:1:2",
                                       rng.choice(EDGE)]),
        "--duration": lambda: num(rng, 0, 30), "--quantum": lambda: rng.choice(["0.001", "0.01", "1e-6"]) if rng.random() < 0.6 else num(rng, 1e-4, 1),
        "--stream": None,
    }


def servo_opts(rng):
    return {
        "--ctrl": lambda: rng.choice(["p", "pid", "PID", "", "pi"]), "--kp": lambda: num(rng, 0, 2),
        "--ki": lambda: num(rng, 0, 2), "--kd": lambda: num(rng, 0, 1),
        "--setpoint": lambda: num(rng, -5000, 5000, True), "--duration": lambda: num(rng, 0.01, 5),
        "--period-ms": lambda: num(rng, 1, 1000, True), "--latency-us": lambda: num(rng, 0, 20000, True),
        "--precision": lambda: rng.choice(["float", "double", "half", ""]), "--metrics": None,
    }


def pid_opts(rng):
    return {"--float": None}


OPTS = {"ramp": ramp_opts, "filter": filter_opts, "servo": servo_opts, "pid-replay": pid_opts}


# ---- input files -------------------------------------------------------------------------------

def mutate_bytes(rng, data):
    b = bytearray(data)
    for _ in range(rng.randint(1, 6)):
        op = rng.random()
        pos = rng.randint(0, len(b))
        if op < 0.2 and b:
            del b[min(pos, len(b) - 1):min(pos, len(b) - 1) + rng.randint(1, 20)]
        elif op < 0.4 and b:
            i = min(pos, len(b) - 1)
            b[i] ^= 1 << rng.randint(0, 7)
        elif op < 0.55:
            b[pos:pos] = rng.choice([b"\0", b",", b"\n", b"\r\n", b"\"", b"-", b"e", b"1e400", b"nan", b" ",
                                      b"\xff\xfe", b"{", b"}", b"[", b"]", b":", b"null", b"true"])
        elif op < 0.7 and b:
            i = min(pos, len(b) - 1)
            b[i:i] = b[i:i + rng.randint(1, 40)]
        elif op < 0.85:
            lines = bytes(b).split(b"\n")
            if len(lines) > 1:
                k = rng.randrange(len(lines))
                if rng.random() < 0.5:
                    del lines[k]
                else:
                    lines.insert(k, lines[k])
                b = bytearray(b"\n".join(lines))
        else:
            b[pos:pos] = str(rng.choice(EDGE)).encode("utf-8")
    return bytes(b)


def make_csv(rng):
    r = rng.random()
    n = rng.randint(0, 300)
    if r < 0.3:
        text = "u\n" + "".join(f"{rng.uniform(0, 5):.3f}\n" for _ in range(n))
    elif r < 0.6:
        text = "t_ms,u,y\n" + "".join(f"{10 * k},{rng.uniform(0, 5):.3f},{rng.uniform(0, 5):.6f}\n" for k in range(n))
    elif r < 0.8:
        text = "k,t_s,u,y\n" + "".join(f"{k},{k * 0.01:.2f},{rng.uniform(0, 5):.3f},0\n" for k in range(n))
    else:
        cols = [rng.choice(["u", "t_ms", "k", "y", "x", "", "u "]) for _ in range(rng.randint(1, 4))]
        text = ",".join(cols) + "\n" + "".join(",".join(rng.choice(EDGE[:20]) for _ in cols) + "\n" for _ in range(n))
    data = text.encode()
    return mutate_bytes(rng, data) if rng.random() < 0.6 else data


def pid_vector_files(rng, tmp, idx):
    """a vector CSV and its JSON set-up, copied from test/data/pid_v1, maybe mutated; returns the CSV's path"""
    names = sorted(f[:-5] for f in os.listdir(PID_DATA) if f.endswith(".json"))
    name = rng.choice(names)
    float32 = rng.random() < 0.3 and os.path.exists(os.path.join(PID_DATA, "float32", name + ".csv"))
    d = os.path.join(tmp, f"v{idx}")
    os.makedirs(os.path.join(d, "float32"), exist_ok=True)
    with open(os.path.join(PID_DATA, name + ".json"), "rb") as f:
        js = f.read()
    with open(os.path.join(PID_DATA, "float32" if float32 else "", name + ".csv"), "rb") as f:
        csv = f.read()
    r = rng.random()
    if r < 0.45:
        js = mutate_bytes(rng, js)
    elif r < 0.9:
        csv = mutate_bytes(rng, csv)
    with open(os.path.join(d, name + ".json"), "wb") as f:
        f.write(js)
    path = os.path.join(d, "float32" if float32 else "", name + ".csv")
    with open(path, "wb") as f:
        f.write(csv)
    return path


# ---- invocations -------------------------------------------------------------------------------

def make_invocation(rng, tmp, idx):
    """argv after the program name; the files it needs are written into tmp"""
    r = rng.random()
    if r < 0.03:
        return rng.choice([[], ["--help"], ["-h"], ["help"], ["rampp"], [""], ["--version"], ["ramp", "--help"],
                           ["filter", "-h"], ["servo", "--help", "--kp", "1"]])
    cmd = rng.choice(["ramp", "ramp", "filter", "servo", "pid-replay"])
    opts = OPTS[cmd](rng)
    argv = [cmd]
    names = list(opts)
    for _ in range(rng.randint(0, 5)):
        name = rng.choice(names)
        make = opts[name]
        val = make() if make else None
        if val is not None and "@tmp" in val:
            val = val.replace("@tmp", os.path.join(tmp, f"c{idx}.csv"))
        if val is not None and "@csv" in val:
            p = os.path.join(tmp, f"in{idx}.csv")
            with open(p, "wb") as f:
                f.write(make_csv(rng))
            val = val.replace("@csv", p)
        q = rng.random()
        if q < 0.04:
            argv.append(name)          # value missing (or a flag)
        elif q < 0.08 and val is not None:
            argv.append(f"{name}={val}")
        elif q < 0.10:
            argv.append(name[:-1] if len(name) > 3 else name + "x")   # a misspelt option
        else:
            argv.append(name)
            if val is not None:
                argv.append(val)
    if cmd == "pid-replay" and rng.random() < 0.9:
        argv.append(pid_vector_files(rng, tmp, idx))
    if cmd == "ramp" and "--compare" in argv and "--algo" in argv and rng.random() < 0.7:
        argv.remove("--compare")   # mostly valid combinations
    q = rng.random()
    if q < 0.06:
        argv.insert(rng.randint(1, len(argv)), rng.choice(EDGE))   # a stray positional word
    elif q < 0.10:
        argv += ["-o", rng.choice(["/dev/full", "/nonexistent/dir/out.csv", os.path.join(tmp, f"o{idx}.csv"), ""])]
    elif q < 0.14:
        argv.append(rng.choice(["-x", "--", "-", "--unknown", "-oo"]))
    elif q < 0.2 and len(argv) > 2:
        k = rng.randrange(1, len(argv))
        argv.insert(k, argv[k])   # something twice
    return argv


def sanitizer_report(stderr):
    for key in ("AddressSanitizer", "LeakSanitizer", "UndefinedBehaviorSanitizer", "runtime error:"):
        if key in stderr:
            return key
    return None


def check_run(argv, rc, stdout, stderr, timed_out):
    """problems with one run (empty: fine)"""
    problems = []
    if timed_out:
        return [f"no exit within {RUN_TIMEOUT_S} s (hang)"]
    san = sanitizer_report(stderr)
    if san:
        lines = [l for l in stderr.splitlines() if "runtime error" in l or "ERROR:" in l or "SUMMARY" in l]
        problems.append(f"{san}: {' | '.join(lines[:3]) or stderr[:300]}")
    if rc < 0:
        problems.append(f"killed by signal {-rc}")
    elif rc not in (0, 1, 2):
        problems.append(f"exit status {rc} (want 0, 1 or 2)")
    if rc in (1, 2) and not san:
        err = stderr.splitlines()
        if len(err) != 1 or not err[0].strip():
            problems.append(f"exit {rc} with {len(err)} lines on stderr (want one): {stderr[:300]!r}")
        elif not err[0].startswith("motionsim"):
            problems.append(f"exit {rc}: the error line does not name motionsim: {err[0][:200]!r}")
    return problems


def run_one(motionsim, argv, tmp):
    env = dict(os.environ, ASAN_OPTIONS="detect_leaks=1:abort_on_error=0:exitcode=99",
               UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1:exitcode=98")
    try:
        p = subprocess.run([motionsim] + argv, stdout=subprocess.PIPE, stderr=subprocess.PIPE, cwd=tmp, env=env,
                           timeout=RUN_TIMEOUT_S)
        return p.returncode, p.stdout, p.stderr.decode("utf-8", "replace"), False
    except subprocess.TimeoutExpired as e:
        return None, e.stdout or b"", (e.stderr or b"").decode("utf-8", "replace"), True


class Outcome:
    def __init__(self):
        self.runs = 0
        self.exits = {}
        self.failures = []   # (argv, problems, stderr)


def fuzz(motionsim, seed, n, keep_dir=None):
    """n invocations of seed `seed`; failing inputs are copied to keep_dir (if given)"""
    rng = random.Random(f"{seed}:motionsim")
    o = Outcome()
    with tempfile.TemporaryDirectory(prefix="motionsim-fuzz-") as tmp:
        for i in range(n):
            argv = make_invocation(rng, tmp, i)
            rc, out, err, timed_out = run_one(motionsim, argv, tmp)
            o.runs += 1
            o.exits[rc] = o.exits.get(rc, 0) + 1
            problems = check_run(argv, rc, out, err, timed_out)
            if problems:
                o.failures.append((argv, problems, err))
                if keep_dir:
                    save_failure(keep_dir, seed, i, argv, tmp)
    return o


def save_failure(keep_dir, seed, i, argv, tmp):
    """the failing invocation as a shell line, with the files it read"""
    d = os.path.join(keep_dir, f"motionsim-{seed}-{i}")
    os.makedirs(d, exist_ok=True)
    args = []
    for a in argv:
        for prefix in ("", "csv:"):
            p = a[len(prefix):] if a.startswith(prefix) else None
            if p and p.startswith(tmp) and os.path.isfile(p):
                rel = os.path.relpath(p, tmp)
                dst = os.path.join(d, rel)
                os.makedirs(os.path.dirname(dst), exist_ok=True)
                with open(p, "rb") as f, open(dst, "wb") as g:
                    g.write(f.read())
                j = os.path.join(os.path.dirname(p), os.path.basename(p)[:-4] + ".json")
                if os.path.isfile(j):
                    with open(j, "rb") as f, open(os.path.join(os.path.dirname(dst), os.path.basename(j)), "wb") as g:
                        g.write(f.read())
                parent = os.path.join(os.path.dirname(os.path.dirname(p)))
                for jj in os.listdir(parent) if os.path.basename(os.path.dirname(p)) == "float32" else []:
                    if jj.endswith(".json"):
                        with open(os.path.join(parent, jj), "rb") as f, \
                                open(os.path.join(os.path.dirname(os.path.dirname(dst)), jj), "wb") as g:
                            g.write(f.read())
                a = prefix + rel
                break
        args.append(a)
    with open(os.path.join(d, "command.sh"), "w") as f:
        f.write("# run in this folder\nmotionsim " + " ".join(shlex.quote(a) for a in args) + "\n")
