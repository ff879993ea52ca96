# Blender imports lambert's lightmapped glb (docs/lightmaps.md "Real clients") with both its UV
# sets: every mesh gets two UV maps, the first TEXCOORD_0 and the second TEXCOORD_1 (the lightmap
# coordinates), corner by corner, as read from the glb's own bytes here (not through Blender).
# Usage: blender -b --factory-startup --python-exit-code 1 --python tests/blender_import.py -- FILE.glb
# Exit 0: both maps match; 1: they do not (what differs is printed); 77: this Blender cannot import
# glTF at all (the reason is printed; the test is skipped).
import json
import struct
import sys

SKIP = 77
TOLERANCE = 1e-5  # float32 coordinates, converted between conventions

glb_path = sys.argv[sys.argv.index('--') + 1]

try:
    import numpy
except ImportError as error:
    print(f'blender-import: skip: Blender\'s glTF importer needs numpy, and this Python has none ({error})')
    sys.exit(SKIP)
# Debian 12's Blender 3.4.1 importer still uses numpy.bool, an alias numpy 1.24 removed (it is
# the builtin bool): give it back, or the import fails before reading anything.
try:
    numpy.bool
except AttributeError:
    numpy.bool = bool

import bpy  # noqa: E402


def read_glb(path):
    """Per primitive, per triangle corner: (position, TEXCOORD_0, TEXCOORD_1), from the bytes."""
    data = open(path, 'rb').read()
    magic, version, length = struct.unpack_from('<4sII', data, 0)
    if magic != b'glTF' or version != 2 or length != len(data):
        raise ValueError(f'{path}: not a glTF 2 binary')
    json_length, _ = struct.unpack_from('<II', data, 12)
    gltf = json.loads(data[20:20 + json_length])
    bin_offset = 20 + json_length
    bin_length, _ = struct.unpack_from('<II', data, bin_offset)
    binary = data[bin_offset + 8:bin_offset + 8 + bin_length]

    def accessor(index):
        a = gltf['accessors'][index]
        view = gltf['bufferViews'][a['bufferView']]
        width = {'SCALAR': 1, 'VEC2': 2, 'VEC3': 3}[a['type']]
        code, size = {5126: ('f', 4), 5125: ('I', 4), 5123: ('H', 2), 5121: ('B', 1)}[a['componentType']]
        stride = view.get('byteStride', width * size)
        start = view.get('byteOffset', 0) + a.get('byteOffset', 0)
        return [struct.unpack_from(f'<{width}{code}', binary, start + i * stride) for i in range(a['count'])]

    corners = []
    for mesh in gltf['meshes']:
        for primitive in mesh['primitives']:
            attributes = primitive['attributes']
            position = accessor(attributes['POSITION'])
            # A set the primitive lacks matches nothing Blender imports.
            uv0 = accessor(attributes['TEXCOORD_0']) if 'TEXCOORD_0' in attributes else [(float('nan'),) * 2] * len(position)
            uv1 = accessor(attributes['TEXCOORD_1']) if 'TEXCOORD_1' in attributes else [(float('nan'),) * 2] * len(position)
            for (i,) in accessor(primitive['indices']):
                corners.append((position[i], uv0[i], uv1[i]))
    return corners


def as_blender(corner):
    """glTF's y-up metres and (0, 0)-top-left coordinates, as Blender's importer converts them."""
    (x, y, z), (u0, v0), (u1, v1) = corner
    return (x, -z, y), (u0, 1 - v0), (u1, 1 - v1)


def close(a, b):
    return all(abs(p - q) <= TOLERANCE for p, q in zip(a, b))


expected = [as_blender(c) for c in read_glb(glb_path)]
bpy.ops.wm.read_factory_settings(use_empty=True)
bpy.ops.import_scene.gltf(filepath=glb_path)

imported = []
failures = []
meshes = [o for o in bpy.data.objects if o.type == 'MESH']
if not meshes:
    failures.append('no mesh imported')
for obj in meshes:
    mesh = obj.data
    names = [layer.name for layer in mesh.uv_layers]
    if len(names) != 2:
        failures.append(f'mesh {obj.name}: {len(names)} UV maps {names}, not 2')
        continue
    first, second = mesh.uv_layers[0].data, mesh.uv_layers[1].data
    for loop in mesh.loops:
        p = obj.matrix_world @ mesh.vertices[loop.vertex_index].co
        imported.append(((p.x, p.y, p.z), tuple(first[loop.index].uv), tuple(second[loop.index].uv)))

# Every imported corner is a corner of the glb and every glb corner is imported: the same
# multiset of (position, first map, second map), matched greedily within the tolerance.
if len(imported) != len(expected) and not failures:
    failures.append(f'{len(imported)} corners imported, the glb has {len(expected)}')
unmatched = list(expected)
for corner in imported:
    match = next((i for i, e in enumerate(unmatched) if all(close(a, b) for a, b in zip(corner, e))), None)
    if match is None:
        failures.append(f'imported corner {corner} is no corner of the glb (position, TEXCOORD_0, TEXCOORD_1)')
        if len(failures) > 5:
            break
    else:
        unmatched.pop(match)

if failures:
    print('blender-import: FAILED: ' + '; '.join(failures))
    sys.exit(1)
print(f'blender-import: ok: {len(meshes)} mesh(es), {len(imported)} corners, UV maps '
      f'{[l.name for l in meshes[0].data.uv_layers]} match TEXCOORD_0 and TEXCOORD_1 within {TOLERANCE}')
sys.exit(0)
