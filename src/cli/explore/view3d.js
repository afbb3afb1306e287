// The page's 3D view of a surface or a solid: the GLB the export gives
// (api/scene.glb), read here and drawn with WebGL, turned by dragging and
// zoomed with the wheel. No library: a GLB is a JSON chunk and a binary one,
// and one shader lights the faces from the eye.
"use strict";

const view3d = { gl: null, program: null, buffers: null, count: 0, centre: [0, 0, 0], radius: 1, zoom: 1, seq: 0, error: null };

// The triangles of a GLB (every TRIANGLES primitive of every mesh), one normal a corner:
// the file's own where it has them, else the face's (flat: a solid's creases stay sharp).
function readGlb(buffer) {
  const dv = new DataView(buffer);
  if (buffer.byteLength < 20 || dv.getUint32(0, true) !== 0x46546c67) throw new Error("not a GLB file");
  let json = null, bin = null;
  for (let at = 12; at + 8 <= buffer.byteLength;) {
    const length = dv.getUint32(at, true), type = dv.getUint32(at + 4, true);
    const chunk = buffer.slice(at + 8, at + 8 + length);
    if (type === 0x4e4f534a) json = JSON.parse(new TextDecoder().decode(chunk));
    else if (type === 0x004e4942) bin = chunk;
    at += 8 + length;
  }
  if (!json) throw new Error("a GLB without its JSON chunk");
  const read = (i) => {
    const a = json.accessors[i], v = json.bufferViews[a.bufferView];
    const width = { SCALAR: 1, VEC2: 2, VEC3: 3, VEC4: 4 }[a.type];
    const Kind = { 5126: Float32Array, 5125: Uint32Array, 5123: Uint16Array, 5121: Uint8Array }[a.componentType];
    const size = Kind.BYTES_PER_ELEMENT, stride = v.byteStride || width * size;
    const view = new DataView(bin, (v.byteOffset || 0) + (a.byteOffset || 0));
    const get = { 5126: (o) => view.getFloat32(o, true), 5125: (o) => view.getUint32(o, true), 5123: (o) => view.getUint16(o, true), 5121: (o) => view.getUint8(o) }[a.componentType];
    const out = new Kind(a.count * width);
    for (let k = 0; k < a.count; k++) for (let c = 0; c < width; c++) out[k * width + c] = get(k * stride + c * size);
    return out;
  };
  const positions = [], normals = [];
  for (const mesh of json.meshes || []) {
    for (const p of mesh.primitives) {
      if ((p.mode ?? 4) !== 4 || p.attributes.POSITION === undefined) continue;
      const pos = read(p.attributes.POSITION);
      const nrm = p.attributes.NORMAL === undefined ? null : read(p.attributes.NORMAL);
      const index = p.indices === undefined ? Uint32Array.from({ length: pos.length / 3 }, (_, i) => i) : read(p.indices);
      for (let t = 0; t + 2 < index.length; t += 3) {
        const c = [index[t], index[t + 1], index[t + 2]];
        const q = c.map((v) => [pos[3 * v], pos[3 * v + 1], pos[3 * v + 2]]);
        const u = q[1].map((x, a) => x - q[0][a]), w = q[2].map((x, a) => x - q[0][a]);
        const face = [u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0]];
        for (let k = 0; k < 3; k++) {
          positions.push(...q[k]);
          normals.push(...(nrm ? [nrm[3 * c[k]], nrm[3 * c[k] + 1], nrm[3 * c[k] + 2]] : face));
        }
      }
    }
  }
  return { positions: new Float32Array(positions), normals: new Float32Array(normals) };
}

function setup3d(canvas) {
  const gl = canvas.getContext("webgl", { preserveDrawingBuffer: true, antialias: true });
  if (!gl) { view3d.error = "this browser has no WebGL: the 3D view needs it (the picture still works)"; return; }
  const shader = (type, text) => {
    const s = gl.createShader(type);
    gl.shaderSource(s, text);
    gl.compileShader(s);
    return s;
  };
  const program = gl.createProgram();
  gl.attachShader(program, shader(gl.VERTEX_SHADER, `
    attribute vec3 position; attribute vec3 normal;
    uniform mat4 view; uniform mat4 projection; varying vec3 n;
    void main() { n = mat3(view) * normal; gl_Position = projection * view * vec4(position, 1.0); }`));
  // Lit from the eye, both sides (an open surface shows its back).
  gl.attachShader(program, shader(gl.FRAGMENT_SHADER, `
    precision mediump float; varying vec3 n;
    void main() { float l = length(n) > 0.0 ? abs(normalize(n).z) : 1.0;
                  gl_FragColor = vec4(vec3(0.56, 0.64, 0.77) * (0.3 + 0.7 * l), 1.0); }`));
  gl.linkProgram(program);
  view3d.gl = gl;
  view3d.program = program;
  view3d.buffers = { position: gl.createBuffer(), normal: gl.createBuffer() };
}

// Column-major 4×4 matrices: a perspective and a camera looking at `centre` from `eye`, y up.
function perspective(fovy, aspect, near, far) {
  const f = 1 / Math.tan(fovy / 2), d = near - far;
  return [f / aspect, 0, 0, 0, 0, f, 0, 0, 0, 0, (far + near) / d, -1, 0, 0, (2 * far * near) / d, 0];
}

function lookAt(eye, centre) {
  const sub = (a, b) => a.map((x, i) => x - b[i]);
  const norm = (a) => { const l = Math.hypot(...a) || 1; return a.map((x) => x / l); };
  const cross = (a, b) => [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]];
  const dot = (a, b) => a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
  const z = norm(sub(eye, centre)), x = norm(cross([0, 1, 0], z)), y = cross(z, x);
  return [x[0], y[0], z[0], 0, x[1], y[1], z[1], 0, x[2], y[2], z[2], 0, -dot(x, eye), -dot(y, eye), -dot(z, eye), 1];
}

function draw3d() {
  const gl = view3d.gl, canvas = $("scene");
  if (!gl) return;
  const side = Math.round(canvas.clientWidth * (window.devicePixelRatio || 1)) || 600;
  if (canvas.width !== side) { canvas.width = side; canvas.height = side; }
  gl.viewport(0, 0, canvas.width, canvas.height);
  gl.clearColor(1, 1, 1, 1);
  gl.clear(gl.COLOR_BUFFER_BIT | gl.DEPTH_BUFFER_BIT);
  if (view3d.count === 0) return;
  gl.enable(gl.DEPTH_TEST);
  gl.useProgram(view3d.program);
  const [yaw, pitch] = [state.yaw, state.pitch].map((d) => (d * Math.PI) / 180);
  const distance = (view3d.radius / Math.sin(Math.PI / 10)) * view3d.zoom;
  const c = view3d.centre;
  const eye = [c[0] + distance * Math.cos(pitch) * Math.sin(yaw), c[1] + distance * Math.sin(pitch), c[2] + distance * Math.cos(pitch) * Math.cos(yaw)];
  gl.uniformMatrix4fv(gl.getUniformLocation(view3d.program, "view"), false, lookAt(eye, c));
  gl.uniformMatrix4fv(gl.getUniformLocation(view3d.program, "projection"), false, perspective(Math.PI / 5, 1, distance / 100, distance * 3));
  for (const name of ["position", "normal"]) {
    const at = gl.getAttribLocation(view3d.program, name);
    gl.bindBuffer(gl.ARRAY_BUFFER, view3d.buffers[name]);
    gl.enableVertexAttribArray(at);
    gl.vertexAttribPointer(at, 3, gl.FLOAT, false, 0, 0);
  }
  gl.drawArrays(gl.TRIANGLES, 0, view3d.count);
}

// The scene at the page's parameters (the preview depth while a slider moves): a newer one cancels it.
async function scene(coarse) {
  if (view3d.error) { refusal("picture", view3d.error); return; }
  const depth = coarse ? Math.min(state.depth, state.preview) : state.depth;
  const seq = ++view3d.seq;
  const response = await get("api/scene.glb?" + query({ depth, slot: `picture-${session}`, seq }));
  if (seq !== view3d.seq) return;
  if (response === null) { refusal("picture", "the server does not answer (is bcifs explore still running?)"); return; }
  if (response.status === 409) return;
  if (!response.ok) { const error = await reason(response); $("status").textContent = error; refusal("picture", error); return; }
  let mesh;
  try { mesh = readGlb(await response.arrayBuffer()); } catch (e) { refusal("picture", String(e.message || e)); return; }
  if (seq !== view3d.seq) return;
  refusal("picture", null);
  $("status").textContent = coarse && depth < state.depth ? `preview at depth ${depth}` : "";
  const gl = view3d.gl;
  gl.bindBuffer(gl.ARRAY_BUFFER, view3d.buffers.position);
  gl.bufferData(gl.ARRAY_BUFFER, mesh.positions, gl.STATIC_DRAW);
  gl.bindBuffer(gl.ARRAY_BUFFER, view3d.buffers.normal);
  gl.bufferData(gl.ARRAY_BUFFER, mesh.normals, gl.STATIC_DRAW);
  view3d.count = mesh.positions.length / 3;
  const lo = [Infinity, Infinity, Infinity], hi = [-Infinity, -Infinity, -Infinity];
  for (let i = 0; i < mesh.positions.length; i++) { lo[i % 3] = Math.min(lo[i % 3], mesh.positions[i]); hi[i % 3] = Math.max(hi[i % 3], mesh.positions[i]); }
  view3d.centre = lo.map((x, a) => (x + hi[a]) / 2);
  view3d.radius = Math.max(1e-9, Math.hypot(...hi.map((x, a) => x - lo[a])) / 2);
  draw3d();
  document.body.dataset.scene = String(view3d.count / 3);
}

// The 3D view on or off: the canvas stands where the picture was; dragging turns it, the wheel zooms.
function show3d(on) {
  state.view3d = on;
  $("picture").hidden = on;
  $("scene").hidden = !on;
  if (on && !view3d.gl && !view3d.error) setup3d($("scene"));
  update(false);
}

function controls3d() {
  const canvas = $("scene");
  let from = null;
  canvas.addEventListener("mousedown", (e) => { from = { x: e.clientX, y: e.clientY, yaw: state.yaw, pitch: state.pitch }; e.preventDefault(); });
  window.addEventListener("mousemove", (e) => {
    if (!from || !state.view3d) return;
    state.yaw = Math.round(((from.yaw + (e.clientX - from.x) / 2 + 540) % 360) - 180);
    state.pitch = Math.round(Math.max(-89, Math.min(89, from.pitch + (e.clientY - from.y) / 2)));
    $("yaw").value = state.yaw; $("pitch").value = state.pitch;
    $("view-value").textContent = `${state.yaw}°, ${state.pitch}°`;
    draw3d();
  });
  window.addEventListener("mouseup", () => { if (from) { from = null; saveUrl(); } });
  canvas.addEventListener("wheel", (e) => {
    e.preventDefault();
    view3d.zoom = Math.max(0.05, Math.min(20, view3d.zoom * Math.exp(e.deltaY / 500)));
    draw3d();
  }, { passive: false });
}
