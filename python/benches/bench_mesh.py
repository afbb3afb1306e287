"""Benchmark: `Design.mesh` of the depth-8 torus into numpy against the
command line writing the same mesh as OBJ (the file the module replaces).

Best of ROUNDS interleaved rounds (the machine is shared: a ratio measured
in one run, never a lone time). Run after `pip install ./python` and
`cargo build --release`:

    python python/benches/bench_mesh.py [--rounds 5] [--depth 8]
"""

import argparse
import pathlib
import subprocess
import sys
import tempfile
import time

import bcifs

ROOT = pathlib.Path(__file__).resolve().parents[2]


def best(times):
    return min(times)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rounds", type=int, default=5)
    parser.add_argument("--depth", type=int, default=8)
    parser.add_argument("--bin", default=str(ROOT / "target/release/bcifs"))
    args = parser.parse_args()
    design = bcifs.load("doo_sabin_torus")
    module, cli, to_numpy = [], [], []
    with tempfile.TemporaryDirectory() as scratch:
        out = pathlib.Path(scratch) / "torus.obj"
        for _ in range(args.rounds):
            t = time.perf_counter()
            mesh = design.mesh(depth=args.depth)
            module.append(time.perf_counter() - t)
            t = time.perf_counter()
            subprocess.run([args.bin, "render", "doo_sabin_torus", "--depth", str(args.depth), "--up", "z", "-o", str(out)], check=True, capture_output=True)
            cli.append(time.perf_counter() - t)
            # What a script that only had the CLI would do: write the OBJ, then read it into arrays.
            t = time.perf_counter()
            subprocess.run([args.bin, "render", "doo_sabin_torus", "--depth", str(args.depth), "--up", "z", "-o", str(out)], check=True, capture_output=True)
            load_obj(out)
            to_numpy.append(time.perf_counter() - t)
    n = len(mesh.vertices)
    print(f"doo_sabin_torus depth {args.depth}: {n} vertices, {len(mesh.faces)} faces; best of {args.rounds} interleaved rounds")
    print(f"  bcifs.Design.mesh → numpy          {best(module):8.3f} s")
    print(f"  bcifs render -o torus.obj (CLI)    {best(cli):8.3f} s   ({best(cli) / best(module):.2f}× the module's time)")
    print(f"  CLI OBJ, then read into numpy      {best(to_numpy):8.3f} s   ({best(to_numpy) / best(module):.2f}×)")
    return 0 if best(module) <= best(cli) else 1


def load_obj(path):
    import numpy as np

    v, f = [], []
    with open(path) as file:
        for line in file:
            if line.startswith("v "):
                v.append(line[2:].split())
            elif line.startswith("f "):
                f.append([int(w.split("/")[0]) - 1 for w in line[2:].split()])
    return np.array(v, dtype=float), np.array(f)


if __name__ == "__main__":
    sys.exit(main())
