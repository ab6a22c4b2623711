"""examples/python/hidden_effect.py runs in one command and finds what it hid: Coulomb friction
named first by diagnose, the held-out error back at the noise once it is added, both figures
written."""
import os
import re
import subprocess
import sys

from conftest import source


def test_the_worked_example(tmp_path):
    r = subprocess.run([sys.executable, source("examples", "python", "hidden_effect.py"), str(tmp_path)],
                       capture_output=True, text=True, timeout=300)
    assert r.returncode == 0, r.stderr
    assert "Coulomb (dry) friction" in r.stdout, r.stdout
    before, after = map(float, re.search(r"held-out RMS: ([0-9.]+) N m without the effect, ([0-9.]+) N m with it",
                                         r.stdout).groups())
    assert after < 1.2 * 0.05 < 5 * 0.05 < before  # the noise is 0.05 N m
    for png in ("residual.png", "online_mass.png"):
        path = tmp_path / png
        assert path.stat().st_size > 10_000
        assert path.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
