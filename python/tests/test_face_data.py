"""Issue 46 §2 and §6: per-face data through `subdivide` (materials, groups,
colours follow the scheme), and Doo-Sabin's digon left out of the arrays as
it is left out of the files."""

import pathlib
import subprocess

import numpy as np
import pytest

import bcifs
from test_module import cli, read_obj

ROOT = pathlib.Path(__file__).resolve().parents[2]

CUBE_V = np.array([[x, y, z] for z in (0.0, 1.0) for y in (0.0, 1.0) for x in (0.0, 1.0)])
CUBE_F = [[0, 2, 3, 1], [4, 5, 7, 6], [0, 1, 5, 4], [1, 3, 7, 5], [3, 2, 6, 7], [2, 0, 4, 6]]


def centroids(mesh):
    return np.array([mesh.vertices[list(f)].mean(axis=0) for f in mesh.faces])


@pytest.mark.parametrize("scheme", ["catmull-clark", "doo-sabin", "loop", "sqrt3"])
@pytest.mark.parametrize("net", [False, True])
def test_each_face_carries_the_data_of_the_face_it_comes_from(scheme, net):
    """A cube with a material per side (Loop and √3 after `triangulate=True`,
    whose split keeps each side's triangles on it): every face of the result
    has its side's material, a colour row and a name alike, except the
    faces of edges and corners (Doo-Sabin, √3), which take the lower of the
    sides they span (where each lies is tested on flat grids in
    tests/mesh/sources.rs); Catmull-Clark's and Doo-Sabin's faces lie
    furthest out along their side's axis."""
    materials = np.array([10, 11, 12, 13, 14, 15])
    colours = np.arange(18, dtype=np.uint8).reshape(6, 3)
    names = np.array(["bottom", "top", "front", "right", "back", "left"])
    triangulate = scheme in ("loop", "sqrt3")
    mesh = bcifs.subdivide(
        CUBE_V, CUBE_F, scheme, 2, net=net, triangulate=triangulate,
        face_data={"material": materials, "colour": colours, "name": names},
    )
    sources = mesh.face_sources
    assert sources.shape == (len(mesh.faces),) and sources.dtype == np.int64
    assert np.array_equal(mesh.face_data["material"], materials[sources])
    assert np.array_equal(mesh.face_data["colour"], colours[sources])
    assert list(mesh.face_data["name"]) == list(names[sources])
    assert set(sources) == set(range(6)), "every side keeps faces"
    if scheme in ("catmull-clark", "loop"):
        # Splits: 16 quads per side in order; two triangles per side, 16 each.
        assert np.array_equal(sources, np.repeat(np.arange(6), 16 if scheme == "catmull-clark" else 32))
    if scheme in ("catmull-clark", "doo-sabin"):
        # Each side's outward axis and sign: the face's centroid is furthest out
        # along its side's axis (a tie on the cube's edges and corners).
        side = [(2, -1), (2, 1), (1, -1), (0, 1), (1, 1), (0, -1)]
        c = centroids(mesh) - 0.5
        for k, s in enumerate(sources):
            axis, sign = side[s]
            assert sign * c[k, axis] >= np.abs(c[k]).max() - 1e-9, (k, s, c[k])


def test_face_data_must_have_a_row_per_face():
    with pytest.raises(bcifs.BcifsError, match=r"face_data\[material\] has 5 rows for 6 faces"):
        bcifs.subdivide(CUBE_V, CUBE_F, "catmull-clark", 1, face_data={"material": np.arange(5)})
    plain = bcifs.subdivide(CUBE_V, CUBE_F, "catmull-clark", 1)
    assert plain.face_sources is None and plain.face_data is None


@pytest.mark.parametrize("net", [False, True])
def test_doo_sabin_digon_is_left_out_of_the_arrays_as_of_the_files(tmp_path, net):
    """Suzanne has a vertex of valence 2: Doo-Sabin makes a two-corner face
    there, a doubled edge that the files leave out. The arrays leave it out
    too: the same faces as `bcifs surface` writes, every face of at least
    three corners, and the sources shortened alike."""
    source = ROOT / "tests/data/suzanne.obj"
    v, f = read_obj(source)
    out = tmp_path / "ds.obj"
    args = [cli(), "surface", str(source), "--scheme", "doo-sabin", "--depth", "2", "-o", str(out)]
    subprocess.run(args + (["--net"] if net else []), check=True, capture_output=True)
    ev, ef = read_obj(out)
    mesh = bcifs.subdivide(v, f, "doo-sabin", 2, net=net, face_data={"index": np.arange(len(f))})
    assert min(len(x) for x in mesh.faces) >= 3
    assert [list(x) for x in mesh.faces] == ef
    assert np.allclose(mesh.vertices, ev, rtol=0, atol=1e-12)
    assert len(mesh.face_sources) == len(ef)
