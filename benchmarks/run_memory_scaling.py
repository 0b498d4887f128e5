#!/usr/bin/env python3
"""Cost of the full fluid step against N, and memory (docs/performance.md "Memory").

The dam break of benchmarks/scenes/dam_break_3d.yaml (dx = 0.01 m, h/dx = 1.3, Wendland C2,
leapfrog, artificial viscosity) with its tank and water column scaled by s (3 wall layers kept),
so that N runs from ~1e4 to ~2e6 particles at the same resolution. For each N the scene runs
K1 and K2 steps on ONE thread under /usr/bin/time; the CPU time per step is
(cpu(K2) - cpu(K1)) / (K2 - K1) (set-up, initialisation and the two snapshots cancel), and the
peak resident memory of the K2 run is reported per particle. CPU time, not wall time: the
machine these numbers came from was shared and loaded.

Usage: python3 benchmarks/run_memory_scaling.py [BUILD_DIR] [N1,N2,...]
"""
import os
import re
import subprocess
import sys
import tempfile

BUILD = sys.argv[1] if len(sys.argv) > 1 else "build"
TARGETS = [int(float(x)) for x in (sys.argv[2] if len(sys.argv) > 2 else "1e4,1e5,5e5,2e6").split(",")]
K1, K2 = 2, 5

TEMPLATE = """dimension: 3
domain: {{lo: [-0.03, -0.03, -0.03], hi: [{X:.4f}, {Y:.4f}, {Z:.4f}]}}
spacing: 0.01
h_over_dx: 1.3
kernel: wendland_c2
integrator: leapfrog
end_time: 100.0
max_steps: {K}
time_step: {{adaptive: true, cfl: 1.0}}
output: {{every_steps: 100000}}
materials:
  - {{name: water, model: fluid, density: 1000, sound_speed: 20, viscosity: 1.0e-3}}
  - {{name: tank, model: wall, density: 1000}}
geometry:
  - {{shape: box, lo: [-0.03, -0.03, -0.03], hi: [{X:.4f}, {Y:.4f}, {Z:.4f}], material: tank}}
  - {{shape: box, lo: [0.0, 0.0, 0.0], hi: [{x:.4f}, {y:.4f}, {Z:.4f}], material: none}}
  - {{shape: box, lo: [0.0, 0.0, 0.0], hi: [{wx:.4f}, {y:.4f}, {wz:.4f}], material: water}}
fluid:
  gravity: [0, 0, -9.81]
  artificial_viscosity: 0.1
"""


def scene(s, k):
    x, y, z = 1.6 * s, 0.67 * s, 0.43 * s
    return TEMPLATE.format(X=x + 0.03, Y=y + 0.03, Z=z, x=x, y=y, wx=0.4 * s, wz=0.3 * s, K=k)


def timed(path, out):
    r = subprocess.run(["/usr/bin/time", "-f", "TIME %U %S %M", f"{BUILD}/poresph", "run", path,
                        "--out", out, "--force", "--threads", "1"],
                       capture_output=True, text=True, env=dict(os.environ, OMP_NUM_THREADS="1"))
    m = re.search(r"TIME ([\d.]+) ([\d.]+) (\d+)", r.stderr)
    if r.returncode != 0 or not m:
        raise RuntimeError(r.stdout[-2000:] + r.stderr[-2000:])
    return float(m.group(1)) + float(m.group(2)), int(m.group(3)) * 1024


def count(path):
    r = subprocess.run([f"{BUILD}/poresph", "info", path, "--estimate-steps", "0"],
                       capture_output=True, text=True)
    n = int(re.search(r"^particles:\s+(\d+)", r.stdout, re.M).group(1))
    fluid = int(re.search(r"^\s+water\s+(\d+)", r.stdout, re.M).group(1))
    return n, fluid


print(f"{'N':>9} {'fluid':>9} {'cpu s/step':>11} {'us/particle-step':>17} "
      f"{'us/fluid-step':>14} {'peak RSS':>10} {'B/particle':>11}")
with tempfile.TemporaryDirectory() as tmp:
    for target in TARGETS:
        s = (target / 176868.0) ** (1.0 / 3.0)
        paths = []
        for k in (K1, K2):
            p = os.path.join(tmp, f"scale_{target}_{k}.yaml")
            with open(p, "w") as f:
                f.write(scene(s, k))
            paths.append(p)
        n, fluid = count(paths[0])
        c1, _ = timed(paths[0], os.path.join(tmp, "o1"))
        c2, rss = timed(paths[1], os.path.join(tmp, "o2"))
        per = (c2 - c1) / (K2 - K1)
        print(f"{n:>9} {fluid:>9} {per:>11.4f} {per / n * 1e6:>17.3f} {per / fluid * 1e6:>14.3f} "
              f"{rss / 2**20:>8.0f} M {rss / n:>11.0f}", flush=True)
