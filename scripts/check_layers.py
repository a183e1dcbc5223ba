#!/usr/bin/env python3
"""Checks that softface's includes point down its layers only.

The layers, lowest first (README, Layout):

    core < io < fe < mapping, validation < models, effects, patient,
    outputs, mesh_sources < simulator < serve < app

A file of a layer may include softface headers (#include <softface/...>) of
its own layer and of the layers below it. An include of a higher layer, or
of a folder that has no layer here, is an error, listed with the file and
line; the exit code is the number of such includes (0: the layers hold).
Run from anywhere:

    scripts/check_layers.py
"""
import os
import re
import sys

LAYERS = [["core"], ["io"], ["fe"], ["mapping", "validation"],
          ["models", "effects", "patient", "outputs", "mesh_sources"],
          ["simulator"], ["serve"], ["app"]]
LEVEL = {system: i for i, systems in enumerate(LAYERS) for system in systems}
INCLUDE = re.compile(r'^\s*#\s*include\s*[<"]\s*softface/([A-Za-z_]+)/')


def system_of(path):
    """The system a file belongs to: its folder under source/ or
    include/softface/, or 'app' for app/."""
    parts = path.split(os.sep)
    if parts[0] == "app":
        return "app"
    if parts[0] == "source" and len(parts) > 2:
        return parts[1]
    if parts[:2] == ["include", "softface"] and len(parts) > 3:
        return parts[2]
    return None


def main():
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    errors = []
    for top in ("source", "include", "app"):
        for folder, _, files in os.walk(os.path.join(root, top)):
            for name in sorted(files):
                if not name.endswith((".h", ".cc")):
                    continue
                path = os.path.relpath(os.path.join(folder, name), root)
                system = system_of(path)
                if system is None:
                    continue
                if system not in LEVEL:
                    errors.append(f"{path}: the folder '{system}' has no "
                                  "layer in scripts/check_layers.py")
                    continue
                with open(os.path.join(root, path)) as f:
                    for number, line in enumerate(f, 1):
                        match = INCLUDE.match(line)
                        if not match:
                            continue
                        target = match.group(1)
                        if target not in LEVEL:
                            errors.append(
                                f"{path}:{number}: includes the folder "
                                f"'{target}', which has no layer in "
                                f"scripts/check_layers.py: {line.strip()}")
                        elif LEVEL[target] > LEVEL[system]:
                            errors.append(
                                f"{path}:{number}: {system} includes "
                                f"{target} (a layer above it): "
                                f"{line.strip()}")
    for e in errors:
        print(e)
    print(f"layers: {len(errors)} include(s) point up")
    return min(len(errors), 255)


if __name__ == "__main__":
    sys.exit(main())
