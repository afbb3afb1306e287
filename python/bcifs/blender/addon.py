"""BC-IFS for Blender: curves and surfaces of a BC-IFS family with live
parameters, and Doo-Sabin, Catmull-Clark, Loop or √3 subdivision (with the
family's weights) of any mesh.

This file is the add-on's ``__init__.py`` inside the zip that
``python -m bcifs.blender zip -o bcifs_blender.zip`` writes; the compiled
module travels beside it (``bcifs_blender/bcifs``), so Blender needs no pip.

- ``bpy.ops.bcifs.add(source="doo_sabin_torus", depth=4)``: a new object
  from a shipped automaton or preset name, or a file (Add › BC-IFS).
- ``bpy.ops.bcifs.subdivide(scheme="catmull-clark", depth=2)``: the active
  mesh subdivided into a new object that stays live, as a modifier's result
  would: editing the source (shown as a wire cage) or the scheme's settings
  re-evaluates it, material indices kept; ``bpy.ops.bcifs.subdivision_apply``
  and ``bpy.ops.bcifs.subdivision_unlink`` end the link (Object › BC-IFS
  subdivide).
- ``bpy.ops.bcifs.fit()``: the active BC-IFS object's parameters fitted to
  the other selected mesh's vertices (``bcifs fit``), proven to converge.
- View3D › Sidebar › BC-IFS: the active object's parameters as sliders over
  their convergence range, its depth, its verdict and JSR bounds, and the
  parameter map as an image; for a live subdivision its settings.

A BC-IFS object's design and parameters live on its data (mesh or curve),
so a linked duplicate (Alt D) shares them as it shares the geometry.
"""

bl_info = {
    "name": "BC-IFS",
    "author": "bcifs",
    "version": (0, 1, 0),
    "blender": (3, 4, 0),
    "location": "View3D > Add > BC-IFS; Object > BC-IFS Subdivide; View3D > Sidebar > BC-IFS",
    "description": "BC-IFS curves and surfaces with live parameters, and BC-IFS subdivision of any mesh",
    "category": "Add Mesh",
}

import math

import bpy
import numpy as np
from bpy.app.handlers import persistent
from bpy.props import BoolProperty, CollectionProperty, EnumProperty, FloatProperty, IntProperty, PointerProperty, StringProperty

from . import bcifs

# The add-on's budget is the library's Blender profile: the deepest mesh, the map's pixels.
_PROFILE = bcifs.profile("blender")
_MAX_DEPTH = _PROFILE["max_depth"]
_MAP_SIZE, _MAP_MAX = _PROFILE["size"][0], _PROFILE["max_side"]

# Designs parsed once per text (a slider's move must not parse and solve again).
_DESIGNS = {}
# The last change of each object, for the full-depth evaluation once a slider rests.
_PENDING = {}
# Seconds a slider must rest before the full depth is evaluated.
SETTLE = 0.4


def design_of(state):
    """The design of a BC-IFS object, from the text it keeps."""
    text = state.toml
    if text not in _DESIGNS:
        _DESIGNS.clear() if len(_DESIGNS) > 16 else None
        _DESIGNS[text] = bcifs.Design.from_toml(text)
    return _DESIGNS[text]


def exact(value):
    """A property's value as the decimal it was meant as: Blender keeps
    float32, so 0.6 reads back as 0.6000000238…; the shortest decimal that
    is the same float32 ("0.6") is the value the module gets, as the CLI
    gets `--param alpha=0.6`."""
    return float(repr(np.float32(value)))


def values_of(state):
    return {p.name: exact(p.value) for p in state.params}


# ---------------------------------------------------------------- geometry


def chains(edges):
    """Polylines of consecutive segments `(a, a+1)` (as the module gives a
    curve's edges): `[(first, count, closed)]`."""
    out = []
    start = None
    for k, (a, b) in enumerate(edges):
        if start is None:
            start, first = k, a
        end_here = k + 1 == len(edges) or edges[k + 1][0] != b
        if end_here:
            closed = b == first
            count = (k - start + 1) + (0 if closed else 1)
            out.append((int(first), int(count), bool(closed)))
            start = None
    return out


def fill_mesh(me, mesh, smooth=True):
    """Mesh data `me` replaced by the arrays of a `bcifs.Mesh`: vertices,
    faces (any degrees), loose edges of curves, custom normals and UVs."""
    me.clear_geometry()
    v = np.ascontiguousarray(mesh.vertices, dtype=np.float32)
    me.vertices.add(len(v))
    me.vertices.foreach_set("co", v.ravel())
    faces = mesh.faces
    if isinstance(faces, np.ndarray):
        totals = np.full(len(faces), faces.shape[1] if faces.ndim == 2 else 0, dtype=np.int32)
        flat = faces.ravel()
    else:
        totals = np.array([len(f) for f in faces], dtype=np.int32)
        flat = np.concatenate(faces) if faces else np.zeros(0, dtype=np.int64)
    if len(totals):
        starts = np.zeros(len(totals), dtype=np.int32)
        starts[1:] = np.cumsum(totals)[:-1]
        me.loops.add(len(flat))
        me.loops.foreach_set("vertex_index", flat.astype(np.int32))
        me.polygons.add(len(totals))
        me.polygons.foreach_set("loop_start", starts)
        me.polygons.foreach_set("loop_total", totals)
    elif len(mesh.edges):
        me.edges.add(len(mesh.edges))
        me.edges.foreach_set("vertices", mesh.edges.astype(np.int32).ravel())
    me.update(calc_edges=True)
    if len(totals):
        me.polygons.foreach_set("use_smooth", np.full(len(totals), smooth))
        if mesh.normals is not None and smooth:
            me.use_auto_smooth = True
            me.normals_split_custom_set_from_vertices(mesh.normals.astype(np.float32).tolist())
        if mesh.uv is not None:
            layer = me.uv_layers.new(name="UVMap")
            uv_flat = np.asarray(mesh.uv_faces if isinstance(mesh.uv_faces, np.ndarray) else np.concatenate(mesh.uv_faces)).ravel()
            layer.data.foreach_set("uv", mesh.uv[uv_flat].astype(np.float32).ravel())
    me.update()


def fill_curve(cu, mesh):
    """Curve data `cu` replaced by poly splines along a curve's edges."""
    cu.splines.clear()
    v = mesh.vertices
    for first, count, closed in chains(mesh.edges.tolist()):
        spline = cu.splines.new("POLY")
        spline.points.add(count - 1)
        co = np.ones((count, 4), dtype=np.float32)
        co[:, :3] = v[first : first + count]
        spline.points.foreach_set("co", co.ravel())
        spline.use_cyclic_u = closed


def rebuild(data, depth):
    """Evaluates the design kept on `data` (a BC-IFS object's mesh or curve)
    at `depth` and its parameter values and puts the result in it, for
    every object that shows it (linked duplicates too). Returns an error
    message, or None."""
    state = data.bcifs
    try:
        mesh = design_of(state).mesh(depth=depth, uv=state.uv, **values_of(state))
    except bcifs.BcifsError as e:
        state.message = str(e)
        return str(e)
    state.message = ""
    state.shown_depth = depth
    if isinstance(data, bpy.types.Curve):
        fill_curve(data, mesh)
    else:
        fill_mesh(data, mesh)
    data.update_tag()
    return None


def check(data):
    """The verdict and JSR bounds at the parameter values kept on `data`."""
    state = data.bcifs
    try:
        report = design_of(state).check(**values_of(state))
    except bcifs.BcifsError as e:
        state.verdict, state.message = "error", str(e)
        return
    converges = report.get("converges")
    state.verdict = {True: "converges", False: "diverges", None: "undecided"}[converges]
    jsr = report.get("jsr") or {}
    state.jsr_lower = jsr.get("lower") or 0.0
    state.jsr_upper = jsr.get("upper") if jsr.get("upper") is not None else math.inf
    state.witness = " ".join(jsr.get("witness") or [])


def default_bevel(curve, vertices):
    """A round bevel a two-hundredth of the curve's extent, so that it renders (a curve without a
    bevel is invisible in renders); the user changes it in the curve's Geometry panel."""
    extent = float(np.ptp(vertices, axis=0).max()) if len(vertices) else 0.0
    curve.bevel_mode = "ROUND"
    curve.bevel_depth = extent / 200.0 if extent > 0 else 0.01
    curve.bevel_resolution = 2
    curve.use_fill_caps = True


# ---------------------------------------------------------------- properties


def _value_changed(param, context):
    """A parameter moved: the preview depth now, the full depth once it rests."""
    data = param.id_data
    state = getattr(data, "bcifs", None)
    if state is None or not state.toml or state.updating:
        return
    preview = min(state.preview_depth, state.depth)
    rebuild(data, preview)
    check(data)
    if preview < state.depth and bpy.app.timers is not None and not bpy.app.background:
        key = (type(data).__name__, data.name)
        token = _PENDING[key] = _PENDING.get(key, 0) + 1
        collection = bpy.data.curves if isinstance(data, bpy.types.Curve) else bpy.data.meshes

        def settle():
            target = collection.get(key[1])
            if target is not None and _PENDING.get(key) == token:
                rebuild(target, target.bcifs.depth)
            return None

        bpy.app.timers.register(settle, first_interval=SETTLE)


def _depth_changed(state, context):
    if state.toml and not state.updating:
        rebuild(state.id_data, state.depth)


def _t_get(self):
    return 0.0 if self.hi == self.lo else (self.value - self.lo) / (self.hi - self.lo)


def _t_set(self, t):
    self.value = self.lo + t * (self.hi - self.lo)


class BcifsParameter(bpy.types.PropertyGroup):
    """A free parameter of the family, with the range where it converges."""

    name: StringProperty(name="Name")
    value: FloatProperty(name="Value", update=_value_changed, precision=4)
    lo: FloatProperty(name="From", precision=4)
    hi: FloatProperty(name="To", precision=4)
    t: FloatProperty(
        name="Position",
        description="Where the value lies in the range where the family converges (from, to)",
        min=0.0,
        max=100.0,
        subtype="PERCENTAGE",
        get=lambda self: 100.0 * _t_get(self),
        set=lambda self, x: _t_set(self, x / 100.0),
    )


class BcifsState(bpy.types.PropertyGroup):
    """What a BC-IFS object keeps in the .blend: its design (as text), parameters and depths."""

    source: StringProperty(name="Source", description="The automaton or preset name, or the file, it was made from")
    toml: StringProperty(name="Design", description="The automaton file's text (the .blend needs no file)")
    depth: IntProperty(name="Depth", min=0, max=_MAX_DEPTH, default=4, update=_depth_changed)
    preview_depth: IntProperty(name="Preview depth", min=0, max=10, default=3, description="The depth while a slider moves")
    shown_depth: IntProperty(name="Shown depth")
    uv: BoolProperty(name="UVs", default=False)
    params: CollectionProperty(type=BcifsParameter)
    verdict: StringProperty(name="Verdict")
    jsr_lower: FloatProperty(name="JSR lower bound", precision=5)
    jsr_upper: FloatProperty(name="JSR upper bound", precision=5)
    witness: StringProperty(name="Witness")
    message: StringProperty(name="Message")
    updating: BoolProperty(default=False, options={"SKIP_SAVE"})


# ---------------------------------------------------------------- operators


class BCIFS_OT_add(bpy.types.Operator):
    """Add a BC-IFS curve, surface or cloud from a shipped automaton, a preset or a file"""

    bl_idname = "bcifs.add"
    bl_label = "BC-IFS Object"
    bl_options = {"REGISTER", "UNDO"}

    source: StringProperty(name="Source", default="doo_sabin_torus", description="A shipped automaton or preset name, or an automaton file")
    depth: IntProperty(name="Depth", min=0, max=_MAX_DEPTH, default=4)
    curve_as: EnumProperty(
        name="Curves as",
        items=[("CURVE", "Curve", "Poly splines with a round bevel, so that they render"), ("EDGES", "Mesh edges", "Loose edges of a mesh")],
        default="CURVE",
    )
    uv: BoolProperty(name="UVs", default=False, description="Texture coordinates on surfaces")

    def execute(self, context):
        try:
            design = bcifs.load(bpy.path.abspath(self.source) if self.source.startswith("//") else self.source)
            mesh = design.mesh(depth=self.depth, uv=self.uv)
        except bcifs.BcifsError as e:
            self.report({"ERROR"}, str(e))
            return {"CANCELLED"}
        name = design.name
        is_curve = not _has_faces(mesh) and len(mesh.edges) > 0
        if is_curve and self.curve_as == "CURVE":
            data = bpy.data.curves.new(name, "CURVE")
            data.dimensions = "3D"
        else:
            data = bpy.data.meshes.new(name)
        obj = bpy.data.objects.new(name, data)
        context.collection.objects.link(obj)
        obj.location = context.scene.cursor.location
        state = data.bcifs
        state.updating = True
        state.source, state.toml, state.uv = self.source, design.to_toml(), self.uv
        state.depth = self.depth
        state.preview_depth = min(3, self.depth)
        try:
            ranges = design.ranges()  # the library's convergence ranges: the sliders' spans
        except bcifs.BcifsError:
            ranges = []
        for r in ranges:
            p = state.params.add()
            p.name = r["name"]
            p.lo, p.hi = r["range"]
            p.value = r["default"]
        state.updating = False
        if is_curve and self.curve_as == "CURVE":
            fill_curve(data, mesh)
            default_bevel(data, mesh.vertices)
        else:
            fill_mesh(data, mesh)
        state.shown_depth = self.depth
        check(data)
        for other in context.selected_objects:
            other.select_set(False)
        obj.select_set(True)
        context.view_layer.objects.active = obj
        return {"FINISHED"}


def data_state(obj):
    """The BC-IFS state of an object's data (mesh or curve), or None."""
    data = getattr(obj, "data", None) if obj is not None else None
    state = getattr(data, "bcifs", None)
    return state if state is not None and state.toml else None


def _has_faces(mesh):
    faces = mesh.faces
    return len(faces) > 0 and (not isinstance(faces, np.ndarray) or faces.ndim == 2 and faces.shape[1] > 0)


class BCIFS_OT_apply(bpy.types.Operator):
    """Evaluate the active BC-IFS object at its full depth and check its parameters"""

    bl_idname = "bcifs.apply"
    bl_label = "Apply"
    bl_options = {"REGISTER", "UNDO"}

    @classmethod
    def poll(cls, context):
        obj = context.active_object
        return data_state(context.active_object) is not None

    def execute(self, context):
        data = context.active_object.data
        error = rebuild(data, data.bcifs.depth)
        check(data)
        if error:
            self.report({"ERROR"}, error)
            return {"CANCELLED"}
        return {"FINISHED"}


class BCIFS_OT_map(bpy.types.Operator):
    """The convergence map of the active object's first two parameters, as an image (the point marked)"""

    bl_idname = "bcifs.map"
    bl_label = "Parameter map"
    bl_options = {"REGISTER"}

    size: IntProperty(name="Pixels", min=8, max=_MAP_MAX, default=_MAP_SIZE)

    @classmethod
    def poll(cls, context):
        obj = context.active_object
        state = data_state(context.active_object)
        return state is not None and len(state.params) >= 2

    def execute(self, context):
        obj = context.active_object
        state = obj.data.bcifs
        px, py = state.params[0], state.params[1]
        wide = lambda p: (min(p.lo, p.value) - 0.5 * (p.hi - p.lo), max(p.hi, p.value) + 0.5 * (p.hi - p.lo))  # noqa: E731
        (x0, x1), (y0, y1) = wide(px), wide(py)
        try:
            codes = bcifs.sweep(design_of(state), x=(px.name, x0, x1, self.size), y=(py.name, y0, y1, self.size))
        except bcifs.BcifsError as e:
            self.report({"ERROR"}, str(e))
            return {"CANCELLED"}
        rgba = np.ones((self.size, self.size, 4), dtype=np.float32)
        rgba[..., :3] = bcifs.map_colours(codes, "verdict") / 255.0  # the library's palette, as analyze map's
        # The current point, a black cross.
        col = int((px.value - x0) / (x1 - x0) * self.size)
        row = int((y1 - py.value) / (y1 - y0) * self.size)
        arm = max(2, self.size // 40)
        for d in range(-arm, arm + 1):
            for c, r in ((col + d, row), (col, row + d)):
                if 0 <= c < self.size and 0 <= r < self.size:
                    rgba[r, c, :3] = 0.0
        name = f"BC-IFS map {obj.name}"
        image = bpy.data.images.get(name) or bpy.data.images.new(name, self.size, self.size)
        if tuple(image.size) != (self.size, self.size):
            image.scale(self.size, self.size)
        image.pixels.foreach_set(rgba[::-1].ravel())  # Blender's rows start at the bottom
        image.update()
        for area in context.screen.areas if context.screen else []:
            if area.type == "IMAGE_EDITOR":
                area.spaces.active.image = image
        self.report({"INFO"}, f"{name}: {px.name} ∈ [{x0:.3g}, {x1:.3g}] × {py.name} ∈ [{y0:.3g}, {y1:.3g}]")
        return {"FINISHED"}


def _fit_target(context):
    """The selected mesh object other than the active one (the fit's target), or None."""
    active = context.active_object
    return next((o for o in context.selected_objects if o is not active and o.type == "MESH"), None)


class BCIFS_OT_fit(bpy.types.Operator):
    """Fit the active BC-IFS object's parameters to the other selected mesh (its vertices), staying where convergence is proven"""

    bl_idname = "bcifs.fit"
    bl_label = "Fit to selected"
    bl_options = {"REGISTER", "UNDO"}

    starts: IntProperty(name="Starts", min=1, max=64, default=4, description="Starts run to the end: the defaults, then the best of a sample of the ranges")

    @classmethod
    def poll(cls, context):
        state = data_state(context.active_object)
        return state is not None and len(state.params) > 0 and _fit_target(context) is not None

    def execute(self, context):
        obj, target = context.active_object, _fit_target(context)
        state = obj.data.bcifs
        depsgraph = context.evaluated_depsgraph_get()
        evaluated = target.evaluated_get(depsgraph)
        me = evaluated.to_mesh()
        try:
            co = np.empty(len(me.vertices) * 3, dtype=np.float64)
            me.vertices.foreach_get("co", co)
        finally:
            evaluated.to_mesh_clear()
        # The target's vertices in the BC-IFS object's own coordinates (the model's).
        to_local = np.array(obj.matrix_world.inverted() @ target.matrix_world)
        points = co.reshape(-1, 3) @ to_local[:3, :3].T + to_local[:3, 3]
        try:
            try:
                _, report = bcifs.fit(design_of(state), points, starts=self.starts)
            except bcifs.BcifsError as e:
                # A plane's model: the target in its plane (Blender's z of a curve is 0).
                if "model is 2D" not in str(e) or not np.allclose(points[:, 2], 0.0, atol=1e-6):
                    raise
                _, report = bcifs.fit(design_of(state), points[:, :2], starts=self.starts)
        except bcifs.BcifsError as e:
            self.report({"ERROR"}, str(e))
            return {"CANCELLED"}
        state.updating = True
        for p in state.params:
            if p.name in report["parameters"]:
                p.value = report["parameters"][p.name]
        state.updating = False
        rebuild(obj.data, state.depth)
        check(obj.data)
        verdict = "proven to converge" if report["converges"] else "not proven to converge"
        text = f"fitted to {target.name}: residual {report['residual']:.3g}, {verdict}"
        state.message = report["reason"] or text
        self.report({"INFO"}, text)
        return {"FINISHED"}


SCHEMES = [
    ("doo-sabin", "Doo-Sabin", "Corner cutting: faces from faces, edges and vertices (weights alpha, beta, gamma on quads)"),
    ("catmull-clark", "Catmull-Clark", "Quads from any polygons; UVs follow"),
    ("loop", "Loop", "Triangles (weights w, sigma); UVs follow"),
    ("sqrt3", "√3", "Triangles, rotated, a third more per step"),
]


CLASSIC = {"doo-sabin": {"alpha": 0.5625, "beta": 0.1875, "gamma": 0.1875}, "loop": {"w": 0.375, "sigma": 1.0}}


def changed_weights(settings):
    """The weights changed from the classic rule of `settings.scheme`, by the CLI's names."""
    rule = CLASSIC.get(settings.scheme, {})
    return {k: getattr(settings, k) for k, v in rule.items() if not math.isclose(getattr(settings, k), v, rel_tol=0, abs_tol=1e-12)}


def subdivided(source, settings, depsgraph):
    """The source object's evaluated mesh (its modifiers applied) subdivided as
    `settings` say, its material indices carried (`face_data`): a `bcifs.Mesh`.
    Raises `bcifs.BcifsError` (diverging weights, a face-less mesh)."""
    evaluated = source.evaluated_get(depsgraph)
    me = evaluated.to_mesh()
    try:
        vertices, faces, uv, uv_faces = mesh_arrays(me, settings.uv)
        materials = np.zeros(len(me.polygons), dtype=np.int32)
        me.polygons.foreach_get("material_index", materials)
    finally:
        evaluated.to_mesh_clear()
    if not faces:
        raise bcifs.BcifsError(f"{source.name} has no faces to subdivide")
    return bcifs.subdivide(
        vertices, faces, settings.scheme, settings.depth, net=settings.net, uv=uv, uv_faces=uv_faces,
        triangulate=settings.triangulate, face_data={"material": materials}, **changed_weights(settings),
    )


def fill_subdivided(me, result, source):
    """Mesh data `me` replaced by a subdivision `result` of `source`: its
    geometry, each face's material index, the source's material slots."""
    # The slots first: clearing them resets the faces' material indices.
    if list(me.materials) != list(source.data.materials):
        me.materials.clear()
        for material in source.data.materials:
            me.materials.append(material)
    fill_mesh(me, result)
    me.polygons.foreach_set("material_index", result.face_data["material"].astype(np.int32))
    me.update()


# Results being re-evaluated (their own update must not start another).
_RESUBDIVIDING = set()


def resubdivide(me, depsgraph=None):
    """Re-evaluates the live subdivision kept on mesh data `me` from its
    source as it is now. Returns an error message, or None."""
    link = me.bcifs_subdivision
    source = link.source
    if not link.live or source is None or source.type != "MESH" or me.name in _RESUBDIVIDING:
        return None
    _RESUBDIVIDING.add(me.name)
    try:
        result = subdivided(source, link, depsgraph or bpy.context.evaluated_depsgraph_get())
        fill_subdivided(me, result, source)
        link.message = ""
        return None
    except bcifs.BcifsError as e:
        link.message = str(e)  # the last good mesh kept, as a slider's divergence keeps it
        return str(e)
    finally:
        _RESUBDIVIDING.discard(me.name)


def _settings_changed(link, context):
    if link.live:
        resubdivide(link.id_data)


def _no_cycle(link, obj):
    """A source may be any mesh object but one whose data is this result, or fed by it."""
    seen = set()
    while obj is not None and obj.type == "MESH" and obj.name not in seen:
        if obj.data == link.id_data:
            return False
        seen.add(obj.name)
        nxt = obj.data.bcifs_subdivision
        obj = nxt.source if nxt.live else None
    return True


def _scheme_settings(update=None):
    """The subdivision's settings as properties, the operator's and the live link's alike
    (`update`: what a change re-evaluates, for the live link)."""
    on = {"update": update} if update else {}
    return {
        "scheme": EnumProperty(name="Scheme", items=SCHEMES, default="catmull-clark", **on),
        "depth": IntProperty(name="Depth", min=0, max=8, default=2, **on),
        "net": BoolProperty(name="Control net", default=False, description="The net after the steps instead of the limit surface", **on),
        "uv": BoolProperty(name="UVs", default=True, description="Carry the active UV map (Catmull-Clark and Loop)", **on),
        "triangulate": BoolProperty(
            name="Triangulate",
            default=False,
            description="Split each face into a fan of triangles first (Loop and √3 on quads), without the edge in four triangles "
            "that Blender's Triangulate modifier makes beside a vertex of valence 2",
            **on,
        ),
        "alpha": FloatProperty(name="alpha", default=0.5625, precision=4, description="Doo-Sabin quad rule: the own corner's weight", **on),
        "beta": FloatProperty(name="beta", default=0.1875, precision=4, description="Doo-Sabin quad rule: a neighbouring corner's weight", **on),
        "gamma": FloatProperty(name="gamma", default=0.1875, precision=4, description="Doo-Sabin quad rule: the other neighbour's weight", **on),
        "w": FloatProperty(name="w", default=0.375, precision=4, description="Loop: the edge rule's weight of the edge's ends", **on),
        "sigma": FloatProperty(name="sigma", default=1.0, precision=4, description="Loop: the vertex rule's scale of Warren's β", **on),
    }


def _draw_settings(layout, settings, names=("scheme", "depth", "net", "uv", "triangulate")):
    """The settings' fields, the weights only of the scheme chosen."""
    for name in names:
        layout.prop(settings, name)
    for name in {"doo-sabin": ("alpha", "beta", "gamma"), "loop": ("w", "sigma")}.get(settings.scheme, ()):
        layout.prop(settings, name)


class BcifsSubdivision(bpy.types.PropertyGroup):
    """A live subdivision, kept on the result's mesh data: its source and settings."""

    __annotations__ = {
        "live": BoolProperty(name="Live", default=False, description="Re-evaluated when the source or a setting changes"),
        "source": PointerProperty(name="Source", type=bpy.types.Object, poll=_no_cycle, update=_settings_changed),
        **_scheme_settings(_settings_changed),
        "message": StringProperty(name="Message"),
    }

    def draw(self, layout):
        _draw_settings(layout, self, ("source", "scheme", "depth", "net", "uv", "triangulate"))


SETTINGS = tuple(_scheme_settings())


class BCIFS_OT_subdivide(bpy.types.Operator):
    """Subdivide the active mesh by a BC-IFS scheme into a new object that stays live (the source kept as its wire cage)"""

    bl_idname = "bcifs.subdivide"
    bl_label = "BC-IFS Subdivide"
    bl_options = {"REGISTER", "UNDO"}

    __annotations__ = _scheme_settings()

    @classmethod
    def poll(cls, context):
        obj = context.active_object
        return obj is not None and obj.type == "MESH"

    def draw(self, context):
        _draw_settings(self.layout, self)

    def execute(self, context):
        source = context.active_object
        try:
            result = subdivided(source, self, context.evaluated_depsgraph_get())
        except bcifs.BcifsError as e:
            self.report({"ERROR"}, str(e))
            return {"CANCELLED"}
        name = f"{source.name}.{self.scheme}"
        data = bpy.data.meshes.new(name)
        fill_subdivided(data, result, source)
        obj = bpy.data.objects.new(name, data)
        for collection in source.users_collection:
            collection.objects.link(obj)
        # A child of its source at the same place: moving the source moves it, as a modifier's result.
        obj.parent = source
        link = data.bcifs_subdivision
        for name in SETTINGS:
            setattr(link, name, getattr(self, name))
        link.source = source
        link.live = True
        # The source stays editable, drawn as the result's wire cage and not rendered.
        source.display_type = "WIRE"
        source.hide_render = True
        for other in context.selected_objects:
            other.select_set(False)
        obj.select_set(True)
        context.view_layer.objects.active = obj
        return {"FINISHED"}


def _live_result(context):
    obj = context.active_object
    return obj is not None and obj.type == "MESH" and obj.data.bcifs_subdivision.live


def _unlink(obj):
    """Ends the live link of the result `obj` (kept where it is) and returns its source."""
    link = obj.data.bcifs_subdivision
    source = link.source
    world = obj.matrix_world.copy()
    obj.parent = None
    obj.matrix_world = world
    link.live = False
    link.source = None
    return source


class BCIFS_OT_subdivision_apply(bpy.types.Operator):
    """Make the live subdivision a plain mesh and remove its source (as applying a modifier)"""

    bl_idname = "bcifs.subdivision_apply"
    bl_label = "Apply subdivision"
    bl_options = {"REGISTER", "UNDO"}

    @classmethod
    def poll(cls, context):
        return _live_result(context)

    def execute(self, context):
        source = _unlink(context.active_object)
        still_used = any(o.type == "MESH" and o.data.bcifs_subdivision.live and o.data.bcifs_subdivision.source == source for o in bpy.data.objects)
        if source is not None and not still_used:
            bpy.data.objects.remove(source)
        return {"FINISHED"}


class BCIFS_OT_subdivision_unlink(bpy.types.Operator):
    """Freeze the live subdivision as it is and give its source back its own look"""

    bl_idname = "bcifs.subdivision_unlink"
    bl_label = "Unlink subdivision"
    bl_options = {"REGISTER", "UNDO"}

    @classmethod
    def poll(cls, context):
        return _live_result(context)

    def execute(self, context):
        source = _unlink(context.active_object)
        if source is not None:
            source.display_type = "TEXTURED"
            source.hide_render = False
        return {"FINISHED"}


@persistent
def _on_depsgraph_update(scene, depsgraph):
    """Live subdivisions follow their sources: a source whose geometry (or
    mesh data) changed re-evaluates every live result fed by it."""
    changed_objects, changed_meshes = set(), set()
    for update in depsgraph.updates:
        original = getattr(update.id, "original", update.id)
        if isinstance(original, bpy.types.Object) and update.is_updated_geometry:
            changed_objects.add(original.name)
        elif isinstance(original, bpy.types.Mesh):
            changed_meshes.add(original.name)
    if not changed_objects and not changed_meshes:
        return
    for me in bpy.data.meshes:
        link = me.bcifs_subdivision
        source = link.source if link.live else None
        if source is not None and (source.name in changed_objects or source.data.name in changed_meshes):
            resubdivide(me, depsgraph)


@persistent
def _move_object_states(*_):
    """Files saved before the state moved to the data (it was on the
    object): each object's state copied onto its data, where it lives now."""
    for obj in bpy.data.objects:
        old = obj.get("bcifs")
        state = getattr(obj.data, "bcifs", None)
        if old is None or state is None or state.toml or not old.get("toml"):
            continue
        old = old.to_dict()
        state.updating = True
        for key in ("source", "toml", "depth", "preview_depth", "shown_depth", "uv", "verdict", "jsr_lower", "jsr_upper", "witness", "message"):
            if key in old:
                setattr(state, key, old[key])
        for p in old.get("params", []):
            q = state.params.add()
            q.name, q.lo, q.hi, q.value = p.get("name", ""), p.get("lo", 0.0), p.get("hi", 0.0), p.get("value", 0.0)
        state.updating = False
        del obj["bcifs"]


def mesh_arrays(me, with_uv):
    """A Blender mesh as the module's arrays: vertices (n, 3), faces (index
    lists), and the active UV map face-varying (uv, uv_faces) or Nones."""
    n = len(me.vertices)
    vertices = np.empty(n * 3, dtype=np.float64)
    me.vertices.foreach_get("co", vertices)
    totals = np.empty(len(me.polygons), dtype=np.int64)
    me.polygons.foreach_get("loop_total", totals)
    corners = np.empty(len(me.loops), dtype=np.int64)
    me.loops.foreach_get("vertex_index", corners)
    cuts = np.cumsum(totals)[:-1]
    faces = [f.tolist() for f in np.split(corners, cuts)] if len(totals) else []
    uv = uv_faces = None
    if with_uv and me.uv_layers.active is not None and len(me.loops):
        per_loop = np.empty(len(me.loops) * 2, dtype=np.float32)
        me.uv_layers.active.data.foreach_get("uv", per_loop)
        uv, index = np.unique(per_loop.reshape(-1, 2).astype(np.float64), axis=0, return_inverse=True)
        uv_faces = [f.tolist() for f in np.split(index.ravel(), cuts)]
    return vertices.reshape(n, 3), faces, uv, uv_faces


# ---------------------------------------------------------------- panel


class BCIFS_PT_panel(bpy.types.Panel):
    """The active BC-IFS object: parameters, depth, verdict, map."""

    bl_label = "BC-IFS"
    bl_idname = "BCIFS_PT_panel"
    bl_space_type = "VIEW_3D"
    bl_region_type = "UI"
    bl_category = "BC-IFS"

    def draw(self, context):
        layout = self.layout
        obj = context.active_object
        state = data_state(obj)
        if obj is not None and obj.type == "MESH" and obj.data.bcifs_subdivision.live:
            link = obj.data.bcifs_subdivision
            box = layout.box()
            box.label(text="Live subdivision", icon="MOD_SUBSURF")
            link.draw(box)
            if link.message:
                box.label(text=link.message[:120], icon="ERROR")
            row = box.row(align=True)
            row.operator("bcifs.subdivision_apply", text="Apply")
            row.operator("bcifs.subdivision_unlink", text="Unlink")
        if state is None:
            layout.label(text="Add › BC-IFS, or select a BC-IFS object")
            layout.operator("bcifs.add", icon="ADD")
            if obj is not None and obj.type == "MESH":
                layout.operator("bcifs.subdivide", icon="MOD_SUBSURF")
            return
        layout.label(text=f"{state.source}", icon="OUTLINER_OB_SURFACE" if obj.type == "MESH" else "OUTLINER_OB_CURVE")
        col = layout.column(align=True)
        for p in state.params:
            split = col.split(factor=0.55, align=True)
            split.prop(p, "t", text=p.name, slider=True)
            split.prop(p, "value", text="")
        if state.params:
            col.label(text="Sliders span each convergence range")
        else:
            col.label(text="No free parameter")
        if obj.data.users > 1:
            col.label(text=f"Shared by {obj.data.users} linked objects", icon="LINKED")
        row = layout.row(align=True)
        row.prop(state, "depth")
        row.prop(state, "preview_depth", text="Preview")
        layout.operator("bcifs.apply", icon="FILE_REFRESH")
        box = layout.box()
        icon = {"converges": "CHECKMARK", "diverges": "ERROR"}.get(state.verdict, "QUESTION")
        box.label(text=f"Verdict: {state.verdict or '—'}", icon=icon)
        box.label(text=f"JSR ∈ [{state.jsr_lower:.4f}, {state.jsr_upper:.4f}]")
        if state.verdict == "diverges" and state.witness:
            box.label(text=f"Witness: {state.witness}")
        if state.message:
            box.label(text=state.message[:120], icon="INFO")
        if state.shown_depth != state.depth:
            box.label(text=f"Shown at depth {state.shown_depth}")
        layout.operator("bcifs.map", icon="IMAGE_DATA")
        layout.operator("bcifs.fit", icon="TRACKING")


def menu_add(self, context):
    self.layout.operator("bcifs.add", text="BC-IFS", icon="MOD_SUBSURF")


def menu_object(self, context):
    self.layout.operator("bcifs.subdivide", icon="MOD_SUBSURF")


CLASSES = (
    BcifsParameter,
    BcifsState,
    BcifsSubdivision,
    BCIFS_OT_add,
    BCIFS_OT_apply,
    BCIFS_OT_map,
    BCIFS_OT_fit,
    BCIFS_OT_subdivide,
    BCIFS_OT_subdivision_apply,
    BCIFS_OT_subdivision_unlink,
    BCIFS_PT_panel,
)


def register():
    for cls in CLASSES:
        bpy.utils.register_class(cls)
    # On the data: linked duplicates share a design's parameters and a live subdivision.
    bpy.types.Mesh.bcifs = PointerProperty(type=BcifsState)
    bpy.types.Curve.bcifs = PointerProperty(type=BcifsState)
    bpy.types.Mesh.bcifs_subdivision = PointerProperty(type=BcifsSubdivision)
    bpy.types.VIEW3D_MT_add.append(menu_add)
    bpy.types.VIEW3D_MT_object.append(menu_object)
    bpy.app.handlers.depsgraph_update_post.append(_on_depsgraph_update)
    bpy.app.handlers.load_post.append(_move_object_states)


def unregister():
    bpy.app.handlers.load_post.remove(_move_object_states)
    bpy.app.handlers.depsgraph_update_post.remove(_on_depsgraph_update)
    bpy.types.VIEW3D_MT_object.remove(menu_object)
    bpy.types.VIEW3D_MT_add.remove(menu_add)
    del bpy.types.Mesh.bcifs_subdivision
    del bpy.types.Curve.bcifs
    del bpy.types.Mesh.bcifs
    for cls in reversed(CLASSES):
        bpy.utils.unregister_class(cls)
