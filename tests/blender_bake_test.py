# The Blender add-on (blender/lambert_bake) bakes a scene built here and its colours agree, corner
# by corner, with the lambert CLI's own result for the same exported glb; a cancelled bake writes
# nothing and leaves no process; a scene lambert refuses gives lambert's message as the error.
# Usage: blender -b --factory-startup --python-exit-code 1 --python tests/blender_bake_test.py -- LAMBERT SCRATCH
# Exit 0: passed; 1: failed (what is printed); 77: this Blender cannot export glTF (skipped).
import csv
import math
import os
import subprocess
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from blender_support import box, checker, material, start  # noqa: E402

started = time.monotonic()
lambert_binary, scratch = start('blender-bake')
source_dir = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

import addon_utils  # noqa: E402
import bmesh  # noqa: E402
import bpy  # noqa: E402
from mathutils import Vector  # noqa: E402

check, failures = checker('blender-bake')


def build_scene(broken=False):
    for collection in (bpy.data.objects, bpy.data.meshes, bpy.data.materials, bpy.data.lights, bpy.data.cameras):
        for item in list(collection):
            collection.remove(item)
    # No world: the bake is compared with the CLI's own solve of the exported glb, which has none
    # (a world goes to lambert in a scene file around the glb: tests/blender_lights_test.py).
    bpy.context.scene.world = None
    room = box('room', (4, 4, 2.5), (0, 0, 1.25), material('wall', (0.7, 0.7, 0.7)), cuts=5, inward=True)
    # The room's floor has vertices every 2/3 m: one at (2/3, 0) deep under the block, one at
    # (−2/3, −2/3) right under the lamp. (The block's bottom corners are off the floor's: where
    # two faces coincide, which one a corner's light comes from is undecided.)
    block = box('block', (0.9, 0.9, 1.0), (2 / 3 + 0.05, 0.03, 0.5), material('block', (0.6, 0.1, 0.08)), cuts=1,
                rotation_z=math.radians(20))
    objects = [room, block]
    if broken:  # a scene lambert refuses: a wireframe, no face
        for obj in (room, block):
            bpy.data.objects.remove(obj)
        wire = bpy.data.meshes.new('wire')
        wire.from_pydata([(0, 0, 0), (1, 0, 0), (1, 1, 0)], [(0, 1), (1, 2)], [])
        bpy.context.scene.collection.objects.link(bpy.data.objects.new('wire', wire))
        bpy.context.view_layer.update()
        return
    # the lamp: 1 m², emission strength 20
    mesh = bpy.data.meshes.new('light')
    bm = bmesh.new()
    bmesh.ops.create_grid(bm, x_segments=1, y_segments=1, size=0.5)  # 1 × 1 m, facing +z
    bmesh.ops.reverse_faces(bm, faces=bm.faces[:])  # facing down, into the room
    bm.to_mesh(mesh)
    bm.free()
    light = bpy.data.objects.new('light', mesh)
    light.location = (-2 / 3, -2 / 3, 2.4)
    mesh.materials.append(material('light', (0.8, 0.8, 0.8), emission=20))
    bpy.context.scene.collection.objects.link(light)
    objects.append(light)
    bpy.context.view_layer.update()
    return objects


def read_cli_vertices(path):
    rows = list(csv.reader(open(path)))
    assert rows[0][:9] == ['x', 'y', 'z', 'nx', 'ny', 'nz', 'r', 'g', 'b'], rows[0]
    # glTF y-up (x, y, z) is Blender's (x, −z, y).
    return [((float(r[0]), -float(r[2]), float(r[1])), (float(r[3]), -float(r[5]), float(r[4])),
             tuple(map(float, r[6:9]))) for r in rows[1:]]


def expected_at(vertices, point, normal, side=1):
    """Brute force: lambert's vertices at the corner (within 1e-5 m), the one facing most along
    `side` × the face's normal."""
    near = [v for v in vertices if sum((a - b) ** 2 for a, b in zip(v[0], point)) < 1e-10]
    if not near:
        return None
    return max(near, key=lambda v: side * sum(a * b for a, b in zip(v[1], normal)))[2]


def luminance(rgb):
    return 0.2126 * rgb[0] + 0.7152 * rgb[1] + 0.0722 * rgb[2]


def corners_of(obj):
    """(polygon, world position, world face normal, baked colour) per corner."""
    mesh = obj.data
    colours = mesh.color_attributes['lambert'].data
    normal_matrix = obj.matrix_world.to_3x3().inverted().transposed()
    out = []
    for polygon in mesh.polygons:
        n = (normal_matrix @ polygon.normal).normalized()
        for li in polygon.loop_indices:
            p = obj.matrix_world @ mesh.vertices[mesh.loops[li].vertex_index].co
            out.append((polygon.index, tuple(p), tuple(n), tuple(colours[li].color)[:3]))
    return out


def error(a, b):
    """Relative difference, against the brighter of the two (and a floor for black)."""
    return max(abs(x - y) / max(abs(x), abs(y), 1e-4) for x, y in zip(a, b))


TOLERANCE = 1e-4  # lambert's CSV has 9 significant digits; the attribute is float32
SEAM_TOLERANCE = 0.03  # a lightmap's step across an edge two quads' islands share

sys.path.insert(0, os.path.join(source_dir, 'blender'))
build_scene()
addon_utils.enable('lambert_bake', default_set=True)
import lambert_bake  # noqa: E402
if 'lambert_bake' not in bpy.context.preferences.addons:
    lambert_bake.register()
preferences = bpy.context.preferences.addons['lambert_bake'].preferences
preferences.binary = lambert_binary


def configure(keep):
    settings = bpy.context.scene.lambert_bake
    settings.method, settings.quality, settings.output, settings.objects = 'HIERARCHICAL', 'DRAFT', 'VERTEX_COLORS', 'ALL'
    preferences.keep_files_in = keep
    return settings


def compare_with_cli(bake_dir, cli_options, objects):
    """Runs the CLI on the glb the add-on exported to bake_dir, with cli_options, and compares the
    objects' "lambert" colours with its vertices corner by corner. Returns (corners compared,
    largest difference, largest difference of the faces' other sides, of the faces' next corners)."""
    exported = os.path.join(bake_dir, 'scene.glb')
    cli_csv = os.path.join(bake_dir, 'cli.csv')
    cli = subprocess.run([lambert_binary, 'solve', '--scene', exported, *cli_options,
                          '--export-vertices', cli_csv, '-q'], capture_output=True, text=True)
    check(cli.returncode == 0, f'the CLI on {exported}: {cli.stderr}')
    if cli.returncode != 0:
        return 0, float('inf'), 0.0, 0.0
    vertices = read_cli_vertices(cli_csv)
    compared, worst, worst_wrong_side, worst_rotated = 0, 0.0, 0.0, 0.0
    for obj in objects:
        if 'lambert' not in obj.data.color_attributes:
            check(False, f'{obj.name}: no "lambert" colour attribute')
            continue
        check(obj.data.color_attributes.active_color.name == 'lambert', f'{obj.name}: "lambert" is not the active colour')
        corners = corners_of(obj)
        front = [expected_at(vertices, p, n) for _, p, n, _ in corners]
        back = [expected_at(vertices, p, n, side=-1) for _, p, n, _ in corners]
        check(None not in front, f'{obj.name}: a corner has no CLI vertex within 1e-5 m')
        if None in front:
            continue
        # Each face shows the side its normal points to (Blender's faces are two-sided: lambert
        # lights both); the room's normals point in, the block's out.
        expected, opposite = front, back
        for i, (polygon, p, n, baked) in enumerate(corners):
            if expected[i] is None:
                continue
            compared += 1
            e = error(baked, expected[i])
            if e > TOLERANCE and worst <= TOLERANCE:
                print(f'blender-bake: {obj.name} corner at {p} normal {n}: baked {baked}, the CLI {expected[i]}')
            worst = max(worst, e)
            worst_wrong_side = max(worst_wrong_side, error(opposite[i], expected[i]))
            # The colour of the polygon's next corner: corners shuffled within faces.
            following = i + 1 if i + 1 < len(corners) and corners[i + 1][0] == polygon else \
                next(j for j in range(len(corners)) if corners[j][0] == polygon)
            worst_rotated = max(worst_rotated, error(expected[following], expected[i]))
    return compared, worst, worst_wrong_side, worst_rotated


# 1. Bake, and compare every corner with the CLI's own solve of the same exported glb.
t0 = time.monotonic()
bake_dir = os.path.join(scratch, 'bake')
configure(bake_dir)
result = bpy.ops.lambert.bake()
bake_seconds = time.monotonic() - t0
check(result == {'FINISHED'}, f'bpy.ops.lambert.bake() returned {result}')
compared, worst, worst_wrong_side, worst_rotated = compare_with_cli(
    bake_dir, ['--method', 'hierarchical', '--link-error', '0.001'], [bpy.data.objects['room'], bpy.data.objects['block']])
check(compared > 200, f'only {compared} corners compared')
check(worst <= TOLERANCE, f'largest per-corner difference from the CLI {worst:.3g} > {TOLERANCE}')
# The comparison can fail: the light on the other side of a face, or the next corner's, is far off.
check(worst_wrong_side > 100 * TOLERANCE, f'the other side differs by only {worst_wrong_side:.3g}: the test cannot tell sides')
check(worst_rotated > 100 * TOLERANCE, f'shuffled corners differ by only {worst_rotated:.3g}: the test cannot tell corners')

# Well-separated points with clearly different light: the floor under the block (in its shadow,
# inside it) against the lit floor under the lamp.
room_corners = corners_of(bpy.data.objects['room'])


def floor_luminance_near(x, y):
    best = min((c for c in room_corners if abs(c[1][2]) < 1e-6 and abs(c[2][2]) > 0.5),
               key=lambda c: (c[1][0] - x) ** 2 + (c[1][1] - y) ** 2)
    return sum(best[3]) / 3, best[1]


dark, dark_at = floor_luminance_near(2 / 3, 0)
lit, lit_at = floor_luminance_near(-2 / 3, -2 / 3)
check(lit > 10 * dark and lit > 0.01, f'floor under the lamp {lit_at}: {lit:.4g}, under the block {dark_at}: {dark:.4g}')

# 1b. Lightmaps of the same scene: on the add-on's second UV map, wired into the materials, and
# agreeing with the vertex bake just checked: at each floor face's centre the lightmap's
# irradiance E against π L / ρ from the face's corner colours (ρ = 0.7, the walls').
t0 = time.monotonic()
settings = configure(os.path.join(scratch, 'lightmaps'))
settings.output = 'LIGHTMAPS'
# As the panel's modal operator drives it: poll, read the progress, finish.
job = lambert_bake.BakeJob(bpy.context, settings)
progress_seen = set()
while job.poll() is None:
    progress_seen.add((job.lambert.progress_label, job.lambert.progress_fraction))
    time.sleep(0.02)
job.poll()
progress_seen.add((job.lambert.progress_label, job.lambert.progress_fraction))
summary = job.finish(bpy.context)
lightmap_seconds = time.monotonic() - t0
check(('lightmap texels', 1.0) in progress_seen, f'lambert\'s progress was not read: {sorted(progress_seen)}')
image = bpy.data.images.get('lambert lightmap')
wall_nodes = bpy.data.materials['wall'].node_tree.nodes
emission = wall_nodes['Principled BSDF'].inputs['Emission']
check(image is not None and image.packed_file is not None, 'no packed "lambert lightmap" image')
check(emission.is_linked and wall_nodes['lambert lightmap'].image == image and
      wall_nodes['lambert lightmap uv'].uv_map == 'lambert_lightmap', 'the wall material does not show the lightmap')
check(not bpy.data.materials['light'].node_tree.nodes['Principled BSDF'].inputs['Emission'].is_linked,
      'the lamp\'s own emission was replaced')
width, height = image.size
pixels = list(image.pixels)
room = bpy.data.objects['room'].data
ratios = []
for polygon in room.polygons:
    world_centre = bpy.data.objects['room'].matrix_world @ polygon.center
    if abs(world_centre.z) > 1e-6:
        continue  # floor faces only
    uv = sum((room.uv_layers['lambert_lightmap'].data[i].uv for i in polygon.loop_indices), Vector((0, 0))) / polygon.loop_total
    x, y = min(int(uv.x * width), width - 1), min(int(uv.y * height), height - 1)
    texel = pixels[4 * (y * width + x):4 * (y * width + x) + 3]
    corners_l = [tuple(room.color_attributes['lambert'].data[i].color)[:3] for i in polygon.loop_indices]
    from_vertices = math.pi / 0.7 * sum(luminance(c) for c in corners_l) / len(corners_l)
    if from_vertices > 0.2:  # lit faces (the faces under the block are black by construction)
        ratios.append(luminance(texel) / from_vertices)
ratios.sort()
median = ratios[len(ratios) // 2] if ratios else 0
check(len(ratios) >= 20, f'only {len(ratios)} lit floor faces compared')
check(0.8 < median < 1.25, f'lightmap / vertex irradiance on the floor: median {median:.3g} (of {len(ratios)} faces)')
# Lightmap Pack gives every quad an island of its own: along every edge two floor quads share, the
# lightmap read (bilinear, as Blender's Linear image node reads it) from either quad's island must
# give the same light, else the floor shows a step at every quad (measured: up to 20% beside the
# block with each seam texel pair set to its mean, 1.2% stitched in least squares).
def lightmap_at(u, v):
    x, y = u * width - 0.5, v * height - 0.5
    x0, y0 = math.floor(x), math.floor(y)
    fx, fy = x - x0, y - y0

    def texel(i, j):
        i, j = min(max(i, 0), width - 1), min(max(j, 0), height - 1)
        return luminance(pixels[4 * (j * width + i):4 * (j * width + i) + 3])

    return ((1 - fy) * ((1 - fx) * texel(x0, y0) + fx * texel(x0 + 1, y0)) +
            fy * ((1 - fx) * texel(x0, y0 + 1) + fx * texel(x0 + 1, y0 + 1)))


room_object = bpy.data.objects['room']
edge_sides = {}  # (vertex, vertex) of a floor edge: per floor quad, the lightmap UVs of its two ends
for polygon in room.polygons:
    if abs((room_object.matrix_world @ polygon.center).z) > 1e-6:
        continue
    loops = list(polygon.loop_indices)
    for k, loop in enumerate(loops):
        following = loops[(k + 1) % len(loops)]
        a, b = room.loops[loop].vertex_index, room.loops[following].vertex_index
        uv_a, uv_b = room.uv_layers['lambert_lightmap'].data[loop].uv.copy(), room.uv_layers['lambert_lightmap'].data[following].uv.copy()
        key, ends = ((a, b), (uv_a, uv_b)) if a < b else ((b, a), (uv_b, uv_a))
        edge_sides.setdefault(key, []).append(ends)
seam_pairs = [tuple(lightmap_at(*(ends[0].lerp(ends[1], t))) for ends in sides)
              for sides in edge_sides.values() if len(sides) == 2 for t in (0.2, 0.5, 0.8)]  # not the floor's rim
brightest = max((max(pair) for pair in seam_pairs), default=0)
# Steps where the light is at least a tenth of the floor's brightest (not in the block's shadow).
seam_steps = sorted(abs(one - other) / max(one, other) for one, other in seam_pairs if max(one, other) > 0.1 * brightest)
seam_median = seam_steps[len(seam_steps) // 2] if seam_steps else 1
seam_worst = seam_steps[-1] if seam_steps else 1
check(len(seam_steps) >= 100, f'only {len(seam_steps)} points on shared floor edges compared')
check(seam_worst < SEAM_TOLERANCE, f'lightmap step across the floor quads\' shared edges: median {100 * seam_median:.2f}%, '
      f'worst {100 * seam_worst:.2f}% (at most {100 * SEAM_TOLERANCE:.0f}% wanted)')
# The packed islands (a box per quad) keep apart by the margin lambert's padding and a viewer's
# bilinear lookups need (results.MARGIN_TEXELS on each side): else a floor island's rim reads the
# lamp's island beside it.
boxes = []
for obj in (bpy.data.objects['room'], bpy.data.objects['block'], bpy.data.objects['light']):
    layer = obj.data.uv_layers['lambert_lightmap'].data
    for polygon in obj.data.polygons:
        us = [layer[i].uv.x * width for i in polygon.loop_indices]
        vs = [layer[i].uv.y * height for i in polygon.loop_indices]
        boxes.append((min(us), min(vs), max(us), max(vs)))
closest = min(max(b[0] - a[2], a[0] - b[2], b[1] - a[3], a[1] - b[3]) for i, a in enumerate(boxes) for b in boxes[i + 1:])
check(closest >= 2 * lambert_bake.results.MARGIN_TEXELS - 1,
      f'two lightmap islands {closest:.2f} texels apart (at least {2 * lambert_bake.results.MARGIN_TEXELS - 1} wanted)')

# 2. Cancel: lambert stops, no process is left, nothing is written.
build_scene()
cancel_dir = os.path.join(scratch, 'cancel')
settings = configure(cancel_dir)
settings.quality = 'HIGH'
job = lambert_bake.BakeJob(bpy.context, settings)
pid = job.lambert.process.pid
check(job.poll() is None, 'lambert finished before it could be cancelled (the scene is too quick)')
job.cancel()
check(job.lambert.process.returncode is not None, 'lambert still runs after cancel')
try:
    os.kill(pid, 0)
    check(False, f'process {pid} still exists after cancel')
except ProcessLookupError:
    pass
check(not os.path.exists(job.result_path), f'a cancelled bake left {job.result_path}')
written = [o.name for o in bpy.data.objects if o.type == 'MESH' and 'lambert' in o.data.color_attributes]
check(not written, f'a cancelled bake wrote colours on {written}')

# 3. lambert's error becomes the operator's error, with lambert's own message.
build_scene(broken=True)
error_dir = os.path.join(scratch, 'error')
configure(error_dir)
try:
    bpy.ops.lambert.bake()
    check(False, 'a scene without a face baked without an error')
except RuntimeError as raised:
    cli = subprocess.run([lambert_binary, 'solve', '--scene', os.path.join(error_dir, 'scene.glb'), '-q'],
                         capture_output=True, text=True)
    message = cli.stderr.strip().splitlines()[-1] if cli.stderr.strip() else '(none)'
    check(cli.returncode != 0, 'the CLI solves the scene without a face')
    check(message in str(raised), f'the error "{raised}" does not carry lambert\'s message "{message}"')
    print(f'blender-bake: the error reported: {str(raised).strip()[:300]}')

# 4. Selected objects, the flat method: only the block (and the lamp) go out; the room keeps no
# colours; the block's agree with the CLI's flat solve of that export.
build_scene()
settings = configure(os.path.join(scratch, 'selected'))
settings.objects, settings.method = 'SELECTED', 'FLAT'
for obj in bpy.data.objects:
    obj.select_set(obj.name in ('block', 'light'))
check(bpy.ops.lambert.bake() == {'FINISHED'}, 'the selected objects\' bake failed')
check('lambert' not in bpy.data.objects['room'].data.color_attributes, 'an unselected object was coloured')
flat_compared, flat_worst, _, _ = compare_with_cli(os.path.join(scratch, 'selected'), ['--method', 'flat', '--patches', '400'],
                                                   [bpy.data.objects['block']])
check(flat_compared >= 90 and flat_worst <= TOLERANCE,
      f'flat, selected: {flat_compared} corners, largest difference from the CLI {flat_worst:.3g}')

total = time.monotonic() - started
if failures:
    print(f'blender-bake: FAILED ({len(failures)}): ' + '; '.join(failures))
    sys.exit(1)
print(f'blender-bake: ok: {compared} corners within {TOLERANCE} of the CLI (other side: {worst_wrong_side:.3g}, '
      f'next corner: {worst_rotated:.3g}); floor lit {lit:.4g} vs under the block {dark:.4g}; cancel and error ok; '
      f'flat on the selected block: {flat_compared} corners within {TOLERANCE}; lightmaps: median lightmap/vertex irradiance {median:.3f} over {len(ratios)} floor faces, islands {closest:.1f} texels apart, '
      f'steps across quad edges median {100 * seam_median:.2f}%, worst {100 * seam_worst:.2f}% over {len(seam_steps)} points; '
      f'bake {bake_seconds:.1f} s, lightmap bake {lightmap_seconds:.1f} s, whole test {total:.1f} s')
sys.exit(0)
