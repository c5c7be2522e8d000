#!/usr/bin/env python3
"""The outputs README.md shows are what the commands print today.

Usage: test_readme_outputs.py MRR SOURCE_DIR

Two blocks of README.md are checked against a fresh run of the command each shows:
- the demo's summary (the block after "The demo prints a summary such as"): the `mrr render` line
  scripts/demo.sh prints it from, run as demo.sh runs it (its `common=(...)` options at the size
  the block's first line states, its outputs in a scratch folder), then demo.sh's own summary
  program (the Python between `<<'PY'` and `PY`) on that render's report;
- the probe (the block whose first line is `$ mrr probe ...`): literally the command after `$ `.
Every line must match exactly but for what depends on the machine: the frame's time
(`frame 329 ms`) and the thread count (`threads 2`). A line `…` in a README block stands for
lines left out. On a mismatch it prints both and exits 1: update the README block to what the
command prints (the deterministic lines change only when the method or its defaults do).
"""
import os
import re
import shlex
import subprocess
import sys
import tempfile

ELLIPSIS = "…"


def fenced_block_after(lines, start):
    """The lines of the first ``` block at or after line index start."""
    i = start
    while not lines[i].startswith("```"):
        i += 1
    j = i + 1
    while not lines[j].startswith("```"):
        j += 1
    return lines[i + 1:j]


def machine_free(line):
    line = re.sub(r"\bthreads \d+\b", "threads N", line)
    line = re.sub(r"\bframe \d+ ms\b", "frame N ms", line)
    return line.rstrip()


def matches(expected, actual):
    """Whether actual matches expected, where a line `…` in expected stands for any lines."""
    segments, current = [], []
    for line in expected:
        if line.strip() == ELLIPSIS:
            segments.append(current)
            current = []
        else:
            current.append(line)
    segments.append(current)
    exp = [[machine_free(l) for l in s] for s in segments]
    act = [machine_free(l) for l in actual]
    if len(exp) == 1:
        return exp[0] == act
    if act[:len(exp[0])] != exp[0] or (exp[-1] and act[-len(exp[-1]):] != exp[-1]):
        return False
    pos, end = len(exp[0]), len(act) - len(exp[-1])
    for seg in exp[1:-1]:
        while pos + len(seg) <= end and act[pos:pos + len(seg)] != seg:
            pos += 1
        if pos + len(seg) > end:
            return False
        pos += len(seg)
    return pos <= end


def report(name, command, expected, actual):
    print(f"FAIL: README.md's {name} block is not what `{command}` prints now.")
    print("--- README.md shows:")
    print("\n".join(expected))
    print("--- the command prints:")
    print("\n".join(actual))
    print("(the frame's time and the thread count may differ; a line … stands for lines left out)")


def check_demo_summary(mrr, src, readme, scratch):
    i = next(k for k, l in enumerate(readme) if "The demo prints a summary such as" in l)
    expected = fenced_block_after(readme, i)
    size = re.search(r"\b(\d+x\d+)\b", expected[0]).group(1)
    demo = open(os.path.join(src, "scripts", "demo.sh"), encoding="utf-8").read()
    common = re.search(r"^common=\(.*\)$", demo, re.M).group(0)
    # The render line the summary is printed from: the first `render` of the method with
    # --reference and --report, with its continuation lines.
    m = re.search(r'^"\$mrr" render "\$\{common\[@\]\}" --method mrr --reference(?:.*\\\n)*.*--report "\$out/report\.json".*$',
                  demo, re.M)
    if not m:
        print("FAIL: scripts/demo.sh has no `\"$mrr\" render \"${common[@]}\" --method mrr --reference ... "
              "--report \"$out/report.json\"` line; update this test with it")
        return False
    render = m.group(0)
    summary = re.search(r"<<'PY'[^\n]*\n(.*?)\nPY\n", demo, re.S).group(1)
    script = "\n".join(["set -euo pipefail", f"mrr={shlex.quote(mrr)}", f"out={shlex.quote(scratch)}",
                        f"size={shlex.quote(size)}", common, render + " 2>/dev/null"])
    subprocess.run(["bash", "-c", script], check=True)
    out = subprocess.run([sys.executable, "-", os.path.join(scratch, "report.json")], input=summary,
                         capture_output=True, text=True, check=True).stdout
    actual = out.rstrip("\n").split("\n")
    command = " ".join(render.replace("\\\n", " ").split(" --out")[0].split())
    command += f" (size {size}), then demo.sh's summary"
    if not matches(expected, actual):
        report("demo summary", command, expected, actual)
        return False
    print(f"ok: the demo summary ({size}) is current")
    return True


def check_probe(mrr, readme):
    i = next(k for k, l in enumerate(readme) if l.startswith("$ mrr probe "))
    command = readme[i][2:]
    expected = []
    for line in readme[i + 1:]:
        if line.startswith("```"):
            break
        expected.append(line)
    argv = shlex.split(command)
    argv[0] = mrr
    actual = subprocess.run(argv, capture_output=True, text=True, check=True).stdout.rstrip("\n").split("\n")
    if not matches(expected, actual):
        report("probe", command, expected, actual)
        return False
    print(f"ok: `{command}` prints what README.md shows")
    return True


def main():
    if len(sys.argv) != 3:
        print(__doc__, file=sys.stderr)
        return 2
    mrr, src = os.path.abspath(sys.argv[1]), os.path.abspath(sys.argv[2])
    readme = open(os.path.join(src, "README.md"), encoding="utf-8").read().split("\n")
    with tempfile.TemporaryDirectory(prefix="mrr-readme-") as scratch:
        ok = check_demo_summary(mrr, src, readme, scratch)
    ok = check_probe(mrr, readme) and ok
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
