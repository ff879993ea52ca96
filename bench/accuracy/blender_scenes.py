#!/usr/bin/env python3
"""Writes the accuracy benchmark's three Blender-style scenes as glTF files.

They reproduce what Blender's glTF exporter writes for a scene a Blender user makes (the
conventions of ../shared/samples/blender_room.glb, written by Blender 3.4 itself): metres, +Y up,
every material `doubleSided: true` (Blender's default), flat-shaded boxes with their corners split
per face, a smooth UV sphere sharing its corners, lights through KHR_lights_punctual in candela
(Blender's W × 683 / 4π) and lux (W/m² × 683), emission as emissiveFactor ×
KHR_materials_emissive_strength. Each scene holds one of the geometries the default method got
wrong on real exports:

  blender-room    a 6 × 3 × 5 m room with inward (flipped) normals, a table whose legs stand on
                  the floor, a UV sphere resting on the floor, a 100 W point lamp;
  blender-panel   a 5 × 3 × 4 m room lit by an emissive panel hung 10 cm under the ceiling (both
                  faces emit, as Blender's emission shader does), a cabinet touching the back wall
                  and the floor, a sphere;
  blender-window  a 5 × 3 × 4 m room lit by the sun through a 1.6 × 1.2 m window, a bed against
                  the wall.

    bench/accuracy/blender_scenes.py --out DIR     # DIR/blender-room.gltf, …
"""
import argparse
import base64
import json
import math
import os
import struct
import sys

LUMENS_PER_WATT = 683.0


class Gltf:
    """The few glTF pieces these scenes need: meshes of triangles with normals, materials, lights."""

    def __init__(self):
        self.binary = bytearray()
        self.doc = {"asset": {"version": "2.0", "generator": "lambert bench/accuracy/blender_scenes.py (Blender-style)"},
                    "scene": 0, "scenes": [{"nodes": []}], "nodes": [], "meshes": [], "materials": [],
                    "accessors": [], "bufferViews": [], "buffers": [],
                    "extensionsUsed": ["KHR_lights_punctual", "KHR_materials_emissive_strength"],
                    "extensions": {"KHR_lights_punctual": {"lights": []}}}

    def material(self, name, colour, emission=None, strength=1.0):
        m = {"name": name, "doubleSided": True,
             "pbrMetallicRoughness": {"baseColorFactor": list(colour) + [1.0], "metallicFactor": 0.0, "roughnessFactor": 1.0}}
        if emission:
            m["emissiveFactor"] = list(emission)
            m["extensions"] = {"KHR_materials_emissive_strength": {"emissiveStrength": strength}}
        self.doc["materials"].append(m)
        return len(self.doc["materials"]) - 1

    def _accessor(self, data, fmt, count, type_, target, minmax=None):
        while len(self.binary) % 4:
            self.binary.append(0)
        offset = len(self.binary)
        self.binary += struct.pack("<" + fmt * (len(data)), *data)
        self.doc["bufferViews"].append({"buffer": 0, "byteOffset": offset, "byteLength": len(self.binary) - offset, "target": target})
        accessor = {"bufferView": len(self.doc["bufferViews"]) - 1, "componentType": 5126 if fmt == "f" else 5125,
                    "count": count, "type": type_}
        if minmax:
            accessor["min"], accessor["max"] = minmax
        self.doc["accessors"].append(accessor)
        return len(self.doc["accessors"]) - 1

    def mesh(self, name, positions, normals, triangles, material):
        flat_p = [c for p in positions for c in p]
        lo = [min(p[k] for p in positions) for k in range(3)]
        hi = [max(p[k] for p in positions) for k in range(3)]
        position = self._accessor(flat_p, "f", len(positions), "VEC3", 34962, (lo, hi))
        normal = self._accessor([c for n in normals for c in n], "f", len(normals), "VEC3", 34962)
        indices = self._accessor([i for t in triangles for i in t], "I", 3 * len(triangles), "SCALAR", 34963)
        self.doc["meshes"].append({"name": name, "primitives": [
            {"attributes": {"POSITION": position, "NORMAL": normal}, "indices": indices, "material": material}]})
        self.node({"name": name, "mesh": len(self.doc["meshes"]) - 1})

    def node(self, node):
        self.doc["nodes"].append(node)
        self.doc["scenes"][0]["nodes"].append(len(self.doc["nodes"]) - 1)

    def light(self, name, light, translation=None, rotation=None):
        self.doc["extensions"]["KHR_lights_punctual"]["lights"].append(dict(light, name=name))
        node = {"name": name, "extensions": {"KHR_lights_punctual": {"light": len(self.doc["extensions"]["KHR_lights_punctual"]["lights"]) - 1}}}
        if translation:
            node["translation"] = list(translation)
        if rotation:
            node["rotation"] = list(rotation)
        self.node(node)

    def point_light(self, name, watts, colour, position):
        # Blender: I [cd] = P [W] × 683 / 4π, whatever the colour.
        self.light(name, {"type": "point", "color": list(colour), "intensity": watts * LUMENS_PER_WATT / (4 * math.pi)}, position)

    def sun(self, name, watts_per_m2, colour, travel):
        # A directional light shines down its node's −Z: the rotation taking −Z to `travel`.
        d = normalised(travel)
        axis = cross((0.0, 0.0, -1.0), d)
        s = math.sqrt(dot(axis, axis))
        angle = math.atan2(s, -d[2])
        q = [0.0, 0.0, 0.0, 1.0] if s < 1e-12 else [axis[0] / s * math.sin(angle / 2), axis[1] / s * math.sin(angle / 2),
                                                    axis[2] / s * math.sin(angle / 2), math.cos(angle / 2)]
        self.light(name, {"type": "directional", "color": list(colour), "intensity": watts_per_m2 * LUMENS_PER_WATT}, rotation=q)

    def camera(self, eye, target):
        forward = normalised(sub(target, eye))
        # A camera looks down its node's −Z with +Y up: the rotation from yaw and pitch.
        yaw = math.atan2(-forward[0], -forward[2])
        pitch = math.asin(max(-1.0, min(1.0, forward[1])))
        qy = (0.0, math.sin(yaw / 2), 0.0, math.cos(yaw / 2))
        qx = (math.sin(pitch / 2), 0.0, 0.0, math.cos(pitch / 2))
        q = quat_mul(qy, qx)
        self.doc.setdefault("cameras", []).append({"type": "perspective", "perspective": {"yfov": math.radians(60), "znear": 0.05, "aspectRatio": 1.0}})
        self.node({"name": "Camera", "camera": len(self.doc["cameras"]) - 1, "translation": list(eye), "rotation": list(q)})

    def write(self, path):
        self.doc["buffers"] = [{"byteLength": len(self.binary),
                                "uri": "data:application/octet-stream;base64," + base64.b64encode(bytes(self.binary)).decode()}]
        temporary = path + ".tmp"
        with open(temporary, "w") as f:
            json.dump(self.doc, f)
        os.replace(temporary, path)


def sub(a, b):
    return (a[0] - b[0], a[1] - b[1], a[2] - b[2])


def dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def normalised(a):
    n = math.sqrt(dot(a, a))
    return (a[0] / n, a[1] / n, a[2] / n)


def quat_mul(a, b):
    ax, ay, az, aw = a
    bx, by, bz, bw = b
    return (aw * bx + ax * bw + ay * bz - az * by, aw * by - ax * bz + ay * bw + az * bx,
            aw * bz + ax * by - ay * bx + az * bw, aw * bw - ax * bx - ay * by - az * bz)


def quads_mesh(quads):
    """Flat-shaded quads (each four corners, counter-clockwise from its front) as Blender exports
    them: every face its own corners and normal, two triangles."""
    positions, normals, triangles = [], [], []
    for quad in quads:
        n = normalised(cross(sub(quad[1], quad[0]), sub(quad[2], quad[0])))
        base = len(positions)
        positions += quad
        normals += [n] * 4
        triangles += [(base, base + 1, base + 2), (base, base + 2, base + 3)]
    return positions, normals, triangles


def box_quads(lo, hi, inward=False):
    """The six faces of an axis-aligned box, normals outward (inward: a room, Blender's flipped normals)."""
    x0, y0, z0 = lo
    x1, y1, z1 = hi
    faces = [
        [(x0, y0, z0), (x0, y0, z1), (x0, y1, z1), (x0, y1, z0)],  # −x
        [(x1, y0, z0), (x1, y1, z0), (x1, y1, z1), (x1, y0, z1)],  # +x
        [(x0, y0, z0), (x1, y0, z0), (x1, y0, z1), (x0, y0, z1)],  # −y
        [(x0, y1, z0), (x0, y1, z1), (x1, y1, z1), (x1, y1, z0)],  # +y
        [(x0, y0, z0), (x0, y1, z0), (x1, y1, z0), (x1, y0, z0)],  # −z
        [(x0, y0, z1), (x1, y0, z1), (x1, y1, z1), (x0, y1, z1)],  # +z
    ]
    return [list(reversed(f)) for f in faces] if inward else faces


def add_box(gltf, name, lo, hi, material, inward=False):
    gltf.mesh(name, *quads_mesh(box_quads(lo, hi, inward)), material)


def add_room(gltf, lo, hi, wall, floor, extra_walls=(), open_sides=()):
    """A room as Blender users model it: a box with its normals flipped in, its floor a mesh of its
    own (another material); `open_sides` are box_quads indices left out (a wall with a window,
    given in `extra_walls`)."""
    room = box_quads(lo, hi, inward=True)
    gltf.mesh("Room", *quads_mesh([q for k, q in enumerate(room) if k != 2 and k not in open_sides] + list(extra_walls)), wall)
    gltf.mesh("Floor", *quads_mesh([room[2]]), floor)


def add_uv_sphere(gltf, name, centre, radius, material, segments=24, rings=12):
    """Blender's UV sphere: smooth-shaded, `segments` around, `rings` from pole to pole, the poles
    one vertex each."""
    positions, normals, triangles = [], [], []
    for ring in range(rings + 1):
        theta = math.pi * ring / rings
        for seg in range(segments if 0 < ring < rings else 1):
            phi = 2 * math.pi * seg / segments
            n = (math.sin(theta) * math.cos(phi), math.cos(theta), -math.sin(theta) * math.sin(phi))
            normals.append(n)
            positions.append(tuple(centre[k] + radius * n[k] for k in range(3)))

    def index(ring, seg):
        if ring == 0:
            return 0
        if ring == rings:
            return len(positions) - 1
        return 1 + (ring - 1) * segments + seg % segments

    for ring in range(rings):
        for seg in range(segments):
            a, b = index(ring, seg), index(ring, seg + 1)
            c, d = index(ring + 1, seg + 1), index(ring + 1, seg)
            if ring == 0:
                triangles.append((a, d, c))
            elif ring == rings - 1:
                triangles.append((a, d, b))
            else:
                triangles += [(a, d, c), (a, c, b)]
    gltf.mesh(name, positions, normals, triangles, material)


def blender_room():
    g = Gltf()
    wall = g.material("wall", (0.8, 0.8, 0.8))
    floor = g.material("floor", (0.5, 0.45, 0.4))
    table = g.material("table", (0.6, 0.1, 0.08))
    sphere = g.material("sphere", (0.7, 0.7, 0.7))
    add_room(g, (-3, 0, -2.5), (3, 3, 2.5), wall, floor)
    add_box(g, "TableTop", (-0.8, 0.72, -0.45), (0.8, 0.77, 0.45), table)
    for k, (x, z) in enumerate([(-0.75, -0.4), (0.7, -0.4), (-0.75, 0.35), (0.7, 0.35)]):
        add_box(g, f"Leg{k}", (x, 0, z), (x + 0.05, 0.72, z + 0.05), table)
    add_uv_sphere(g, "Sphere", (1.7, 0.4, 1.0), 0.4, sphere)
    g.point_light("Lamp", 100, (1.0, 1.0, 1.0), (0.0, 2.5, 0.0))
    g.camera((2.6, 1.6, 2.2), (-0.5, 0.6, -0.8))
    return g


def blender_panel():
    g = Gltf()
    wall = g.material("wall", (0.75, 0.75, 0.75))
    floor = g.material("floor", (0.4, 0.4, 0.45))
    cabinet = g.material("cabinet", (0.3, 0.5, 0.7))
    sphere = g.material("sphere", (0.8, 0.6, 0.2))
    lamp = g.material("lamp", (0.8, 0.8, 0.8), emission=(1.0, 0.95, 0.9), strength=10.0)
    add_room(g, (-2.5, 0, -2), (2.5, 3, 2), wall, floor)
    # The panel: a plane facing down, 10 cm under the ceiling (both its faces emit in Blender).
    g.mesh("Panel", *quads_mesh([[(-0.6, 2.9, -0.3), (0.6, 2.9, -0.3), (0.6, 2.9, 0.3), (-0.6, 2.9, 0.3)]]), lamp)
    add_box(g, "Cabinet", (-2.0, 0, -2.0), (-0.8, 1.8, -1.5), cabinet)
    add_uv_sphere(g, "Sphere", (1.2, 0.3, 0.8), 0.3, sphere)
    g.camera((2.2, 1.5, 1.8), (-0.8, 0.9, -1.2))
    return g


def blender_window():
    g = Gltf()
    wall = g.material("wall", (0.8, 0.78, 0.75))
    floor = g.material("floor", (0.45, 0.35, 0.25))
    bed = g.material("bed", (0.7, 0.7, 0.75))
    # The room with a 1.6 × 1.2 m hole in its +x wall (sill 0.9 m, z from −0.8 to 0.8).
    x = 2.5
    window_wall = [
        [(x, 0, -2), (x, 0, 2), (x, 0.9, 2), (x, 0.9, -2)],
        [(x, 2.1, -2), (x, 2.1, 2), (x, 3, 2), (x, 3, -2)],
        [(x, 0.9, -2), (x, 0.9, -0.8), (x, 2.1, -0.8), (x, 2.1, -2)],
        [(x, 0.9, 0.8), (x, 0.9, 2), (x, 2.1, 2), (x, 2.1, 0.8)],
    ]
    window_wall = [list(reversed(q)) for q in window_wall]  # facing −x, into the room
    add_room(g, (-2.5, 0, -2), (2.5, 3, 2), wall, floor, extra_walls=window_wall, open_sides=(1,))
    add_box(g, "Bed", (-2.5, 0, -2.0), (-0.5, 0.5, -0.6), bed)
    g.sun("Sun", 3.0, (1.0, 1.0, 0.95), (-0.75, -0.55, 0.2))
    g.camera((-2.2, 1.6, 1.7), (1.5, 0.7, -0.8))
    return g


SCENES = {"blender-room": blender_room, "blender-panel": blender_panel, "blender-window": blender_window}


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--out", required=True, help="folder to write the .gltf files into")
    args = parser.parse_args()
    os.makedirs(args.out, exist_ok=True)
    for name, build in SCENES.items():
        build().write(os.path.join(args.out, name + ".gltf"))
        print(os.path.join(args.out, name + ".gltf"))
    return 0


if __name__ == "__main__":
    sys.exit(main())
