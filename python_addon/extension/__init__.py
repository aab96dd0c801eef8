"""PointNPR as a Blender 4.2+ extension.

The add-on is the ``pointnpr`` package: Blender installs it from the wheel
in wheels/ (see blender_manifest.toml) into its extensions' site-packages,
and this module, ``bl_ext.<repository>.pointnpr``, forwards to it. The
legacy add-on zip for Blender 3.4-4.1 is that same package, unwrapped.
"""


def register():
    import pointnpr

    pointnpr.register()


def unregister():
    import pointnpr

    pointnpr.unregister()
