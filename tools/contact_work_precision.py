#!/usr/bin/env python3
"""contact_work_precision.py [BUILD_DIR] — speed against accuracy for contact:
the bouncing ball (examples/bouncing_ball) as a unilateral contact and as a
compliant one (Hunt-Crossley, k = 1e6, 1e8, 1e10 N/m^1.5), each run over a
sweep of tolerances (rk4: of steps), every run's error measured against the
closed form (the gap's largest error over the first 3 s, where 9 impacts
happen: before the Zeno tail), not against its own reference. Writes
examples/bouncing_ball/work_precision_contact.{csv,png}. Wall times are the
run summary's (noisy: compare ratios within one run of this script)."""
import math
import re
import subprocess
import sys
import tempfile
from pathlib import Path

here = Path(__file__).resolve().parent.parent
build = Path(sys.argv[1] if len(sys.argv) > 1 else here / "build")
G, H0, E = 9.81, 1.0, 0.8
T0 = math.sqrt(2 * H0 / G)
V0 = G * T0
T_END = 3.0


def gap(t):
    """The closed form: free fall, then flights after impact k at t_k with e^(k+1) v0."""
    if t <= T0:
        return H0 - G * t * t / 2
    k, tk = 0, T0
    while True:
        v = E ** (k + 1) * V0
        flight = 2 * v / G
        if t <= tk + flight:
            s = t - tk
            return v * s - G * s * s / 2
        tk += flight
        k += 1


def run(sim, args):
    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp) / "o.csv"
        p = subprocess.run([str(sim), "--t-end", str(T_END), "--interval", "0.001", *args, "-o", str(out)],
                           capture_output=True, text=True)
        if p.returncode != 0:
            return None
        header, *lines = out.read_text().splitlines()
        col = [name.split(" [")[0] for name in header.split(",")].index("gap")  # "gap [m]"
        err = max(abs(float(l.split(",")[col]) - gap(float(l.split(",")[0]))) for l in lines)
    wall = float(re.search(r"wall time\s+([0-9.e-]+)", p.stderr).group(1))
    steps = int(re.search(r"steps\s+(\d+)", p.stderr).group(1))
    return wall, steps, err


rows = []
cases = [("unilateral", build / "examples/bouncing_ball", [])]
for k in ["1e6", "1e8", "1e10"]:
    cases.append((f"compliant k={k}", build / "examples/bouncing_ball_compliant", ["--set", f"k={k}"]))
for label, sim, extra in cases:
    for solver in ["cvode", "dopri5"]:
        for rtol in [1e-4, 1e-6, 1e-8, 1e-10]:
            r = run(sim, [*extra, "--solver", solver, "--rtol", f"{rtol:g}", "--atol", f"{rtol * 1e-2:g}"])
            rows.append((label, solver, f"{rtol:g}", "", r))
    for step in [1e-4, 2.5e-5]:
        r = run(sim, [*extra, "--solver", "rk4", "--step", f"{step:g}"])
        rows.append((label, "rk4", "", f"{step:g}", r))

csv = here / "examples/bouncing_ball/work_precision_contact.csv"
series = []
with csv.open("w") as f:
    f.write("series,contact,solver,rtol,step_s,wall_s,steps,max_gap_error_m,status\n")
    for label, solver, rtol, step, r in rows:
        key = f"{label.replace('compliant k=', 'k').replace(' ', '')}-{solver}"
        if key not in series:
            series.append(key)
        if r is None:
            f.write(f"{key},{label},{solver},{rtol},{step},,,,failed\n")
        else:
            f.write(f"{key},{label},{solver},{rtol},{step},{r[0]},{r[1]},{r[2]:.3e},ok\n")
print(csv.read_text())
png = csv.with_suffix(".png")
script = f"""
set datafile separator ','
set terminal pngcairo size 900, 600 font 'DejaVu Sans,10'
set output '{png}'
set title 'bouncing ball: error against the closed form (unilateral; compliant at k = 1e6, 1e8, 1e10)' noenhanced
set logscale xy
set format x '10^{{%L}}'
set format y '10^{{%L}}'
set xlabel 'wall time per run [s]'
set ylabel 'largest gap error over 3 s [m]'
set grid
set key outside right top noenhanced
plot for [s in '{" ".join(series)}'] '{csv}' every ::1 using (strcol(1) eq s ? $6 : NaN):($8 > 0 ? $8 : NaN) \\
  with linespoints linewidth 2 pointtype 7 title s
"""
subprocess.run(["gnuplot"], input=script, text=True, check=True)
print(f"wrote {csv} and {png}")
