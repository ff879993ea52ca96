# The panel's modal bake, in a real Blender window (Xvfb), cancelled with Esc: lambert's process is
# gone and nothing is written (no lightmap image, no result file). The test's scene and add-on set-up
# are tests/blender_bake_test.py's.
# Usage: xvfb-run -a -s "-screen 0 1280x800x24" blender --factory-startup --enable-event-simulate
#          EMPTY.blend --python tests/blender_cancel_ui_test.py -- LAMBERT SCRATCH
# (a file to open keeps the splash screen away; blender -b --factory-startup --python-expr
# "import bpy; bpy.ops.wm.save_as_mainfile(filepath='EMPTY.blend')" writes one.)
# Prints "blender-cancel-ui: ok" and exits 0, or "blender-cancel-ui: FAIL …" and exits 1.
import os
import sys
import traceback

__file__ = os.path.join(os.path.dirname(os.path.abspath(__file__)), 'blender_bake_test.py')
_source = open(__file__).read()
exec(compile(_source[:_source.index('# 1. Bake')], __file__, 'exec'))  # scene, add-on, configure()

import bpy  # noqa: E402

build_scene()
keep = os.path.join(scratch, 'cancel-ui')
settings = configure(keep)
settings.output, settings.quality = 'LIGHTMAPS', 'HIGH'  # a minute's bake: Esc comes long before its end
step = [0]
state = {}


def finish(code):
    print('blender-cancel-ui: ' + ('ok: ' if code == 0 else 'FAIL: ') + state.get('summary', '; '.join(failures)))
    sys.stdout.flush()
    os._exit(code)  # quit at once, with the code (wm.quit_blender exits 0)


def tick():
    try:
        window = bpy.context.window_manager.windows[0]
        view = next(a for a in window.screen.areas if a.type == 'VIEW_3D')
        region = next(r for r in view.regions if r.type == 'WINDOW')
        s = step[0]
        step[0] += 1
        if s == 0:
            with bpy.context.temp_override(window=window, area=view, region=region):
                result = bpy.ops.lambert.bake('INVOKE_DEFAULT')
            check(result == {'RUNNING_MODAL'}, f'the panel\'s bake did not start modally: {result}')
            state['pid'] = lambert_bake._running_job.lambert.process.pid
            return 3.0
        if s == 1:
            check(lambert_bake._running_job is not None and lambert_bake._running_job.poll() is None,
                  'lambert ended before Esc')
            state['progress'] = settings.status, settings.progress
            window.event_simulate(type='MOUSEMOVE', value='NOTHING', x=500, y=400)
            window.event_simulate(type='ESC', value='PRESS')
            return 1.0
        check(lambert_bake._running_job is None, 'the bake still runs after Esc')
        try:
            os.kill(state['pid'], 0)
            check(False, f'lambert (process {state["pid"]}) is still there after Esc')
        except ProcessLookupError:
            pass
        check(bpy.data.images.get('lambert lightmap') is None, 'a cancelled bake wrote a lightmap image')
        left = sorted(f for f in os.listdir(keep) if f not in ('scene.glb', 'scene.json'))  # the export (and the world around it)
        check(not left, f'a cancelled bake left {left}')
        state['summary'] = f'Esc at "{state["progress"][0]}" {state["progress"][1]:.0f}%: process gone, nothing written'
        finish(1 if failures else 0)
    except Exception:
        traceback.print_exc()
        failures.append('an exception')
        finish(1)


bpy.app.timers.register(tick, first_interval=1.0)
