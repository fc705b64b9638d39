#!/usr/bin/env python3
"""snap_fit_fidelity.py [BUILD_DIR] — the snap-fit's fidelity table (examples/snap_fit/README.md):
the scene with the nose unilateral and compliant at four stiffnesses. Needs the
simulators snap_fit and snap_fit_compliant from the README's build."""
import math
import re
import subprocess
import sys
import tempfile
from pathlib import Path

build = Path(sys.argv[1] if len(sys.argv) > 1 else Path(__file__).resolve().parent.parent / "build")
E, I, L = 2.5e9, 5e-3 * 1e-9 / 12, 0.02
k = 3 * E * I / L**3
alpha, mu = math.radians(30), 0.2
factor = (mu + math.tan(alpha)) / (1 - mu * math.tan(alpha))


def row(cmd, tag):
    with tempfile.TemporaryDirectory() as tmp:
        csv, log = Path(tmp) / "s.csv", Path(tmp) / "e.csv"
        p = subprocess.run(cmd + ["--event-log", str(log), "-o", str(csv)], capture_output=True, text=True, check=True)
        header, *lines = csv.read_text().splitlines()
        col = {name.split(" [")[0]: i for i, name in enumerate(header.split(","))}  # "push [N]"
        rows = [list(map(float, l.split(","))) for l in lines]
        switches = len(log.read_text().splitlines()) - 1
    P, d = col["insertion_force"], col["hook_deflection"]
    formula = max(abs(r[P] / (k * r[d] * factor) - 1) for r in rows if 0.175 < r[0] < 0.24 and r[d] > 0)
    lost = next(r[0] for r in rows if r[0] > 0.25 and r[col["in_contact"]] == 0)
    steps = re.search(r"steps\s+(\d+)", p.stderr).group(1)
    wall = re.search(r"wall time\s+([0-9.e-]+)", p.stderr).group(1)
    print(f"| {tag} | {max(r[P] for r in rows):.4f} | {max(r[d] for r in rows) * 1e3:.4f} | {formula * 100:.2f} % "
          f"| {lost:.4f} | {rows[-1][col['push']]:.4f} | {switches} | {steps} | {wall} |")


print("| contact | peak P | peak δ | formula | lost at | final push | switches | steps | wall |")
print("|---|---|---|---|---|---|---|---|---|")
row([str(build / "examples/snap_fit")], "unilateral, e = 0, μ = 0.2 (stick/slip events)")
for kc in ["1e5", "1e6", "1e7", "1e8"]:
    row([str(build / "examples/snap_fit_compliant"), "--set", f"k_contact={kc}"], f"compliant, e = 0.1, k = {kc}")
