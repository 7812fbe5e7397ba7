"""tools/bench/code_size.py, the code figures of `make bench` (issue 23's line and include-closure
targets), on small trees whose answers are counted by hand here."""
import os
import sys

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "tools", "bench"))
import code_size  # noqa: E402


def write(path, text):
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(text)
    return str(path)


def test_code_lines_leave_out_comments_and_blank_lines():
    c = "/* a comment\n   of two lines */\nint a; // trailing\n\n// alone\nint b; /* in */ int c;\n"
    assert code_size.code_lines(c) == 2
    asm = "; a comment\n  ldi r24, 1 ; load\n/* C-style\n too */\n  ret\n"
    assert code_size.code_lines(asm, asm=True) == 2
    assert code_size.code_lines(asm) == 3  # without asm, ';' lines count


def test_include_closure_follows_headers_and_their_sources(tmp_path):
    lib = tmp_path / "lib" / "src"
    board = tmp_path / "firmware" / "libraries" / "Board" / "src"
    ino = write(tmp_path / "firmware" / "S" / "S.ino", '#include <Console.h>\n#include <Arduino.h>\n')
    write(board / "Console.h", '#include "planner.h"\n')
    write(board / "Console.cpp", '#include "Console.h"\n#include <queue.h>\n')
    write(lib / "planner.h", "/* no #include here */\n")
    write(lib / "planner.c", '#include "planner.h"\n')
    write(lib / "queue.h", "")
    write(lib / "unused.h", "")
    write(lib / "unused.c", '#include "unused.h"\n')
    got = code_size.include_closure(ino, code_size.project_files(str(tmp_path)))
    names = sorted(os.path.basename(p) for p in got)
    # the sketch, Console.h + .cpp, planner.h + .c (through the header), queue.h (through Console.cpp);
    # Arduino.h is not ours and unused.* is never named
    assert names == ["Console.cpp", "Console.h", "S.ino", "planner.c", "planner.h", "queue.h"]


def test_section_counts_the_engine_and_the_consoles(tmp_path):
    board = tmp_path / "firmware" / "libraries" / "MotionBoard" / "src"
    write(board / "MultiStepEngine.h", "/* doc */\nint x;\n")           # 2 lines, 1 code line
    write(board / "MultiStepEngineIsr.inc", "; c\n ret\n nop ; n\n")   # 3 lines, 2 code lines
    write(board / "MotionConsole.cpp", "int a;\n\nint b;\n")           # 3 lines, 2 code lines
    write(board / "Other.cpp", "int z;\n")                              # neither
    # the MotionStepper library's console counts with the consoles, its API beside them
    stepper = tmp_path / "firmware" / "libraries" / "MotionStepper" / "src"
    write(stepper / "MotionConsole.h", "int c;\n// d\n")
    write(stepper / "Stepper.cpp", "int s;\n/* e\n */\nint t;\n")          # 4 lines, 2 code lines
    write(tmp_path / "firmware" / "LeibRampStepper" / "LeibRampStepper.ino", '#include "Nothing.h"\n')
    out = "\n".join(code_size.section(str(tmp_path), ["LeibRampStepper"]))
    assert "| step engine (MultiStepEngine*, StepCut.*) | 2 | 5 | 3 |" in out
    assert "| consoles (MotionConsole*) | 2 | 5 | 3 |" in out
    assert "| engine + consoles | 4 | 10 | 6 |" in out
    assert "| the MotionStepper API beside them (Stepper*, BackgroundPlanner*) | 1 | 4 | 2 |" in out
    assert "| LeibRampStepper | 1 |" in out  # Nothing.h does not exist: only the sketch
