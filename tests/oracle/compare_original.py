"""Compares the engine's original rules with the authors' own code on random goods lists.

A helper, not a test: pytest does not collect it. It needs the `original_run` example built
(`cargo build --release -p multibots-core --example original_run`) and the headless
reference (`run_authors.py`, from the authors' code ported to Python 3):

    python3 tests/oracle/compare_original.py --cases 1000 [--reference DIR] [--jobs 2]

Each case draws N in 1..6 and a goods list of length N..--max-len (default 50, the most the
original can deliver; up to 80 also exercises the refusal) from cells 0..79 without
repeats, seeded, so a case is reproduced by its seed and number. Both sides run with the
same tick cap (--max-ticks). Per outcome of the engine:

- complete or incomplete: ticks, S, C, goods delivered, and per robot the collisions,
  charges and every delivery (tick, cell) must be equal;
- deadlock at tick D: the reference stopped after D ticks must agree on S, C and the
  per-robot figures, and show the same stuck state: the first pair of its stop list is two
  stopped robots, away from their chargers, in contact (then neither can ever move again);
  it must still be unfinished --confirm ticks later;
- fault at tick K: both stopped after K - 1 ticks must agree as above, and the reference must
  raise the same exception in tick K, having counted the same S, C and deliveries by then;
- refused (more than 50 goods): the reference must fail to finish (its 51st delivery raises
  IndexError).

Prints every mismatch and one summary line, `K cases: M exact matches`.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import random
import subprocess
import sys
from collections import Counter
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
FAULT_SIGNATURES = {
    "Strategy.takeoffgoods": ("IndexError", "in takeoffgoods"),
    "Controller.chargeController": ("IndexError", "in chargeController"),
    "Strategy.computeStartToGood": ("KeyError: 'x'", "in BFS"),
}


def draw(seed: int, k: int, max_len: int) -> tuple[int, list[int]]:
    rng = random.Random(f"{seed}:{k}")
    n = rng.randint(1, 6)
    length = rng.randint(n, max(n, max_len))
    return n, rng.sample(range(80), length)


def engine(args: argparse.Namespace, n: int, goods: list[int], cap: int) -> dict:
    cmd = [args.engine, "--robots", str(n), "--goods", ",".join(map(str, goods)), "--max-ticks", str(cap)]
    p = subprocess.run(cmd, capture_output=True, text=True, check=False)
    if p.returncode not in (0, 2):
        raise RuntimeError(f"{' '.join(cmd)}: {p.stderr.strip()}")
    return json.loads(p.stdout)


def reference(args: argparse.Namespace, n: int, goods: list[int], cap: int) -> dict:
    """run_authors.py's JSON, or {"crash": last traceback lines} when it raises."""
    cmd = [args.python, str(Path(args.reference) / "run_authors.py"), "--robots", str(n),
           "--goods", ",".join(map(str, goods)), "--max-ticks", str(cap)]
    p = subprocess.run(cmd, capture_output=True, text=True, check=False, cwd=args.reference)
    if p.returncode != 0:
        return {"crash": p.stderr.strip().splitlines()[-6:]}
    return json.loads(p.stdout)


# A fresh interpreter (the code keeps global state) runs the reference as run_authors.py
# does, until it raises, and prints what the code had counted at that moment.
AT_CRASH = r"""
import io, json, sys, traceback, contextlib
n, goods, cap = int(sys.argv[1]), [int(g) for g in sys.argv[2].split(",")], int(sys.argv[3])
sys.path.insert(0, ".")
sys.dont_write_bytecode = True
with contextlib.redirect_stdout(io.StringIO()):
    import param
    param.num_agents, param.GOOD_NUM, param.goodstotal = n, list(goods), len(goods)
    import Strategy, WorldController, ChargeThreshold
    ChargeThreshold.input = lambda prompt="": ""
    ctrl = WorldController.Controller()
    tick, error = 0, None
    while tick < cap and error is None:
        tick += 1
        try:
            ctrl.update()
        except Exception as e:
            error = "%s: %s in %s" % (type(e).__name__, e, traceback.extract_tb(e.__traceback__)[-1].name)
print(json.dumps({"tick": tick, "error": error, "delivered": Strategy.goodscurrentcnt,
                  "S": sum(WorldController.collisioncnt[i] for i in range(n)),
                  "C": sum(a.chargecnts for a in ctrl.agents),
                  "per_robot": [[WorldController.collisioncnt[i], a.chargecnts] for i, a in enumerate(ctrl.agents)]}))
"""


def reference_at_crash(args: argparse.Namespace, n: int, goods: list[int], cap: int) -> dict:
    cmd = [args.python, "-c", AT_CRASH, str(n), ",".join(map(str, goods)), str(cap)]
    p = subprocess.run(cmd, capture_output=True, text=True, check=True, cwd=args.reference)
    return json.loads(p.stdout)


def figures_ours(o: dict) -> dict:
    return {
        "S": o["S"], "C": o["C"], "delivered": o["delivered"],
        "per_robot": [(r["collisions"], r["charges"], [tuple(d) for d in r["deliveries"]]) for r in o["per_robot"]],
    }


def figures_ref(r: dict) -> dict:
    return {
        "S": r["S"], "C": r["C"], "delivered": r["goods_delivered"],
        "per_robot": [(p["collisions"], p["chargecnts"], [tuple(d) for d in p["deliveries"]]) for p in r["per_robot"]],
    }


def diff(ours: dict, ref: dict) -> list[str]:
    return [f"{k}: engine {ours[k]} reference {ref[k]}" for k in ours if ours[k] != ref[k]]


def stuck(state: dict) -> bool:
    """The reference's state shows a first stop pair that can never be released."""
    if not state["cillioned"]:
        return False
    i, j = state["cillioned"][0]
    a, b = state["agents"][i], state["agents"][j]
    frozen = all(r["stopmark"] == 1 and r["chargemark"] == 0 for r in (a, b))
    return frozen and math.hypot(a["x"] - b["x"], a["y"] - b["y"]) <= 32


def compare(args: argparse.Namespace, k: int) -> tuple[int, list[int], str, list[str]]:
    n, goods = draw(args.seed, k, args.max_len)
    ours = engine(args, n, goods, args.max_ticks)
    problems: list[str] = []
    if "error" in ours:
        kind = "refused"
        if len(goods) <= 50:
            problems.append(f"engine refused a list the original can run: {ours['error']}")
        ref = reference(args, n, goods, args.max_ticks)
        if ref.get("finished"):
            problems.append("the reference finished a list the engine refused")
        return n, goods, kind, problems
    kind = ours["outcome"]
    if kind in ("complete", "incomplete"):
        ref = reference(args, n, goods, args.max_ticks)
        if "crash" in ref:
            return n, goods, kind, [f"reference raised: {ref['crash'][-1]}"]
        ticks_ref = ref["ticks"] if ref["finished"] else None
        if ours["ticks"] != ticks_ref:
            problems.append(f"ticks: engine {ours['ticks']} reference {ticks_ref}")
        if ours["steps"] != ref["ticks"]:
            problems.append(f"steps: engine {ours['steps']} reference {ref['ticks']}")
        problems += diff(figures_ours(ours), figures_ref(ref))
    elif kind == "deadlock":
        d = ours["steps"]
        ref = reference(args, n, goods, d)
        if "crash" in ref:
            return n, goods, kind, [f"reference raised before tick {d}: {ref['crash'][-1]}"]
        if ref["finished"] or ref["ticks"] != d:
            problems.append(f"reference finished at {ref['ticks']} (engine: deadlock at {d})")
        else:
            problems += diff(figures_ours(ours), figures_ref(ref))
            if not stuck(ref["state_at_cap"]):
                problems.append(f"reference not stuck at tick {d}: {ref['state_at_cap']['cillioned'][:2]}")
            # The other robots go on working (and the code may even raise later), but the
            # stuck pair stays stuck and the run never finishes.
            later = reference(args, n, goods, d + args.confirm)
            if "crash" not in later and (later["finished"] or not stuck(later["state_at_cap"])):
                problems.append(f"reference moved on within {args.confirm} ticks of the deadlock")
    elif kind == "fault":
        # Tick for tick up to the last tick the reference completes, then the same exception
        # in the next one, with the same counts at that moment.
        t = ours["steps"]
        before = engine(args, n, goods, t - 1)
        ref = reference(args, n, goods, t - 1)
        if "crash" in ref:
            problems.append(f"reference raised before tick {t}: {ref['crash'][-1]}")
        else:
            problems += diff(figures_ours(before), figures_ref(ref))
        at = reference_at_crash(args, n, goods, t)
        where = ours["fault"].split(":")[0]
        exc, frame = FAULT_SIGNATURES[where]
        if at["error"] is None or at["tick"] != t or not at["error"].startswith(exc) or not at["error"].endswith(frame):
            problems.append(f"reference: {at['error']} in tick {at['tick']} (engine: {ours['fault']} in tick {t})")
        mine = {"S": ours["S"], "C": ours["C"], "delivered": ours["delivered"],
                "per_robot": [[r["collisions"], r["charges"]] for r in ours["per_robot"]]}
        problems += diff(mine, {k: at[k] for k in mine})
    else:
        problems.append(f"unexpected outcome {kind}")
    return n, goods, kind, problems


def main() -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--cases", type=int, default=1000)
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--jobs", type=int, default=2)
    p.add_argument("--max-len", type=int, default=50, help="longest goods list (up to 80)")
    p.add_argument("--max-ticks", type=int, default=100000)
    p.add_argument("--confirm", type=int, default=2000, help="ticks past a deadlock to confirm it")
    p.add_argument("--reference", default=str(ROOT.parent / "shared" / "reference" / "authors-multibots"))
    p.add_argument("--engine", default=str(ROOT / "target" / "release" / "examples" / "original_run"))
    p.add_argument("--python", default=sys.executable)
    args = p.parse_args()
    if not os.access(args.engine, os.X_OK):
        sys.exit(f"{args.engine}: build it with `cargo build --release -p multibots-core --example original_run`")
    if not (Path(args.reference) / "run_authors.py").exists():
        sys.exit(f"{args.reference}: no run_authors.py there (give --reference DIR)")
    kinds: Counter[str] = Counter()
    matches = 0
    with ThreadPoolExecutor(max_workers=args.jobs) as pool:
        for k, (n, goods, kind, problems) in enumerate(pool.map(lambda k: compare(args, k), range(args.cases))):
            kinds[kind] += 1
            if problems:
                print(f"case {k} (seed {args.seed}): --robots {n} --goods {','.join(map(str, goods))} [{kind}]")
                for line in problems:
                    print(f"    {line}")
            else:
                matches += 1
            sys.stdout.flush()
    print(f"outcomes: {dict(sorted(kinds.items()))}")
    print(f"{args.cases} cases: {matches} exact matches")
    return 0 if matches == args.cases else 1


if __name__ == "__main__":
    sys.exit(main())
