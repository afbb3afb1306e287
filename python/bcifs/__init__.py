"""bcifs: iterative geometric modelling with Boundary Controlled IFS.

Designs (automata with a model) are loaded by name or path, evaluated into
numpy arrays, drawn, and written in every format of the command line::

    import bcifs
    torus = bcifs.load("doo_sabin_torus")
    mesh = torus.mesh(depth=4)          # mesh.vertices: (n, 3) float64, mesh.faces: (m, 4) int64
    torus.render("torus.glb", depth=5)  # any format of `bcifs render`
"""

import os

import numpy as np

from ._bcifs import (
    REGIONS,
    BcifsError,
    Builder,
    Design,
    Mesh,
    __version__,
    analyze_curve,
    dimension,
    lacunarity,
    load,
    map_colours,
    option_keys,
    pattern,
    polyhedral_lace,
    profile,
    subdivide,
    sweep_rows,
)
from ._bcifs import (
    fit as _fit,
    fit_starts as _fit_starts,
    topology,
)

__all__ = [
    "__version__",
    "REGIONS",
    "BcifsError",
    "Builder",
    "Design",
    "Mesh",
    "analyze_curve",
    "dimension",
    "fit",
    "lacunarity",
    "load",
    "map_colours",
    "option_keys",
    "pattern",
    "polyhedral_lace",
    "profile",
    "subdivide",
    "sweep",
    "topology",
]


def _sweep_band(toml, x, y, rows, what, thorough):
    """One band of rows of a sweep (what a Dask worker runs: the design travels as its TOML text)."""
    return sweep_rows(toml, x, y, rows, what, thorough)


def _axis(key, axis):
    """`(NAME, lo, hi, n)` checked: finite bounds with lo < hi, at least one sample."""
    try:
        name, lo, hi, n = axis
        lo, hi, n = float(lo), float(hi), int(n)
    except (TypeError, ValueError):
        raise BcifsError(f"{key}={axis!r}: expected (NAME, lo, hi, n)") from None
    if not (np.isfinite(lo) and np.isfinite(hi) and lo < hi):
        raise BcifsError(f"{key}: the range {lo} to {hi} must be finite and increasing (lo < hi)")
    if n < 1:
        raise BcifsError(f"{key}: {n} samples: at least 1")
    return (str(name), lo, hi, n)


def sweep(design, x, y, what="verdict", client=None, tiles=None, thorough=False, scheduler=None):
    """A parameter plane of `design`: `x` and `y` are `(NAME, lo, hi, n)`,
    the other parameters at their defaults; an (ny, nx) array, row 0 at the
    top (y = hi), pixel centres as `bcifs analyze map` samples them, of

    - ``what="verdict"``: int8 convergence verdicts: 1 converges, 0
      undecided, -1 diverges (JSR >= 1), -2 a subdivision matrix fails the
      per-matrix condition of Zhang et al. (2015) §3;
    - ``what="region"``: int8 regions of a curve family (their Fig. 8), an
      index into `bcifs.REGIONS`;
    - ``what="angle"``: float64 junction angles of a curve family in
      degrees (NaN where there are no half-tangents);
    - ``what="dimension"``: float64 box-counting dimensions where the bounds
      prove convergence (NaN elsewhere);
    - ``what="porosity"``, ``what="lacunarity"``: float64 porosity and
      gliding-box lacunarity Λ(9) of the depth-4 cells where the bounds prove
      convergence (NaN elsewhere): how the parameters move the holes.

    The same values as `bcifs analyze map --what WHAT -o map.csv`.

    The plane is split into `tiles` bands of rows; with `client` (a
    `dask.distributed.Client`) the bands run on its workers, each loading
    the design from its TOML text; with `scheduler` (any Dask scheduler:
    ``"processes"``, or Ray's ``ray.util.dask.ray_dask_get`` to run them as
    Ray tasks) as `dask.delayed` tasks; otherwise here. The array is the
    same either way, bit for bit.
    """
    design = design if isinstance(design, Design) else load(design)
    text = design.to_toml()
    x, y = _axis("x", x), _axis("y", y)
    # Checked here, before any band is sent (a misspelt name used to fail on every worker).
    names = design.parameters
    for key, axis in (("x", x), ("y", y)):
        if axis[0] not in names:
            raise BcifsError(f"{key}: `{axis[0]}` is not a parameter of {design.name}; its parameters: {', '.join(names)}")
    if x[0] == y[0]:
        raise BcifsError(f"x and y both sweep `{x[0]}`: give two different parameters")
    ny = y[3]
    if tiles is None:
        workers = len(client.scheduler_info()["workers"]) if client is not None else (os.cpu_count() or 1)
        workers = workers if scheduler is None else max(workers, 4)
        tiles = max(1, min(ny, 4 * workers))
    edges = [round(k * ny / tiles) for k in range(tiles + 1)]
    bands = [(a, b) for a, b in zip(edges, edges[1:]) if b > a]
    if client is None and scheduler is not None:
        import dask

        tasks = [dask.delayed(_sweep_band, pure=True)(text, x, y, band, what, thorough) for band in bands]
        parts = list(dask.compute(*tasks, scheduler=scheduler))
    elif client is None:
        parts = [_sweep_band(text, x, y, band, what, thorough) for band in bands]
    else:
        k = len(bands)
        futures = client.map(_sweep_band, [text] * k, [x] * k, [y] * k, bands, [what] * k, [thorough] * k, pure=False)
        parts = client.gather(futures)
    if parts:
        return np.concatenate(parts, axis=0)
    return np.zeros((0, x[3]), dtype=np.int8 if what in ("verdict", "region", "regions") else np.float64)


def _fit_from(toml, points, free_pose, numbers, depth, start, control_points):
    """One start of a fit, on a worker: the fitted design's TOML and the report."""
    design = Design.from_toml(toml)
    dimension, angle, porosity = numbers
    target = np.asarray(points) if len(points) else None
    fitted, report = _fit(
        design, target, dimension, angle, porosity, depth=depth, start=start, free_pose=free_pose, control_points=control_points
    )
    return fitted.to_toml(), report


def fit(
    design,
    target=None,
    dimension=None,
    angle=None,
    porosity=None,
    depth=None,
    starts=4,
    progress=None,
    client=None,
    control_points=False,
):
    """Fits `design`'s free parameters to `target` (a path to an OBJ, OFF,
    PLY or PNG file, an (n, 2) or (n, 3) array, a `bcifs.Mesh` or trimesh
    mesh) and/or numbers (`dimension`, `angle` in degrees, `porosity`),
    staying where convergence is proven: `(fitted design, report)`, the
    report as `bcifs fit --json` prints it. With a Dask `client`, the starts
    (the defaults and the best of a sample of the convergence ranges,
    `starts` of them) run on its workers, one each, and the lowest residual
    is kept; `progress(done, total)` then counts the starts done.
    `control_points=True` fits the model's control points too."""
    if isinstance(design, (str, os.PathLike)):
        design = load(design)
    if client is None:
        return _fit(
            design, target, dimension, angle, porosity, depth=depth, starts=starts, progress=progress, control_points=control_points
        )
    members, points, free_pose = _fit_starts(design, target, dimension, angle, porosity, depth=depth, starts=starts)
    toml = design.to_toml()
    numbers = (dimension, angle, porosity)
    args = (toml, points, free_pose, numbers, depth)
    futures = [client.submit(_fit_from, *args, m, control_points, pure=False) for m in members]
    results = []
    for k, future in enumerate(futures):
        results.append(future.result())
        if progress is not None:
            progress(k + 1, len(futures))
    best_toml, best = min(results, key=lambda r: r[1]["residual"])
    best = dict(best)
    best["starts"] = len(members)
    best["iterations"] = sum(r[1]["iterations"] for r in results)
    return Design.from_toml(best_toml), best
