"""Scene templates shipped with femslide (installed as the package ``femslide.meshes``).

Every built-in scene as a scene file ``NAME.toml`` (the FE statics scenes with their reference mesh
``NAME.vtu``) and the FE statics scenes declared as structure files ``structures/NAME.toml``.
``femslide init NAME [DIR]`` copies one out to edit; ``femslide.app.scenefile.templates()`` finds this
folder.  ``python meshes/make_scene_files.py`` (from a source checkout) regenerates the files.
"""
