#!/usr/bin/env python3
"""Writes scenes/room/: a furnished room as glTF 2.0 (room.gltf, room.bin, textures/*.png).

Pure standard library (json, struct, zlib), deterministic: running it twice gives the same bytes.

    scripts/make-room-gltf.py [OUTPUT_DIR]      # default: scenes/room beside this script's repo

The scene, in glTF conventions (metres, +Y up, counter-clockwise front faces):
  - a room 5 m (x) by 4 m (z), 2.7 m high, every face of its shell facing into the room;
  - a window, 1.8 m x 1.2 m, in the wall z = 0: the wall is four quads around the hole, with
    reveals 0.2 m deep and a thin stone sill;
  - furniture as boxes: one unit box's accessors shared by one mesh per material, placed by
    nodes with translation, rotation and scale (a table, a sofa, a bookshelf with books, a rug);
  - textures: oak floor planks (1 repeat per metre) and a patterned rug (one repeat over it);
  - a sun (KHR_lights_punctual directional, 3000 lx) shining through the window onto the floor,
    an emissive ceiling panel (KHR_materials_emissive_strength), and a perspective camera.
"""

import json
import math
import os
import struct
import sys
import zlib

# ---------------------------------------------------------------------------------------------
# Geometry helpers


def sub(a, b):
    return tuple(x - y for x, y in zip(a, b))


def add(*vs):
    return tuple(sum(c) for c in zip(*vs))


def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def normalize(v):
    n = math.sqrt(sum(c * c for c in v))
    return tuple(c / n for c in v)


class Primitive:
    """Triangles over vertices with a position, a normal and (optionally) a texture coordinate."""

    def __init__(self, with_uv):
        self.with_uv = with_uv
        self.positions, self.normals, self.uvs, self.indices = [], [], [], []

    def quad(self, origin, u, v, uv=None):
        """The quad origin, origin + u, origin + u + v, origin + v; its front faces u x v.
        uv: a function of the corner position giving its texture coordinate (default: 0..1)."""
        normal = normalize(cross(u, v))
        corners = [origin, add(origin, u), add(origin, u, v), add(origin, v)]
        unit = [(0.0, 1.0), (1.0, 1.0), (1.0, 0.0), (0.0, 0.0)]  # glTF: v = 0 is the image's top row
        base = len(self.positions)
        for k, p in enumerate(corners):
            self.positions.append(p)
            self.normals.append(normal)
            if self.with_uv:
                self.uvs.append(uv(p) if uv else unit[k])
        self.indices += [base, base + 1, base + 2, base, base + 2, base + 3]


# ---------------------------------------------------------------------------------------------
# The room

W, D, H = 5.0, 4.0, 2.7                    # x, z, y extents in metres
WIN_X0, WIN_X1 = 1.6, 3.4                  # the window opening in the wall z = 0
WIN_Y0, WIN_Y1 = 0.9, 2.1
REVEAL = 0.2                               # wall thickness shown in the opening

floor = Primitive(with_uv=True)
floor.quad((0, 0, D), (W, 0, 0), (0, 0, -D), uv=lambda p: (p[0], p[2]))  # 1 repeat per metre

ceiling = Primitive(with_uv=False)
ceiling.quad((0, H, 0), (W, 0, 0), (0, 0, D))

walls = Primitive(with_uv=False)
walls.quad((W, 0, D), (-W, 0, 0), (0, H, 0))          # back wall z = D, facing -z
walls.quad((0, 0, D), (0, 0, -D), (0, H, 0))          # left wall x = 0, facing +x
walls.quad((W, 0, 0), (0, 0, D), (0, H, 0))           # right wall x = W, facing -x
# The window wall z = 0, facing +z: four quads around the opening.
for x0, x1, y0, y1 in [(0, WIN_X0, 0, H), (WIN_X1, W, 0, H), (WIN_X0, WIN_X1, 0, WIN_Y0), (WIN_X0, WIN_X1, WIN_Y1, H)]:
    walls.quad((x0, y0, 0), (x1 - x0, 0, 0), (0, y1 - y0, 0))
# Reveals in the wall's thickness, facing into the opening (the sill is the bottom one).
walls.quad((WIN_X0, WIN_Y0, 0), (0, 0, -REVEAL), (0, WIN_Y1 - WIN_Y0, 0))          # left jamb, +x
walls.quad((WIN_X1, WIN_Y0, -REVEAL), (0, 0, REVEAL), (0, WIN_Y1 - WIN_Y0, 0))     # right jamb, -x
walls.quad((WIN_X0, WIN_Y1, -REVEAL), (WIN_X1 - WIN_X0, 0, 0), (0, 0, REVEAL))     # head, -y

# The ceiling lamp: a 0.6 m square diffuser 2 mm below the ceiling, facing down.
LAMP = 0.6
lamp = Primitive(with_uv=False)
lamp.quad((W / 2 - LAMP / 2, H - 0.002, D / 2 - LAMP / 2), (LAMP, 0, 0), (0, 0, LAMP))

# The unit box, [-0.5, 0.5]^3, outward faces, texture coordinates 0..1 on every face.
box = Primitive(with_uv=True)
box.quad((0.5, -0.5, 0.5), (0, 0, -1), (0, 1, 0))     # +x
box.quad((-0.5, -0.5, -0.5), (0, 0, 1), (0, 1, 0))    # -x
box.quad((-0.5, 0.5, 0.5), (1, 0, 0), (0, 0, -1))     # +y
box.quad((-0.5, -0.5, -0.5), (1, 0, 0), (0, 0, 1))    # -y
box.quad((-0.5, -0.5, 0.5), (1, 0, 0), (0, 1, 0))     # +z
box.quad((0.5, -0.5, -0.5), (-1, 0, 0), (0, 1, 0))    # -z
for k in range(0, len(box.positions), 4):              # every face's normal points away from the centre
    assert sum(a * b for a, b in zip(box.normals[k], box.positions[k])) > 0

# ---------------------------------------------------------------------------------------------
# Textures: 256 x 256 sRGB PNGs


def png(width, height, pixel):
    """An 8-bit RGB PNG of pixel(x, y) -> (r, g, b)."""
    rows = bytearray()
    for y in range(height):
        rows.append(0)  # filter: none
        for x in range(width):
            rows += bytes(pixel(x, y))

    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)

    header = struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0, 0)
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", header) + chunk(b"sRGB", b"\x00")
            + chunk(b"IDAT", zlib.compress(bytes(rows), 9)) + chunk(b"IEND", b""))


def hash01(*ints):
    """A deterministic pseudo-random number in [0, 1) from integers."""
    h = 2166136261
    for i in ints:
        h = ((h ^ (i & 0xFFFFFFFF)) * 16777619) & 0xFFFFFFFF
        h ^= h >> 13
        h = (h * 0x5BD1E995) & 0xFFFFFFFF
        h ^= h >> 15
    return h / 2**32


def clamp8(v):
    return max(0, min(255, int(round(v))))


TEX = 256
PLANK_ROWS = 8                 # 12.5 cm wide planks at 1 repeat per metre
PLANK_LENGTH = TEX // 2        # 0.5 m long, staggered row by row


def oak(x, y):
    row = y // (TEX // PLANK_ROWS)
    shift = int(hash01(row, 1) * PLANK_LENGTH)
    along = (x + shift) % TEX
    plank = along // PLANK_LENGTH
    tone = 0.85 + 0.3 * hash01(row, plank, 2)           # each plank a little lighter or darker
    across = y % (TEX // PLANK_ROWS)
    grain = 0.92 + 0.08 * math.sin(0.9 * across + 6 * math.sin(2 * math.pi * along / PLANK_LENGTH + row))
    joint = across == 0 or along % PLANK_LENGTH == 0    # dark gaps between planks
    f = tone * grain * (0.45 if joint else 1.0)
    return (clamp8(168 * f), clamp8(118 * f), clamp8(72 * f))   # sRGB mid brown, linear albedo < 0.4


def rug(x, y):
    u, v = (x + 0.5) / TEX, (y + 0.5) / TEX
    edge = min(u, v, 1 - u, 1 - v)
    if edge < 0.06:
        return (70, 35, 30)                                # dark border
    if edge < 0.09:
        return (190, 160, 110)                             # cream band
    # Diamonds on red, 4 x 3 over the field.
    du = abs(((u - 0.09) / 0.82 * 4) % 1 - 0.5)
    dv = abs(((v - 0.09) / 0.82 * 3) % 1 - 0.5)
    d = du + dv
    if d < 0.18:
        return (40, 60, 110)                               # blue centre
    if d < 0.26:
        return (190, 160, 110)
    return (150, 40, 35)                                   # red field


# ---------------------------------------------------------------------------------------------
# The buffer, its views and accessors

buffer = bytearray()
buffer_views, accessors = [], []


def add_view(data, target):
    while len(buffer) % 4:
        buffer.append(0)
    buffer_views.append({"buffer": 0, "byteOffset": len(buffer), "byteLength": len(data), "target": target})
    buffer.extend(data)
    return len(buffer_views) - 1


def add_floats(values, kind, with_bounds=False):
    n = {"VEC2": 2, "VEC3": 3}[kind]
    flat = [c for v in values for c in v]
    view = add_view(struct.pack("<%df" % len(flat), *flat), 34962)  # ARRAY_BUFFER
    accessor = {"bufferView": view, "componentType": 5126, "count": len(values), "type": kind}
    if with_bounds:
        # The bounds of the float32 values as stored.
        stored = [struct.unpack("<f", struct.pack("<f", c))[0] for c in flat]
        accessor["min"] = [min(stored[k::n]) for k in range(n)]
        accessor["max"] = [max(stored[k::n]) for k in range(n)]
    accessors.append(accessor)
    return len(accessors) - 1


def add_indices(indices):
    view = add_view(struct.pack("<%dH" % len(indices), *indices), 34963)  # ELEMENT_ARRAY_BUFFER
    accessors.append({"bufferView": view, "componentType": 5123, "count": len(indices), "type": "SCALAR"})
    return len(accessors) - 1


def add_primitive(p, material):
    attributes = {"POSITION": add_floats(p.positions, "VEC3", with_bounds=True), "NORMAL": add_floats(p.normals, "VEC3")}
    if p.with_uv:
        attributes["TEXCOORD_0"] = add_floats(p.uvs, "VEC2")
    return {"attributes": attributes, "indices": add_indices(p.indices), "material": material, "mode": 4}


# ---------------------------------------------------------------------------------------------
# Materials

materials = []


def material(name, rgb, texture=None, emissive=None, strength=None):
    m = {"name": name,
         "pbrMetallicRoughness": {"baseColorFactor": [rgb[0], rgb[1], rgb[2], 1.0], "metallicFactor": 0.0, "roughnessFactor": 1.0},
         "doubleSided": False}
    if texture is not None:
        m["pbrMetallicRoughness"]["baseColorTexture"] = {"index": texture, "texCoord": 0}
    if emissive is not None:
        m["emissiveFactor"] = list(emissive)
        m["extensions"] = {"KHR_materials_emissive_strength": {"emissiveStrength": strength}}
    materials.append(m)
    return len(materials) - 1


OAK = material("oak floor", (0.9, 0.9, 0.9), texture=0)
PLASTER = material("plaster walls", (0.72, 0.70, 0.66))
CEILING = material("ceiling paint", (0.78, 0.78, 0.76))
WALNUT = material("walnut", (0.24, 0.13, 0.07))
FABRIC = material("sofa fabric", (0.10, 0.20, 0.36))
RUG = material("wool rug", (0.9, 0.9, 0.9), texture=1)
STONE = material("sill stone", (0.60, 0.59, 0.56))
BOOK_RED = material("book red", (0.45, 0.08, 0.06))
BOOK_GREEN = material("book green", (0.10, 0.30, 0.15))
BOOK_CREAM = material("book cream", (0.65, 0.58, 0.42))
# L_e = emissiveFactor x strength, in W/(m^2 sr) as lambert reads it (x 683 lm/W: cd/m^2).
LAMP_COLOUR = (1.0, 0.93, 0.82)
LAMP_STRENGTH = 4.0
DIFFUSER = material("lamp diffuser", (0.8, 0.8, 0.8), emissive=LAMP_COLOUR, strength=LAMP_STRENGTH)

# ---------------------------------------------------------------------------------------------
# Meshes: the shell, the lamp, and the unit box once per material (all sharing its accessors)

meshes = [{"name": "room shell", "primitives": [add_primitive(floor, OAK), add_primitive(ceiling, CEILING),
                                                 add_primitive(walls, PLASTER)]},
          {"name": "ceiling lamp", "primitives": [add_primitive(lamp, DIFFUSER)]}]
SHELL_MESH, LAMP_MESH = 0, 1
unit_box = add_primitive(box, None)
box_mesh = {}
for m in [WALNUT, FABRIC, RUG, STONE, BOOK_RED, BOOK_GREEN, BOOK_CREAM]:
    p = dict(unit_box)
    p["material"] = m
    box_mesh[m] = len(meshes)
    meshes.append({"name": "unit box, " + materials[m]["name"], "primitives": [p]})

# ---------------------------------------------------------------------------------------------
# Nodes

nodes = []


def r6(x):
    return round(x + 0.0, 6) + 0.0


def node(name, translation=None, rotation=None, scale=None, **extra):
    n = {"name": name}
    if translation is not None:
        n["translation"] = [r6(c) for c in translation]
    if rotation is not None:
        n["rotation"] = [r6(c) for c in rotation]
    if scale is not None:
        n["scale"] = [r6(c) for c in scale]
    n.update(extra)
    nodes.append(n)
    return len(nodes) - 1


def box_node(name, material, lo, hi):
    """A box from corner lo to corner hi (in its parent's frame): the unit box, scaled and moved."""
    centre = [(a + b) / 2 for a, b in zip(lo, hi)]
    size = [b - a for a, b in zip(lo, hi)]
    return node(name, translation=centre, scale=size, mesh=box_mesh[material])


def yaw(degrees):
    """A rotation about +y (counter-clockwise seen from above) as a glTF quaternion [x, y, z, w]."""
    h = math.radians(degrees) / 2
    return [0.0, math.sin(h), 0.0, math.cos(h)]


def rotation_from_minus_z(d):
    """The shortest rotation taking -z (where glTF lights and cameras point) onto unit vector d."""
    v = (0.0, 0.0, -1.0)
    axis = cross(v, d)
    q = [axis[0], axis[1], axis[2], 1.0 + sum(a * b for a, b in zip(v, d))]
    n = math.sqrt(sum(c * c for c in q))
    return [c / n for c in q]


roots = []
roots.append(node("room", mesh=SHELL_MESH))
roots.append(box_node("window sill", STONE, (WIN_X0 - 0.08, WIN_Y0 - 0.04, -REVEAL - 0.02), (WIN_X1 + 0.08, WIN_Y0, 0.12)))
roots.append(box_node("rug", RUG, (1.3, 0.0, 1.25), (3.5, 0.012, 2.75)))

# The table: 1.2 m x 0.8 m, 0.76 m high, its legs children of its node.
TABLE_W, TABLE_D, TABLE_H, TOP, LEG = 1.2, 0.8, 0.76, 0.04, 0.05
table_parts = [box_node("table top", WALNUT, (-TABLE_W / 2, TABLE_H - TOP, -TABLE_D / 2), (TABLE_W / 2, TABLE_H, TABLE_D / 2))]
for i, (sx, sz) in enumerate([(-1, -1), (1, -1), (1, 1), (-1, 1)]):
    x = sx * (TABLE_W / 2 - 0.06)
    z = sz * (TABLE_D / 2 - 0.06)
    table_parts.append(box_node("table leg %d" % (i + 1), WALNUT, (x - LEG / 2, 0.012, z - LEG / 2),
                                (x + LEG / 2, TABLE_H - TOP, z + LEG / 2)))
roots.append(node("table", translation=(2.4, 0.0, 2.0), rotation=yaw(8), children=table_parts))

# The sofa, built facing +z in its own frame, turned to face -x against the right wall.
SOFA_W, SOFA_D = 2.0, 0.85
sofa_parts = [
    box_node("sofa seat", FABRIC, (-SOFA_W / 2 + 0.2, 0.0, -SOFA_D / 2 + 0.2), (SOFA_W / 2 - 0.2, 0.42, SOFA_D / 2)),
    box_node("sofa back", FABRIC, (-SOFA_W / 2 + 0.2, 0.0, -SOFA_D / 2), (SOFA_W / 2 - 0.2, 0.85, -SOFA_D / 2 + 0.2)),
    box_node("sofa arm left", FABRIC, (-SOFA_W / 2, 0.0, -SOFA_D / 2), (-SOFA_W / 2 + 0.2, 0.62, SOFA_D / 2)),
    box_node("sofa arm right", FABRIC, (SOFA_W / 2 - 0.2, 0.0, -SOFA_D / 2), (SOFA_W / 2, 0.62, SOFA_D / 2)),
]
roots.append(node("sofa", translation=(W - SOFA_D / 2 - 0.02, 0.0, 2.3), rotation=yaw(-90), children=sofa_parts))

# The bookshelf, built facing +z in its own frame, turned to face +x against the left wall.
SHELF_W, SHELF_D, SHELF_H, BOARD = 1.0, 0.32, 1.9, 0.03
shelf_parts = [
    box_node("bookshelf side left", WALNUT, (-SHELF_W / 2, 0.0, -SHELF_D / 2), (-SHELF_W / 2 + BOARD, SHELF_H, SHELF_D / 2)),
    box_node("bookshelf side right", WALNUT, (SHELF_W / 2 - BOARD, 0.0, -SHELF_D / 2), (SHELF_W / 2, SHELF_H, SHELF_D / 2)),
    box_node("bookshelf back", WALNUT, (-SHELF_W / 2 + BOARD, 0.0, -SHELF_D / 2), (SHELF_W / 2 - BOARD, SHELF_H, -SHELF_D / 2 + 0.01)),
]
levels = [0.05, 0.5, 0.95, 1.4, SHELF_H - BOARD]
for i, y in enumerate(levels):
    shelf_parts.append(box_node("bookshelf board %d" % (i + 1), WALNUT, (-SHELF_W / 2 + BOARD, y, -SHELF_D / 2 + 0.01),
                                (SHELF_W / 2 - BOARD, y + BOARD, SHELF_D / 2)))
books = [(0, BOOK_RED, -0.44, -0.05, 0.30), (0, BOOK_CREAM, 0.02, 0.40, 0.26), (1, BOOK_GREEN, -0.44, 0.10, 0.28),
         (2, BOOK_CREAM, -0.30, 0.15, 0.24), (2, BOOK_RED, 0.18, 0.44, 0.30), (3, BOOK_GREEN, -0.44, -0.12, 0.22)]
for i, (level, m, x0, x1, height) in enumerate(books):
    y = levels[level] + BOARD
    shelf_parts.append(box_node("books %d" % (i + 1), m, (x0, y, -SHELF_D / 2 + 0.03), (x1, y + height, SHELF_D / 2 - 0.04)))
roots.append(node("bookshelf", translation=(SHELF_D / 2 + 0.01, 0.0, 2.7), rotation=yaw(90), children=shelf_parts))

roots.append(node("ceiling lamp", mesh=LAMP_MESH))

# The sun: 40 degrees above the horizon, travelling into the room (+z) and a little towards -x.
SUN_ELEVATION, SUN_AZIMUTH = 40.0, -12.0
el, az = math.radians(SUN_ELEVATION), math.radians(SUN_AZIMUTH)
sun_direction = (math.cos(el) * math.sin(az), -math.sin(el), math.cos(el) * math.cos(az))
SUN_LUX = 3000.0
roots.append(node("sun", translation=(2.5, 4.0, -3.0), rotation=rotation_from_minus_z(sun_direction),
                  extensions={"KHR_lights_punctual": {"light": 0}}))

# The camera: in the corner by the door (x = W, z = D) at 1.7 m, looking at the window wall's far
# side, so the window, the sunlit floor, the bookshelf and the lamp are all in view.
CAMERA_EYE, CAMERA_TARGET = (4.55, 1.75, 3.85), (1.4, 0.75, 0.6)


def look_at(eye, target):
    """The rotation (quaternion [x, y, z, w]) that points a glTF camera's -z at target, +y up."""
    f = normalize(sub(target, eye))
    x = normalize(cross(f, (0.0, 1.0, 0.0)))
    y = cross(x, f)
    z = tuple(-c for c in f)
    m = [[x[0], y[0], z[0]], [x[1], y[1], z[1]], [x[2], y[2], z[2]]]  # columns: the camera's axes
    w = math.sqrt(max(0.0, 1 + m[0][0] + m[1][1] + m[2][2])) / 2
    return [(m[2][1] - m[1][2]) / (4 * w), (m[0][2] - m[2][0]) / (4 * w), (m[1][0] - m[0][1]) / (4 * w), w]


roots.append(node("camera", translation=CAMERA_EYE, rotation=look_at(CAMERA_EYE, CAMERA_TARGET), camera=0))

# ---------------------------------------------------------------------------------------------
# The document

gltf = {
    "asset": {"version": "2.0", "generator": "lambert scripts/make-room-gltf.py"},
    "extensionsUsed": ["KHR_lights_punctual", "KHR_materials_emissive_strength"],
    "scene": 0,
    "scenes": [{"name": "room", "nodes": roots}],
    "nodes": nodes,
    "meshes": meshes,
    "materials": materials,
    "textures": [{"name": "oak floor", "sampler": 0, "source": 0}, {"name": "rug", "sampler": 0, "source": 1}],
    "images": [{"name": "oak floor", "uri": "textures/oak_floor.png", "mimeType": "image/png"},
               {"name": "rug", "uri": "textures/rug.png", "mimeType": "image/png"}],
    "samplers": [{"magFilter": 9729, "minFilter": 9987, "wrapS": 10497, "wrapT": 10497}],
    "cameras": [{"name": "eye", "type": "perspective",
                 "perspective": {"yfov": r6(math.radians(65)), "aspectRatio": r6(4 / 3), "znear": 0.05, "zfar": 100.0}}],
    "extensions": {"KHR_lights_punctual": {"lights": [
        {"name": "sun", "type": "directional", "color": [1.0, 0.96, 0.9], "intensity": SUN_LUX}]}},
    "buffers": None,
    "bufferViews": buffer_views,
    "accessors": accessors,
}


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    out = sys.argv[1] if len(sys.argv) > 1 else os.path.join(here, "..", "scenes", "room")
    os.makedirs(os.path.join(out, "textures"), exist_ok=True)
    while len(buffer) % 4:
        buffer.append(0)
    gltf["buffers"] = [{"uri": "room.bin", "byteLength": len(buffer)}]
    with open(os.path.join(out, "room.bin"), "wb") as f:
        f.write(buffer)
    with open(os.path.join(out, "room.gltf"), "w", encoding="utf-8") as f:
        json.dump(gltf, f, indent=1)
        f.write("\n")
    for name, pixel in [("oak_floor.png", oak), ("rug.png", rug)]:
        with open(os.path.join(out, "textures", name), "wb") as f:
            f.write(png(TEX, TEX, pixel))
    triangles = sum(accessors[p["indices"]]["count"] // 3 for n in nodes if "mesh" in n for p in meshes[n["mesh"]]["primitives"])
    print("%s: %d nodes, %d meshes, %d materials, %d triangles, %d bytes of buffer"
          % (os.path.normpath(out), len(nodes), len(meshes), len(materials), triangles, len(buffer)))


if __name__ == "__main__":
    main()
