"""`bcifs explore` in a real browser: Debian's headless Chromium driven by
selenium (chromium-driver). The page loads the design, draws the attractor
and the map, follows a slider (the URL holds the parameters), sets the
parameters from a click on the map, shows a divergent point as such, and a
link reopens the same member, a one-parameter family (the ternary scheme's
tension) has a strip, the slider ranges are editable, a solid turns and zooms in
the WebGL 3D view over the export's GLB. Skipped, with the reason, without Chromium,
chromium-driver or selenium (`.ci/run` installs them)."""

import shutil
import subprocess
import time
import urllib.parse

import pytest

from test_module import cli


def browser():
    webdriver = pytest.importorskip("selenium.webdriver", reason="selenium is not installed (pip install selenium)")
    binary = shutil.which("chromium")
    driver = shutil.which("chromedriver")
    if not binary or not driver:
        pytest.skip("Chromium or chromium-driver is not installed (apt-get install chromium chromium-driver)")
    from selenium.webdriver.chrome.service import Service

    options = webdriver.ChromeOptions()
    options.binary_location = binary
    # WebGL without a GPU: Chromium's software renderer (SwiftShader), which it asks to be allowed.
    flags = ["--headless=new", "--no-sandbox", "--disable-gpu", "--window-size=1400,900", "--disable-dev-shm-usage"]
    for flag in flags + ["--enable-unsafe-swiftshader", "--use-angle=swiftshader"]:
        options.add_argument(flag)
    return webdriver.Chrome(service=Service(driver), options=options)


@pytest.fixture(scope="module")
def server():
    child = subprocess.Popen([cli(), "explore", "corner_cutting", "--port", "0", "--no-open"], stdout=subprocess.PIPE, text=True)
    url = child.stdout.readline().strip()
    assert url.startswith("http://127.0.0.1:")
    yield url
    child.send_signal(2)
    child.wait(timeout=10)


@pytest.fixture(scope="module")
def page():
    driver = browser()
    yield driver
    driver.quit()


def wait(predicate, timeout=20.0):
    started = time.monotonic()
    while time.monotonic() - started < timeout:
        value = predicate()
        if value:
            return value
        time.sleep(0.1)
    raise AssertionError("timed out")


def loaded(page, element_id):
    return page.execute_script(f"const i = document.getElementById('{element_id}'); return i.complete && i.naturalWidth > 0;")


def params(page):
    return dict(urllib.parse.parse_qsl(urllib.parse.urlparse(page.current_url).query))


def test_the_page_follows_sliders_and_the_map(server, page, tmp_path):
    page.get(server)
    wait(lambda: page.execute_script("return document.body.dataset.ready === 'yes'"))
    assert page.find_element("id", "name").text == "corner_cutting"
    wait(lambda: loaded(page, "picture"))
    wait(lambda: loaded(page, "map"))
    sliders = page.find_elements("css selector", "#sliders input[type=range]")
    assert [s.get_attribute("id") for s in sliders] == ["param-a", "param-b"]
    wait(lambda: "converges" in page.find_element("id", "verdict").text)
    assert "junction angle" in page.find_element("id", "check").text
    # A slider moves: the URL holds the new value, the picture is redrawn.
    before = page.execute_script("return document.getElementById('picture').src")
    page.execute_script(
        "const s = document.getElementById('param-a'); s.value = 0.4;"
        "s.dispatchEvent(new Event('input')); s.dispatchEvent(new Event('change'));"
    )
    wait(lambda: abs(float(params(page).get("a", "nan")) - 0.4) < 1e-3)
    wait(lambda: page.execute_script("return document.getElementById('picture').src") != before and loaded(page, "picture"))
    # A click on the map sets both parameters (the map spans the ranges, widened by half each side).
    image = page.find_element("id", "map")
    from selenium.webdriver.common.action_chains import ActionChains

    ActionChains(page).move_to_element_with_offset(image, 0, 0).click().perform()  # the centre
    centre = wait(lambda: params(page) if abs(float(params(page)["a"]) - 0.4) > 1e-3 else None)
    design = page.execute_script("return state.design.parameters")
    for p in design:
        lo, hi = p["range"]
        assert abs(float(centre[p["name"]]) - (lo + hi) / 2) < 0.02 * (hi - lo) * 2, (centre, p)
    marker = page.find_element("id", "marker").value_of_css_property("left")
    assert marker.endswith("px") or marker.endswith("%")
    wait(lambda: loaded(page, "picture"))
    # The smooth map asks for its threshold, and is drawn (no refusal where the map is).
    page.execute_script("const k = document.getElementById('mapkind'); k.value = 'smooth'; k.dispatchEvent(new Event('change'));")
    assert page.find_element("id", "threshold-box").is_displayed()
    wait(lambda: loaded(page, "map") and page.find_element("id", "map-refusal").get_attribute("hidden") is not None)
    page.execute_script("const k = document.getElementById('mapkind'); k.value = 'verdict'; k.dispatchEvent(new Event('change'));")
    wait(lambda: loaded(page, "map"))
    page.save_screenshot(str(tmp_path / "explore.png"))  # the README's picture
    assert (tmp_path / "explore.png").stat().st_size > 10_000


def test_a_divergent_point_is_shown_as_such_and_a_link_reopens_a_member(server, page):
    page.get(server + "?a=-0.9&b=0.95&depth=5")
    wait(lambda: page.execute_script("return document.body.dataset.ready === 'yes'"))
    wait(lambda: "diverges" in page.find_element("id", "status").text)
    assert page.execute_script("return document.getElementById('picture').style.opacity") == "0.25"
    wait(lambda: "diverges" in page.find_element("id", "verdict").text)
    assert page.find_element("id", "param-a").get_attribute("value") == "-0.9", "the slider's range widens to the value given"
    assert float(page.find_element("id", "range-a-0").get_attribute("value")) == -0.9
    assert page.execute_script("return state.values.a") == -0.9
    page.get(server + "?a=0.3&b=0.2&depth=4")
    wait(lambda: page.execute_script("return document.body.dataset.ready === 'yes'"))
    assert page.execute_script("return [state.values.a, state.values.b, state.depth]") == [0.3, 0.2, 4]
    href = page.find_element("id", "export-obj").get_attribute("href")
    assert "a=0.3" in href and "depth=4" in href


def test_fit_to_a_file_moves_the_sliders_to_the_member(server, page, tmp_path):
    """Issue 47 §4: "Fit to…" uploads a file (the OBJ `bcifs render` wrote of
    the member a = 0.1, b = 0.35); the sliders move to it, proven to
    converge; a file of another kind is refused with the library's reason."""
    obj = tmp_path / "member.obj"
    subprocess.run([cli(), "render", "corner_cutting", "--depth", "6", "--param", "a=0.1", "--param", "b=0.35", "-o", str(obj)], check=True, capture_output=True)
    page.get(server + "?depth=5")
    wait(lambda: page.execute_script("return document.body.dataset.ready === 'yes'"))
    page.find_element("id", "fit-file").send_keys(str(obj))
    wait(lambda: "fitted to member.obj" in page.find_element("id", "fit-status").text)
    assert "proven to converge" in page.find_element("id", "fit-status").text
    a, b = page.execute_script("return [state.values.a, state.values.b]")
    assert abs(a - 0.1) < 1e-6 and abs(b - 0.35) < 1e-6
    slider = page.find_element("id", "param-a")  # a range input snaps to its steps; the state keeps the value
    assert abs(float(slider.get_attribute("value")) - 0.1) <= float(slider.get_attribute("step"))
    wait(lambda: "a=0.0999" in page.current_url or "a=0.1" in page.current_url)
    bad = tmp_path / "notes.txt"
    bad.write_text("hello")
    page.find_element("id", "fit-file").send_keys(str(bad))
    wait(lambda: "not fitted" in page.find_element("id", "fit-status").text)
    assert "not `.txt`" in page.find_element("id", "fit-status").text


def test_a_surface_turns_when_dragged(page):
    child = subprocess.Popen([cli(), "explore", "doo_sabin_torus", "--port", "0", "--no-open"], stdout=subprocess.PIPE, text=True)
    try:
        url = child.stdout.readline().strip()
        page.get(url + "?depth=4")
        wait(lambda: page.execute_script("return document.body.dataset.ready === 'yes'"))
        wait(lambda: loaded(page, "picture"))
        assert page.find_element("id", "mapbox").is_displayed(), "three parameters: a map of two of them"
        before = page.execute_script("return document.getElementById('picture').src")
        from selenium.webdriver.common.action_chains import ActionChains

        ActionChains(page).drag_and_drop_by_offset(page.find_element("id", "picture"), 80, 30).perform()
        view = wait(lambda: params(page).get("view") if params(page).get("view") != "30,35" else None)
        yaw, pitch = (float(v) for v in view.split(","))
        assert (yaw, pitch) == (70.0, 50.0), view
        wait(lambda: page.execute_script("return document.getElementById('picture').src") != before and loaded(page, "picture"))
    finally:
        child.send_signal(2)
        child.wait(timeout=10)


def test_a_one_parameter_family_has_a_strip_and_ranges_are_editable(page, tmp_path):
    file = tmp_path / "ternary5_w.toml"
    file.write_text(subprocess.run([cli(), "scheme", "ifs", "ternary5", "--omega", "w", "--print"], check=True, capture_output=True, text=True).stdout)
    child = subprocess.Popen([cli(), "explore", str(file), "--port", "0", "--no-open"], stdout=subprocess.PIPE, text=True)
    try:
        url = child.stdout.readline().strip()
        page.get(url + "?depth=5")
        wait(lambda: page.execute_script("return document.body.dataset.ready === 'yes'"))
        wait(lambda: loaded(page, "map") and loaded(page, "picture"))
        assert not page.find_element("id", "mapy").is_displayed(), "one parameter: no y axis"
        width, height = page.execute_script("const m = document.getElementById('map'); return [m.naturalWidth, m.naturalHeight]")
        assert width > 4 * height, (width, height)
        # A click at a quarter of the strip sets ω there (the strip spans the range widened by half each side).
        from selenium.webdriver.common.action_chains import ActionChains

        strip = page.find_element("id", "map")
        lo, hi = page.execute_script("return state.map.xr")
        box_width = strip.size["width"]
        ActionChains(page).move_to_element_with_offset(strip, -box_width // 4, 0).click().perform()
        w = wait(lambda: float(params(page)["w"]) if abs(float(params(page)["w"]) - 0.06) > 1e-6 else None)
        assert abs(w - (lo + (hi - lo) / 4)) < 0.02 * (hi - lo), (w, lo, hi)
        wait(lambda: page.find_element("id", "verdict").text != "")
        # The slider's range is editable: the slider and the strip follow it.
        before = page.execute_script("return document.getElementById('map').src")
        page.execute_script(
            "const b = document.getElementById('range-w-0'); b.value = -0.5; b.dispatchEvent(new Event('change'));"
        )
        assert page.find_element("id", "param-w").get_attribute("min") == "-0.5"
        wait(lambda: page.execute_script("return document.getElementById('map').src") != before and loaded(page, "map"))
        assert page.execute_script("return state.map.xr[0]") < -0.5
        # The ternary scheme is no curve of two halves (T0, T1): no curve maps (regions, angles).
        kinds = page.execute_script("return [...document.getElementById('mapkind').options].map((o) => o.value)")
        assert kinds == ["verdict", "dimension", "porosity", "lacunarity"], kinds
    finally:
        child.send_signal(2)
        child.wait(timeout=10)


def _refusal_shown(page, element_id):
    """The reason shown where the picture or map would be, or ''."""
    return page.execute_script(
        f"const r = document.getElementById('{element_id}-refusal'); return r && !r.hidden ? r.textContent : '';"
    )


def test_a_surface_page_driven_for_a_minute_stays_within_its_budget(page):
    """The torus page left open and driven (sliders, turns, depth 16, maps of
    every kind) brought the machine down: every request now estimates its
    memory, stops at its time budget and gives way to the page's newer one.
    The server runs under a 3 GiB address-space limit (`prlimit --as`), as the
    report that found it did, and must stay alive and answer throughout."""
    prlimit = shutil.which("prlimit")
    if not prlimit:
        pytest.skip("prlimit (util-linux) is not installed")
    child = subprocess.Popen(
        [prlimit, f"--as={3 << 30}", cli(), "explore", "doo_sabin_torus", "--port", "0", "--no-open"],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    try:
        url = child.stdout.readline().strip()
        assert url.startswith("http://127.0.0.1:"), child.stderr.read()
        # Sloppy URL values open with the defaults, not NaN.
        page.get(url + "?alpha=abc&depth=zz&view=1,x")
        wait(lambda: page.execute_script("return document.body.dataset.ready === 'yes'"))
        defaults = page.execute_script("return [state.values.alpha, state.depth, state.yaw, state.pitch, state.design.parameters[0].default]")
        assert defaults[:4] == [defaults[4], 6, 30, 35], defaults
        assert page.find_element("id", "depth").get_attribute("max") == "16"
        kinds = page.execute_script("return [...document.getElementById('mapkind').options].map((o) => o.value)")
        assert kinds == ["verdict", "dimension", "porosity", "lacunarity"], "a surface is offered no curve maps: %s" % kinds
        started = time.monotonic()
        step = 0
        while time.monotonic() - started < 60:
            step += 1
            value = 0.5 + 0.02 * (step % 10)
            page.execute_script(
                f"const s = document.getElementById('param-alpha'); s.value = {value};"
                "s.dispatchEvent(new Event('input')); s.dispatchEvent(new Event('change'));"
            )
            if step % 4 == 0:
                page.execute_script(
                    f"const d = document.getElementById('depth'); d.value = {16 if step % 8 == 0 else 5};"
                    "d.dispatchEvent(new Event('input')); d.dispatchEvent(new Event('change'));"
                )
            if step % 6 == 0:
                kind = "dimension" if step % 12 == 0 else "verdict"
                page.execute_script(
                    f"const k = document.getElementById('mapkind'); k.value = '{kind}'; k.dispatchEvent(new Event('change'));"
                )
            if step % 3 == 0:
                page.execute_script(
                    f"const y = document.getElementById('yaw'); y.value = {(step * 15) % 360 - 180};"
                    "y.dispatchEvent(new Event('input')); y.dispatchEvent(new Event('change'));"
                )
            time.sleep(0.5)
            assert child.poll() is None, "the server died: %s" % child.stderr.read()
        with open(f"/proc/{child.pid}/status") as status:
            peak = next(int(line.split()[1]) for line in status if line.startswith("VmHWM:")) << 10
        assert peak < 3 << 30, f"peak resident memory {peak >> 20} MiB"
        # The page settles: a picture, or the reason there is none, where the picture is.
        page.execute_script(
            "const d = document.getElementById('depth'); d.value = 5; d.dispatchEvent(new Event('input')); d.dispatchEvent(new Event('change'));"
        )
        wait(lambda: loaded(page, "picture") and not _refusal_shown(page, "picture"), timeout=60)
        # A map over the time budget says so where the map would be, not a broken image.
        page.execute_script("const k = document.getElementById('mapkind'); k.value = 'dimension'; k.dispatchEvent(new Event('change'));")
        shown = wait(lambda: _refusal_shown(page, "map") or (loaded(page, "map") and "map"), timeout=90)
        assert shown == "map" or "budget" in shown, shown
        import urllib.request

        with urllib.request.urlopen(url + "api/design", timeout=20) as answer:
            assert answer.status == 200
        assert child.poll() is None
    finally:
        child.send_signal(2)
        child.wait(timeout=30)


def glb_triangles(path):
    """The triangles of a GLB's first primitive (its index count over 3), read here with the standard library."""
    import json
    import struct

    data = path.read_bytes()
    length = struct.unpack("<I", data[12:16])[0]
    gltf = json.loads(data[20 : 20 + length])
    primitive = gltf["meshes"][0]["primitives"][0]
    return gltf["accessors"][primitive["indices"]]["count"] // 3


def drawn(page):
    """The share of the 3D view's pixels that are not the white background."""
    return page.execute_script(
        "const gl = view3d.gl; const w = gl.drawingBufferWidth, h = gl.drawingBufferHeight;"
        "const px = new Uint8Array(w * h * 4); gl.readPixels(0, 0, w, h, gl.RGBA, gl.UNSIGNED_BYTE, px);"
        "let n = 0; for (let i = 0; i < px.length; i += 4) if (px[i] < 250 || px[i + 1] < 250 || px[i + 2] < 250) n++;"
        "return [n / (w * h), Array.from(px.subarray(0, px.length)).reduce((a, x, i) => (a * 31 + x * (i % 7 + 1)) % 1000000007, 7)];"
    )


def test_a_solid_turns_and_zooms_in_the_3d_view(page, tmp_path):
    """The Menger sponge's page offers the 3D view (a curve's does not): it
    loads the GLB the export gives (as many triangles as `render -o x.glb`
    writes), draws it with WebGL, turns when dragged without asking the
    server again, and zooms with the wheel (the sponge covers less of the view)."""
    glb = tmp_path / "menger.glb"
    subprocess.run([cli(), "render", "menger", "--depth", "2", "-o", str(glb)], check=True, capture_output=True)
    child = subprocess.Popen([cli(), "explore", "menger", "--port", "0", "--no-open"], stdout=subprocess.PIPE, text=True)
    try:
        url = child.stdout.readline().strip()
        page.get(url + "?depth=2")
        wait(lambda: page.execute_script("return document.body.dataset.ready === 'yes'"))
        toggle = page.find_element("id", "toggle3d")
        assert toggle.is_displayed()
        toggle.click()
        webgl = page.execute_script("return view3d.error")
        if webgl:
            pytest.skip(f"headless Chromium gives no WebGL here: {webgl}")
        triangles = wait(lambda: page.execute_script("return document.body.dataset.scene"))
        assert int(triangles) == glb_triangles(glb) > 0
        assert not page.find_element("id", "picture").is_displayed()
        share, before = drawn(page)
        assert 0.1 < share < 0.9, share
        requests = page.execute_script("return view3d.seq")
        from selenium.webdriver.common.action_chains import ActionChains

        ActionChains(page).drag_and_drop_by_offset(page.find_element("id", "scene"), 60, 20).perform()
        wait(lambda: params(page).get("view") == "60,45")
        _, after = drawn(page)
        assert after != before, "the view turned"
        assert page.execute_script("return view3d.seq") == requests, "turning asks the server for nothing"
        page.execute_script("document.getElementById('scene').dispatchEvent(new WheelEvent('wheel', {deltaY: 400, cancelable: true}))")
        zoomed, _ = drawn(page)
        assert zoomed < share, (zoomed, share)
    finally:
        child.send_signal(2)
        child.wait(timeout=10)
    # A curve has no 3D view.
    child = subprocess.Popen([cli(), "explore", "corner_cutting", "--port", "0", "--no-open"], stdout=subprocess.PIPE, text=True)
    try:
        page.get(child.stdout.readline().strip())
        wait(lambda: page.execute_script("return document.body.dataset.ready === 'yes'"))
        assert not page.find_element("id", "toggle3d").is_displayed()
    finally:
        child.send_signal(2)
        child.wait(timeout=10)
