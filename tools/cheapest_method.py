#!/usr/bin/env python3
"""cheapest_method.py WP.csv ... — from work-precision sweeps (a simulator's
--work-precision CSV), the cheapest run per sweep that meets a relative error
of 1e-3 and of 1e-6: the integrator, its step or tolerance, and its wall
time, as a Markdown table. Only runs that ended "ok" count; a sweep none of
whose runs meets a target says so."""
import csv
import os
import sys

TARGETS = (1e-3, 1e-6)


def setting(row):
    return f"step {float(row['step_s']):.3g} s" if row["step_s"] else f"rtol {float(row['rtol']):.0e}"


def cheapest(rows, target):
    ok = [r for r in rows if r["status"] == "ok" and float(r["max_rel_error"]) <= target]
    if not ok:
        return "none reaches it"
    best = min(ok, key=lambda r: float(r["wall_s"]))
    return f"{best['solver']}, {setting(best)}: {float(best['wall_s']) * 1e3:.3g} ms"


def main(paths):
    print("| example | form | cheapest at 1e-3 | cheapest at 1e-6 |")
    print("|---|---|---|---|")
    for path in paths:
        with open(path, newline="") as f:
            rows = [r for r in csv.DictReader(f) if r["solver"] != "reference"]
        if not rows or "contact" in os.path.basename(path):
            continue
        folder = os.path.basename(os.path.dirname(path))
        stem = os.path.splitext(os.path.basename(path))[0]
        name = stem[len("work_precision_"):] if stem.startswith("work_precision_") else folder
        form = "DAE (multipliers)" if all(r["solver"] == "ida" for r in rows) else "ODE"
        print(f"| {name} | {form} | {cheapest(rows, TARGETS[0])} | {cheapest(rows, TARGETS[1])} |")


if __name__ == "__main__":
    main(sys.argv[1:])
