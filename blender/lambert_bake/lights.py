# Blender's lights as the bake carries them (docs/blender.md, "Lights").
#
# Blender's glTF exporter writes point, spot and sun lights (KHR_lights_punctual, converted at
# Blender's 683 lm/W, which lambert reads back the same way) and drops area lights, printing only
# `WARNING: Unsupported light source AREA` to the console. To Cycles an area light is a one-sided
# Lambertian emitter of its shape: of power P watts, colour C and area A it shows the radiance
# C · P / (4 A) in the unit an emission strength is given in (Blender 3.4's Cycles, measured: a
# 100 W square of 1 m² and a disk of 1 m diameter, 2 m over a floor, light it as an emissive face
# of that strength does, within 0.1%; P / (π A), a Lambertian emitter of power P, gave 27% more).
# So for the export each becomes a face of its shape and size with an emissive material of that
# strength, black (a light reflects nothing) and one-sided (backface culling, which the exporter
# writes as doubleSided false), and is removed again after it.
import json
import math
import os

import bpy

# Sides of the polygon a disk or an ellipse becomes, scaled to the ellipse's own area.
ELLIPSE_SIDES = 32
NAME_PREFIX = 'lambert area light '
# Half a degree: a spread this close to 180° is the default's Lambertian emitter.
FULL_SPREAD = math.pi - math.radians(0.5)


def area_light_radiance(power_watts, area):
    """The radiance (emission strength) Cycles gives an area light of this power and area."""
    return power_watts / (4.0 * area)


def _outline(light):
    """The light's outline in its own plane (x, y; it shines toward −z), before its object's scale,
    and the area of the shape it stands for."""
    width = light.size
    height = light.size_y if light.shape in ('RECTANGLE', 'ELLIPSE') else light.size
    if light.shape in ('SQUARE', 'RECTANGLE'):
        return [(-width / 2, -height / 2), (-width / 2, height / 2), (width / 2, height / 2), (width / 2, -height / 2)], width * height
    area = math.pi * width * height / 4
    # The polygon's area is n/2 sin(2π/n) r²: scaled up to the ellipse's, so that it emits its power.
    grow = math.sqrt(math.pi / (ELLIPSE_SIDES / 2 * math.sin(2 * math.pi / ELLIPSE_SIDES)))
    # Clockwise seen from +z, so that the face's normal is −z, the way the light shines.
    return [(grow * width / 2 * math.cos(-2 * math.pi * k / ELLIPSE_SIDES), grow * height / 2 * math.sin(-2 * math.pi * k / ELLIPSE_SIDES))
            for k in range(ELLIPSE_SIDES)], area


def _scaled_area(obj, outline_area):
    """The area an outline of outline_area in the object's xy plane has in the world (its scale)."""
    m = obj.matrix_world.to_3x3()
    return outline_area * m.col[0].cross(m.col[1]).length


def area_light_stand_ins(objects):
    """Adds, for each area light among objects, an emissive face standing in for it; returns the
    objects added and the warnings about what they cannot carry (a list of strings)."""
    added, warnings = [], []
    for obj in objects:
        if obj.type != 'LIGHT' or obj.data.type != 'AREA':
            continue
        light = obj.data
        if getattr(light, 'cycles', None) is not None and getattr(light.cycles, 'is_portal', False):
            continue  # a portal guides Cycles' sampling of the world; it emits nothing
        outline, outline_area = _outline(light)
        # Blender units, as Cycles takes them and the exporter writes them (lambert reads metres).
        area = _scaled_area(obj, outline_area)
        if not area > 0:
            warnings.append(f'area light "{obj.name}" has no area: left out')
            continue
        if getattr(light, 'spread', math.pi) < FULL_SPREAD:
            warnings.append(f'area light "{obj.name}": spread {math.degrees(light.spread):.0f}° is not carried '
                            '(lambert emits over the whole half-space, as a spread of 180°)')
        if light.energy < 0:
            warnings.append(f'area light "{obj.name}": negative power {light.energy:g} W left out')
            continue
        mesh = bpy.data.meshes.new(NAME_PREFIX + obj.name)
        mesh.from_pydata([(x, y, 0.0) for x, y in outline], [], [list(range(len(outline)))])
        mesh.update()
        material = bpy.data.materials.new(NAME_PREFIX + obj.name)
        material.use_nodes = True
        material.use_backface_culling = True  # exported as doubleSided false: it shines one way
        bsdf = material.node_tree.nodes.get('Principled BSDF')
        bsdf.inputs['Base Color'].default_value = (0, 0, 0, 1)
        bsdf.inputs['Specular'].default_value = 0
        bsdf.inputs['Emission'].default_value = (*light.color, 1)
        bsdf.inputs['Emission Strength'].default_value = area_light_radiance(light.energy, area)
        mesh.materials.append(material)
        stand_in = bpy.data.objects.new(NAME_PREFIX + obj.name, mesh)
        stand_in.matrix_world = obj.matrix_world.copy()
        bpy.context.scene.collection.objects.link(stand_in)
        added.append(stand_in)
    return added, warnings


def remove_stand_ins(stand_ins):
    """Removes what area_light_stand_ins added, its meshes and materials with it."""
    for obj in stand_ins:
        mesh = obj.data
        materials = list(mesh.materials)
        bpy.data.objects.remove(obj, do_unlink=True)
        bpy.data.meshes.remove(mesh)
        for material in materials:
            if material is not None and material.users == 0:
                bpy.data.materials.remove(material)


def write_world_scene(folder, glb_name, radiance):
    """scene.json in folder: lambert's scene file holding the exported glb as its one mesh and the
    world as a uniform environment of radiance (r, g, b) W/(m²·sr) (docs/scene-format.md, a sky
    with "radiance"): from every direction, below the horizon too, as Cycles' world lights."""
    path = os.path.join(folder, 'scene.json')
    scene = {'version': 1, 'name': 'scene', 'unit': 'm', 'meshes': [{'path': glb_name}],
             'lights': [{'type': 'sky', 'name': 'world', 'radiance': [float(c) for c in radiance]}]}
    with open(path, 'w') as f:
        json.dump(scene, f, indent=1)
    return path


def world_radiance(world):
    """The world's uniform radiance (r, g, b): a Background node's Color × Strength, or the world's
    colour without nodes; and, where its light is not one colour, what it is instead (or None)."""
    if world is None:
        return (0.0, 0.0, 0.0), None
    if not world.use_nodes or world.node_tree is None:
        return tuple(world.color), None
    output = next((n for n in world.node_tree.nodes if n.type == 'OUTPUT_WORLD' and n.is_active_output), None)
    surface = output.inputs['Surface'] if output else None
    if surface is None or not surface.is_linked:
        return (0.0, 0.0, 0.0), None
    background = surface.links[0].from_node
    if background.type != 'BACKGROUND':
        return (0.0, 0.0, 0.0), f'its "{background.name}" node'
    color, strength = background.inputs['Color'], background.inputs['Strength']
    if color.is_linked or strength.is_linked:
        return (0.0, 0.0, 0.0), 'a textured Background'
    c = color.default_value
    return (c[0] * strength.default_value, c[1] * strength.default_value, c[2] * strength.default_value), None
