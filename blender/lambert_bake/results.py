# Writes lambert's results into the .blend: per-corner vertex colours from --export-vertices, or
# lightmap images on the objects' second UV map from --lightmaps.
import csv
import json
import math
import os
import struct

import bpy
from mathutils import Vector
from mathutils.kdtree import KDTree

ATTRIBUTE = 'lambert'
LIGHTMAP_UV = 'lambert_lightmap'
LIGHTMAP_NODE = 'lambert lightmap'


def read_vertices(path):
    """lambert's vertex CSV (x,y,z,nx,ny,nz,r,g,b in glTF's y-up metres) as Blender z-up
    (positions, normals, radiance) lists."""
    positions, normals, radiance = [], [], []
    with open(path, newline='') as f:
        rows = csv.reader(f)
        header = next(rows)
        if header[:9] != ['x', 'y', 'z', 'nx', 'ny', 'nz', 'r', 'g', 'b']:
            raise ValueError(f'{path}: not a lambert vertex CSV (header {header})')
        for row in rows:
            x, y, z, nx, ny, nz, r, g, b = map(float, row[:9])
            # glTF y-up to Blender z-up, as Blender's glTF exporter converted them.
            positions.append(Vector((x, -z, y)))
            normals.append(Vector((nx, -nz, ny)))
            radiance.append((r, g, b))
    return positions, normals, radiance


class VertexMatcher:
    """Finds, for a Blender face corner, lambert's vertex at the same place on the same side.

    lambert welds the exported corners, meshes finer, and has a vertex on each side of a
    two-sided face (opposite normals); its original corners stay vertices. So: the vertices
    within a small distance of the corner, the one whose normal faces most like the face's."""

    def __init__(self, positions, normals):
        self.positions = positions
        self.normals = normals
        self.tree = KDTree(len(positions))
        for i, p in enumerate(positions):
            self.tree.insert(p, i)
        self.tree.balance()
        lo = Vector((min(p[k] for p in positions) for k in range(3))) if positions else Vector()
        hi = Vector((max(p[k] for p in positions) for k in range(3))) if positions else Vector()
        # float32 positions through the exporter, lambert's metres: a millionth of the scene.
        self.radius = max(1e-6 * (hi - lo).length, 1e-7)
        self.far = 0

    def match(self, point, normal):
        """lambert's vertex at the point facing most along normal (its index)."""
        near = self.tree.find_range(point, self.radius)
        if not near:  # not an original corner (a modifier, or a face lambert dropped): the nearest
            near = self.tree.find_n(point, 8)
            self.far += 1
        return max(near, key=lambda hit: self.normals[hit[1]].dot(normal) - 1e-3 * hit[2])[1]


def write_vertex_colors(objects, csv_path):
    """Sets a float colour attribute "lambert" (face-corner domain, linear radiance W/(m²·sr))
    on each object's mesh, made active so that the viewport's Attribute colour shows it."""
    positions, normals, radiance = read_vertices(csv_path)
    if not positions:
        raise ValueError(f'{csv_path}: lambert exported no vertex')
    matcher = VertexMatcher(positions, normals)
    corners = 0
    for obj in objects:
        mesh = obj.data
        world = obj.matrix_world
        normal_matrix = world.to_3x3().inverted_safe().transposed()
        if ATTRIBUTE in mesh.color_attributes:
            mesh.color_attributes.remove(mesh.color_attributes[ATTRIBUTE])
        attribute = mesh.color_attributes.new(ATTRIBUTE, 'FLOAT_COLOR', 'CORNER')
        colors = [0.0] * (4 * len(mesh.loops))
        for polygon in mesh.polygons:
            normal = (normal_matrix @ polygon.normal).normalized()
            points = [world @ mesh.vertices[mesh.loops[i].vertex_index].co for i in polygon.loop_indices]
            # A two-sided face (Blender's default) has light on both sides in lambert, one colour
            # per corner here: the side the face's normal points to, as Cycles shades a face seen
            # from that side (a room is modelled with its normals pointing in: Mesh > Normals >
            # Flip). Each face on its brighter side instead mixed sides from face to face.
            front = [radiance[matcher.match(p, normal)] for p in points]
            for loop_index, (r, g, b) in zip(polygon.loop_indices, front):
                colors[4 * loop_index:4 * loop_index + 4] = (r, g, b, 1.0)
                corners += 1
        attribute.data.foreach_set('color', colors)
        mesh.color_attributes.active_color = attribute
        mesh.color_attributes.render_color_index = mesh.color_attributes.find(ATTRIBUTE)
        mesh.update()
    return corners, matcher.far


def show_attribute_in_viewports(screen_context):
    """Solid shading by the active colour attribute in every 3D view, so the bake shows at once."""
    window_manager = screen_context.window_manager
    for window in window_manager.windows:
        for area in window.screen.areas:
            if area.type == 'VIEW_3D':
                for space in area.spaces:
                    if space.type == 'VIEW_3D' and space.shading.type == 'SOLID':
                        space.shading.color_type = 'VERTEX'


# Empty texels kept on each side of every packed island: lambert fills its own padding ring by
# ring (--lightmap-padding 2, three rings), and a viewer's bilinear lookup at an island's rim reads
# the next texel out. Six texels between islands keep both within the island's own light: with
# Blender's default margin (about one texel at 512²) a floor island's rim read the dilated light
# of the lamp's island packed beside it, a dotted bright line across the floor.
MARGIN_TEXELS = 3


def add_lightmap_uvs(context, objects, size):
    """A second UV map "lambert_lightmap" packed over all the objects together (one atlas, no
    two faces overlapping, MARGIN_TEXELS empty texels around each island of a size² atlas), which
    Blender's exporter writes as TEXCOORD_1 and lambert then bakes into (docs/lightmaps.md: given
    lightmap UVs are used when every surface has them)."""
    for obj in objects:
        mesh = obj.data
        if LIGHTMAP_UV in mesh.uv_layers:
            mesh.uv_layers.remove(mesh.uv_layers[LIGHTMAP_UV])
        while len(mesh.uv_layers) < 1:
            mesh.uv_layers.new(name='UVMap')
        if len(mesh.uv_layers) >= 2:
            raise ValueError(f'object "{obj.name}" has {len(mesh.uv_layers)} UV maps already; glTF\'s TEXCOORD_1 '
                             'must be the lightmap: remove the second one or bake vertex colours')
        layer = mesh.uv_layers.new(name=LIGHTMAP_UV)
        mesh.uv_layers.active = layer
    previous_active = context.view_layer.objects.active
    previous_selection = [o for o in context.view_layer.objects if o.select_get()]
    for o in previous_selection:
        o.select_set(False)
    for obj in objects:
        obj.select_set(True)
    context.view_layer.objects.active = objects[0]
    # In object mode the operator packs every face of the selected objects (edit mode's data
    # would not be synced when the bake starts from another editor than the 3D view).
    # PREF_MARGIN_DIV is the margin on each side of an island in percent of the atlas's side.
    bpy.ops.uv.lightmap_pack(PREF_CONTEXT='ALL_FACES', PREF_PACK_IN_ONE=True, PREF_NEW_UVLAYER=False,
                             PREF_BOX_DIV=12, PREF_MARGIN_DIV=100.0 * MARGIN_TEXELS / size)
    for obj in objects:
        obj.select_set(False)
        obj.data.uv_layers.active = obj.data.uv_layers[0]
    for o in previous_selection:
        o.select_set(True)
    context.view_layer.objects.active = previous_active


def read_glb_json(path):
    data = open(path, 'rb').read()
    magic, version, _ = struct.unpack_from('<4sII', data, 0)
    if magic != b'glTF' or version != 2:
        raise ValueError(f'{path}: not a glTF 2 binary')
    length, _ = struct.unpack_from('<II', data, 12)
    return json.loads(data[20:20 + length])


def lightmap_atlases(glb_path):
    """The atlas files lambert wrote beside the glb: OUT-lightmap-K.exr for each K its images name."""
    gltf = read_glb_json(glb_path)
    stem = glb_path[:-len('.glb')]
    indices = sorted({int(image['name'].rsplit('-', 1)[-1]) for image in gltf.get('images', [])
                      if image.get('name', '').startswith(os.path.basename(stem) + '-lightmap-')})
    if not indices:
        raise ValueError(f'{glb_path}: lambert wrote no lightmap (no image named {os.path.basename(stem)}-lightmap-K)')
    return [f'{stem}-lightmap-{k}.exr' for k in indices]


def front_lightmap(glb_path):
    """The irradiance image (E, W/m², linear float) of the faces' fronts, laid out on the
    "lambert_lightmap" UVs.

    The UVs are the add-on's own (lambert keeps given lightmap coordinates), so every atlas has the
    same layout; lambert puts the fronts first and the backs of two-sided faces (Blender's default),
    which share their UVs, in the next atlas. A face shows the side its normal points to, as the
    vertex colours do."""
    import numpy
    path = lightmap_atlases(glb_path)[0]
    image = bpy.data.images.load(path, check_existing=False)
    try:
        size = tuple(image.size)
        pixels = numpy.empty(size[0] * size[1] * 4, dtype=numpy.float32)
        image.pixels.foreach_get(pixels)
    finally:
        bpy.data.images.remove(image)
    pixels = pixels.reshape(-1, 4)
    pixels[:, 3] = 1.0
    image = bpy.data.images.new('lambert lightmap', size[0], size[1], alpha=False, float_buffer=True)
    image.colorspace_settings.name = 'Linear'
    image.pixels.foreach_set(pixels.ravel())
    image.pack()  # the scratch folder goes; the .blend keeps the lightmap
    return image


def wire_lightmaps(objects, glb_path):
    """Puts the baked irradiance E into every material of the objects: base colour × E/π is the
    outgoing radiance of a diffuse surface, given as the Principled BSDF's emission (strength 1),
    so Material Preview and Rendered modes show the baked light. The nodes are named
    "lambert lightmap …" and replaced on a re-bake; emitters keep their own emission."""
    previous = bpy.data.images.get('lambert lightmap')
    image = front_lightmap(glb_path)
    if previous is not None:
        bpy.data.images.remove(previous)
        image.name = 'lambert lightmap'
    wired = 0
    for material in {slot.material for obj in objects for slot in obj.material_slots}:
        if material is not None and material.use_nodes and _wire_material(material, image):
            wired += 1
    return wired, image


def _wire_material(material, image):
    nodes, links = material.node_tree.nodes, material.node_tree.links
    bsdf = next((n for n in nodes if n.type == 'BSDF_PRINCIPLED'), None)
    if bsdf is None:
        raise ValueError(f'material "{material.name}" has no Principled BSDF to wire the lightmap into')
    for name in (LIGHTMAP_NODE, LIGHTMAP_NODE + ' uv', LIGHTMAP_NODE + ' scale', LIGHTMAP_NODE + ' albedo',
                 LIGHTMAP_NODE + ' sum'):
        if name in nodes:
            nodes.remove(nodes[name])
    uv = nodes.new('ShaderNodeUVMap')
    uv.name = LIGHTMAP_NODE + ' uv'
    uv.uv_map = LIGHTMAP_UV
    texture = nodes.new('ShaderNodeTexImage')
    texture.name = LIGHTMAP_NODE
    texture.image = image
    texture.interpolation = 'Linear'
    links.new(uv.outputs['UV'], texture.inputs['Vector'])
    scale = nodes.new('ShaderNodeMixRGB')  # E × (1/π)
    scale.name = LIGHTMAP_NODE + ' scale'
    scale.blend_type = 'MULTIPLY'
    scale.inputs['Fac'].default_value = 1.0
    scale.inputs['Color2'].default_value = (1 / math.pi, 1 / math.pi, 1 / math.pi, 1)
    links.new(texture.outputs['Color'], scale.inputs['Color1'])
    albedo = nodes.new('ShaderNodeMixRGB')  # × base colour
    albedo.name = LIGHTMAP_NODE + ' albedo'
    albedo.blend_type = 'MULTIPLY'
    albedo.inputs['Fac'].default_value = 1.0
    links.new(scale.outputs['Color'], albedo.inputs['Color1'])
    base = bsdf.inputs['Base Color']
    if base.is_linked:
        links.new(base.links[0].from_socket, albedo.inputs['Color2'])
    else:
        albedo.inputs['Color2'].default_value = base.default_value
    emission = bsdf.inputs['Emission']
    if emission.is_linked or tuple(emission.default_value)[:3] != (0.0, 0.0, 0.0):
        # An emitter keeps its own emission (its baked light is its emission already).
        for n in (uv, texture, scale, albedo):
            nodes.remove(n)
        return False
    links.new(albedo.outputs['Color'], emission)
    bsdf.inputs['Emission Strength'].default_value = 1.0
    for offset, n in enumerate((uv, texture, scale, albedo)):
        n.location = (bsdf.location.x - 900 + 220 * offset, bsdf.location.y - 500)
    return True


def remove_lightmap_nodes(objects):
    """Takes a previous bake's lightmap out of the materials before they are exported again
    (else the exporter would write the baked light as emission, and lambert would read it so)."""
    for obj in objects:
        for slot in obj.material_slots:
            material = slot.material
            if material is None or not material.use_nodes:
                continue
            nodes = material.node_tree.nodes
            albedo = nodes.get(LIGHTMAP_NODE + ' albedo')
            if albedo is None:
                continue
            for link in list(albedo.outputs['Color'].links):
                if link.to_socket.name == 'Emission':
                    material.node_tree.links.remove(link)
            for name in (LIGHTMAP_NODE, LIGHTMAP_NODE + ' uv', LIGHTMAP_NODE + ' scale', LIGHTMAP_NODE + ' albedo'):
                if name in nodes:
                    nodes.remove(nodes[name])
