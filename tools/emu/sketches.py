"""tools/emu/sketches.py - what the emulator knows about each sketch (stub)."""
import os
import emulog

ROOT = emulog.ROOT


class Env:
    def __init__(self, firmware_dir=None, source_dir=None, motionsim=None):
        self.firmware_dir = firmware_dir or os.path.join(ROOT, "build", "firmware")
        self.source_dir = source_dir or ROOT
        self.motionsim = motionsim or os.path.join(ROOT, "build", "motionsim")

    def sketch_names(self):
        fw = os.path.join(self.source_dir, "firmware")
        return sorted(d for d in os.listdir(fw) if os.path.isfile(os.path.join(fw, d, d + ".ino")))
