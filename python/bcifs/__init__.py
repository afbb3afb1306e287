"""bcifs: iterative geometric modelling with Boundary Controlled IFS.

Designs (automata with a model) are loaded by name or path, evaluated into
numpy arrays, drawn, and written in every format of the command line::

    import bcifs
    torus = bcifs.load("doo_sabin_torus")
    mesh = torus.mesh(depth=4)          # mesh.vertices: (n, 3) float64, mesh.faces: (m, 4) int64
    torus.render("torus.glb", depth=5)  # any format of `bcifs render`
"""

from ._bcifs import BcifsError, Design, Mesh, load, subdivide

__all__ = ["BcifsError", "Design", "Mesh", "load", "subdivide"]

