"""Convergence verdicts of the corner-cutting family over its (a, b) plane,
on Dask: a LocalCluster here, or a remote scheduler whose workers have the
module installed (`pip install ./python`):

    python sweep_dask.py                      # a local cluster of two processes
    python sweep_dask.py tcp://scheduler:8786 # the same code on a cluster

Writes sweep.png (green converges, red diverges, grey a matrix fails, amber undecided).
"""

import sys

import numpy as np
from dask.distributed import Client, LocalCluster

import bcifs

COLOURS = {1: (150, 205, 150), 0: (240, 200, 80), -1: (215, 60, 60), -2: (228, 228, 228)}


def sweep(client):
    return bcifs.sweep("corner_cutting", x=("a", -1, 1, 256), y=("b", -1, 1, 256), client=client)


def main():
    if len(sys.argv) > 1:
        with Client(sys.argv[1]) as client:
            verdicts = sweep(client)
    else:
        with LocalCluster(n_workers=2, threads_per_worker=1, dashboard_address=None) as cluster, Client(cluster) as client:
            verdicts = sweep(client)
    picture = np.zeros(verdicts.shape + (3,), dtype=np.uint8)
    for code, colour in COLOURS.items():
        picture[verdicts == code] = colour
    try:
        from PIL import Image

        Image.fromarray(picture).save("sweep.png")
        print("sweep.png:", {k: int((verdicts == k).sum()) for k in COLOURS})
    except ImportError:
        print({k: int((verdicts == k).sum()) for k in COLOURS})


if __name__ == "__main__":
    main()
