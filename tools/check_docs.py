# SPDX-FileCopyrightText: 2026 selfcol authors
# SPDX-License-Identifier: MIT
"""Doc drift, checked (ctest docs_drift; issue 40).

1. The generated tables of docs/benchmarks.md are what the committed
   results in tools/bench/results give (tools/plot/plot.py --check).
2. The README quotes no measured number the committed results do not hold:
   a time (ms, s) or a ratio (N.Nx, N.N×) in its prose, outside code blocks
   and the CLI's sample output, must be one that docs/benchmarks.md or a
   results page (tools/bench/results/*.md) shows, to the quoted decimals.
3. Every selfcol-cli option that docs/cli.md and the README name exists in
   the CLI's --help (of the command or of selfcol-cli itself).

usage: python3 tools/check_docs.py ROOT SELFCOL_CLI
Standard library only.
"""
import bisect
import glob
import os
import re
import subprocess
import sys

MEASURE = re.compile(r"(?<![\w.])(\d[\d,]*(?:\.\d+)?)\s?(ms|s|x|×)(?![\w])")
OPTION = re.compile(r"(?<![\w-])--([a-z][a-z-]+)")


def prose(text):
    """The lines of a Markdown text outside fenced code blocks."""
    out, fenced = [], False
    for line in text.splitlines():
        if line.lstrip().startswith("```"):
            fenced = not fenced
            continue
        if not fenced:
            out.append(line)
    return out


def check_numbers(root, errors):
    readme = open(os.path.join(root, "README.md"), encoding="utf-8").read()
    # What a reader is pointed to: the benchmarks page (whose generated
    # tables check 1 holds to the results) and the results' own pages.
    # Not the CSVs: with thousands of values, nearly any number is in one.
    sources = [os.path.join(root, "docs", "benchmarks.md")]
    sources += glob.glob(os.path.join(root, "tools", "bench", "results", "*.md"))
    held = "\n".join(open(p, encoding="utf-8", errors="replace").read() for p in sources)
    # Every number the sources hold, as a value: a quoted number matches one
    # that rounds to it at the quoted number of decimals (79.8 matches
    # 79.8123 in a CSV, not 379.81).
    values = sorted(float(v.replace(",", "")) for v in re.findall(r"(?<![\w.])\d[\d,]*(?:\.\d+)?", held)
                    if v.replace(",", "").replace(".", "", 1).isdigit())
    for number, unit in MEASURE.findall("\n".join(prose(readme))):
        if unit == "s" and "." not in number:
            continue  # "2 s", "90 s": budgets and durations, not measurements
        if unit in ("x", "×") and "." not in number:
            continue  # "0 x", "3 x 3": counts and sizes, not ratios
        value = float(number.replace(",", ""))
        decimals = len(number.split(".")[1]) if "." in number else 0
        half = 0.5 * 10 ** -decimals * (1 + 1e-9)
        i = bisect.bisect_left(values, value - half)
        if i < len(values) and values[i] <= value + half:
            continue
        errors.append("README.md quotes %s %s, which neither docs/benchmarks.md nor "
                      "tools/bench/results/*.md shows" % (number, unit))


def check_options(root, cli, errors):
    helps = []
    for command in ([], ["check"], ["track"], ["info"]):
        r = subprocess.run([cli] + command + ["--help"], capture_output=True, text=True)
        helps.append(r.stdout + r.stderr)
    known = set(OPTION.findall("\n".join(helps)))
    cli_doc = open(os.path.join(root, "docs", "cli.md"), encoding="utf-8").read()
    named = set(OPTION.findall(cli_doc))
    readme = open(os.path.join(root, "README.md"), encoding="utf-8").read()
    for line in readme.splitlines():
        if "selfcol-cli" in line:
            named |= set(OPTION.findall(line))
    for option in sorted(named - known):
        errors.append("--%s is named in docs/cli.md or the README's selfcol-cli lines but "
                      "not in selfcol-cli's --help" % option)


def main():
    if len(sys.argv) != 3:
        print(__doc__, file=sys.stderr)
        return 2
    root, cli = sys.argv[1], sys.argv[2]
    errors = []
    plot = subprocess.run([sys.executable, os.path.join(root, "tools", "plot", "plot.py"),
                           "--root", root, "--check"], capture_output=True, text=True)
    if plot.returncode != 0:
        errors.extend(line for line in plot.stderr.splitlines() if line)
    check_numbers(root, errors)
    check_options(root, cli, errors)
    for e in errors:
        print("check_docs: " + e, file=sys.stderr)
    if errors:
        return 1
    print("check_docs: generated tables, README numbers and CLI options hold")
    return 0


if __name__ == "__main__":
    sys.exit(main())
