"""Run inside Blender by test_blender.py: `blender [-b] --factory-startup
--python blender_session.py -- MODE ZIP OUT_DIR`. Installs the add-on zip,
drives its operators and writes what it saw to OUT_DIR/MODE.json (arrays as
lists) for the test to compare with the command line's files.

MODE `operators` (background): add, change a parameter, apply, curves as
curves and as edges, a cloud, subdivide Suzanne (written as OBJ for the
CLI), a divergent weight refused, the parameter map, a saved .blend.
MODE `reload` (background): the saved .blend reopened, its parameters
editable. MODE `ui` (under Xvfb, a window): undo of both operators, the
full depth once a slider rests, a screenshot of the panel.
"""

import json
import pathlib
import sys
import traceback

import bmesh
import bpy

MODE, ZIP, OUT = sys.argv[sys.argv.index("--") + 1 :][:3]
OUT = pathlib.Path(OUT)
seen = {}


def enable():
    bpy.ops.preferences.addon_install(filepath=ZIP, overwrite=True)
    bpy.ops.preferences.addon_enable(module="bcifs_blender")


def vertices(obj):
    if obj.type == "CURVE":
        return [list(p.co[:3]) for s in obj.data.splines for p in s.points]
    return [list(v.co) for v in obj.data.vertices]


def faces(obj):
    return [list(p.vertices) for p in obj.data.polygons]


def write_obj(obj, path):
    """The mesh's vertices, UVs and faces as an OBJ (its local coordinates, as Blender holds them)."""
    me = obj.data
    lines = [f"v {v.co.x!r} {v.co.y!r} {v.co.z!r}" for v in me.vertices]
    uv = me.uv_layers.active
    if uv is not None:
        lines += [f"vt {d.uv.x!r} {d.uv.y!r}" for d in uv.data]
        lines += ["f " + " ".join(f"{me.loops[k].vertex_index + 1}/{k + 1}" for k in p.loop_indices) for p in me.polygons]
    else:
        lines += ["f " + " ".join(str(i + 1) for i in p.vertices) for p in me.polygons]
    pathlib.Path(path).write_text("\n".join(lines) + "\n")


def operators():
    enable()
    bpy.ops.object.select_all(action="SELECT")
    bpy.ops.object.delete()
    assert bpy.ops.bcifs.add(source="doo_sabin_torus", depth=3) == {"FINISHED"}
    torus = bpy.context.active_object
    state = torus.data.bcifs
    seen["torus"] = {
        "type": torus.type,
        "vertices": vertices(torus),
        "faces": faces(torus),
        "smooth": all(p.use_smooth for p in torus.data.polygons),
        "params": {p.name: [p.value, p.lo, p.hi] for p in state.params},
        "verdict": state.verdict,
        "jsr": [state.jsr_lower, state.jsr_upper],
    }
    state.params["alpha"].value = 0.7  # a slider's move: the preview depth at once
    seen["preview"] = {"depth": state.shown_depth, "vertices": len(torus.data.vertices)}
    state.depth = 3
    assert bpy.ops.bcifs.apply() == {"FINISHED"}
    seen["alpha"] = {"vertices": vertices(torus), "depth": state.shown_depth}
    # A divergent point: refused, the verdict says so, the mesh kept.
    state.params["alpha"].value = 3.0
    seen["divergent"] = {"verdict": state.verdict, "message": state.message, "vertices": len(torus.data.vertices)}
    state.params["alpha"].value = 0.7
    assert bpy.ops.bcifs.map(size=64) == {"FINISHED"}
    image = bpy.data.images[f"BC-IFS map {torus.name}"]
    pixels = list(image.pixels[:])
    rgb = {tuple(round(255 * c) for c in pixels[k : k + 3]) for k in range(0, len(pixels), 4)}
    seen["map"] = {"size": list(image.size), "colours": sorted(rgb)}
    assert bpy.ops.bcifs.add(source="koch", depth=4) == {"FINISHED"}
    koch = bpy.context.active_object
    seen["koch"] = {"type": koch.type, "splines": len(koch.data.splines), "vertices": vertices(koch), "poly": koch.data.splines[0].type}
    # A curve renders: a round bevel, so its evaluated mesh has faces.
    evaluated = koch.evaluated_get(bpy.context.evaluated_depsgraph_get())
    seen["koch"]["bevel"] = [koch.data.bevel_depth, len(evaluated.to_mesh().polygons)]
    evaluated.to_mesh_clear()
    assert bpy.ops.bcifs.add(source="koch", depth=4, curve_as="EDGES") == {"FINISHED"}
    edges = bpy.context.active_object
    seen["koch_edges"] = {"type": edges.type, "vertices": len(edges.data.vertices), "edges": len(edges.data.edges)}
    assert bpy.ops.bcifs.add(source="fern", depth=5) == {"FINISHED"}
    fern = bpy.context.active_object
    seen["fern"] = {"vertices": len(fern.data.vertices), "faces": len(fern.data.polygons), "edges": len(fern.data.edges)}
    # A porous solid: the sponge's boundary mesh, closed, with sliders for its parameters.
    assert bpy.ops.bcifs.add(source="menger", depth=2) == {"FINISHED"}
    sponge = bpy.context.active_object
    bm = bmesh.new()
    bm.from_mesh(sponge.data)
    seen["menger"] = {
        "vertices": len(sponge.data.vertices),
        "faces": len(sponge.data.polygons),
        "manifold": all(e.is_manifold for e in bm.edges),
        "volume": bm.calc_volume(signed=True),
        "params": len(sponge.data.bcifs.params),
        "verdict": sponge.data.bcifs.verdict,
    }
    try:
        bpy.ops.bcifs.add(source="no_such_design")
        seen["unknown"] = ""
    except RuntimeError as e:
        seen["unknown"] = str(e)
    for scheme, depth in [("catmull-clark", 2), ("doo-sabin", 2), ("loop", 2)]:
        bpy.ops.object.select_all(action="DESELECT")
        # Loop takes triangles: an icosphere (UV-mapped) for it, Suzanne for the others.
        if scheme == "loop":
            bpy.ops.mesh.primitive_ico_sphere_add(subdivisions=2)
        else:
            bpy.ops.mesh.primitive_monkey_add()
        monkey = bpy.context.active_object
        write_obj(monkey, OUT / f"suzanne-{scheme}.obj")
        assert bpy.ops.bcifs.subdivide(scheme=scheme, depth=depth) == {"FINISHED"}
        result = bpy.context.active_object
        seen[scheme] = {
            "vertices": vertices(result),
            "faces": faces(result),
            "uv": result.data.uv_layers.active is not None,
            "source": [monkey.hide_get(), monkey.display_type, monkey.hide_render, result.parent == monkey],
            "name": result.name,
            "settings": {k: getattr(result.data.bcifs_subdivision, k) for k in ("scheme", "depth", "live")},
        }
    try:
        bpy.ops.bcifs.subdivide(scheme="doo-sabin", depth=1, alpha=3.0, beta=-1.0, gamma=-1.0)
        seen["diverging"] = ""
    except RuntimeError as e:
        seen["diverging"] = str(e)
    live()
    bpy.ops.wm.save_as_mainfile(filepath=str(OUT / "scene.blend"))


def mesh_of(obj):
    return [list(v.co) for v in obj.data.vertices], [list(p.vertices) for p in obj.data.polygons]


def over_two_faces(obj):
    """Edges of `obj` in more than two faces."""
    bm = bmesh.new()
    bm.from_mesh(obj.data)
    return sum(1 for e in bm.edges if len(e.link_faces) > 2)


def live():
    """Issue 46 §7-8: a live subdivision follows its source and settings,
    keeps material indices, triangulates without Blender's non-manifold
    edge, and ends by apply or unlink; linked duplicates share parameters."""
    import bcifs_blender

    module = bcifs_blender.bcifs
    bpy.ops.object.select_all(action="DESELECT")
    bpy.ops.mesh.primitive_cube_add()
    cube = bpy.context.active_object
    cube.name = "cage"
    for k in range(2):
        cube.data.materials.append(bpy.data.materials.new(f"m{k}"))
    cube.data.polygons.foreach_set("material_index", [0, 0, 0, 1, 1, 1])
    cube.data.update()
    assert bpy.ops.bcifs.subdivide(scheme="catmull-clark", depth=2) == {"FINISHED"}
    result = bpy.context.active_object
    link = result.data.bcifs_subdivision
    got = {"materials": [p.material_index for p in result.data.polygons], "slots": [m.name for m in result.data.materials]}
    # Editing the source re-evaluates the result: equal to the module on the edited cube.
    cube.data.vertices[0].co.x -= 0.5
    cube.data.update()
    bpy.context.view_layer.update()
    v = [list(x.co) for x in cube.data.vertices]
    f = [list(p.vertices) for p in cube.data.polygons]
    expected = module.subdivide(v, f, "catmull-clark", 2)
    got["follows"] = [mesh_of(result)[0], expected.vertices.tolist()]
    # A setting re-evaluates too.
    link.depth = 1
    got["depth1"] = len(result.data.polygons)
    # Loop on the quads, triangulated by bcifs: every edge in at most two faces, materials kept.
    link.scheme, link.triangulate = "loop", True
    got["loop"] = [len(result.data.polygons), over_two_faces(result), sorted({p.material_index for p in result.data.polygons})]
    # Moving the source moves its result (a child), as a modifier's.
    cube.location.x = 3.0
    bpy.context.view_layer.update()
    got["moved"] = list(result.matrix_world.translation)
    # Unlink: the result frozen, the source drawn as itself again.
    assert bpy.ops.bcifs.subdivision_unlink() == {"FINISHED"}
    frozen = mesh_of(result)[0]
    cube.data.vertices[1].co.y += 0.5
    cube.data.update()
    bpy.context.view_layer.update()
    got["unlinked"] = [mesh_of(result)[0] == frozen, cube.display_type, cube.hide_render, link.live, result.parent is None, list(result.matrix_world.translation)]
    # Apply: the result stays, the source is removed.
    bpy.ops.object.select_all(action="DESELECT")
    bpy.context.view_layer.objects.active = cube
    assert bpy.ops.bcifs.subdivide(scheme="doo-sabin", depth=1) == {"FINISHED"}
    applied = bpy.context.active_object
    assert bpy.ops.bcifs.subdivision_apply() == {"FINISHED"}
    got["applied"] = ["cage" in bpy.data.objects, applied.name in bpy.data.objects, applied.data.bcifs_subdivision.live, len(applied.data.polygons)]
    # Suzanne through Loop: Blender's Triangulate modifier, then bcifs's own split (kept live for the saved file).
    bpy.ops.object.select_all(action="DESELECT")
    bpy.ops.mesh.primitive_monkey_add()
    monkey = bpy.context.active_object
    monkey.name = "suzanne_live"
    theirs = monkey.copy()
    theirs.data = monkey.data.copy()
    bpy.context.collection.objects.link(theirs)
    theirs.modifiers.new("t", "TRIANGULATE")
    with bpy.context.temp_override(object=theirs, active_object=theirs):
        bpy.ops.object.modifier_apply(modifier="t")
    assert bpy.ops.bcifs.subdivide(scheme="loop", depth=1, triangulate=True) == {"FINISHED"}
    ours = bpy.context.active_object
    got["suzanne"] = [over_two_faces(theirs), over_two_faces(ours), len(ours.data.polygons)]
    bpy.data.objects.remove(theirs)
    # A linked duplicate shares the design's parameters with the object whose mesh it shares.
    torus = bpy.data.objects["doo_sabin_torus"]
    twin = torus.copy()
    bpy.context.collection.objects.link(twin)
    twin.data.bcifs.params["alpha"].value = 0.65
    got["linked"] = [torus.data.bcifs.params["alpha"].value, twin.data == torus.data, len(torus.data.vertices)]
    twin.data.bcifs.params["alpha"].value = 0.7
    bpy.data.objects.remove(twin)
    # Fit to the selected mesh: a plain copy of a torus at alpha = 0.62 is the target.
    bpy.ops.object.select_all(action="DESELECT")
    assert bpy.ops.bcifs.add(source="doo_sabin_torus", depth=2) == {"FINISHED"}
    model = bpy.context.active_object
    model.data.bcifs.params["alpha"].value = 0.62
    bpy.ops.bcifs.apply()
    target = model.copy()
    target.data = model.data.copy()
    target.location = (2.0, -1.0, 0.5)  # moved with its model: the fit works in the model's coordinates
    model.location = (2.0, -1.0, 0.5)
    bpy.context.collection.objects.link(target)
    model.data.bcifs.params["alpha"].value = 0.6
    bpy.ops.bcifs.apply()
    bpy.ops.object.select_all(action="DESELECT")
    target.select_set(True)
    model.select_set(True)
    bpy.context.view_layer.objects.active = model
    assert bpy.ops.bcifs.fit() == {"FINISHED"}
    got["fit"] = [model.data.bcifs.params["alpha"].value, model.data.bcifs.verdict, model.data.bcifs.message]
    bpy.data.objects.remove(target)
    bpy.data.objects.remove(model)
    # A file saved when the state was on the object: moved onto the data when loaded.
    legacy = bpy.data.objects.new("legacy", bpy.data.meshes.new("legacy"))
    bpy.context.collection.objects.link(legacy)
    legacy["bcifs"] = {"source": "koch", "toml": torus.data.bcifs.toml, "depth": 2, "params": [{"name": "alpha", "value": 0.6, "lo": 0.1, "hi": 0.9}]}
    bcifs_blender._move_object_states()
    got["legacy"] = [legacy.data.bcifs.source, legacy.data.bcifs.depth, [p.name for p in legacy.data.bcifs.params], "bcifs" in legacy.keys()]
    bpy.data.objects.remove(legacy)
    seen["live"] = got


def reload():
    enable()
    bpy.ops.wm.open_mainfile(filepath=str(OUT / "scene.blend"))
    torus = bpy.data.objects["doo_sabin_torus"]
    state = torus.data.bcifs
    before = vertices(torus)
    # The live subdivision of Suzanne still follows its source.
    monkey = bpy.data.objects["suzanne_live"]
    result = next(o for o in bpy.data.objects if o.type == "MESH" and o.data.bcifs_subdivision.source == monkey)
    was = [list(v.co) for v in result.data.vertices]
    monkey.data.vertices[0].co.z += 0.25
    monkey.data.update()
    bpy.context.view_layer.update()
    seen["live_reloaded"] = [result.data.bcifs_subdivision.live, [list(v.co) for v in result.data.vertices] != was]
    seen["reloaded"] = {
        "source": state.source,
        "params": {p.name: p.value for p in state.params},
        "depth": state.depth,
        "vertices": len(before),
    }
    bpy.context.view_layer.objects.active = torus
    state.params["beta"].value = 0.1
    assert bpy.ops.bcifs.apply() == {"FINISHED"}
    seen["reloaded"]["changed"] = vertices(torus) != before


def undo():
    """Undo, in the window's context (a timer's context may have lost it after a memfile undo)."""
    window = bpy.context.window_manager.windows[0]
    with bpy.context.temp_override(window=window, screen=window.screen):
        bpy.ops.ed.undo()


def ui_steps():
    """The window session, step by step: each `yield` returns to Blender's
    event loop (undo needs the window's context back between operators)."""
    enable()
    scene_objects = len(bpy.data.objects)
    bpy.ops.ed.undo_push(message="before")
    yield
    # As from a menu: EXEC_DEFAULT with an undo step (the second argument), which the UNDO flag makes.
    bpy.ops.bcifs.add("EXEC_DEFAULT", True, source="doo_sabin_torus", depth=4)
    added = len(bpy.data.objects)
    yield
    undo()
    yield
    seen["undo_add"] = [scene_objects, added, len(bpy.data.objects)]
    bpy.ops.object.select_all(action="DESELECT")
    bpy.ops.mesh.primitive_cube_add("EXEC_DEFAULT", True)
    name = bpy.context.active_object.name
    with_cube = len(bpy.data.objects)
    yield
    bpy.ops.bcifs.subdivide("EXEC_DEFAULT", True, scheme="catmull-clark", depth=2)
    subdivided = len(bpy.data.objects)
    yield
    undo()
    yield
    seen["undo_subdivide"] = [with_cube, subdivided, len(bpy.data.objects), bpy.data.objects[name].hide_get()]
    for obj in list(bpy.data.objects):
        obj.hide_set(True)
    bpy.ops.bcifs.add(source="doo_sabin_torus", depth=5)
    torus = bpy.context.active_object
    torus.data.bcifs.preview_depth = 2
    torus.data.bcifs.params["alpha"].value = 0.66
    seen["settle"] = {"preview": torus.data.bcifs.shown_depth}
    for area in bpy.context.screen.areas:
        if area.type == "VIEW_3D":
            area.spaces.active.show_region_ui = True
            for region in area.regions:
                if region.type == "UI":
                    try:
                        region.active_panel_category = "BC-IFS"
                    except (AttributeError, TypeError):
                        pass
                if region.type == "WINDOW":
                    with bpy.context.temp_override(area=area, region=region):
                        bpy.ops.view3d.view_selected()
    # The sidebar's BC-IFS tab, as a user reaches it: Ctrl + wheel over the
    # sidebar's tab strip (its right edge) steps through the tabs (Item,
    # Tool, View, BC-IFS); Blender runs with --enable-event-simulate for this.
    window = bpy.context.window_manager.windows[0]
    for area in bpy.context.screen.areas:
        for region in area.regions if area.type == "VIEW_3D" else []:
            if region.type == "UI" and hasattr(window, "event_simulate"):
                x, y = region.x + region.width - 8, region.y + region.height - 40
                seen["sidebar"] = [region.x, region.y, region.width, region.height]
                window.event_simulate(type="MOUSEMOVE", value="NOTHING", x=x, y=y)
                yield
                for _ in range(3):
                    window.event_simulate(type="WHEELDOWNMOUSE", value="PRESS", ctrl=True, x=x, y=y)
                    yield
    for _ in range(15):  # 1.5 s: the slider rests, the full depth comes
        yield
    seen["settle"]["after"] = torus.data.bcifs.shown_depth
    seen["settle"]["depth"] = torus.data.bcifs.depth
    bpy.ops.screen.screenshot(filepath=str(OUT / "panel.png"))


def ui():
    steps = ui_steps()

    def tick():
        try:
            next(steps)
            return 0.1
        except StopIteration:
            done()
        except Exception:
            seen["error"] = traceback.format_exc()
            done()
        bpy.ops.wm.quit_blender()
        return None

    bpy.app.timers.register(tick, first_interval=0.5)


def done():
    (OUT / f"{MODE}.json").write_text(json.dumps(seen))


def main():
    try:
        {"operators": operators, "reload": reload, "ui": ui}[MODE]()
        if MODE != "ui":
            done()
    except Exception:
        traceback.print_exc()
        seen["error"] = traceback.format_exc()
        done()


main()
