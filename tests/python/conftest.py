"""Shared fixtures of the Python tests (run by ctest as Python.*: PYTHONPATH is the build tree's
python/ folder, XCUT_BINARY the CLI, XCUT_SOURCE_DIR the checkout)."""
import json
import os
import subprocess

import pytest

SOURCE = os.environ.get("XCUT_SOURCE_DIR", os.path.abspath(os.path.join(os.path.dirname(__file__), "..", "..")))


@pytest.fixture(scope="session")
def source_dir():
    return SOURCE


@pytest.fixture(scope="session")
def binary():
    b = os.environ.get("XCUT_BINARY")
    if not b or not os.path.isfile(b):
        pytest.fail("XCUT_BINARY must name the xcut binary (ctest sets it)")
    return b


@pytest.fixture(scope="session")
def skin_scene_path():
    return os.path.join(SOURCE, "scenes", "skin_slab.json")


@pytest.fixture(scope="session")
def skin_scene_dict(skin_scene_path):
    with open(skin_scene_path) as f:
        return json.load(f)


def run_cli(binary, *args, cwd=None):
    """Runs the xcut binary; returns (exit code, stdout, stderr)."""
    p = subprocess.run([binary, *args], capture_output=True, text=True, cwd=cwd, timeout=600)
    return p.returncode, p.stdout, p.stderr
