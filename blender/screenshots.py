# The screenshots of docs/blender.md (docs/images/blender-*.png): the test's scene, baked from the
# panel as a user would (vertex colours, then lightmaps), under Xvfb.
# Usage: blender -b --factory-startup --python-expr "import bpy; bpy.ops.wm.save_as_mainfile(filepath='/tmp/empty.blend')"
#        LAMBERT_BINARY=build/bin/lambert xvfb-run -a -s "-screen 0 1280x800x24" \
#          blender --factory-startup /tmp/empty.blend --python blender/screenshots.py -- OUT_DIR
# (opening a file keeps the splash screen away.)
import sys, os, math
source_dir = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
OUT = os.path.abspath(sys.argv[sys.argv.index('--') + 1])
os.makedirs(OUT, exist_ok=True)
sys.argv = [sys.argv[0], '--', os.environ.get('LAMBERT_BINARY', os.path.join(source_dir, 'build/bin/lambert')),
            os.path.join(OUT, 'scratch')]
# The scene and set-up of tests/blender_bake_test.py (everything before its first check).
src = open(os.path.join(source_dir, 'tests/blender_bake_test.py')).read()
src = src[:src.index('# 1. Bake')]
__file__ = os.path.join(source_dir, 'tests/blender_bake_test.py')
exec(compile(src, __file__, 'exec'))
import bpy
from mathutils import Euler
build_scene()
cam_data = bpy.data.cameras.new('camera'); cam_data.lens = 16
cam = bpy.data.objects.new('camera', cam_data)
cam.location = (1.85, -1.85, 2.0); cam.rotation_euler = Euler((math.radians(68), 0, math.radians(45)))
bpy.context.scene.collection.objects.link(cam); bpy.context.scene.camera = cam
settings = configure('')
settings.quality = 'MEDIUM'

def areas(kind):
    return [a for a in bpy.context.window.screen.areas if a.type == kind]

def setup():
    win = bpy.context.window
    bpy.context.scene.render.engine = 'BLENDER_EEVEE'
    bpy.context.scene.world.node_tree.nodes['Background'].inputs['Color'].default_value = (0, 0, 0, 1)
    for a in areas('VIEW_3D'):
        a.spaces[0].region_3d.view_perspective = 'CAMERA'
        a.spaces[0].shading.type = 'SOLID'
        a.spaces[0].shading.light = 'FLAT'
        a.spaces[0].overlay.show_overlays = False
    return 1.0

state = {}
step = [0]
def tick():
    win = bpy.context.window
    s = step[0]; step[0] += 1
    if s == 0:
        return setup()
    if s == 1:
        view = areas('VIEW_3D')[0]
        state['view'] = view
        region = [r for r in view.regions if r.type == 'WINDOW'][0]
        with bpy.context.temp_override(window=win, area=view, region=region):
            bpy.ops.view3d.view_center_camera()
            print('invoke', bpy.ops.lambert.bake('INVOKE_DEFAULT'))
        return 3.0
    if s == 2:
        with bpy.context.temp_override(window=win):
            bpy.ops.screen.screenshot(filepath=OUT + '/blender-baked-vertex.png')
        view = state['view']
        view.type = 'PROPERTIES'
        return 0.5
    if s == 3:
        view = state['view']
        view.spaces[0].context = 'RENDER'
        region = [r for r in view.regions if r.type == 'WINDOW'][0]
        settings.output = 'LIGHTMAPS'
        settings.quality = 'MEDIUM'
        with bpy.context.temp_override(window=win, area=view, region=region):
            print('invoke', bpy.ops.lambert.bake('INVOKE_DEFAULT'))
        return 1.0
    if s == 4:
        view = state['view']
        region = [r for r in view.regions if r.type == 'WINDOW'][0]
        with bpy.context.temp_override(window=win, area=view, region=region):
            for _ in range(10):
                bpy.ops.view2d.scroll_down(deltay=100, page=True)
        return 3.0
    if s == 5:
        view = state['view']
        with bpy.context.temp_override(window=win, area=view):
            bpy.ops.screen.screenshot_area(filepath=OUT + '/blender-panel.png')
        return 1.0
    if s == 6:
        if lambert_bake._running_job is not None:
            step[0] = 6
            return 1.0
        view = state['view']
        with bpy.context.temp_override(window=win, area=view):
            bpy.ops.screen.screenshot_area(filepath=OUT + '/blender-panel-done.png')
        view.type = 'VIEW_3D'
        sp = view.spaces[0]
        sp.region_3d.view_perspective = 'CAMERA'
        sp.shading.type = 'RENDERED'
        sp.overlay.show_overlays = False
        region = [r for r in view.regions if r.type == 'WINDOW'][0]
        with bpy.context.temp_override(window=win, area=view, region=region):
            bpy.ops.view3d.view_center_camera()
        return 5.0
    if s in (7, 8):  # EEVEE compiles its shaders first (tens of seconds under Xvfb's software GL)
        return 10.0
    if s == 9:
        with bpy.context.temp_override(window=win):
            bpy.ops.screen.screenshot(filepath=OUT + '/blender-baked.png')
        return 0.5
    bpy.ops.wm.quit_blender()
    return None

bpy.app.timers.register(tick, first_interval=2.0)
