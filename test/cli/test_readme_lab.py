"""README's "Do the lab" block, as a student runs it after `make setup` on a fresh clone: it starts
by building what it uses (`make sim`), writes only into `lab/` (which git ignores), and its
commands run; step 2 shows the handout's checkpoint intervals 218.218, 188.528, 157.245 (the lab
handout's values, written here), step 3 and 5 make the plot and the workbook.

The block runs here with `lab` pointing at a temporary folder; the commands that need a board or
the emulator (`make emulate`, `make upload`, `make monitor`) are left out (test/cli/test_emulate.py
covers `make emulate`)."""
import os
import re
import subprocess

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def lab_block():
    text = open(os.path.join(ROOT, "README.md"), encoding="utf-8").read()
    section = text[text.index("## Do the lab"):]
    m = re.search(r"```sh\n(.*?)```", section, re.S)
    assert m, "no sh block in README's Do the lab"
    # commands without their comments
    return [line.split("  #", 1)[0].split(" # ", 1)[0].rstrip() for line in m.group(1).splitlines()
            if line.strip() and not line.lstrip().startswith("#")]


def test_the_block_builds_motionsim_before_it_uses_it():
    cmds = lab_block()
    first_use = next(i for i, c in enumerate(cmds) if "build/motionsim" in c)
    assert any(re.match(r"^make sim\b", c) for c in cmds[:first_use]), cmds


def test_the_block_writes_only_into_lab_which_git_ignores():
    cmds = lab_block()
    outputs = re.findall(r"(?:>|-o)\s+(\S+)", " ".join(cmds))
    assert outputs and all(o.startswith("lab/") for o in outputs), outputs
    r = subprocess.run(["git", "check-ignore", "-q", "lab/table.csv"], cwd=ROOT)
    assert r.returncode == 0, "lab/ is not ignored by git"


def test_the_block_runs_and_shows_the_handouts_checkpoint(tmp_path):
    lab = tmp_path / "lab"
    script = []
    for c in lab_block():
        if re.match(r"^make (emulate|upload|monitor)\b", c):
            continue
        script.append(re.sub(r"(?<![\w/])lab(?=/|\s|$)", str(lab), c))
    r = subprocess.run(["bash", "-euo", "pipefail", "-c", "\n".join(script)], cwd=ROOT, capture_output=True,
                       text=True, timeout=300)
    assert r.returncode == 0, "\n".join(script) + "\n" + r.stdout + r.stderr
    for checkpoint in ("218.21788", "188.52837", "157.24506"):
        assert checkpoint in r.stdout, r.stdout
    assert (lab / "ramps.png").stat().st_size > 1000
    assert (lab / "lab.xlsx").stat().st_size > 1000
