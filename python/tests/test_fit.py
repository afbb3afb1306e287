"""Issue 47 in Python: `bcifs.fit(design, target, dimension=, angle=,
porosity=)` returns the fitted design (its parameters as defaults) and the
report `bcifs fit --json` prints; targets as paths, arrays, meshes; Ctrl-C
answers with the best member so far."""

import json
import pathlib
import subprocess
import sys

import numpy as np
import pytest

import bcifs
from test_module import cli


def test_a_member_is_recovered_from_a_mesh_an_array_and_a_file(tmp_path):
    design = bcifs.load("corner_cutting")
    mesh = design.mesh(depth=6, a=0.1, b=0.35)
    obj = tmp_path / "member.obj"
    subprocess.run([cli(), "render", "corner_cutting", "--depth", "6", "--param", "a=0.1", "--param", "b=0.35", "-o", str(obj)], check=True, capture_output=True)
    for target in [mesh, mesh.vertices[:, :2].tolist(), obj, str(obj)]:
        fitted, report = bcifs.fit(design, target)
        assert report["parameters"]["a"] == pytest.approx(0.1, abs=1e-6)
        assert report["parameters"]["b"] == pytest.approx(0.35, abs=1e-6)
        assert report["converges"] and report["residual"] < 1e-9
        # The fitted design carries them as its defaults.
        assert fitted.check()["parameters"]["b"] == pytest.approx(0.35, abs=1e-6)
    # The same report as the command line's.
    out = subprocess.run([cli(), "fit", "corner_cutting", "--to", str(obj), "--json"], check=True, capture_output=True, text=True)
    assert json.loads(out.stdout)["parameters"] == pytest.approx(report["parameters"], abs=1e-12)


def test_numbers_and_trimesh_targets():
    _, report = bcifs.fit(bcifs.load("cantor"), dimension=0.5)
    assert report["numbers"]["dimension"]["value"] == pytest.approx(0.5, abs=1e-9)
    assert report["numbers"]["dimension"]["within"] == 0 and report["numbers"]["dimension"]["reached"]
    # A lace's porosity (the carpet's 16 split points), as its lacunarity report measures it.
    carpet = bcifs.load("carpet")
    fitted, report = bcifs.fit(carpet, porosity=0.5)
    assert report["numbers"]["porosity"]["reached"] and report["converges"]
    assert bcifs.lacunarity(fitted, depth=1)["porosity"][0] == pytest.approx(0.5, abs=1e-9)
    with pytest.raises(bcifs.BcifsError, match=r"outside \[0, 1\]"):
        bcifs.fit(carpet, porosity=1.5)
    trimesh = pytest.importorskip("trimesh")
    torus = bcifs.load("doo_sabin_torus")
    member = torus.mesh(depth=2, alpha=0.62).to_trimesh()
    assert isinstance(member, trimesh.Trimesh)
    _, report = bcifs.fit(torus, member)
    assert report["parameters"]["alpha"] == pytest.approx(0.62, abs=1e-6)


def test_control_points_are_fitted_when_asked():
    moved = bcifs.load("corner_cutting").to_toml().replace("points = [\n  [0.0, 0.0],", "points = [\n  [0.2, -0.1],")
    assert "[0.2, -0.1]" in moved
    member = bcifs.Design.from_toml(moved).mesh(depth=6, a=0.1, b=0.35)
    fitted, report = bcifs.fit(bcifs.load("corner_cutting"), member, control_points=True)
    assert report["control_points"][0] == pytest.approx([0.2, -0.1], abs=1e-9)
    assert report["parameters"]["a"] == pytest.approx(0.1, abs=1e-9)
    # The fitted design (its defaults and its model's points) draws the member.
    assert np.allclose(fitted.mesh(depth=6).vertices, member.vertices, rtol=0, atol=1e-9)


def test_bad_input_raises_before_any_work():
    design = bcifs.load("corner_cutting")
    with pytest.raises(bcifs.BcifsError, match="nothing to fit to"):
        bcifs.fit(design)
    with pytest.raises(bcifs.BcifsError, match="no free parameter"):
        bcifs.fit(bcifs.load("gasket"), dimension=1.5)
    with pytest.raises(bcifs.BcifsError, match="not finite"):
        bcifs.fit(design, np.array([[0.0, np.nan]]))
    with pytest.raises(bcifs.BcifsError, match=r"\(n, 2\) or \(n, 3\)"):
        bcifs.fit(design, np.zeros((4, 5)))


def test_ctrl_c_returns_the_best_member_so_far():
    """A long fit (noisy points, many starts) interrupted: the call returns
    the best member found, proven to converge, marked interrupted."""
    import signal
    import time

    script = (
        "import bcifs, numpy as np, json\n"
        "d = bcifs.load('corner_cutting')\n"
        "p = d.mesh(depth=7, a=0.1, b=0.35).vertices[:, :2]\n"
        "p = p + np.random.default_rng(1).uniform(-0.02, 0.02, p.shape)\n"
        "print('start', flush=True)\n"
        "f, r = bcifs.fit(d, p, starts=200)\n"
        "print(json.dumps(r), flush=True)\n"
    )
    child = subprocess.Popen([sys.executable, "-c", script], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    assert child.stdout.readline().strip() == "start"
    time.sleep(2.0)
    assert child.poll() is None, "still fitting when interrupted"
    child.send_signal(signal.SIGINT)
    out, err = child.communicate(timeout=60)
    assert child.returncode == 0, err
    report = json.loads(out)
    assert report["interrupted"] and report["converges"]
    assert abs(report["parameters"]["a"] - 0.1) < 0.05


def test_starts_run_on_dask_workers():
    """With a Dask client the starts run on the workers (processes, each
    loading the design from its TOML text), one each: the same member as the
    serial fit, the starts counted."""
    distributed = pytest.importorskip("dask.distributed")
    design = bcifs.load("corner_cutting")
    points = design.mesh(depth=6, a=0.1, b=0.35).vertices
    # Noisy, so that no start fits exactly and every start runs.
    noisy = points + np.random.default_rng(3).uniform(-0.005, 0.005, points.shape) * [1, 1, 0]
    _, serial = bcifs.fit(design, noisy, starts=3)
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None) as cluster:
        with distributed.Client(cluster) as client:
            done = []
            fitted, report = bcifs.fit(design, noisy, starts=3, client=client, progress=lambda k, n: done.append((k, n)))
    assert report["starts"] == len(done) and done[-1][0] == done[-1][1] >= 2
    assert report["parameters"] == pytest.approx(serial["parameters"], abs=1e-6)
    assert report["converges"] and fitted.check()["parameters"]["a"] == pytest.approx(report["parameters"]["a"])
