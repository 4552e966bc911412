"""The wgpu device layer: the context, its caches and validation, cffi access, shaders, textures, targets, timing."""
