# Makes irregular5120.obj: random edge flips on a level-4 icosphere (python3 irregular5120.py, with trimesh).
import numpy as np, trimesh, random
random.seed(3)
m = trimesh.creation.icosphere(subdivisions=4)
F = [list(f) for f in m.faces]
V = m.vertices.copy()
def edge_map(F):
    e = {}
    for fi, f in enumerate(F):
        for k in range(3):
            e[(f[k], f[(k+1)%3])] = fi
    return e
flips = 0
from collections import Counter
valc = Counter(np.array(F).ravel().tolist())
for it in range(6000):
    e = edge_map(F) if it % 500 == 0 else e
    keys = list(e.keys()) if it % 500 == 0 else keys
    (a, b) = random.choice(keys)
    f1 = e.get((a, b))
    if f1 is None: continue
    f2 = e.get((b, a))
    if f2 is None or f1 == f2: continue
    c = [x for x in F[f1] if x not in (a, b)][0]
    d = [x for x in F[f2] if x not in (a, b)][0]
    if c == d or (c, d) in e or (d, c) in e: continue
    # valence check: keep valence >= 4 for a and b
    val = lambda v: valc[v]
    if val(a) <= 4 or val(b) <= 4: continue
    # faces (a,b,c) ccw and (b,a,d) ccw -> (c,d,b)?? orientation: f1 = a->b->c, f2 = b->a->d
    F[f1] = [c, a, d]
    F[f2] = [d, b, c]
    for k in list(e.keys()):
        if e[k] in (f1, f2): del e[k]
    for fi in (f1, f2):
        f = F[fi]
        for k in range(3): e[(f[k], f[(k+1)%3])] = fi
    flips += 1
    valc[a] -= 1; valc[b] -= 1; valc[c] += 1; valc[d] += 1
mesh = trimesh.Trimesh(V, np.array(F), process=False)
print(flips, len(F), mesh.is_watertight, mesh.is_winding_consistent, np.bincount(np.bincount(mesh.faces.ravel())))
mesh.export('irregular5120.obj')
