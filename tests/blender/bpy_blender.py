"""The part of Blender's command line the tests use, for bpy (Blender as a
Python module, which has no executable to start):

    python bpy_blender.py [file.blend] [-b] [--factory-startup] [--python-exit-code N]
        [--python script.py] [-o pattern] [-F FORMAT] [-f N | -a] [-- args...]

Arguments are processed in order, as Blender does. The extension installed
in BLENDER_USER_RESOURCES (tests/blender/run.py) is enabled first, as the
saved preferences would in a Blender started by a user
(POINTNPR_TESTED_PACKAGE=extension).
"""
import os
import runpy
import sys

args = sys.argv[1:]
if "--" in args:
    args, sys.argv = args[:args.index("--")], [sys.argv[0], "--"] + args[args.index("--") + 1:]
else:
    sys.argv = [sys.argv[0]]

import bpy  # noqa: E402  (first: it puts Blender's scripts on sys.path)
import addon_utils  # noqa: E402

# bpy starts with factory preferences (and its read_userpref crashes in
# 4.2), so the installed extension is enabled here, as saved preferences
# would in the Blender executable, before any file is opened.
if os.environ.get("POINTNPR_TESTED_PACKAGE") == "extension":
    if addon_utils.enable("bl_ext.user_default.pointnpr", default_set=False) is None:
        sys.exit("the installed extension did not enable")

exit_code = 0
pattern = None
i = 0
while i < len(args):
    arg = args[i]
    value = args[i + 1] if i + 1 < len(args) else None
    i += 1
    if arg in ("-b", "--background", "--factory-startup"):
        continue
    if arg == "--python-exit-code":
        exit_code, i = int(value), i + 1
    elif arg == "--python":
        i += 1
        try:
            runpy.run_path(value, run_name="__main__")
        except SystemExit as e:
            sys.stdout.flush()
            os._exit(e.code if isinstance(e.code, int) else 1)
        except BaseException:
            import traceback

            traceback.print_exc()
            sys.stdout.flush()
            os._exit(exit_code)
    elif arg == "-o":
        pattern, i = value, i + 1
    elif arg == "-F":
        bpy.context.scene.render.image_settings.file_format, i = value, i + 1
    elif arg == "-f":
        render = bpy.context.scene.render
        bpy.context.scene.frame_set(int(value))
        if pattern is not None:  # "#" -> the frame number, as Blender's -f does
            render.filepath = pattern
            render.filepath = render.frame_path(frame=int(value))
        bpy.ops.render.render(write_still=True)
        i += 1
    elif arg == "-a":
        if pattern is not None:
            bpy.context.scene.render.filepath = pattern
        bpy.ops.render.render(animation=True)
    elif arg.endswith(".blend"):
        bpy.ops.wm.open_mainfile(filepath=arg)
    else:
        sys.exit("bpy_blender.py: unsupported argument %r" % arg)
# bpy's own exit crashes or hangs once a Panel class was registered (see run.py).
sys.stdout.flush()
sys.stderr.flush()
os._exit(0)
