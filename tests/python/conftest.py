"""Shared helpers of the Python module's tests: the built CLI (INERTIAL_CLI) as the C++ reference
and the bundled examples (INERTIAL_SOURCE_DIR)."""
import json
import os
import subprocess

import pytest


def source(*parts):
    return os.path.join(os.environ.get("INERTIAL_SOURCE_DIR", "."), *parts)


def cli(*args, check=True):
    """Runs the `inertial` program; returns (exit code, stdout, stderr)."""
    program = os.environ.get("INERTIAL_CLI")
    if not program:
        pytest.skip("INERTIAL_CLI is not set (run through ctest)")
    r = subprocess.run([program, *args], capture_output=True, text=True)
    if check and r.returncode != 0:
        raise AssertionError(f"inertial {' '.join(args)} exited {r.returncode}: {r.stderr}")
    return r.returncode, r.stdout, r.stderr


def cli_json(command, *args):
    """`inertial COMMAND --json ARGS...` parsed (--json first: ARGS may end in `-- numbers`)."""
    return json.loads(cli(command, "--json", *args)[1])
