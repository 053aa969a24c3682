#!/usr/bin/env python3
"""Mesa llvmpipe (OpenGL on the CPU) draws a model file in relief's anchor view.

The other side of `relief bench --anchors --model FILE` (docs/bench.md, "A model file
side by side with llvmpipe"): the same file, view, lighting and timing, so the two
run one after the other and compare as ratios. Not part of relief's build or CI.

    docs/tools/llvmpipe_setup.sh                      # venv in target/llvmpipe-venv
    PY=target/llvmpipe-venv/bin/python
    $PY docs/tools/llvmpipe_mesh.py sphere --triangles 1000000 --out /tmp/s1m.ply
    $PY docs/tools/llvmpipe_mesh.py bench /tmp/s1m.ply --threads 1,2
    $PY docs/tools/llvmpipe_mesh.py bench /tmp/s1m.ply --sizes 320x240 --png /tmp/llvmpipe.png
    $PY docs/tools/llvmpipe_mesh.py compare /tmp/relief.png /tmp/llvmpipe.png
    $PY docs/tools/llvmpipe_mesh.py table relief_1m.txt llvmpipe_1m.txt [more pairs...]

The view (relief's, see crates/bench/src/mesh_anchor.rs):
- the model is centred on its bounding box and scaled so its farthest vertex is 1.5
  from the centre; model matrix Rz(0)·Ry(35°)·Rx(25°) (X turned first);
- camera at (0,0,5) looking at the origin, y up, 60° vertical field of view, aspect
  width/height, near 0.1, far 100 (OpenGL clip depth);
- vertex colour 0.4 + 0.3·(p/1.5 + 1) per channel of the fitted position p;
- per pixel: N = normalize(interpolated world normal), for each light
  L = normalize(light − P): colour · (0.1 + Σ light colour · max(0, N·L)), clamped;
  white light (1,1,1) at (3,4,6), red 0.3 at (−8,1,3), green 0.3 at (8,−2,3),
  blue 0.3 at (0,−8,2); no attenuation, no highlight, no shadow;
- background (16,24,32), depth test LESS on a 24-bit depth buffer, back faces culled
  (counter-clockwise front) unless --no-cull (relief culls a closed model only).

A timed frame: two mat4 uniforms, glClear, glDrawElements over the whole mesh, then
glFinish ("finish", the median_ms column) or glReadPixels into a kept buffer
("readback"). Each thread count (LP_NUM_THREADS, read when llvmpipe makes its
context) runs in its own process; in it the sizes are interleaved over --rounds
rounds, each of one warm-up frame and then as many frames as fit in 0.6 s (2 to
40), as relief's side does. Rows print as relief's do.

Reads binary little-endian PLY (float x y z nx ny nz vertices, `list uchar int|uint`
triangle faces) and binary STL (facet normals, a vertex per corner). Needs the
normals: relief would compute missing ones, this harness does not.
"""
import argparse
import ctypes
import json
import math
import os
import statistics
import subprocess
import sys
import time

os.environ.setdefault("PYOPENGL_PLATFORM", "egl")

import numpy as np  # noqa: E402

FIT_RADIUS = 1.5
AMBIENT = 0.1
BACKGROUND = (16, 24, 32)
LIGHTS = [((3.0, 4.0, 6.0), (1.0, 1.0, 1.0)),
          ((-8.0, 1.0, 3.0), (0.3, 0.0, 0.0)),
          ((8.0, -2.0, 3.0), (0.0, 0.3, 0.0)),
          ((0.0, -8.0, 2.0), (0.0, 0.0, 0.3))]
ROTATION_DEGREES = (25.0, 35.0, 0.0)
ROUND_BUDGET_S = 0.6
MIN_FRAMES, MAX_FRAMES = 2, 40


# ---------------------------------------------------------------- mesh files

def uv_sphere(rings, segments):
    """Unit UV sphere: positions (= normals) and triangles, counter-clockwise from
    outside; laid out as relief's `mesh_anchor::uv_sphere_ply` lays it out."""
    i = np.arange(1, rings, dtype=np.float64)[:, None]
    j = np.arange(segments, dtype=np.float64)[None, :]
    theta = np.pi * i / rings
    phi = 2.0 * np.pi * j / segments
    ring = np.stack([np.sin(theta) * np.cos(phi),
                     np.broadcast_to(np.cos(theta), (rings - 1, segments)),
                     np.sin(theta) * np.sin(phi)], axis=-1).reshape(-1, 3)
    normals = np.concatenate([[[0.0, 1.0, 0.0]], ring, [[0.0, -1.0, 0.0]]])
    top, bottom = 0, len(normals) - 1
    jj = np.arange(segments, dtype=np.uint32)
    at = lambda r, c: 1 + (r - 1) * segments + c % segments  # noqa: E731
    caps_top = np.stack([np.full(segments, top, np.uint32), at(1, jj + 1), at(1, jj)], axis=1)
    r = np.arange(1, rings - 1, dtype=np.uint32)[:, None]
    a, b, c, d = at(r, jj), at(r, jj + 1), at(r + 1, jj + 1), at(r + 1, jj)
    middle = np.stack([np.stack([a, b, c], -1), np.stack([a, c, d], -1)], axis=2).reshape(-1, 3)
    caps_bottom = np.stack([np.full(segments, bottom, np.uint32), at(rings - 1, jj), at(rings - 1, jj + 1)],
                           axis=1)
    return normals, np.concatenate([caps_top, middle, caps_bottom]).astype(np.uint32)


def write_ply(path, positions, normals, triangles):
    header = ("ply\nformat binary_little_endian 1.0\n"
              f"element vertex {len(positions)}\n"
              "property float x\nproperty float y\nproperty float z\n"
              "property float nx\nproperty float ny\nproperty float nz\n"
              f"element face {len(triangles)}\n"
              "property list uchar uint vertex_indices\nend_header\n")
    verts = np.concatenate([positions, normals], axis=1).astype("<f4")
    faces = np.zeros(len(triangles), dtype=[("n", "u1"), ("i", "<u4", 3)])
    faces["n"] = 3
    faces["i"] = triangles
    with open(path, "wb") as fh:
        fh.write(header.encode())
        fh.write(verts.tobytes())
        fh.write(faces.tobytes())


PLY_TYPES = {"char": "i1", "int8": "i1", "uchar": "u1", "uint8": "u1", "short": "<i2", "int16": "<i2",
             "ushort": "<u2", "uint16": "<u2", "int": "<i4", "int32": "<i4", "uint": "<u4", "uint32": "<u4",
             "float": "<f4", "float32": "<f4", "double": "<f8", "float64": "<f8"}


def read_ply(path):
    data = open(path, "rb").read()
    end = data.index(b"end_header\n") + len(b"end_header\n")
    lines = data[:end].decode("ascii").split("\n")
    if "format binary_little_endian 1.0" not in lines:
        sys.exit(f"{path}: only binary little-endian PLY is read here")
    elements, current = [], None
    for line in lines:
        w = line.split()
        if w[:1] == ["element"]:
            current = {"name": w[1], "count": int(w[2]), "props": []}
            elements.append(current)
        elif w[:1] == ["property"]:
            current["props"].append(w[1:])
    offset, out = end, {}
    for el in elements:
        if el["name"] == "face":
            p = el["props"]
            if len(p) != 1 or p[0][0] != "list" or p[0][1] not in ("uchar", "uint8"):
                sys.exit(f"{path}: faces must be one `list uchar <int type>`")
            dt = np.dtype([("n", "u1"), ("i", PLY_TYPES[p[0][2]], 3)])
            faces = np.frombuffer(data, dt, el["count"], offset)
            if np.any(faces["n"] != 3):
                sys.exit(f"{path}: faces must be triangles")
            out["triangles"] = faces["i"].astype(np.uint32)
        else:
            if any(p[0] == "list" for p in el["props"]):
                sys.exit(f"{path}: list property in element {el['name']}")
            dt = np.dtype([(p[1], PLY_TYPES[p[0]]) for p in el["props"]])
            arr = np.frombuffer(data, dt, el["count"], offset)
            if el["name"] == "vertex":
                names = dt.names
                if not all(k in names for k in ("x", "y", "z", "nx", "ny", "nz")):
                    sys.exit(f"{path}: vertices need x y z nx ny nz")
                out["positions"] = np.stack([arr[k] for k in ("x", "y", "z")], 1).astype(np.float32)
                out["normals"] = np.stack([arr[k] for k in ("nx", "ny", "nz")], 1).astype(np.float32)
        offset += dt.itemsize * el["count"]
    return out["positions"], out["normals"], out["triangles"]


def read_stl(path):
    data = open(path, "rb").read()
    count = int.from_bytes(data[80:84], "little")
    if len(data) != 84 + 50 * count:
        sys.exit(f"{path}: not a binary STL of {count} triangles")
    dt = np.dtype([("n", "<f4", 3), ("v", "<f4", (3, 3)), ("attr", "<u2")])
    facets = np.frombuffer(data, dt, count, 84)
    positions = facets["v"].reshape(-1, 3).astype(np.float32)
    normals = np.repeat(facets["n"], 3, axis=0).astype(np.float32)
    return positions, normals, np.arange(3 * count, dtype=np.uint32).reshape(-1, 3)


def load_mesh(path):
    positions, normals, triangles = (read_stl if path.lower().endswith(".stl") else read_ply)(path)
    # relief's fit: centre of the bounding box, farthest vertex at FIT_RADIUS (in f64).
    p = positions.astype(np.float64)
    centre = (p.min(axis=0) + p.max(axis=0)) * 0.5
    scale = FIT_RADIUS / np.sqrt(((p - centre) ** 2).sum(axis=1)).max()
    fitted = ((p - centre) * scale).astype(np.float32)
    lengths = np.linalg.norm(normals, axis=1, keepdims=True)
    normals = np.where(lengths > 0, normals / np.maximum(lengths, 1e-30), [[0.0, 0.0, 1.0]]).astype(np.float32)
    return fitted, normals, np.ascontiguousarray(triangles, dtype=np.uint32)


# ---------------------------------------------------------------- the view

def rotation(axis, degrees):
    c, s = math.cos(math.radians(degrees)), math.sin(math.radians(degrees))
    m = np.eye(4)
    a, b = {"x": (1, 2), "y": (2, 0), "z": (0, 1)}[axis]
    m[a, a], m[a, b], m[b, a], m[b, b] = c, -s, s, c
    return m


def model_matrix():
    x, y, z = ROTATION_DEGREES
    return rotation("z", z) @ rotation("y", y) @ rotation("x", x)


def view_projection(width, height, fov=60.0, near=0.1, far=100.0):
    f = 1.0 / math.tan(math.radians(fov) / 2.0)
    projection = np.zeros((4, 4))
    projection[0, 0], projection[1, 1] = f * height / width, f
    projection[2, 2], projection[2, 3] = (far + near) / (near - far), 2.0 * far * near / (near - far)
    projection[3, 2] = -1.0
    view = np.eye(4)
    view[2, 3] = -5.0  # the eye at (0,0,5) looking down −z
    return projection @ view


VERTEX_SHADER = """#version 330 core
layout(location = 0) in vec3 position;
layout(location = 1) in vec3 normal;
uniform mat4 mvp;
uniform mat4 model;
out vec3 world;
out vec3 world_normal;
out vec3 colour;
void main() {
    world = (model * vec4(position, 1.0)).xyz;
    world_normal = mat3(model) * normal;
    colour = min(vec3(0.4) + 0.3 * (position / 1.5 + vec3(1.0)), vec3(1.0));
    gl_Position = mvp * vec4(position, 1.0);
}
"""

FRAGMENT_SHADER = """#version 330 core
in vec3 world;
in vec3 world_normal;
in vec3 colour;
uniform vec3 light_position[4];
uniform vec3 light_colour[4];
uniform float ambient;
out vec4 frag;
void main() {
    vec3 n = normalize(world_normal);
    vec3 light = vec3(ambient);
    for (int k = 0; k < 4; ++k) {
        light += light_colour[k] * max(dot(n, normalize(light_position[k] - world)), 0.0);
    }
    frag = vec4(clamp(colour * light, 0.0, 1.0), 1.0);
}
"""


# ---------------------------------------------------------------- OpenGL

def gl_context():
    """A GL 3.3 core context on EGL's surfaceless platform (no window, no X)."""
    from OpenGL import EGL
    surfaceless = 0x31DD  # EGL_PLATFORM_SURFACELESS_MESA
    display = EGL.eglGetPlatformDisplayEXT(surfaceless, EGL.EGL_DEFAULT_DISPLAY, None)
    if not EGL.eglInitialize(display, None, None):
        sys.exit("eglInitialize failed")
    EGL.eglBindAPI(EGL.EGL_OPENGL_API)
    # No surface type: the default (window) has no config on the surfaceless platform.
    wanted = (EGL.EGLint * 5)(EGL.EGL_RENDERABLE_TYPE, EGL.EGL_OPENGL_BIT, EGL.EGL_SURFACE_TYPE, 0, EGL.EGL_NONE)
    config, found = EGL.EGLConfig(), EGL.EGLint()
    if not EGL.eglChooseConfig(display, wanted, ctypes.pointer(config), 1, ctypes.pointer(found)) or not found.value:
        sys.exit("no EGL config for desktop OpenGL")
    version = (EGL.EGLint * 7)(EGL.EGL_CONTEXT_MAJOR_VERSION, 3, EGL.EGL_CONTEXT_MINOR_VERSION, 3,
                               EGL.EGL_CONTEXT_OPENGL_PROFILE_MASK, EGL.EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
                               EGL.EGL_NONE)
    context = EGL.eglCreateContext(display, config, EGL.EGL_NO_CONTEXT, version)
    if not context or not EGL.eglMakeCurrent(display, EGL.EGL_NO_SURFACE, EGL.EGL_NO_SURFACE, context):
        sys.exit("cannot make a GL 3.3 core context current")


class Target:
    """An RGBA8 + DEPTH24 framebuffer object of one size, and its readback buffer."""

    def __init__(self, GL, width, height):
        self.width, self.height = width, height
        self.fbo = GL.glGenFramebuffers(1)
        GL.glBindFramebuffer(GL.GL_FRAMEBUFFER, self.fbo)
        colour, depth = GL.glGenRenderbuffers(2)
        for rb, fmt, attachment in ((colour, GL.GL_RGBA8, GL.GL_COLOR_ATTACHMENT0),
                                    (depth, GL.GL_DEPTH_COMPONENT24, GL.GL_DEPTH_ATTACHMENT)):
            GL.glBindRenderbuffer(GL.GL_RENDERBUFFER, rb)
            GL.glRenderbufferStorage(GL.GL_RENDERBUFFER, fmt, width, height)
            GL.glFramebufferRenderbuffer(GL.GL_FRAMEBUFFER, attachment, GL.GL_RENDERBUFFER, rb)
        if GL.glCheckFramebufferStatus(GL.GL_FRAMEBUFFER) != GL.GL_FRAMEBUFFER_COMPLETE:
            sys.exit("framebuffer incomplete")
        self.pixels = np.zeros(width * height * 4, np.uint8)
        m = model_matrix()
        self.mvp = np.ascontiguousarray(view_projection(width, height) @ m, np.float32)
        self.model = np.ascontiguousarray(m, np.float32)

    def picture(self):
        """RGB rows, top first."""
        return self.pixels.reshape(self.height, self.width, 4)[::-1, :, :3]

    def covered(self):
        return int(np.count_nonzero(np.any(self.picture() != np.array(BACKGROUND, np.uint8), axis=2)))


def frames_for(seconds):
    return max(MIN_FRAMES, min(MAX_FRAMES, int(ROUND_BUDGET_S / max(seconds, 1e-6))))


def child(args):
    import OpenGL
    OpenGL.ERROR_CHECKING = False  # no glGetError after each call; checked by hand below
    try:
        import OpenGL.raw.EGL._errors as egl_errors  # PyOpenGL 3.1 needs this name with checking off
        if not hasattr(egl_errors, "_error_checker"):
            egl_errors._error_checker = None
    except ImportError:
        pass
    gl_context()
    from OpenGL import GL
    from OpenGL.GL import shaders

    renderer = GL.glGetString(GL.GL_RENDERER).decode()
    load_start = time.perf_counter()
    positions, normals, triangles = load_mesh(args.mesh)
    load_s = time.perf_counter() - load_start

    program = shaders.compileProgram(shaders.compileShader(VERTEX_SHADER, GL.GL_VERTEX_SHADER),
                                     shaders.compileShader(FRAGMENT_SHADER, GL.GL_FRAGMENT_SHADER))
    GL.glUseProgram(program)
    GL.glUniform3fv(GL.glGetUniformLocation(program, "light_position"), 4,
                    np.array([p for p, _ in LIGHTS], np.float32))
    GL.glUniform3fv(GL.glGetUniformLocation(program, "light_colour"), 4,
                    np.array([c for _, c in LIGHTS], np.float32))
    GL.glUniform1f(GL.glGetUniformLocation(program, "ambient"), AMBIENT)
    mvp_at, model_at = (GL.glGetUniformLocation(program, n) for n in ("mvp", "model"))

    GL.glBindVertexArray(GL.glGenVertexArrays(1))
    for location, array in enumerate((positions, normals)):
        GL.glBindBuffer(GL.GL_ARRAY_BUFFER, GL.glGenBuffers(1))
        GL.glBufferData(GL.GL_ARRAY_BUFFER, array.nbytes, array, GL.GL_STATIC_DRAW)
        GL.glEnableVertexAttribArray(location)
        GL.glVertexAttribPointer(location, 3, GL.GL_FLOAT, GL.GL_FALSE, 12, None)
    GL.glBindBuffer(GL.GL_ELEMENT_ARRAY_BUFFER, GL.glGenBuffers(1))
    GL.glBufferData(GL.GL_ELEMENT_ARRAY_BUFFER, triangles.nbytes, triangles, GL.GL_STATIC_DRAW)
    index_count = triangles.size
    del positions, normals, triangles  # GL has its copies

    GL.glClearColor(*(c / 255.0 for c in BACKGROUND), 1.0)
    GL.glEnable(GL.GL_DEPTH_TEST)
    GL.glDepthFunc(GL.GL_LESS)
    if args.cull:
        GL.glEnable(GL.GL_CULL_FACE)
        GL.glCullFace(GL.GL_BACK)
        GL.glFrontFace(GL.GL_CCW)
    GL.glPixelStorei(GL.GL_PACK_ALIGNMENT, 1)

    from OpenGL.raw.GL.VERSION.GL_1_0 import glClear, glFinish, glReadPixels, glViewport
    from OpenGL.raw.GL.VERSION.GL_1_1 import glDrawElements
    from OpenGL.raw.GL.VERSION.GL_2_0 import glUniformMatrix4fv
    from OpenGL.raw.GL.VERSION.GL_3_0 import glBindFramebuffer

    targets = [Target(GL, w, h) for w, h in args.sizes]
    clear_bits = GL.GL_COLOR_BUFFER_BIT | GL.GL_DEPTH_BUFFER_BIT

    def draw(t):
        glBindFramebuffer(GL.GL_FRAMEBUFFER, t.fbo)
        glViewport(0, 0, t.width, t.height)
        glUniformMatrix4fv(mvp_at, 1, GL.GL_TRUE, t.mvp.ctypes.data_as(ctypes.c_void_p))
        glUniformMatrix4fv(model_at, 1, GL.GL_TRUE, t.model.ctypes.data_as(ctypes.c_void_p))
        glClear(clear_bits)
        glDrawElements(GL.GL_TRIANGLES, index_count, GL.GL_UNSIGNED_INT, None)

    def read_back(t):
        glReadPixels(0, 0, t.width, t.height, GL.GL_RGBA, GL.GL_UNSIGNED_BYTE,
                     t.pixels.ctypes.data_as(ctypes.c_void_p))

    first = {}  # the second frame's time (the first compiles the shaders)
    for t in targets:
        for _ in range(2):
            start = time.perf_counter()
            draw(t)
            read_back(t)
            first[t] = time.perf_counter() - start
    if GL.glGetError() != GL.GL_NO_ERROR:
        sys.exit("GL error while drawing")
    covered = {t: t.covered() for t in targets}
    if args.png:
        write_png(args.png, targets[0].picture())

    times = {(t, mode): [] for t in targets for mode in ("finish", "readback")}
    for _ in range(args.rounds):
        for t in targets:
            n = frames_for(first[t])
            for mode in ("finish", "readback"):
                end = glFinish if mode == "finish" else (lambda: read_back(t))
                draw(t)
                end()  # warm-up
                for _ in range(n):
                    start = time.perf_counter()
                    draw(t)
                    end()
                    times[(t, mode)].append(time.perf_counter() - start)
    if GL.glGetError() != GL.GL_NO_ERROR:
        sys.exit("GL error while timing")
    for t in targets:
        print("RESULT " + json.dumps({
            "renderer": renderer, "width": t.width, "height": t.height, "covered": covered[t],
            "triangles": index_count // 3, "load_s": load_s,
            "finish": times[(t, "finish")], "readback": times[(t, "readback")]}), flush=True)


def write_png(path, rgb):
    import png
    h, w, _ = rgb.shape
    with open(path, "wb") as fh:
        png.Writer(w, h, greyscale=False).write(fh, np.ascontiguousarray(rgb).reshape(h, w * 3).tolist())


def read_png(path):
    import png
    w, h, rows, info = png.Reader(filename=path).asRGB8()
    return np.array([np.frombuffer(bytes(r), np.uint8) for r in rows]).reshape(h, w, 3)


# ---------------------------------------------------------------- commands

def cmd_sphere(args):
    n = args.triangles
    rings = max(2, round(math.sqrt(n / 4.0)) + 1)
    segments = max(3, round(n / (2.0 * (rings - 1))))
    normals, triangles = uv_sphere(rings, segments)
    write_ply(args.out, normals * args.radius, normals, triangles)
    print(f"{args.out}: UV sphere of {rings} rings, {segments} segments: "
          f"{len(triangles)} triangles, {len(normals)} vertices")


def cmd_bench(args):
    sizes = ",".join(f"{w}x{h}" for w, h in args.sizes)
    rows = []
    for threads in args.threads.split(","):
        env = dict(os.environ)
        if threads == "default":
            env.pop("LP_NUM_THREADS", None)
        else:
            env["LP_NUM_THREADS"] = threads
        argv = [sys.executable, os.path.abspath(__file__), "child", args.mesh, "--sizes", sizes,
                "--rounds", str(args.rounds)] + ([] if args.cull else ["--no-cull"]) + \
               (["--png", args.png] if args.png and not rows else [])
        done = subprocess.run(argv, env=env, stdout=subprocess.PIPE, text=True)
        if done.returncode:
            return done.returncode
        for line in done.stdout.splitlines():
            if line.startswith("RESULT "):
                rows.append((threads, json.loads(line[7:])))
    first = rows[0][1]
    print(f"llvmpipe_mesh.py bench {args.mesh}: {first['triangles']} triangles, "
          f"{'back faces culled' if args.cull else 'both sides drawn'}; {first['renderer']}; "
          f"loaded in {first['load_s']:.2f} s; {args.rounds} rounds, each {MIN_FRAMES} to {MAX_FRAMES} frames "
          f"(about {int(ROUND_BUDGET_S * 1000)} ms) after one warm-up frame; median and min per frame "
          "(finish: glFinish; readback: glReadPixels)")
    order = {(w, h): k for k, (w, h) in enumerate(args.sizes)}
    rows.sort(key=lambda r: (order[(r[1]["width"], r[1]["height"])]))
    for threads, r in rows:
        f, rb = r["finish"], r["readback"]
        med = statistics.median(f) * 1e3
        print(f"variant=mesh    size={r['width']}x{r['height']} threads={threads} frames={len(f)} "
              f"median_ms={med:.4f} min_ms={min(f) * 1e3:.4f} covered_px={r['covered']} "
              f"ns_per_px={med * 1e6 / max(r['covered'], 1):.1f} "
              f"readback_median_ms={statistics.median(rb) * 1e3:.4f}", flush=True)
    return 0


def cmd_compare(args):
    a, b = read_png(args.relief), read_png(args.llvmpipe)
    if a.shape != b.shape:
        sys.exit(f"sizes differ: {a.shape[1]}x{a.shape[0]} and {b.shape[1]}x{b.shape[0]}")
    bg = np.array(BACKGROUND, np.uint8)
    ca, cb = np.any(a != bg, axis=2), np.any(b != bg, axis=2)
    both = ca & cb
    diff = np.abs(a.astype(int) - b.astype(int))[both]
    print(f"covered: relief {int(ca.sum())}, llvmpipe {int(cb.sum())}, by one only {int((ca ^ cb).sum())}; "
          f"where both: largest channel difference {int(diff.max()) if diff.size else 0}, "
          f"mean {diff.mean() if diff.size else 0:.3f}, pixels off by more than 2: "
          f"{int(np.any(np.abs(a.astype(int) - b.astype(int)) > 2, axis=2)[both].sum())}")


def read_rows(path):
    """The triangle count of the header line and the `key=value` rows of a bench output."""
    triangles, rows = None, []
    for line in open(path):
        if line.startswith(("relief bench", "llvmpipe_mesh.py bench")) and " triangles" in line:
            triangles = int(line.split(" triangles")[0].rsplit(" ", 1)[1])
        elif line.startswith("variant="):
            rows.append(dict(kv.split("=", 1) for kv in line.split()))
    return triangles, rows


def cmd_table(args):
    """Markdown rows of relief's and llvmpipe's outputs side by side (median, min in parentheses)."""
    print("| triangles | size | threads | relief | relief + shadow pass | llvmpipe | relief / llvmpipe |")
    print("|--:|:--|--:|--:|--:|--:|--:|")
    for relief_path, llvmpipe_path in zip(args.files[::2], args.files[1::2]):
        triangles, ours = read_rows(relief_path)
        their_triangles, theirs = read_rows(llvmpipe_path)
        triangles = triangles or their_triangles  # relief may have refused the file
        for t in theirs:
            key = (t["size"], t["threads"])
            cell = lambda r: f"{float(r['median_ms']):.1f} ({float(r['min_ms']):.1f})"  # noqa: E731
            mine = {r["variant"]: r for r in ours if (r["size"], r["threads"]) == key}
            mesh, shadows = mine.get("mesh"), mine.get("mesh+shadows")
            ratio = f"{float(mesh['median_ms']) / float(t['median_ms']):.2f}" if mesh else "—"
            print(f"| {triangles:,} | {t['size'].replace('x', '×')} | {t['threads']} | "
                  f"{cell(mesh) if mesh else 'refused'} | {cell(shadows) if shadows else '—'} | "
                  f"{cell(t)} | {ratio} |")


def parse_sizes(text):
    return [tuple(int(v) for v in s.split("x")) for s in text.split(",")]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    sub = ap.add_subparsers(dest="command", required=True)
    s = sub.add_parser("sphere", help="write a UV sphere as a binary PLY")
    s.add_argument("--triangles", type=int, required=True)
    s.add_argument("--radius", type=float, default=1.0)
    s.add_argument("--out", required=True)
    for name in ("bench", "child"):
        b = sub.add_parser(name, help="time the view of MESH" if name == "bench" else argparse.SUPPRESS)
        b.add_argument("mesh")
        b.add_argument("--sizes", type=parse_sizes, default=parse_sizes("320x192,640x480"))
        b.add_argument("--rounds", type=int, default=3)
        b.add_argument("--no-cull", dest="cull", action="store_false")
        b.add_argument("--png", help="write the first size's picture (first thread count) as PNG")
        if name == "bench":
            b.add_argument("--threads", default="1,2", help="LP_NUM_THREADS values, each in its own process")
    c = sub.add_parser("compare", help="coverage and colour of two pictures of the view")
    c.add_argument("relief")
    c.add_argument("llvmpipe")
    t = sub.add_parser("table", help="a Markdown table of relief's and this harness' outputs side by side")
    t.add_argument("files", nargs="+", help="RELIEF.txt LLVMPIPE.txt pairs, one pair per mesh")
    args = ap.parse_args()
    commands = {"sphere": cmd_sphere, "bench": cmd_bench, "child": child, "compare": cmd_compare, "table": cmd_table}
    return commands[args.command](args)


if __name__ == "__main__":
    sys.exit(main() or 0)
