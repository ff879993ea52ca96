# What the headless Blender tests share (tests/blender_bake_test.py, tests/blender_lights_test.py):
# their arguments and scratch folder, the skip where Blender's glTF exporter cannot run, the
# failure list, and the materials and boxes their scenes are built of.
import os
import shutil
import sys

SKIP = 77  # CTest's SKIP_RETURN_CODE for these tests


def start(name):
    """LAMBERT and SCRATCH from after Blender's '--' (absolute; SCRATCH emptied), or exit SKIP where
    this Python has no numpy (Blender's glTF exporter needs it). name prefixes every line printed."""
    lambert_binary, scratch = sys.argv[sys.argv.index('--') + 1:][:2]
    scratch = os.path.abspath(scratch)
    shutil.rmtree(scratch, ignore_errors=True)
    os.makedirs(scratch)
    try:
        import numpy  # noqa: F401
    except ImportError as error:
        print(f'{name}: skip: Blender\'s glTF exporter needs numpy, and this Python has none ({error})')
        sys.exit(SKIP)
    return os.path.abspath(lambert_binary), scratch


def checker(name):
    """check(condition, message), which prints and records each failure, and the list of them."""
    failures = []

    def check(condition, message):
        if not condition:
            failures.append(message)
            print(f'{name}: FAIL: {message}')
    return check, failures


def material(name, color, emission=None):
    """A diffuse Principled BSDF (roughness 1, no specular) of base colour color; emission: a white
    emission of that strength."""
    import bpy
    m = bpy.data.materials.new(name)
    m.use_nodes = True
    bsdf = m.node_tree.nodes['Principled BSDF']
    bsdf.inputs['Base Color'].default_value = (*color, 1)
    bsdf.inputs['Roughness'].default_value = 1
    bsdf.inputs['Specular'].default_value = 0
    if emission:
        bsdf.inputs['Emission'].default_value = (1, 1, 1, 1)
        bsdf.inputs['Emission Strength'].default_value = emission
    return m


def box(name, size, location, mat, cuts=0, rotation_z=0.0, inward=False):
    """A box of unit size scaled by its object transform (so the world transform matters), its
    faces subdivided by cuts; inward: its normals flipped, as a room is modelled (Mesh > Normals >
    Flip)."""
    import bmesh
    import bpy
    mesh = bpy.data.meshes.new(name)
    bm = bmesh.new()
    bmesh.ops.create_cube(bm, size=1.0)
    if cuts:
        bmesh.ops.subdivide_edges(bm, edges=bm.edges[:], cuts=cuts, use_grid_fill=True)
    if inward:
        bmesh.ops.reverse_faces(bm, faces=bm.faces[:])
    bm.to_mesh(mesh)
    bm.free()
    obj = bpy.data.objects.new(name, mesh)
    obj.scale = size
    obj.location = location
    obj.rotation_euler = (0, 0, rotation_z)
    mesh.materials.append(mat)
    bpy.context.scene.collection.objects.link(obj)
    return obj
