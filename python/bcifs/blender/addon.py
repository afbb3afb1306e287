"""BC-IFS for Blender: curves and surfaces of a BC-IFS family with live
parameters, and Doo-Sabin, Catmull-Clark, Loop or √3 subdivision (with the
family's weights) of any mesh.

This file is the add-on's ``__init__.py`` inside the zip that
``python -m bcifs.blender zip -o bcifs_blender.zip`` writes; the compiled
module travels beside it (``bcifs_blender/bcifs``), so Blender needs no pip.

- ``bpy.ops.bcifs.add(source="doo_sabin_torus", depth=4)``: a new object
  from a shipped automaton or preset name, or a file (Add › BC-IFS).
- ``bpy.ops.bcifs.subdivide(scheme="catmull-clark", depth=2)``: the active
  mesh subdivided into a new object, the original kept and hidden
  (Object › BC-IFS subdivide).
- View3D › Sidebar › BC-IFS: the active object's parameters as sliders over
  their convergence range, its depth, its verdict and JSR bounds, and the
  parameter map as an image.
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


def rebuild(obj, depth):
    """Evaluates the object's design at `depth` and its parameter values and
    puts the result in its data. Returns an error message, or None."""
    state = obj.bcifs
    try:
        mesh = design_of(state).mesh(depth=depth, uv=state.uv, **values_of(state))
    except bcifs.BcifsError as e:
        state.message = str(e)
        return str(e)
    state.message = ""
    state.shown_depth = depth
    if obj.type == "CURVE":
        fill_curve(obj.data, mesh)
    else:
        fill_mesh(obj.data, mesh)
    obj.data.update_tag() if hasattr(obj.data, "update_tag") else None
    return None


def check(obj):
    """The verdict and JSR bounds at the object's parameter values."""
    state = obj.bcifs
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


# ---------------------------------------------------------------- properties


def _value_changed(param, context):
    """A parameter moved: the preview depth now, the full depth once it rests."""
    obj = param.id_data
    if not getattr(obj, "bcifs", None) or not obj.bcifs.toml or obj.bcifs.updating:
        return
    state = obj.bcifs
    preview = min(state.preview_depth, state.depth)
    rebuild(obj, preview)
    check(obj)
    if preview < state.depth and bpy.app.timers is not None and not bpy.app.background:
        token = _PENDING[obj.name] = _PENDING.get(obj.name, 0) + 1
        name = obj.name

        def settle():
            target = bpy.data.objects.get(name)
            if target is not None and _PENDING.get(name) == token:
                rebuild(target, target.bcifs.depth)
            return None

        bpy.app.timers.register(settle, first_interval=SETTLE)


def _depth_changed(state, context):
    obj = state.id_data
    if state.toml and not state.updating:
        rebuild(obj, state.depth)


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
        items=[("CURVE", "Curve", "Poly splines (render with a bevel depth)"), ("EDGES", "Mesh edges", "Loose edges of a mesh")],
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
        state = obj.bcifs
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
        else:
            fill_mesh(data, mesh)
        state.shown_depth = self.depth
        check(obj)
        for other in context.selected_objects:
            other.select_set(False)
        obj.select_set(True)
        context.view_layer.objects.active = obj
        return {"FINISHED"}


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
        return obj is not None and bool(obj.bcifs.toml)

    def execute(self, context):
        obj = context.active_object
        error = rebuild(obj, obj.bcifs.depth)
        check(obj)
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
        return obj is not None and bool(obj.bcifs.toml) and len(obj.bcifs.params) >= 2

    def execute(self, context):
        obj = context.active_object
        state = obj.bcifs
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


SCHEMES = [
    ("doo-sabin", "Doo-Sabin", "Corner cutting: faces from faces, edges and vertices (weights alpha, beta, gamma on quads)"),
    ("catmull-clark", "Catmull-Clark", "Quads from any polygons; UVs follow"),
    ("loop", "Loop", "Triangles (weights w, sigma); UVs follow"),
    ("sqrt3", "√3", "Triangles, rotated, a third more per step"),
]


class BCIFS_OT_subdivide(bpy.types.Operator):
    """Subdivide the active mesh by a BC-IFS scheme into a new object (the original kept, hidden)"""

    bl_idname = "bcifs.subdivide"
    bl_label = "BC-IFS Subdivide"
    bl_options = {"REGISTER", "UNDO"}

    scheme: EnumProperty(name="Scheme", items=SCHEMES, default="catmull-clark")
    depth: IntProperty(name="Depth", min=0, max=8, default=2)
    net: BoolProperty(name="Control net", default=False, description="The net after the steps instead of the limit surface")
    uv: BoolProperty(name="UVs", default=True, description="Carry the active UV map (Catmull-Clark and Loop)")
    alpha: FloatProperty(name="alpha", default=0.5625, precision=4, description="Doo-Sabin quad rule: the own corner's weight")
    beta: FloatProperty(name="beta", default=0.1875, precision=4, description="Doo-Sabin quad rule: a neighbouring corner's weight")
    gamma: FloatProperty(name="gamma", default=0.1875, precision=4, description="Doo-Sabin quad rule: the other neighbour's weight")
    w: FloatProperty(name="w", default=0.375, precision=4, description="Loop: the edge rule's weight of the edge's ends")
    sigma: FloatProperty(name="sigma", default=1.0, precision=4, description="Loop: the vertex rule's scale of Warren's β")

    @classmethod
    def poll(cls, context):
        obj = context.active_object
        return obj is not None and obj.type == "MESH"

    def draw(self, context):
        layout = self.layout
        for name in ("scheme", "depth", "net", "uv"):
            layout.prop(self, name)
        weights = {"doo-sabin": ("alpha", "beta", "gamma"), "loop": ("w", "sigma")}.get(self.scheme, ())
        for name in weights:
            layout.prop(self, name)

    def weights(self):
        """The weights the user changed from the classic rule, by the CLI's names."""
        classic = {"doo-sabin": {"alpha": 0.5625, "beta": 0.1875, "gamma": 0.1875}, "loop": {"w": 0.375, "sigma": 1.0}}
        rule = classic.get(self.scheme, {})
        return {k: getattr(self, k) for k, v in rule.items() if not math.isclose(getattr(self, k), v, rel_tol=0, abs_tol=1e-12)}

    def execute(self, context):
        source = context.active_object
        depsgraph = context.evaluated_depsgraph_get()
        evaluated = source.evaluated_get(depsgraph)
        me = evaluated.to_mesh()
        try:
            vertices, faces, uv, uv_faces = mesh_arrays(me, self.uv)
        finally:
            evaluated.to_mesh_clear()
        if not faces:
            self.report({"ERROR"}, f"{source.name} has no faces to subdivide")
            return {"CANCELLED"}
        try:
            result = bcifs.subdivide(vertices, faces, self.scheme, self.depth, net=self.net, uv=uv, uv_faces=uv_faces, **self.weights())
        except bcifs.BcifsError as e:
            self.report({"ERROR"}, str(e))
            return {"CANCELLED"}
        name = f"{source.name}.{self.scheme}"
        data = bpy.data.meshes.new(name)
        fill_mesh(data, result)
        for material in source.data.materials:
            data.materials.append(material)
        obj = bpy.data.objects.new(name, data)
        for collection in source.users_collection:
            collection.objects.link(obj)
        obj.matrix_world = source.matrix_world.copy()
        obj["bcifs_scheme"], obj["bcifs_depth"], obj["bcifs_source"] = self.scheme, self.depth, source.name
        for k, v in self.weights().items():
            obj[f"bcifs_{k}"] = v
        source.hide_set(True)
        source.hide_render = True
        for other in context.selected_objects:
            other.select_set(False)
        obj.select_set(True)
        context.view_layer.objects.active = obj
        return {"FINISHED"}


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
        if obj is None or not obj.bcifs.toml:
            layout.label(text="Add › BC-IFS, or select a BC-IFS object")
            layout.operator("bcifs.add", icon="ADD")
            if obj is not None and obj.type == "MESH":
                layout.operator("bcifs.subdivide", icon="MOD_SUBSURF")
            return
        state = obj.bcifs
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


def menu_add(self, context):
    self.layout.operator("bcifs.add", text="BC-IFS", icon="MOD_SUBSURF")


def menu_object(self, context):
    self.layout.operator("bcifs.subdivide", icon="MOD_SUBSURF")


CLASSES = (BcifsParameter, BcifsState, BCIFS_OT_add, BCIFS_OT_apply, BCIFS_OT_map, BCIFS_OT_subdivide, BCIFS_PT_panel)


def register():
    for cls in CLASSES:
        bpy.utils.register_class(cls)
    bpy.types.Object.bcifs = PointerProperty(type=BcifsState)
    bpy.types.VIEW3D_MT_add.append(menu_add)
    bpy.types.VIEW3D_MT_object.append(menu_object)


def unregister():
    bpy.types.VIEW3D_MT_object.remove(menu_object)
    bpy.types.VIEW3D_MT_add.remove(menu_add)
    del bpy.types.Object.bcifs
    for cls in reversed(CLASSES):
        bpy.utils.unregister_class(cls)
