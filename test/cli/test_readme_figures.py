"""README's headline step rates must be those of their one home (issue 25): ours from docs/bench.md
(written by `make bench`: "Highest clean rate per sketch: ... ExactRampStepper N steps/s" and
MultiAxisStepper's "Highest clean rate per axis (...): ... independent x+y+z N steps/s"), the peers'
from docs/peers.md's table. Every number in a cell of README's table "| highest clean step rate |"
must equal the figures of its home, in order (a peer's clean rate, then its own limit if it has one);
a figure changed in either place without the other fails here.

bench.md must say what it was made from (a commit and a date), and nothing in README or docs may
point at build/bench/bench.md any more (it is not committed; docs/bench.md is)."""
import glob
import os
import re

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def read(*path):
    with open(os.path.join(ROOT, *path), encoding="utf-8") as f:
        return f.read()


def number(text):
    return int(text.replace(",", ""))


def numbers(cell):
    """the figures in a table cell, in order: '70,000 steps/s (past its own limit, 50,000)' -> [70000, 50000]"""
    return [number(n) for n in re.findall(r"\d[\d,]*\d|\d", cell)]


def table(text, first_header):
    """{first cell: [other cells]} of the markdown table whose header starts with first_header"""
    lines = text.splitlines()
    start = next(i for i, l in enumerate(lines) if re.match(r"^\|\s*" + re.escape(first_header) + r"\s*\|", l))
    rows = {}
    for l in lines[start + 2:]:
        if not l.startswith("|"):
            break
        cells = [c.strip() for c in l.strip().strip("|").split("|")]
        rows[cells[0]] = cells[1:]
    return rows


def bench_figures():
    text = read("docs", "bench.md")
    single = re.search(r"^Highest clean rate per sketch: (.*)$", text, re.M).group(1)
    exact = re.search(r"\bExactRampStepper (?:>= )?([\d,]+) steps/s", single)
    multi_line = re.search(r"^Highest clean rate per axis \(MultiAxisStepper;.*?\): (.*)$", text, re.M).group(1)
    multi = re.search(r"\bindependent x\+y\+z (?:>= )?([\d,]+) steps/s", multi_line)
    assert exact and multi, (single, multi_line)
    return number(exact.group(1)), number(multi.group(1))


def test_bench_md_says_what_it_was_made_from():
    text = read("docs", "bench.md")
    assert re.search(r"Made from commit `[0-9a-f]{7,40}`.*, on \d{4}-\d{2}-\d{2} \d{2}:\d{2} UTC", text), text[:400]


def test_readmes_headline_rates_are_those_of_bench_md_and_peers_md():
    readme = table(read("README.md"), "highest clean step rate")
    peers = table(read("docs", "peers.md"), "library")
    exact, multi = bench_figures()
    ours = next(k for k in readme if k.startswith("ours"))
    assert [numbers(c) for c in readme[ours]] == [[exact], [multi]], readme[ours]
    seen = set()
    for name, cells in peers.items():
        version, clean1, limit1, clean3, limit3 = cells
        row = next((k for k in readme if k.startswith(f"{name} {version}")), None)
        assert row, f"README's table has no row for {name} {version}"
        seen.add(row)
        assert numbers(readme[row][0]) == numbers(clean1) + numbers(limit1), (row, readme[row], cells)
        assert numbers(readme[row][1]) == numbers(clean3) + numbers(limit3), (row, readme[row], cells)
    assert set(readme) == seen | {ours}, "a README row without a home in docs/peers.md"


def test_no_link_to_the_uncommitted_build_bench():
    sources = [f for ext in ("ino", "h", "cpp") for f in glob.glob(os.path.join(ROOT, "firmware", "**", "*." + ext),
                                                                   recursive=True)]
    for path in ["README.md"] + sorted(glob.glob(os.path.join(ROOT, "docs", "*.md"))) + sorted(sources):
        text = read(path)
        assert "build/bench/bench.md" not in text, path


def test_the_smooth_ramps_limit_is_its_highest_clean_rate_in_bench_md():
    """issue 24: STEPPER_MAX_SPS_SMOOTH (MotionStepper's Stepper.h) is the rate `make bench` proves
    clean for the smooth ramp ("Highest clean rate of the smooth ramp" in docs/bench.md), and
    docs/smooth-move.md and README quote that same figure"""
    bench = re.search(r"^Highest clean rate of the smooth ramp \(.*?\): (?:>= )?([\d,]+) steps/s",
                      read("docs", "bench.md"), re.M)
    assert bench, "docs/bench.md has no smooth ramp section (make bench)"
    header = read("firmware", "libraries", "MotionStepper", "src", "Stepper.h")
    limit = re.search(r"#define STEPPER_MAX_SPS_SMOOTH ([0-9.]+)", header)
    quoted = re.search(r"`STEPPER_MAX_SPS_SMOOTH`, \*\*([\d,]+)\*\* steps/s\) is the highest\s+rate `make bench` "
                       r"measures clean", read("docs", "smooth-move.md"))
    readme = re.search(r"Jerk-limited moves \(\[docs/smooth-move.md\]\(docs/smooth-move.md\)\) are clean to\s+"
                       r"\*\*([\d,]+)\*\* steps/s", read("README.md"))
    assert limit and quoted and readme, "Stepper.h's define, docs/smooth-move.md's or README's sentence is missing"
    assert int(float(limit.group(1))) == number(bench.group(1)) == number(quoted.group(1)) == number(readme.group(1)), \
        (limit.group(1), bench.group(1), quoted.group(1), readme.group(1))


def test_readmes_rate_of_one_stepper_through_the_library_is_bench_mds():
    """README's figure for one Stepper of the MotionStepper library (its limit lifted) is the "Highest
    clean rate of one Stepper" that `make bench` wrote into docs/bench.md"""
    bench = re.search(r"^Highest clean rate of one Stepper \(.*?\): (?:>= )?([\d,]+) steps/s",
                      read("docs", "bench.md"), re.M)
    assert bench, "docs/bench.md has no section of one Stepper through the library (make bench)"
    readme = re.search(r"Through the MotionStepper library \(one\s+`Stepper`.*?\) it is clean to\s+"
                       r"\*\*([\d,]+)\*\* steps/s", read("README.md"), re.S)
    assert readme, "README's sentence on one Stepper of the library is missing"
    assert number(readme.group(1)) == number(bench.group(1)), (readme.group(1), bench.group(1))
