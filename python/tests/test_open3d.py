"""Issue 46 §6: `Mesh.to_open3d()` as Open3D users expect it: the same
vertices, triangles (faces fanned as `to_trimesh` fans them), normals,
colours and UVs, and Open3D's own checks of the result. Skipped where
Open3D is not installed (`.ci/run` installs it)."""

import pathlib

import numpy as np
import pytest

import bcifs
from test_module import read_obj

o3d = pytest.importorskip("open3d")
ROOT = pathlib.Path(__file__).resolve().parents[2]


def fan(faces):
    return np.array([[f[0], f[i], f[i + 1]] for f in faces for i in range(1, len(f) - 1)])


def test_a_closed_surface_is_a_watertight_triangle_mesh_in_open3d():
    """The Doo-Sabin torus: Open3D sees it edge- and vertex-manifold,
    watertight and orientable; its volume is the signed volume of our
    triangles (positive: facing outwards); the normals are ours."""
    mesh = bcifs.load("doo_sabin_torus").mesh(depth=4)
    t = mesh.to_open3d()
    assert isinstance(t, o3d.geometry.TriangleMesh)
    assert np.array_equal(np.asarray(t.vertices), mesh.vertices)
    triangles = fan(mesh.faces)
    assert np.array_equal(np.asarray(t.triangles), triangles)
    assert np.array_equal(np.asarray(t.vertex_normals), mesh.normals)
    assert t.is_edge_manifold() and t.is_vertex_manifold() and t.is_watertight() and t.is_orientable()
    v = mesh.vertices[triangles]
    signed = np.einsum("ij,ij->i", v[:, 0], np.cross(v[:, 1], v[:, 2])).sum() / 6
    assert signed > 0 and t.get_volume() == pytest.approx(signed, rel=1e-12)


def test_colours_uvs_curves_and_clouds_reach_open3d():
    coloured = bcifs.load("box-spline").mesh(depth=3, colour="level", palette="fire")
    t = coloured.to_open3d()
    assert np.allclose(np.asarray(t.vertex_colors) * 255, coloured.colours, atol=1e-9)
    # Suzanne's UVs through Catmull-Clark: Open3D's triangle_uvs, per triangle corner.
    v, f = read_obj(ROOT / "tests/data/suzanne.obj")
    vt, ft = [], []
    for line in (ROOT / "tests/data/suzanne.obj").read_text().splitlines():
        w = line.split()
        if w and w[0] == "vt":
            vt.append([float(x) for x in w[1:3]])
        elif w and w[0] == "f":
            ft.append([int(x.split("/")[1]) - 1 for x in w[1:]])
    smooth = bcifs.subdivide(v, f, "catmull-clark", 1, uv=np.array(vt), uv_faces=ft)
    t = smooth.to_open3d()
    expected = smooth.uv[fan(smooth.uv_faces).ravel()]
    assert np.array_equal(np.asarray(t.triangle_uvs), expected) and t.has_triangle_uvs()
    koch = bcifs.load("koch").mesh(depth=3)
    lines = koch.to_open3d()
    assert isinstance(lines, o3d.geometry.LineSet)
    assert np.array_equal(np.asarray(lines.lines), koch.edges) and np.array_equal(np.asarray(lines.points), koch.vertices)
    fern = bcifs.load("fern").mesh(depth=4)
    cloud = fern.to_open3d()
    assert isinstance(cloud, o3d.geometry.PointCloud) and np.array_equal(np.asarray(cloud.points), fern.vertices)
