# SPDX-FileCopyrightText: 2026 selfcol authors
# SPDX-License-Identifier: MIT
"""The README's Python example against an installed selfcol (a wheel's
smoke test: tools/wheel.sh here, cibuildwheel's test-command elsewhere).

Runs the first ```python block of the README's "Python: `import selfcol`"
section as a newcomer would paste it, and checks what it prints: the two
edges crossing triangle 0, and triangles 0 and 1 intersecting.

usage: python wheel_smoke.py [README.md]  (default: the repository's)
Not collected by pytest (no test_ prefix): it needs no pytest.
"""
import contextlib
import io
import os
import sys


def readme_example(path):
    with open(path, encoding="utf-8") as f:
        lines = f.read().splitlines()
    start = next(i for i, line in enumerate(lines)
                 if line.startswith("### Python: `import selfcol`"))
    begin = next(i for i in range(start, len(lines)) if lines[i].startswith("```python"))
    end = next(i for i in range(begin + 1, len(lines)) if lines[i].startswith("```"))
    return "\n".join(lines[begin + 1:end])


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    readme = sys.argv[1] if len(sys.argv) > 1 else os.path.join(here, "..", "..", "README.md")
    code = readme_example(readme)
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        exec(compile(code, readme, "exec"), {"__name__": "__main__"})
    text = out.getvalue()
    print(text, end="")
    if "ef=2" not in text or "[[0 1]]" not in text:
        print("wheel_smoke: the README example did not print its 2 crossings and [[0 1]]",
              file=sys.stderr)
        return 1
    import selfcol
    print("wheel_smoke: OK, selfcol %s from %s" % (selfcol.version(), os.path.dirname(selfcol.__file__)))
    return 0


if __name__ == "__main__":
    sys.exit(main())
