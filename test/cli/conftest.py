"""Shared fixtures for the motionsim command-line tests (pytest, run by `make test`)."""
import csv
import io
import os
import subprocess

import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


class Run:
    def __init__(self, p):
        self.rc = p.returncode
        self.out = p.stdout
        self.err = p.stderr

    def rows(self):
        """stdout parsed as CSV: (header, list of dicts with float values)."""
        r = list(csv.reader(io.StringIO(self.out)))
        header = r[0]
        return header, [dict(zip(header, map(float, row))) for row in r[1:] if row]


@pytest.fixture(scope="session")
def motionsim():
    path = os.environ.get("MOTIONSIM", os.path.join(ROOT, "build", "motionsim"))
    if not os.access(path, os.X_OK):
        pytest.fail(f"{path} not built (make sim)")

    def run(*args, timeout=120):
        return Run(subprocess.run([path] + [str(a) for a in args], capture_output=True, text=True, timeout=timeout))

    return run
