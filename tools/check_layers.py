# SPDX-FileCopyrightText: 2026 selfcol authors
# SPDX-License-Identifier: MIT
"""The layering of lib/ (docs/architecture.md, "lib/ by folder"), checked.

Every C file and private header of the library sits in one folder of
LAYERS, and includes private headers by their folder ("query/records.h")
from its own folder or an earlier one only: no circle between folders, and
a reader knows from an include what it depends on. Fails (exit 1) naming
each offending include, a file outside the folders, or an include of a
private header without its folder. Standard library only.

usage: python3 tools/check_layers.py [ROOT]
"""
import os
import re
import sys

# Lowest first: a folder may include its own headers and those of folders
# before it.
LAYERS = ["base", "mesh", "narrow", "hierarchy", "query", "continuous", "frames", "scene"]

INCLUDE = re.compile(r'^\s*#\s*include\s+"([^"]+)"', re.M)


def main():
    root = sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), "..")
    lib = os.path.join(root, "lib")
    rank = {name: i for i, name in enumerate(LAYERS)}
    errors = []
    headers = {}
    sources = []
    for entry in sorted(os.listdir(lib)):
        path = os.path.join(lib, entry)
        if os.path.isdir(path):
            if entry not in rank:
                errors.append("lib/%s: a folder not in tools/check_layers.py's LAYERS" % entry)
                continue
            for name in sorted(os.listdir(path)):
                if name.endswith((".c", ".h")):
                    sources.append((entry, name))
                    if name.endswith(".h"):
                        if name in headers:
                            errors.append("lib/%s/%s: a second header of that name (lib/%s)"
                                          % (entry, name, headers[name]))
                        headers[name] = entry
        elif entry.endswith((".c", ".h")):
            errors.append("lib/%s: C file outside the folders" % entry)
    for folder, name in sources:
        with open(os.path.join(lib, folder, name)) as f:
            text = f.read()
        for inc in INCLUDE.findall(text):
            parts = inc.split("/")
            if len(parts) == 1:
                if inc in headers:
                    errors.append("lib/%s/%s: includes \"%s\" without its folder (\"%s/%s\")"
                                  % (folder, name, inc, headers[inc], inc))
                continue
            if len(parts) != 2 or parts[0] not in rank:
                errors.append("lib/%s/%s: includes \"%s\", not a folder of lib/" % (folder, name, inc))
                continue
            if not os.path.exists(os.path.join(lib, inc)):
                errors.append("lib/%s/%s: includes \"%s\", which does not exist" % (folder, name, inc))
            elif rank[parts[0]] > rank[folder]:
                errors.append("lib/%s/%s: includes \"%s\" from a later folder (order: %s)"
                              % (folder, name, inc, " < ".join(LAYERS)))
    for e in errors:
        print("check_layers: " + e, file=sys.stderr)
    if errors:
        return 1
    print("check_layers: %d files in %d folders, every include from its folder or an earlier one"
          % (len(sources), len(LAYERS)))
    return 0


if __name__ == "__main__":
    sys.exit(main())
