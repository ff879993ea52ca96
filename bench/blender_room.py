"""A small room as a Blender user makes one, for the lightmap bake's benchmark (bench/lightmap_room_bench.py).

    blender -b --factory-startup -P bench/blender_room.py -- OUT.glb

A 5 x 4 x 2.7 m room (walls, floor and ceiling as subdivided planes, 91 m2 in all with its
fittings), six 0.6 m emissive ceiling panels (strength 5), a 0.1 m floor slab whose top lies on
the room's floor (faces that coincide, as modelled rooms have them), a desk. Every object gets a
second UV layer from Blender's own Lightmap Pack, which the glTF exporter writes as TEXCOORD_1;
Blender's defaults otherwise (two-sided materials, +Y up).
"""
import sys

import bpy


def out_path():
    argv = sys.argv
    return argv[argv.index("--") + 1] if "--" in argv else "blender_room.glb"


def material(name, colour, emission=None):
    m = bpy.data.materials.new(name)
    m.use_nodes = True
    bsdf = m.node_tree.nodes["Principled BSDF"]
    bsdf.inputs["Base Color"].default_value = (*colour, 1)
    bsdf.inputs["Roughness"].default_value = 1.0
    bsdf.inputs["Specular"].default_value = 0.0
    if emission:
        bsdf.inputs["Emission"].default_value = (*emission, 1)
        bsdf.inputs["Emission Strength"].default_value = 5.0
    return m


def plane(name, size, location, rotation, cuts, mat):
    bpy.ops.mesh.primitive_plane_add(size=1, location=location, rotation=rotation)
    obj = bpy.context.active_object
    obj.name = name
    obj.scale = (size[0], size[1], 1)
    bpy.ops.object.transform_apply(scale=True)
    if cuts:
        bpy.ops.object.mode_set(mode="EDIT")
        bpy.ops.mesh.subdivide(number_cuts=cuts)
        bpy.ops.object.mode_set(mode="OBJECT")
    obj.data.materials.append(mat)
    return obj


def box(name, size, location, mat):
    bpy.ops.mesh.primitive_cube_add(size=1, location=location)
    obj = bpy.context.active_object
    obj.name = name
    obj.scale = size
    bpy.ops.object.transform_apply(scale=True)
    obj.data.materials.append(mat)
    return obj


def main():
    bpy.ops.wm.read_factory_settings(use_empty=True)
    wall, floor_mat, ceiling = material("wall", (0.7, 0.7, 0.68)), material("floor", (0.45, 0.35, 0.25)), material("ceiling", (0.8, 0.8, 0.8))
    panel, wood = material("panel", (0.8, 0.8, 0.8), emission=(1.0, 0.95, 0.85)), material("desk", (0.5, 0.4, 0.3))
    w, d, h = 5.0, 4.0, 2.7
    half = 3.14159265 / 2
    objects = [
        plane("floor", (w, d), (0, 0, 0), (0, 0, 0), 11, floor_mat),
        plane("ceiling", (w, d), (0, 0, h), (3.14159265, 0, 0), 11, ceiling),
        plane("wall_north", (w, h), (0, d / 2, h / 2), (half, 0, 0), 7, wall),
        plane("wall_south", (w, h), (0, -d / 2, h / 2), (-half, 0, 0), 7, wall),
        plane("wall_east", (h, d), (w / 2, 0, h / 2), (0, -half, 0), 7, wall),
        plane("wall_west", (h, d), (-w / 2, 0, h / 2), (0, half, 0), 7, wall),
        box("slab", (w, d, 0.1), (0, 0, -0.05), floor_mat),
        box("desk", (1.4, 0.7, 0.04), (0.8, 0.6, 0.74), wood),
    ]
    for i in range(6):
        x, y = (-1.5 + 1.5 * (i % 3)), (-0.9 if i < 3 else 0.9)
        objects.append(plane(f"panel_{i}", (0.6, 0.6), (x, y, h - 0.02), (3.14159265, 0, 0), 0, panel))
    for obj in objects:
        bpy.ops.object.select_all(action="DESELECT")
        obj.select_set(True)
        bpy.context.view_layer.objects.active = obj
        obj.data.uv_layers.new(name="lightmap")
        obj.data.uv_layers.active_index = 1
        bpy.ops.object.mode_set(mode="EDIT")
        bpy.ops.mesh.select_all(action="SELECT")
        bpy.ops.uv.lightmap_pack(PREF_CONTEXT="ALL_FACES", PREF_PACK_IN_ONE=True, PREF_NEW_UVLAYER=False, PREF_MARGIN_DIV=0.2)
        bpy.ops.object.mode_set(mode="OBJECT")
        obj.data.uv_layers.active_index = 0
    faces = sum(len(o.data.polygons) for o in objects)
    print(f"blender_room: {len(objects)} objects, {faces} faces")
    bpy.ops.export_scene.gltf(filepath=out_path(), export_format="GLB")


main()
