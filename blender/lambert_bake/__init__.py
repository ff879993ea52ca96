# Lambert Bake: bakes the open scene's lighting with lambert (a radiosity engine) from Blender.
# The scene goes out through Blender's own glTF exporter, lambert runs as a separate process, and
# the result comes back into the .blend as a colour attribute or a lightmap (docs/blender.md).
bl_info = {
    'name': 'Lambert Bake',
    'author': 'lambert',
    'version': (0, 1, 0),
    'blender': (3, 4, 0),
    'location': 'Properties > Render > Lambert',
    'description': 'Bake the scene\'s diffuse lighting with the lambert radiosity engine '
                   '(vertex colours or lightmaps)',
    'category': 'Render',
}

import atexit
import os
import shutil
import tempfile
import time

import bpy

from . import lights, process, results


def _numpy_bool_for_the_exporter():
    # Debian 12's Blender 3.4.1 glTF add-on still uses numpy.bool, an alias numpy 1.24 removed
    # (it is the builtin bool): give it back, or the export fails before writing anything.
    try:
        import numpy
    except ImportError:
        return
    if 'bool' not in vars(numpy):  # (reading numpy.bool to test it warns)
        numpy.bool = bool


class LambertBakePreferences(bpy.types.AddonPreferences):
    bl_idname = __name__

    binary: bpy.props.StringProperty(
        name='lambert binary', subtype='FILE_PATH', default='',
        description='The lambert executable (build/bin/lambert); empty: $LAMBERT_BINARY, else lambert on PATH')
    keep_files_in: bpy.props.StringProperty(
        name='Keep files in', subtype='DIR_PATH', default='',
        description='A folder to keep each bake\'s files in (scene.glb as exported, lambert\'s output), '
                    'for inspection; empty: a temporary folder, removed after the bake')

    def draw(self, context):
        self.layout.prop(self, 'binary')
        self.layout.prop(self, 'keep_files_in')


class LambertBakeSettings(bpy.types.PropertyGroup):
    method: bpy.props.EnumProperty(
        name='Method', default='HIERARCHICAL',
        items=[('HIERARCHICAL', 'Hierarchical', 'Element trees refined where the light needs it (lambert\'s default)'),
               ('FLAT', 'Flat', 'A uniform mesh with a dense form-factor matrix (small scenes)')])
    quality: bpy.props.EnumProperty(
        name='Quality', default='MEDIUM',
        items=[('DRAFT', 'Draft', '--link-error 1e-3 (hierarchical) / --patches 400 (flat)'),
               ('MEDIUM', 'Medium', '--link-error 2e-4, lambert\'s default (hierarchical) / --patches 1600 (flat)'),
               ('HIGH', 'High', '--link-error 5e-5 (hierarchical) / --patches 6400 (flat)')])
    output: bpy.props.EnumProperty(
        name='Output', default='VERTEX_COLORS',
        items=[('VERTEX_COLORS', 'Vertex colours', 'A colour attribute "lambert" per face corner: outgoing radiance'),
               ('LIGHTMAPS', 'Lightmaps', 'A lightmap image on a second UV map, wired into the materials')])
    objects: bpy.props.EnumProperty(
        name='Objects', default='ALL',
        items=[('ALL', 'All', 'Every visible mesh object and light of the scene'),
               ('SELECTED', 'Selected', 'The selected objects only (select the lights too)')])
    apply_modifiers: bpy.props.BoolProperty(
        name='Apply modifiers', default=True,
        description='Apply the baked objects\' modifiers first (Ctrl+Z restores them), so that what they make '
                    '(an Array\'s copies, a Mirror\'s half) is lit and gets light of its own; off: the objects '
                    'go out as their own meshes, and what a modifier adds shares their colours')
    status: bpy.props.StringProperty(name='Status', default='', options={'SKIP_SAVE'})
    progress: bpy.props.FloatProperty(name='Progress', default=0.0, min=0.0, max=100.0, subtype='PERCENTAGE')



# The bake the panel runs (one at a time): not a scene property, so a .blend saved mid-bake does
# not open as still baking, and Blender quitting mid-bake stops lambert too.
_running_job = None


def _stop_running_job():
    if _running_job is not None:
        _running_job.cancel()


atexit.register(_stop_running_job)


def _preferences(context):
    addon = context.preferences.addons.get(__name__)
    return addon.preferences if addon else None


def _binary(context):
    preferences = _preferences(context)
    return process.find_binary(preferences.binary if preferences else '')


def _pool(context, settings):
    return context.selected_objects if settings.objects == 'SELECTED' else context.scene.objects


def _meshes(context, settings):
    return [o for o in _pool(context, settings) if o.type == 'MESH' and o.visible_get()]


def _apply_modifiers(context, objects):
    """Replaces each object's mesh by what its modifiers make of it, and drops the modifiers
    (the operator's undo step brings them back); returns how many objects had some."""
    depsgraph = context.evaluated_depsgraph_get()
    applied = 0
    for obj in objects:
        if not any(m.show_viewport for m in obj.modifiers):
            continue
        mesh = bpy.data.meshes.new_from_object(obj.evaluated_get(depsgraph), preserve_all_data_layers=True, depsgraph=depsgraph)
        obj.modifiers.clear()
        obj.data = mesh
        applied += 1
    return applied


class BakeJob:
    """One bake: export, run lambert, write back. The operator drives it modally (the UI stays
    live, Esc cancels) or synchronously (background mode, scripts)."""

    def __init__(self, context, settings):
        self.settings = settings
        self.objects = _meshes(context, settings)
        if not self.objects:
            raise ValueError('nothing to bake: no visible mesh object' +
                             (' is selected' if settings.objects == 'SELECTED' else ' in the scene'))
        binary = _binary(context)
        preferences = _preferences(context)
        self.keep = bool(preferences and preferences.keep_files_in)
        if self.keep:
            self.folder = bpy.path.abspath(preferences.keep_files_in)
            os.makedirs(self.folder, exist_ok=True)
        else:
            self.folder = tempfile.mkdtemp(prefix='lambert-bake-')
        self.scene_glb = os.path.join(self.folder, 'scene.glb')
        self.scene_path = self.scene_glb  # what lambert reads: the glb, or a scene file around it with the world
        self.warnings = []
        if settings.apply_modifiers and settings.output == 'LIGHTMAPS':
            # Each copy a modifier makes needs lightmap UVs of its own, made on the applied mesh below.
            self.apply_modifiers(context)
        # A previous lightmap bake's emission must not go out as the scene's own.
        results.remove_lightmap_nodes(self.objects)
        if settings.output == 'LIGHTMAPS':
            self.result_path = os.path.join(self.folder, 'baked.glb')
        else:
            self.result_path = os.path.join(self.folder, 'vertices.csv')
        if os.path.exists(self.result_path):  # a kept folder's previous result must not pass for this one
            os.remove(self.result_path)
        self.export(context, process.LIGHTMAP_SIZE[settings.quality] if settings.output == 'LIGHTMAPS' else None)
        self.started = time.monotonic()
        self.lambert = process.LambertProcess(process.solve_arguments(
            binary, self.scene_path, settings.method, settings.quality, settings.output, self.result_path))

    def apply_modifiers(self, context):
        applied = _apply_modifiers(context, self.objects)
        if applied:
            self.warnings.append(f'modifiers of {applied} objects applied (Ctrl+Z restores them)')

    def export(self, context, lightmap_size):
        """Exports the objects (and the stand-ins of what the exporter drops) to scene.glb; with
        lightmap_size, after packing their lightmap UVs at that atlas size."""
        _numpy_bool_for_the_exporter()
        selected = [o for o in context.view_layer.objects if o.select_get()]
        # Area lights go out as emissive faces (lambert_bake/lights.py), selected for the export.
        stand_ins, warnings = lights.area_light_stand_ins([o for o in _pool(context, self.settings) if o.visible_get()])
        self.warnings += warnings
        # A uniform world goes to lambert as a uniform environment (docs/blender.md, "Lights"); one
        # that is not one colour is named in the panel as not carried.
        radiance, warning = lights.world_radiance(context.scene.world)
        if warning:
            self.warnings.append(f'the world\'s light is not carried ({warning}): lambert takes a uniform Background colour only')
        elif max(radiance) > 0:
            self.scene_path = lights.write_world_scene(self.folder, os.path.basename(self.scene_glb), radiance)
            self.warnings.append(f'the world lights the scene as a uniform environment of {radiance[0]:.3g}, {radiance[1]:.3g}, '
                                 f'{radiance[2]:.3g} W/(m²·sr)')
        if lightmap_size is not None:
            # The area lights' faces are packed with the objects (they are small): lambert keeps the
            # given UVs only where every face has them.
            try:
                results.add_lightmap_uvs(context, self.objects + stand_ins, lightmap_size)
            except Exception:
                lights.remove_stand_ins(stand_ins)
                raise
        if self.settings.objects == 'ALL':
            # Export exactly the objects baked (and every light): the visible ones.
            for o in selected:
                o.select_set(False)
            for o in context.scene.objects:
                if (o in self.objects or o.type == 'LIGHT') and o.visible_get():
                    o.select_set(True)
        for o in stand_ins:
            o.select_set(True)
        try:
            result = bpy.ops.export_scene.gltf(
                filepath=self.scene_glb, export_format='GLB', use_selection=True, export_apply=self.settings.apply_modifiers,
                export_lights=True, export_cameras=True, export_yup=True, export_materials='EXPORT',
                export_texcoords=True, export_normals=True, export_colors=False, export_animations=False)
        finally:
            lights.remove_stand_ins(stand_ins)
            if self.settings.objects == 'ALL':
                for o in context.view_layer.objects:
                    o.select_set(o in selected)
        if 'FINISHED' not in result or not os.path.isfile(self.scene_glb):
            raise RuntimeError(f'Blender\'s glTF exporter did not write {self.scene_glb}')

    def poll(self):
        return self.lambert.poll()

    def cancel(self):
        self.lambert.cancel()
        self.cleanup(cancelled=True)

    def finish(self, context):
        """Writes the result into the .blend; raises with lambert's message when it failed."""
        status = self.lambert.poll()
        self.lambert.close()
        try:
            if status != 0:
                raise RuntimeError('lambert failed: ' + self.lambert.error_message())
            if self.settings.output == 'VERTEX_COLORS':
                if self.settings.apply_modifiers:
                    # The meshes as exported (export_apply), now that there is light to write on them.
                    self.apply_modifiers(context)
                corners, far = results.write_vertex_colors(self.objects, self.result_path)
                results.show_attribute_in_viewports(context)
                summary = f'{corners} corners of {len(self.objects)} objects coloured'
                if far:
                    summary += f' ({far} corners not on a lambert vertex took the nearest)'
            else:
                wired, image = results.wire_lightmaps(self.objects, self.result_path)
                summary = f'a {image.size[0]}² lightmap wired into {wired} materials'
            summary += f' (lambert {time.monotonic() - self.started:.1f} s)'
            return '; '.join([summary] + self.warnings)
        finally:
            self.cleanup()

    def cleanup(self, cancelled=False):
        if not self.keep:
            shutil.rmtree(self.folder, ignore_errors=True)
        elif cancelled and os.path.exists(self.result_path):  # a cancelled bake leaves no result
            os.remove(self.result_path)


class LAMBERT_OT_bake(bpy.types.Operator):
    """Bake the scene's lighting with lambert (Esc cancels)"""
    bl_idname = 'lambert.bake'
    bl_label = 'Bake with lambert'
    bl_options = {'REGISTER', 'UNDO'}

    _job = None
    _timer = None

    @classmethod
    def poll(cls, context):
        return context.scene is not None and context.mode == 'OBJECT'

    def execute(self, context):
        """Synchronous: waits for lambert (background mode, scripts)."""
        settings = context.scene.lambert_bake
        try:
            job = BakeJob(context, settings)
        except (OSError, ValueError, RuntimeError) as error:
            self.report({'ERROR'}, str(error))
            return {'CANCELLED'}
        job.lambert.wait()
        return self._finish(context, job)

    def invoke(self, context, event):
        global _running_job
        settings = context.scene.lambert_bake
        if _running_job is not None:
            self.report({'WARNING'}, 'a lambert bake is running already (Esc cancels it)')
            return {'CANCELLED'}
        try:
            self._job = BakeJob(context, settings)
        except (OSError, ValueError, RuntimeError) as error:
            self.report({'ERROR'}, str(error))
            return {'CANCELLED'}
        _running_job = self._job
        settings.progress, settings.status = 0.0, 'starting lambert'
        window_manager = context.window_manager
        self._timer = window_manager.event_timer_add(0.2, window=context.window)
        window_manager.progress_begin(0, 100)
        window_manager.modal_handler_add(self)
        return {'RUNNING_MODAL'}

    def modal(self, context, event):
        settings = context.scene.lambert_bake
        if event.type == 'ESC':
            self._job.cancel()
            self._end_modal(context)
            settings.status = 'cancelled: nothing written'
            self.report({'WARNING'}, 'lambert bake cancelled: nothing written')
            return {'CANCELLED'}
        if event.type != 'TIMER':
            return {'PASS_THROUGH'}
        status = self._job.poll()
        lambert = self._job.lambert
        settings.progress = 100 * lambert.progress_fraction
        settings.status = lambert.progress_label
        context.window_manager.progress_update(int(100 * lambert.progress_fraction))
        context.workspace.status_text_set(f'lambert: {settings.status} {settings.progress:.0f}% (Esc cancels)')
        for area in context.screen.areas:
            if area.type == 'PROPERTIES':
                area.tag_redraw()
        if status is None:
            return {'RUNNING_MODAL'}
        self._end_modal(context)
        return self._finish(context, self._job)

    def cancel(self, context):
        """Blender ends the modal operator itself (a file loaded, the window closed): stop lambert."""
        self._job.cancel()
        self._end_modal(context)

    def _end_modal(self, context):
        global _running_job
        _running_job = None
        context.window_manager.event_timer_remove(self._timer)
        context.window_manager.progress_end()
        context.workspace.status_text_set(None)

    def _finish(self, context, job):
        settings = context.scene.lambert_bake
        try:
            summary = job.finish(context)
        except (OSError, ValueError, RuntimeError) as error:
            settings.status = 'failed'
            self.report({'ERROR'}, str(error))
            return {'CANCELLED'}
        settings.status, settings.progress = 'done: ' + summary, 100.0
        self.report({'WARNING'} if job.warnings else {'INFO'}, 'lambert: ' + summary)
        return {'FINISHED'}


class RENDER_PT_lambert(bpy.types.Panel):
    bl_label = 'Lambert'
    bl_idname = 'RENDER_PT_lambert'
    bl_space_type = 'PROPERTIES'
    bl_region_type = 'WINDOW'
    bl_context = 'render'

    def draw(self, context):
        layout = self.layout
        settings = context.scene.lambert_bake
        layout.use_property_split = True
        layout.prop(settings, 'method')
        layout.prop(settings, 'quality')
        layout.prop(settings, 'output', expand=True)
        layout.prop(settings, 'objects', expand=True)
        layout.prop(settings, 'apply_modifiers')
        if _running_job is not None:
            layout.prop(settings, 'progress', text=settings.status or 'running', slider=True)
            layout.label(text='Esc cancels', icon='CANCEL')
        else:
            layout.operator(LAMBERT_OT_bake.bl_idname, icon='LIGHT_AREA')
            if settings.status:
                layout.label(text=settings.status)


_classes = (LambertBakePreferences, LambertBakeSettings, LAMBERT_OT_bake, RENDER_PT_lambert)


def register():
    for cls in _classes:
        bpy.utils.register_class(cls)
    bpy.types.Scene.lambert_bake = bpy.props.PointerProperty(type=LambertBakeSettings)


def unregister():
    del bpy.types.Scene.lambert_bake
    for cls in reversed(_classes):
        bpy.utils.unregister_class(cls)
