"""code_size.py - how big the step engine and the stepper consoles are, and how many of our files a
stepper sketch reaches: the code figures of `make bench` (docs/bench.md, "Code size"), against issue
23's targets (engine + consoles at most 2,000 lines, the Leib sketch's include closure at most 20
files).

Lines: every line of the file (`wc -l`); code lines: those left with something on them once the
comments are taken out (/* ... */ and // in C, C++ and the assembly, ; in the assembly).
Include closure of a sketch: the project files (lib/src, firmware/libraries/*/src) reached from its
.ino by #include, each header bringing the source of the same name next to it (.c, .cpp, .S: the
code behind it), whose own #includes are followed too; the sketch itself counts. It is what a
student follows from the sketch by name, not the linker's list (a source no header names, such as
an axis's ring, is not in it)."""
import glob
import os
import re

ENGINE = ("MultiStepEngine*", "StepCut.*")
CONSOLES = ("MotionConsole*",)
# the MotionStepper library's API over the engine (not counted in issue 23's engine + consoles, shown
# beside them: the engine's C paths it calls are the engine's)
API = ("Stepper*", "BackgroundPlanner*")
SOURCE_EXT = (".c", ".cpp", ".S")
INCLUDE = re.compile(r'^\s*#\s*include\s*[<"]([^>"]+)[>"]', re.M)


def code_lines(text, asm=False):
    """lines with code once comments are removed"""
    text = re.sub(r"/\*.*?\*/", lambda m: "\n" * m.group(0).count("\n"), text, flags=re.S)
    n = 0
    for line in text.splitlines():
        line = re.sub(r"//.*", "", line)
        if asm:
            line = re.sub(r";.*", "", line)
        if line.strip():
            n += 1
    return n


def group_files(src_dir, patterns):
    out = set()
    for p in patterns:
        out.update(glob.glob(os.path.join(src_dir, p)))
    return sorted(out)


def line_counts(paths):
    """(lines, code lines) summed over paths"""
    lines = code = 0
    for p in paths:
        with open(p, encoding="utf-8", errors="replace") as f:
            text = f.read()
        lines += text.count("\n")
        code += code_lines(text, asm=p.endswith((".S", ".inc")))
    return lines, code


def project_files(root):
    """basename -> path of every file in lib/src and firmware/libraries/*/src"""
    files = {}
    for p in glob.glob(os.path.join(root, "lib", "src", "*")) + \
            glob.glob(os.path.join(root, "firmware", "libraries", "*", "src", "*")):
        files.setdefault(os.path.basename(p), p)
    return files


def include_closure(start, files):
    """the set of paths reached from `start` (see the module's doc)"""
    seen, todo = set(), [start]
    while todo:
        path = todo.pop()
        if path in seen:
            continue
        seen.add(path)
        with open(path, encoding="utf-8", errors="replace") as f:
            for name in INCLUDE.findall(f.read()):
                hit = files.get(os.path.basename(name))
                if hit:
                    todo.append(hit)
        stem, ext = os.path.splitext(path)
        if ext == ".h":
            todo += [stem + e for e in SOURCE_EXT if os.path.isfile(stem + e)]
    return seen


def section(root, sketches):
    """docs/bench.md's lines: the engine and consoles' size, and each stepper sketch's closure"""
    board = os.path.join(root, "firmware", "libraries", "MotionBoard", "src")
    stepper = os.path.join(root, "firmware", "libraries", "MotionStepper", "src")  # MotionConsole
    engine = group_files(board, ENGINE)
    consoles = sorted(set(group_files(board, CONSOLES)) | set(group_files(stepper, CONSOLES)))
    api = group_files(stepper, API)
    el, ec = line_counts(engine)
    cl, cc = line_counts(consoles)
    al, ac = line_counts(api)
    files = project_files(root)
    out = ["## Code size (tools/bench/code_size.py)", "",
           "Issue 23's targets: step engine + consoles at most 2,000 lines, the Leib sketch's include closure at most "
           "20 files. Lines as `wc -l` counts them; code lines: those with something left once the comments are "
           "removed. Include closure: our files reached from the sketch by #include, each header with the source "
           "of its name (the code behind it); the sketch counts.", "",
           "| part | files | lines | code lines |", "|---|---|---|---|",
           f"| step engine ({', '.join(ENGINE)}) | {len(engine)} | {el:,} | {ec:,} |",
           f"| consoles ({', '.join(CONSOLES)}) | {len(consoles)} | {cl:,} | {cc:,} |",
           f"| engine + consoles | {len(engine) + len(consoles)} | {el + cl:,} | {ec + cc:,} |",
           f"| the MotionStepper API beside them ({', '.join(API)}) | {len(api)} | {al:,} | {ac:,} |", "",
           "| sketch | include closure (files) |", "|---|---|"]
    closures = {}
    for name in sketches:
        ino = os.path.join(root, "firmware", name, name + ".ino")
        if os.path.isfile(ino):
            closures[name] = include_closure(ino, files)
            out.append(f"| {name} | {len(closures[name])} |")
    if "LeibRampStepper" in closures:
        rel = sorted(os.path.relpath(p, root) for p in closures["LeibRampStepper"])
        out += ["", "LeibRampStepper's closure: " + ", ".join(f"`{p}`" for p in rel)]
    return out + [""]
