"""Regression guard for reviewers: the engine now against a pinned earlier build, runs
interleaved on one thread, medians and their ratio, and whether both give bit-identical
results (the `scale` example's fingerprint).

    .venv/bin/python benchmarks/guard.py [--base REV] [--sizes paper,small,large,huge] [--repeats 5] [--steps 1000]

`--base` is any git revision (default: the one pinned in BASE below). Its `scale` example is
built once from a `git worktree` under target/guard/ with its own target directory, and
reused while the revision is the same. Both builds run each size in turn, `--repeats`
times, so the machine's drift hits both alike. Prints a Markdown table; exits 1 if a size's
fingerprints differ (a change of behaviour, not of speed). It is not a test: speed is
noisy, and the verdict on it is the reader's.

Quote two windows. `--steps 1000` times steps 101..1100 of a run, while the fleet spreads out
from its parking; `--steps 20000` times mostly the state a long run settles into, which in
the overloaded large and huge sizes is queues and jams. A change can win one and lose the
other: a neighbour list kept from step to step won the first by 16% and lost the second by
14% at the large size, and was dropped.
"""

from __future__ import annotations

import argparse
import json
import statistics
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
#: The pinned earlier build: the start of the session that split the engine into rule files
#: (issue 9), the last build before the traffic policies, original rules and people.
BASE = "2f5342d"


def git(*args: str) -> str:
    return subprocess.run(["git", *args], cwd=ROOT, capture_output=True, text=True, check=True).stdout.strip()


def build_base(rev: str) -> Path:
    """The `scale` binary of revision `rev`, built in a worktree under target/guard/."""
    sha = git("rev-parse", "--verify", f"{rev}^{{commit}}")
    tree = ROOT / "target" / "guard" / sha[:12]
    if not tree.exists():
        subprocess.run(["git", "worktree", "add", "--detach", str(tree), sha], cwd=ROOT, check=True,
                       capture_output=True)
    # A target directory per revision: with one shared directory cargo may leave another
    # revision's binary at the shared path when the build is already fresh, and the guard
    # would then time the wrong build.
    target = tree / "target"
    subprocess.run(["cargo", "build", "-q", "--release", "-p", "multibots-core", "--example", "scale",
                    "--target-dir", str(target)], cwd=tree, check=True)
    return target / "release" / "examples" / "scale"


def build_head() -> Path:
    subprocess.run(["cargo", "build", "-q", "--release", "-p", "multibots-core", "--example", "scale"],
                   cwd=ROOT, check=True)
    return ROOT / "target" / "release" / "examples" / "scale"


def run(binary: Path, size: str, steps: int) -> dict:
    # Each build reads the size as its own revision wrote it: newer files pin new keys to the
    # values older builds had by default (`aisles = "paper"`, which 2f5342d cannot parse),
    # and the fingerprints check that both runs are the same scenario.
    path = binary.parents[3] / "benchmarks" / "sizes" / f"{size}.toml"
    if not path.exists():
        path = ROOT / "benchmarks" / "sizes" / f"{size}.toml"
    out = subprocess.run([str(binary), str(path), str(steps)], capture_output=True, text=True, check=True)
    return json.loads(out.stdout.splitlines()[-1])


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--base", default=BASE, help=f"git revision to compare with (default {BASE})")
    ap.add_argument("--sizes", default="paper,small,large,huge")
    ap.add_argument("--repeats", type=int, default=5)
    ap.add_argument("--steps", type=int, default=1000)
    a = ap.parse_args()
    base, head = build_base(a.base), build_head()
    sizes = [s.strip() for s in a.sizes.split(",") if s.strip()]
    speed: dict[tuple[str, str], list[float]] = {}
    prints: dict[tuple[str, str], set[str]] = {}
    for _ in range(a.repeats):
        for size in sizes:
            for name, binary in (("base", base), ("head", head)):
                r = run(binary, size, a.steps)
                speed.setdefault((name, size), []).append(r["robot_steps_per_s"])
                prints.setdefault((name, size), set()).add(r.get("fingerprint", "?"))
    short = (git("rev-parse", "--short", a.base), git("rev-parse", "--short", "HEAD"))
    print(f"base {a.base} ({short[0]}) against head ({short[1]}), {a.steps} steps, {a.repeats} interleaved runs each, "
          "one thread")
    print("| size | base, median | head, median | head / base | same results |")
    print("| --- | ---: | ---: | ---: | --- |")
    differ = False
    for size in sizes:
        b, h = statistics.median(speed[("base", size)]), statistics.median(speed[("head", size)])
        same = prints[("base", size)] == prints[("head", size)] and len(prints[("head", size)]) == 1
        differ |= not same
        print(f"| {size} | {b / 1e6:.2f} M | {h / 1e6:.2f} M | {h / b:.2f} | {'yes' if same else 'NO'} |")
    if differ:
        print("fingerprints differ: the engine's behaviour changed", file=sys.stderr)
        sys.exit(1)


if __name__ == "__main__":
    main()
