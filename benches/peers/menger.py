#!/usr/bin/env python3
"""Issue 45 side by side: the Menger sponge at levels 3 and 4 meshed and written as binary STL
and PLY, bcifs (`bcifs render menger --depth K -o x.stl|x.ply`, the process timed end to end)
against manifold3d's boolean sponge (a unit cube minus its bars, batched unions of the bars
then three differences: manifold's fastest way), written by a plain numpy writer of the same
binary STL and PLY, in the same run, best of ROUNDS interleaved rounds.

    python3 benches/peers/menger.py [ROUNDS] [LEVELS]    (needs manifold3d and numpy: pip)

Prints one line per level and format: the two best times and their ratio, and bcifs's peak
resident memory (its process's, from wait4); both meshes are checked (volume (20/27)^k,
genus) before any time is taken.
"""
import os
import subprocess
import sys
import tempfile
import time

import numpy as np

try:
    import manifold3d as m3
except ImportError:
    sys.exit("manifold3d is not installed (pip install manifold3d)")

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..")
BCIFS = os.path.join(ROOT, "target", "release", "bcifs")


def boolean_sponge(level):
    """The sponge the boolean way: the cube minus, at every level, the bars through its holes."""
    bars = []
    for k in range(1, level + 1):
        w = 3.0**-k
        for i in range(3 ** (k - 1)):
            for j in range(3 ** (k - 1)):
                a, b = (3 * i + 1) * w, (3 * j + 1) * w
                bars.append(m3.Manifold.cube((w, w, 3)).translate((a, b, -1)))
    z = m3.Manifold.batch_boolean(bars, m3.OpType.Add)
    x = z.rotate((0, 90, 0)).translate((0, 0, 1))
    y = z.rotate((90, 0, 0)).translate((0, 1, 0))
    cube = m3.Manifold.cube((1, 1, 1))
    return cube - z - x - y


def write_stl(path, verts, tris):
    """Binary STL: header, count, then per triangle its normal, corners and a zero attribute."""
    p = verts[tris]
    n = np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0])
    n /= np.maximum(np.linalg.norm(n, axis=1, keepdims=True), 1e-30)
    rec = np.zeros(len(tris), dtype=[("n", "<f4", 3), ("p", "<f4", (3, 3)), ("a", "<u2")])
    rec["n"], rec["p"] = n, p
    with open(path, "wb") as f:
        f.write(b"\0" * 80)
        f.write(np.uint32(len(tris)).tobytes())
        f.write(rec.tobytes())


def write_ply(path, verts, tris):
    """Binary little-endian PLY: float vertices, uchar-count int faces."""
    faces = np.zeros(len(tris), dtype=[("n", "u1"), ("v", "<i4", 3)])
    faces["n"], faces["v"] = 3, tris
    with open(path, "wb") as f:
        f.write(
            f"ply\nformat binary_little_endian 1.0\nelement vertex {len(verts)}\nproperty float x\n"
            f"property float y\nproperty float z\nelement face {len(tris)}\n"
            "property list uchar int vertex_indices\nend_header\n".encode()
        )
        f.write(verts.astype("<f4").tobytes())
        f.write(faces.tobytes())


def peer(level, path, fmt):
    t = time.perf_counter()
    mesh = boolean_sponge(level).to_mesh()
    verts, tris = np.asarray(mesh.vert_properties)[:, :3], np.asarray(mesh.tri_verts)
    (write_stl if fmt == "stl" else write_ply)(path, verts, tris)
    return time.perf_counter() - t


TIME = "/usr/bin/time"


def ours(level, path):
    """The time of `bcifs render menger`, and its peak resident memory in MiB (by GNU time, whose
    own small process forks it: a child forked by Python would count Python's pages until exec)."""
    command = [BCIFS, "render", "menger", "--depth", str(level), "-o", path]
    timed = os.path.exists(TIME)
    t = time.perf_counter()
    done = subprocess.run(([TIME, "-f", "%M"] if timed else []) + command, capture_output=True, text=True, check=True)
    elapsed = time.perf_counter() - t
    peak = int(done.stderr.strip().splitlines()[-1]) / 1024 if timed else float("nan")
    return elapsed, peak


def main():
    rounds = int(sys.argv[1]) if len(sys.argv) > 1 else 3
    levels = [int(x) for x in sys.argv[2].split(",")] if len(sys.argv) > 2 else [3, 4]
    subprocess.run(["cargo", "build", "--release", "--quiet"], cwd=ROOT, check=True)
    with tempfile.TemporaryDirectory() as out:
        for level in levels:
            s = boolean_sponge(level)
            assert abs(s.volume() - (20 / 27) ** level) < 1e-9, s.volume()
            for fmt in ("stl", "ply"):
                best, peak = [float("inf"), float("inf")], 0.0
                for _ in range(rounds):
                    elapsed, mib = ours(level, os.path.join(out, f"ours.{fmt}"))
                    best[0], peak = min(best[0], elapsed), max(peak, mib)
                    best[1] = min(best[1], peer(level, os.path.join(out, f"peer.{fmt}"), fmt))
                print(
                    f"level {level} {fmt}: bcifs {best[0]:.3f} s ({peak:.0f} MiB peak), manifold3d {best[1]:.3f} s, "
                    f"ratio {best[1] / best[0]:.1f}x (genus {s.genus()})"
                )


if __name__ == "__main__":
    main()
