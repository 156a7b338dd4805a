"""The installed package: `cmake --install` of this build into a temporary prefix; the package
imports from there (as Debian's Python finds it under /usr/local), steps a scene, and finds the
installed xcut binary for sweeps."""
import glob
import os
import subprocess
import sys

import pytest


def test_the_installed_package_imports_steps_and_finds_its_binary(tmp_path):
    build = os.environ.get("XCUT_BUILD_DIR")
    if not build:
        pytest.fail("XCUT_BUILD_DIR must name the build tree (ctest sets it)")
    prefix = tmp_path / "prefix"
    p = subprocess.run(["cmake", "--install", build, "--prefix", str(prefix)], capture_output=True, text=True)
    assert p.returncode == 0, p.stdout + p.stderr
    found = glob.glob(str(prefix / "lib" / "python3*" / "*-packages" / "xcut"))
    assert len(found) == 1, "the package under <prefix>/lib/pythonX.Y/dist-packages"
    package = found[0]
    for f in ("__init__.py", "_xcut.pyi", "py.typed", "sweep.py", "bench.py", os.path.join("envs", "incision.py")):
        assert os.path.isfile(os.path.join(package, f)), f
    assert glob.glob(os.path.join(package, "_xcut*.so"))
    scene = prefix / "share" / "xcut" / "scenes" / "skin_slab.json"
    code = ("import xcut, xcut.sweep as s; sim = xcut.Simulation(%r); sim.step(3); "
            "print(sim.step_count, xcut.__file__, s.find_binary())" % str(scene))
    env = dict(os.environ, PYTHONPATH=os.path.dirname(package))
    env.pop("XCUT_BINARY", None)
    p = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=tmp_path, env=env)
    assert p.returncode == 0, p.stderr
    steps, module, binary = p.stdout.split()
    assert steps == "3" and module.startswith(str(prefix))
    assert os.path.samefile(binary, prefix / "bin" / "xcut")
