#!/usr/bin/env python3
"""Fails when an include in src/lambert/ runs up the layers (docs/layout.md).

The library is a stack of folders; a file may include its own folder and the folders below it,
never one above, and never a peer on its level (flat/ and hierarchical/ are two methods that know
nothing of each other). Above engine/, the consumers read the SolutionView: they may not include
the methods' folders (flat/, hierarchical/) or the solvers (solve/), which are the engine's
internals. Tests beside the code (*_test.cpp) are programs over the library and may include any
layer. Usage: check-layers.py [SOURCE_ROOT]; prints every offending include as file:line.
"""
import pathlib
import re
import sys

# Bottom first; folders in one tuple share a level and may not include each other.
LAYERS = [
    ("core",),
    ("scene",),
    ("mesh",),
    ("geometry",),
    ("light",),
    ("load",),
    ("formfactor",),
    ("solve",),
    ("method",),
    ("flat", "hierarchical"),
    ("engine",),
    ("bake",),
    ("render",),
    ("io",),
    ("design", "reference"),
    ("distributed",),
]
ENGINE_INTERNALS = {"flat", "hierarchical", "solve"}
# method/ holds what the engine and every method share: the interface a method implements
# (method.h), the options it reads (options.h, collecting flat_options.h and
# hierarchical_options.h), a solve call's budget and report, the view and its point types.
LEVEL = {folder: level for level, group in enumerate(LAYERS) for folder in group}
INCLUDE = re.compile(r'^\s*#\s*include\s+"lambert/(([a-z_]+)/[a-z_0-9]+\.h)"')


def level_of(relative):
    return LEVEL.get(relative.split("/")[0])


def problems(root):
    library = root / "src" / "lambert"
    found = []
    for path in sorted(library.rglob("*")):
        if path.suffix not in (".h", ".cpp") or path.name.endswith("_test.cpp"):
            continue
        relative = path.relative_to(library).as_posix()
        folder = relative.split("/")[0]
        if folder not in LEVEL:
            if path.parent != library:
                found.append(f"{path}: folder {folder}/ is in no layer (add it to scripts/check-layers.py and docs/layout.md)")
            continue
        for number, line in enumerate(path.read_text(encoding="utf-8").splitlines(), 1):
            match = INCLUDE.match(line)
            if not match:
                continue
            header, target = match.group(1), match.group(2)
            where = f"{path.relative_to(root)}:{number}"
            mine, theirs = level_of(relative), level_of(header)
            if target not in LEVEL:
                found.append(f"{where}: includes lambert/{target}/, a folder in no layer")
            elif theirs > mine:
                found.append(f"{where}: {relative} includes {header}, a layer above it")
            elif target == folder:
                continue
            elif theirs == mine:
                found.append(f"{where}: {folder}/ includes its peer {target}/")
            elif mine > LEVEL["engine"] and target in ENGINE_INTERNALS:
                found.append(f"{where}: {folder}/ includes the engine's internals ({target}/); read the SolutionView")
    return found


def main():
    root = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else pathlib.Path(__file__).resolve().parent.parent)
    found = problems(root)
    for problem in found:
        print(problem)
    if found:
        print(f"check-layers: {len(found)} include(s) against the layers of docs/layout.md", file=sys.stderr)
        return 1
    print("check-layers: every include runs down the layers")
    return 0


if __name__ == "__main__":
    sys.exit(main())
