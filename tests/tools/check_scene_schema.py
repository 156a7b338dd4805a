#!/usr/bin/env python3
"""Checks docs/scene.schema.json (run by ctest as Scenes.SchemaAcceptsEveryShippedScene):

- every shipped scene (scenes/*.json) and every ```json example in docs/*.md and README.md is valid
  under the schema, and each documented example also loads in xcut (`xcut schedule`);
- scenes the loader refuses for a reason the schema can express are refused by the schema too.

    check_scene_schema.py SOURCE_DIR XCUT_BINARY
"""
import glob
import json
import os
import re
import subprocess
import sys
import tempfile

import jsonschema


def main():
    root, xcut = sys.argv[1], sys.argv[2]
    with open(os.path.join(root, "docs", "scene.schema.json")) as f:
        schema = json.load(f)
    jsonschema.Draft202012Validator.check_schema(schema)
    validator = jsonschema.Draft202012Validator(schema)
    failures = []

    def check(name, scene, expect_valid=True):
        errors = sorted(validator.iter_errors(scene), key=lambda e: list(e.path))
        if expect_valid and errors:
            failures.append(f"{name}: " + "; ".join(f"{'/'.join(map(str, e.path))}: {e.message}" for e in errors[:3]))
        if not expect_valid and not errors:
            failures.append(f"{name}: the schema accepts a scene the loader refuses")

    scenes = sorted(glob.glob(os.path.join(root, "scenes", "*.json")))
    for path in scenes:
        with open(path) as f:
            check(os.path.relpath(path, root), json.load(f))
    examples = 0
    for doc in sorted(glob.glob(os.path.join(root, "docs", "*.md"))) + [os.path.join(root, "README.md")]:
        with open(doc) as f:
            text = f.read()
        for k, block in enumerate(re.findall(r"```json\n(.*?)```", text, re.S)):
            scene = json.loads(block)
            name = f"{os.path.relpath(doc, root)} example {k + 1}"
            check(name, scene)
            examples += 1
            with tempfile.TemporaryDirectory() as d:
                path = os.path.join(d, "example.json")
                with open(path, "w") as f:
                    f.write(block)
                r = subprocess.run([xcut, "schedule", path], capture_output=True, text=True)
                if r.returncode != 0:
                    failures.append(f"{name}: xcut refuses it: {r.stderr.strip()}")

    base = {"mesh": {"generator": "box", "size": [0.01, 0.01, 0.01], "cells": [2, 2, 2]}}
    bad = {
        "unknown top-level field": {**base, "gravty": [0, 0, -9.81]},
        "Poisson ratio of 0.5": {**base, "material": {"poisson": 0.5}},
        "steps and duration": {**base, "steps": 10, "duration": 1.0},
        "file and generator": {"mesh": {"file": "m.msh", "generator": "box", "size": [1, 1, 1], "cells": [1, 1, 1]}},
        "generator without a size": {"mesh": {"generator": "box", "cells": [1, 1, 1]}},
        "units on a generator": {"mesh": {**base["mesh"], "units": "cm"}},
        "unknown units": {"mesh": {"file": "m.msh", "units": "inch"}},
        "unknown linear solver": {**base, "solver": {"linear": "lu"}},
        "tool with two trajectories": {**base, "tools": [{"trajectory": [{"time": 0, "position": [0, 0, 0]}],
                                                          "trajectory_csv": "t.csv"}]},
        "sphere without a radius": {**base, "tools": [{"shape": {"type": "sphere"},
                                                       "trajectory": [{"time": 0, "position": [0, 0, 0]}]}]},
        "unknown material field in a region": {**base, "region_materials": {"fat": {"stiffness": 1}}},
        "bodies and a top-level mesh": {**base, "bodies": [base]},
        "a body without a mesh": {"bodies": [{"name": "skin"}]},
    }
    for name, scene in bad.items():
        check(name, scene, expect_valid=False)
        with tempfile.TemporaryDirectory() as d:  # and the loader refuses it too, with exit 2
            path = os.path.join(d, "bad.json")
            with open(path, "w") as f:
                json.dump(scene, f)
            r = subprocess.run([xcut, "schedule", path], capture_output=True, text=True)
            if r.returncode != 2:
                failures.append(f"{name}: xcut exits {r.returncode}, not 2 (an input error)")

    if failures:
        print("\n".join(failures))
        return 1
    print(f"schema: {len(scenes)} shipped scenes and {examples} documented examples valid; {len(bad)} bad scenes refused")
    return 0 if scenes and examples else 1


if __name__ == "__main__":
    sys.exit(main())
