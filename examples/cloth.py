"""A waving cloth through cdbench's broad phase, checked against the oracle each frame.

    PYTHONPATH=<prefix>/lib/python3/dist-packages /usr/bin/python3 examples/cloth.py [pipeline]

Exits 1 on a mismatch.
"""
import sys

import numpy as np

import cdbench

n = 24
quads = [(i * (n + 1) + j) for i in range(n) for j in range(n)]
faces = np.array([t for v in quads for t in ((v, v + 1, v + n + 1), (v + 1, v + n + 2, v + n + 1))])
topology = cdbench.Topology(faces)
pipeline = sys.argv[1] if len(sys.argv) > 1 else "c"
broad_phase = cdbench.BroadPhase(topology, pipeline=pipeline, executor="cpu", skip_adjacent=True)
x, y = np.meshgrid(np.linspace(0, 1, n + 1), np.linspace(0, 1, n + 1))
for frame in range(20):
    t = 0.15 * frame
    positions = np.stack([x + 0.08 * np.sin(6 * y + t), y, 0.1 * np.sin(9 * x - 2 * t)], axis=-1)
    positions = positions.reshape(-1, 3).astype(np.float32)
    stats = broad_phase.run(positions)
    same = np.array_equal(broad_phase.pairs(), cdbench.oracle_pairs(topology, positions, skip_adjacent=True))
    print(f"frame {frame:2d}  {stats['op']:16s} {stats['time_ms']:8.3f} ms  pairs {stats['pairs']:6d}  "
          f"{'= oracle' if same else 'MISMATCH'}")
    if not same:
        sys.exit(1)
print(f"{pipeline}: every frame equals the oracle")
