#!/usr/bin/env python3
"""Mesa llvmpipe (OpenGL on the CPU) draws a model file in relief's anchor view.

The other side of `relief bench --anchors --model FILE` (docs/bench.md, "A model file
side by side with llvmpipe"): the same file, view, lighting and timing, so the two
run one after the other and compare as ratios. Not part of relief's build or CI.

    docs/tools/llvmpipe_setup.sh                      # venv in target/llvmpipe-venv
    PY=target/llvmpipe-venv/bin/python
    $PY docs/tools/llvmpipe_mesh.py sphere --triangles 1000000 --out /tmp/s1m.ply
    $PY docs/tools/llvmpipe_mesh.py sphere --triangles 1000000 --dent 0.06 --out /tmp/d1m.ply  # not convex
    $PY docs/tools/llvmpipe_mesh.py bench /tmp/s1m.ply --threads 1,2
    $PY docs/tools/llvmpipe_mesh.py bench /tmp/s1m.ply --sizes 320x240 --png /tmp/llvmpipe.png
    $PY docs/tools/llvmpipe_mesh.py compare /tmp/relief.png /tmp/llvmpipe.png
    $PY docs/tools/llvmpipe_mesh.py table relief_1m.txt llvmpipe_1m.txt [more pairs...]
    $PY docs/tools/llvmpipe_mesh.py environment --out /tmp/env.hdr
    $PY docs/tools/llvmpipe_mesh.py bench /tmp/s1m.ply --pbr metal --environment /tmp/env.hdr

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

With --pbr (the other side of `relief bench --anchors --model FILE --pbr
--environment-map ENV`, docs/bench.md, "The physically based frame side by side with
llvmpipe"): the same fit, pose and camera, shaded with the glTF 2.0 metallic-roughness
BRDF (appendix B) of one material given by its factors, evaluated here in GLSL:
- base colour, metallic, roughness (held >= 0.045) from --pbr metal|dielectric;
- one white point light at (3,4,6), no falloff: colour · N·L · ((1 − F)·(1 − metallic)·base
  + π·F·D·Vis), D = GGX, Vis = Smith height-correlated, F = Schlick of V·H,
  F0 = mix(0.04, base, metallic), F90 = 1, α = roughness²;
- the environment (an equirectangular Radiance .hdr, e.g. the one `environment` writes,
  read by this file's own decoder): diffuse = irradiance(N)·(1 − metallic)·base·(1 − S),
  specular = prefiltered(R, roughness)·S, S = F0·A + B, R = 2(N·V)N − V. irradiance is 9
  spherical-harmonic coefficients (uniforms) projected here with numpy; prefiltered is ONE
  textureLod of an RGBA16F cube map whose 6 levels (128² to 4² a face) this file prefilters with
  numpy for roughness 0, 0.2, … 1 (GGX-weighted sums over a shrunken picture, N = V = R),
  read at lod 5·roughness (trilinear); A, B a 32×32 split-sum table (N·V, roughness)
  integrated here by GGX importance sampling (1024 Hammersley points);
- then Khronos PBR Neutral and the exact sRGB encoding. Rows print as variant=pbr.

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
# --pbr: the materials by their factors (base colour linear, metallic, roughness), and
# the one white light.
MATERIALS = {"metal": ((1.0, 0.71, 0.29), 1.0, 0.4), "dielectric": ((0.05, 0.2, 0.6), 0.0, 0.5)}
KEY_LIGHT = (3.0, 4.0, 6.0)
EYE = (0.0, 0.0, 5.0)
MIN_ROUGHNESS = 0.045
CUBE_SIZE, CUBE_LEVELS = 128, 6  # levels for roughness 0, 0.2, … 1: 128² … 4² a face
LUT_SIZE, LUT_SAMPLES = 32, 1024
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


PBR_VERTEX_SHADER = """#version 330 core
layout(location = 0) in vec3 position;
layout(location = 1) in vec3 normal;
uniform mat4 mvp;
uniform mat4 model;
out vec3 world;
out vec3 world_normal;
void main() {
    world = (model * vec4(position, 1.0)).xyz;
    world_normal = mat3(model) * normal;
    gl_Position = mvp * vec4(position, 1.0);
}
"""

PBR_FRAGMENT_SHADER = """#version 330 core
in vec3 world;
in vec3 world_normal;
uniform vec3 eye;
uniform vec3 light_position;
uniform vec3 light_colour;
uniform vec3 base;
uniform float metallic;
uniform float roughness;
uniform vec3 sh[9];
uniform samplerCube prefiltered;
uniform float max_lod;
uniform sampler2D split_sum;
uniform float lut_size;
out vec4 frag;
const float PI = 3.14159265358979;

vec3 irradiance(vec3 n) {
    vec3 e = sh[0] * 0.282095
        + sh[1] * (0.488603 * n.y) + sh[2] * (0.488603 * n.z) + sh[3] * (0.488603 * n.x)
        + sh[4] * (1.092548 * n.x * n.y) + sh[5] * (1.092548 * n.y * n.z)
        + sh[6] * (0.315392 * (3.0 * n.z * n.z - 1.0)) + sh[7] * (1.092548 * n.x * n.z)
        + sh[8] * (0.546274 * (n.x * n.x - n.y * n.y));
    return max(e, vec3(0.0));
}

// Khronos PBR Neutral.
vec3 neutral(vec3 c) {
    const float start = 0.8 - 0.04;
    const float desaturation = 0.15;
    float x = min(c.r, min(c.g, c.b));
    float offset = x < 0.08 ? x - 6.25 * x * x : 0.04;
    c -= offset;
    float peak = max(c.r, max(c.g, c.b));
    if (peak < start) return c;
    const float d = 1.0 - start;
    float new_peak = 1.0 - d * d / (peak + d - start);
    c *= new_peak / peak;
    float g = 1.0 - 1.0 / (desaturation * (peak - new_peak) + 1.0);
    return mix(c, vec3(new_peak), g);
}

vec3 srgb(vec3 c) {
    c = clamp(c, 0.0, 1.0);
    return mix(12.92 * c, 1.055 * pow(c, vec3(1.0 / 2.4)) - 0.055, step(vec3(0.0031308), c));
}

void main() {
    vec3 n = normalize(world_normal);
    vec3 v = normalize(eye - world);
    float nv = clamp(dot(n, v), 1e-4, 1.0);
    float r = clamp(roughness, 0.045, 1.0);
    float a2 = r * r * r * r;
    vec3 f0 = mix(vec3(0.04), base, metallic);
    vec3 diffuse = base * (1.0 - metallic);
    vec3 colour = vec3(0.0);
    vec3 l = normalize(light_position - world);
    float nl = dot(n, l);
    if (nl > 0.0) {
        vec3 h = normalize(l + v);
        float nh = clamp(dot(n, h), 0.0, 1.0);
        float vh = clamp(dot(v, h), 0.0, 1.0);
        float dd = nh * nh * (a2 - 1.0) + 1.0;
        float D = a2 / (PI * dd * dd);
        float vis = 0.5 / (nl * sqrt(nv * nv * (1.0 - a2) + a2) + nv * sqrt(nl * nl * (1.0 - a2) + a2));
        vec3 F = f0 + (1.0 - f0) * pow(1.0 - vh, 5.0);
        colour += light_colour * nl * ((1.0 - F) * diffuse + PI * F * D * vis);
    }
    vec3 reflected = 2.0 * nv * n - v;
    vec2 ab = texture(split_sum, (vec2(nv, r) * (lut_size - 1.0) + 0.5) / lut_size).rg;
    vec3 S = f0 * ab.x + ab.y;
    vec3 specular = textureLod(prefiltered, reflected, r * max_lod).rgb;
    colour += diffuse * (1.0 - S) * irradiance(n) + S * specular;
    frag = vec4(srgb(neutral(colour)), 1.0);
}
"""


# ---------------------------------------------------------------- the environment (--pbr)
# Directions follow relief's equirectangular convention (docs/environment.md): u = 1/2 +
# atan2(x, −z)/2π across, v = acos(y)/π down (top row straight up).

def equirect_directions(width, height):
    """Unit directions of the texel centres of a width × height equirectangular picture."""
    u = (np.arange(width) + 0.5) / width
    v = (np.arange(height) + 0.5) / height
    phi = (u - 0.5) * 2.0 * np.pi  # atan2(x, −z)
    theta = v * np.pi
    st = np.sin(theta)[:, None]
    return np.stack([st * np.sin(phi)[None, :],
                     np.broadcast_to(np.cos(theta)[:, None], (height, width)),
                     -st * np.cos(phi)[None, :]], axis=-1)


def smoothstep(a, b, x):
    t = np.clip((x - a) / (b - a), 0.0, 1.0)
    return t * t * (3.0 - 2.0 * t)


def studio_like(d):
    """The harness' test environment: a blue sky over a dark floor, a large white softbox
    up and left in front and a small warm lamp behind on the right. Every radiance is at
    most 1: relief's picture loader holds texels to 0..1, even a Radiance file's."""
    y = d[..., 1:2]
    horizon, zenith = np.array([0.6, 0.65, 0.75]), np.array([0.2, 0.35, 0.7])
    sky = horizon + (zenith - horizon) * np.sqrt(np.clip(y, 0.0, 1.0))
    ground = np.array([0.15, 0.12, 0.09])
    floor = ground + (horizon * 0.5 - ground) * np.exp(8.0 * np.minimum(y, 0.0))
    c = np.where(y >= 0.0, sky, floor)
    for centre, radius, radiance in (((-0.4, 0.7, 0.6), 18.0, (1.0, 1.0, 1.0)),
                                     ((0.8, 0.25, -0.55), 10.0, (1.0, 0.75, 0.45))):
        k = np.array(centre) / np.linalg.norm(centre)
        cos = d @ k
        edge = smoothstep(math.cos(math.radians(radius + 4.0)), math.cos(math.radians(radius)), cos)[..., None]
        c = c + edge * (np.array(radiance) - c)
    return c


def write_hdr(path, rgb):
    """A Radiance .hdr (RGBE, new-style run-length scanlines of literal runs only)."""
    h, w, _ = rgb.shape
    m = rgb.max(axis=2)
    mant, exp = np.frexp(m)
    scale = np.where(m > 1e-32, np.ldexp(256.0, -exp), 0.0)
    rgbe = np.zeros((h, w, 4), np.uint8)
    rgbe[..., :3] = np.clip(np.floor(rgb * scale[..., None]), 0, 255).astype(np.uint8)
    rgbe[..., 3] = np.where(m > 1e-32, exp + 128, 0).astype(np.uint8)
    out = bytearray(f"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y {h} +X {w}\n".encode())
    for row in rgbe:
        out += bytes([2, 2, w >> 8, w & 255])
        for k in range(4):
            channel = row[:, k].tobytes()
            for start in range(0, w, 128):
                chunk = channel[start:start + 128]
                out.append(len(chunk))
                out += chunk
    with open(path, "wb") as fh:
        fh.write(out)


def read_hdr(path):
    """Linear RGB (float64, top row first) of a Radiance .hdr in the standard orientation:
    value = mantissa · 2^(exponent − 136), exponent 0 black."""
    data = open(path, "rb").read()
    pos = 0
    while True:  # header lines, up to the blank line
        end = data.index(b"\n", pos)
        line, pos = data[pos:end], end + 1
        if line.startswith(b"FORMAT=") and line.strip() != b"FORMAT=32-bit_rle_rgbe":
            sys.exit(f"{path}: only 32-bit_rle_rgbe is read here")
        if not line.strip():
            break
    end = data.index(b"\n", pos)
    size, pos = data[pos:end].split(), end + 1
    if len(size) != 4 or size[0] != b"-Y" or size[2] != b"+X":
        sys.exit(f"{path}: only the -Y H +X W orientation is read here")
    h, w = int(size[1]), int(size[3])
    rgbe = np.zeros((h, w, 4), np.uint8)
    for y in range(h):
        if data[pos] == 2 and data[pos + 1] == 2 and data[pos + 2] < 128:
            pos += 4
            for k in range(4):
                x = 0
                while x < w:
                    n = data[pos]
                    if n > 128:
                        rgbe[y, x:x + n - 128, k] = data[pos + 1]
                        x, pos = x + n - 128, pos + 2
                    else:
                        rgbe[y, x:x + n, k] = np.frombuffer(data, np.uint8, n, pos + 1)
                        x, pos = x + n, pos + 1 + n
        else:  # flat scanline
            rgbe[y] = np.frombuffer(data, np.uint8, 4 * w, pos).reshape(w, 4)
            pos += 4 * w
    e = rgbe[..., 3].astype(np.int64)
    scale = np.where(e > 0, np.ldexp(1.0, e - 136), 0.0)
    return rgbe[..., :3].astype(np.float64) * scale[..., None]


def row_solid_angles(height, width):
    """Each texel's solid angle per row: Δφ·(cos θ_top − cos θ_bottom), summing to 4π."""
    edges = np.cos(np.arange(height + 1) / height * np.pi)
    return (edges[:-1] - edges[1:]) * 2.0 * np.pi / width


def sh_basis(d):
    x, y, z = d[..., 0], d[..., 1], d[..., 2]
    return np.stack([0.282095 * np.ones_like(x), 0.488603 * y, 0.488603 * z, 0.488603 * x,
                     1.092548 * x * y, 1.092548 * y * z, 0.315392 * (3.0 * z * z - 1.0),
                     1.092548 * x * z, 0.546274 * (x * x - y * y)], axis=-1)


def sh_irradiance(env):
    """Nine coefficients of the irradiance over π (Ramamoorthi and Hanrahan): the radiance
    projected on bands 0–2 with each texel's solid angle, band l times A_l/π = 1, 2/3, 1/4."""
    h, w, _ = env.shape
    weights = sh_basis(equirect_directions(w, h)) * row_solid_angles(h, w)[:, None, None]
    coefficients = np.einsum("hwk,hwc->kc", weights, env)
    return coefficients * np.array([1.0, 2 / 3, 2 / 3, 2 / 3, 0.25, 0.25, 0.25, 0.25, 0.25])[:, None]


def shrink(env, factor):
    """Boxes of factor × factor texels averaged (a ragged last row or column dropped)."""
    h, w, _ = env.shape
    h, w = h // factor, w // factor
    return env[:h * factor, :w * factor].reshape(h, factor, w, factor, 3).mean(axis=(1, 3))


def equirect_read(env, d):
    """Bilinear read of directions d (columns wrap, rows clamp)."""
    h, w, _ = env.shape
    u = 0.5 + np.arctan2(d[..., 0], -d[..., 2]) / (2.0 * np.pi)
    v = np.arccos(np.clip(d[..., 1], -1.0, 1.0)) / np.pi
    x, y = u * w - 0.5, np.clip(v * h - 0.5, 0.0, h - 1.0)
    x0, y0 = np.floor(x).astype(int), np.floor(y).astype(int)
    fx, fy = (x - x0)[..., None], (y - y0)[..., None]
    c0, c1 = x0 % w, (x0 + 1) % w
    r0, r1 = y0, np.minimum(y0 + 1, h - 1)
    top = env[r0, c0] * (1 - fx) + env[r0, c1] * fx
    bottom = env[r1, c0] * (1 - fx) + env[r1, c1] * fx
    return top * (1 - fy) + bottom * fy


def cube_directions(size):
    """Unit directions of the texel centres of the six faces (+X, −X, +Y, −Y, +Z, −Z), in
    OpenGL's cube map layout: row t, column s of each face's glTexImage2D data."""
    c = (np.arange(size) + 0.5) / size * 2.0 - 1.0
    tc, sc = np.meshgrid(c, c, indexing="ij")
    one = np.ones_like(sc)
    faces = [(one, -tc, -sc), (-one, -tc, sc), (sc, one, tc), (sc, -one, -tc), (sc, -tc, one), (-sc, -tc, -one)]
    d = np.stack([np.stack(f, axis=-1) for f in faces])
    return d / np.linalg.norm(d, axis=-1, keepdims=True)


def prefiltered_level(env, roughness, size):
    """The cube map level for `roughness`: at each texel's direction R, with N = V = R, the
    sum over the texels L of `env` of radiance · D(N·H) · N·L · dω, normalised by the sum of
    the weights (N·H = √((1 + R·L)/2)); roughness 0 reads the picture itself."""
    out_dirs = cube_directions(size).reshape(-1, 3)
    if roughness == 0.0:
        return equirect_read(env, out_dirs).reshape(6, size, size, 3)
    h, w, _ = env.shape
    src = equirect_directions(w, h).reshape(-1, 3)
    d_omega = np.repeat(row_solid_angles(h, w), w)
    radiance = env.reshape(-1, 3)
    a2 = roughness ** 4
    out = np.empty((len(out_dirs), 3))
    for start in range(0, len(out_dirs), 2048):
        cos = out_dirs[start:start + 2048] @ src.T
        nh2 = (1.0 + cos) * 0.5
        d = a2 / (np.pi * (nh2 * (a2 - 1.0) + 1.0) ** 2)
        weight = np.where(cos > 0.0, d * cos, 0.0) * d_omega
        out[start:start + 2048] = (weight @ radiance) / weight.sum(axis=1, keepdims=True)
    return out.reshape(6, size, size, 3)


def prefiltered_cube(env):
    """The levels, level k for roughness k/5 and of side 128/2^k; the rough levels sum over
    the picture shrunk to 128 × 64 (roughness 0.2, 0.4) or 64 × 32 texels."""
    h, w, _ = env.shape
    levels = []
    for k in range(CUBE_LEVELS):
        roughness = k / (CUBE_LEVELS - 1)
        width = w if k == 0 else (128 if k <= 2 else 64)
        source = shrink(env, max(1, w // width))
        levels.append(prefiltered_level(source, roughness, CUBE_SIZE >> k).astype(np.float32))
    return levels


def split_sum_table():
    """A and B of the split sum, LUT_SIZE² entries over N·V (x) and roughness (y), both 0..1
    with the ends on the first and last texel centres: ∫ (1 − Fc)·f·N·L and ∫ Fc·f·N·L with
    Fc = (1 − V·H)⁵ and f = D·Vis, by LUT_SAMPLES GGX-distributed half vectors (Hammersley)
    each weighing Vis·4·N·L·V·H/N·H."""
    n = LUT_SAMPLES
    i = np.arange(n, dtype=np.uint64)
    bits = np.zeros(n, np.float64)  # radical inverse of i in base 2
    for b in range(32):
        bits += ((i >> np.uint64(b)) & np.uint64(1)).astype(np.float64) * 2.0 ** (-b - 1)
    u1, u2 = (np.arange(n) + 0.5) / n, bits
    nv = np.maximum(np.linspace(0.0, 1.0, LUT_SIZE), 1e-4)[None, :, None]
    alpha = np.linspace(0.0, 1.0, LUT_SIZE)[:, None, None] ** 2
    a2 = alpha * alpha
    cos_h = np.sqrt((1.0 - u2) / (1.0 + (a2 - 1.0) * u2))
    sin_h = np.sqrt(1.0 - cos_h * cos_h)
    phi = 2.0 * np.pi * u1
    hx, hz = sin_h * np.cos(phi), cos_h  # H in the frame of N = z, V in the xz plane
    vx = np.sqrt(1.0 - nv * nv)
    vh = vx * hx + nv * hz
    nl = 2.0 * vh * hz - nv
    vis = 0.5 / (nl * np.sqrt(nv * nv * (1.0 - a2) + a2) + nv * np.sqrt(nl * nl * (1.0 - a2) + a2))
    g = np.where(nl > 0.0, vis * 4.0 * nl * vh / hz, 0.0)
    fc = (1.0 - vh) ** 5
    return np.stack([((1.0 - fc) * g).mean(axis=2), (fc * g).mean(axis=2)], axis=-1).astype(np.float32)


def cmd_environment(args):
    w, h = args.size
    write_hdr(args.out, studio_like(equirect_directions(w, h)))
    print(f"{args.out}: {w}x{h} equirectangular Radiance picture (sky, floor, softbox, lamp)")


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


def pbr_program(GL, shaders, material, environment):
    """The --pbr program in use, its uniforms set and its two textures bound: the
    prefiltered cube map on unit 0, the split-sum table on unit 1."""
    env = read_hdr(environment)
    coefficients = sh_irradiance(env)
    levels = prefiltered_cube(env)
    table = split_sum_table()
    program = shaders.compileProgram(shaders.compileShader(PBR_VERTEX_SHADER, GL.GL_VERTEX_SHADER),
                                     shaders.compileShader(PBR_FRAGMENT_SHADER, GL.GL_FRAGMENT_SHADER),
                                     validate=False)  # both samplers are on unit 0 until set below
    GL.glUseProgram(program)
    at = lambda name: GL.glGetUniformLocation(program, name)  # noqa: E731
    base, metallic, roughness = MATERIALS[material]
    GL.glUniform3f(at("eye"), *EYE)
    GL.glUniform3f(at("light_position"), *KEY_LIGHT)
    GL.glUniform3f(at("light_colour"), 1.0, 1.0, 1.0)
    GL.glUniform3f(at("base"), *base)
    GL.glUniform1f(at("metallic"), metallic)
    GL.glUniform1f(at("roughness"), roughness)
    GL.glUniform3fv(at("sh"), 9, coefficients.astype(np.float32))
    GL.glUniform1f(at("max_lod"), CUBE_LEVELS - 1)
    GL.glUniform1f(at("lut_size"), LUT_SIZE)
    GL.glUniform1i(at("prefiltered"), 0)
    GL.glUniform1i(at("split_sum"), 1)

    GL.glEnable(GL.GL_TEXTURE_CUBE_MAP_SEAMLESS)
    GL.glActiveTexture(GL.GL_TEXTURE0)
    GL.glBindTexture(GL.GL_TEXTURE_CUBE_MAP, GL.glGenTextures(1))
    for k, level in enumerate(levels):
        size = level.shape[1]
        rgba = np.ascontiguousarray(np.concatenate([level, np.ones(level.shape[:3] + (1,), np.float32)], axis=3))
        for face in range(6):
            GL.glTexImage2D(GL.GL_TEXTURE_CUBE_MAP_POSITIVE_X + face, k, GL.GL_RGBA16F, size, size, 0,
                            GL.GL_RGBA, GL.GL_FLOAT, rgba[face])
    for name, value in ((GL.GL_TEXTURE_MIN_FILTER, GL.GL_LINEAR_MIPMAP_LINEAR),
                        (GL.GL_TEXTURE_MAG_FILTER, GL.GL_LINEAR), (GL.GL_TEXTURE_BASE_LEVEL, 0),
                        (GL.GL_TEXTURE_MAX_LEVEL, CUBE_LEVELS - 1),
                        (GL.GL_TEXTURE_WRAP_S, GL.GL_CLAMP_TO_EDGE), (GL.GL_TEXTURE_WRAP_T, GL.GL_CLAMP_TO_EDGE)):
        GL.glTexParameteri(GL.GL_TEXTURE_CUBE_MAP, name, value)
    GL.glActiveTexture(GL.GL_TEXTURE1)
    GL.glBindTexture(GL.GL_TEXTURE_2D, GL.glGenTextures(1))
    GL.glTexImage2D(GL.GL_TEXTURE_2D, 0, GL.GL_RG16F, LUT_SIZE, LUT_SIZE, 0, GL.GL_RG, GL.GL_FLOAT,
                    np.ascontiguousarray(table))
    for name, value in ((GL.GL_TEXTURE_MIN_FILTER, GL.GL_LINEAR), (GL.GL_TEXTURE_MAG_FILTER, GL.GL_LINEAR),
                        (GL.GL_TEXTURE_WRAP_S, GL.GL_CLAMP_TO_EDGE), (GL.GL_TEXTURE_WRAP_T, GL.GL_CLAMP_TO_EDGE)):
        GL.glTexParameteri(GL.GL_TEXTURE_2D, name, value)
    return program


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

    if args.pbr:
        program = pbr_program(GL, shaders, args.pbr, args.environment)
    else:
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
    # --dent: the radius times 1 + dent·sin 7θ·sin 9φ (θ from +Y, φ about it), the
    # normals the sphere's: a mesh relief does not find convex (docs/bench.md).
    theta = np.arccos(np.clip(normals[:, 1], -1.0, 1.0))
    phi = np.arctan2(normals[:, 2], normals[:, 0])
    radius = args.radius * (1.0 + args.dent * np.sin(7.0 * theta) * np.sin(9.0 * phi))
    write_ply(args.out, normals * radius[:, None], normals, triangles)
    dented = f", radius dented by {args.dent:g}" if args.dent else ""
    print(f"{args.out}: UV sphere of {rings} rings, {segments} segments{dented}: "
          f"{len(triangles)} triangles, {len(normals)} vertices")


def shading(args):
    if not args.pbr:
        return "4 point lights, Lambert per pixel, vertex colours"
    base, metallic, roughness = MATERIALS[args.pbr]
    return (f"glTF metallic-roughness ({args.pbr}: base {','.join(map(str, base))} linear, metallic {metallic}, "
            f"roughness {roughness}), one white point light at ({','.join(map(str, KEY_LIGHT))}), the image-based "
            f"light of {args.environment} (9 SH coefficients, a prefiltered cube map read once with textureLod, "
            "a split-sum table), PBR Neutral, sRGB")


def cmd_bench(args):
    if args.pbr and not args.environment:
        sys.exit("--pbr needs --environment FILE.hdr (the picture relief reads with --environment-map)")
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
               (["--png", args.png] if args.png and not rows else []) + \
               (["--pbr", args.pbr, "--environment", args.environment] if args.pbr else [])
        done = subprocess.run(argv, env=env, stdout=subprocess.PIPE, text=True)
        if done.returncode:
            return done.returncode
        for line in done.stdout.splitlines():
            if line.startswith("RESULT "):
                rows.append((threads, json.loads(line[7:])))
    first = rows[0][1]
    print(f"llvmpipe_mesh.py bench {args.mesh}: {first['triangles']} triangles, "
          f"{'back faces culled' if args.cull else 'both sides drawn'}; {shading(args)}; {first['renderer']}; "
          f"loaded in {first['load_s']:.2f} s; {args.rounds} rounds, each {MIN_FRAMES} to {MAX_FRAMES} frames "
          f"(about {int(ROUND_BUDGET_S * 1000)} ms) after one warm-up frame; median and min per frame "
          "(finish: glFinish; readback: glReadPixels)")
    order = {(w, h): k for k, (w, h) in enumerate(args.sizes)}
    rows.sort(key=lambda r: (order[(r[1]["width"], r[1]["height"])]))
    for threads, r in rows:
        f, rb = r["finish"], r["readback"]
        med = statistics.median(f) * 1e3
        variant = "pbr" if args.pbr else "mesh"
        print(f"variant={variant:<7} size={r['width']}x{r['height']} threads={threads} frames={len(f)} "
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
            mesh, shadows = mine.get(t["variant"]), mine.get(t["variant"] + "+shadows")
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
    s.add_argument("--dent", type=float, default=0.0,
                   help="radius times 1 + DENT*sin(7 theta)*sin(9 phi), normals kept: not convex")
    s.add_argument("--out", required=True)
    for name in ("bench", "child"):
        b = sub.add_parser(name, help="time the view of MESH" if name == "bench" else argparse.SUPPRESS)
        b.add_argument("mesh")
        b.add_argument("--sizes", type=parse_sizes, default=parse_sizes("320x192,640x480"))
        b.add_argument("--rounds", type=int, default=3)
        b.add_argument("--no-cull", dest="cull", action="store_false")
        b.add_argument("--png", help="write the first size's picture (first thread count) as PNG")
        b.add_argument("--pbr", nargs="?", const="metal", choices=sorted(MATERIALS),
                       help="shade with the glTF metallic-roughness BRDF and image-based light (default metal)")
        b.add_argument("--environment", help="with --pbr: the equirectangular Radiance .hdr of the light")
        if name == "bench":
            b.add_argument("--threads", default="1,2", help="LP_NUM_THREADS values, each in its own process")
    c = sub.add_parser("compare", help="coverage and colour of two pictures of the view")
    c.add_argument("relief")
    c.add_argument("llvmpipe")
    t = sub.add_parser("table", help="a Markdown table of relief's and this harness' outputs side by side")
    t.add_argument("files", nargs="+", help="RELIEF.txt LLVMPIPE.txt pairs, one pair per mesh")
    e = sub.add_parser("environment", help="write the harness' test environment as a Radiance .hdr")
    e.add_argument("--size", type=lambda t: parse_sizes(t)[0], default=(512, 256))
    e.add_argument("--out", required=True)
    args = ap.parse_args()
    commands = {"environment": cmd_environment, "sphere": cmd_sphere, "bench": cmd_bench, "child": child,
                "compare": cmd_compare, "table": cmd_table}
    return commands[args.command](args)


if __name__ == "__main__":
    sys.exit(main() or 0)
