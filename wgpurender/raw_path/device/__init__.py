"""The Vulkan device layer: the context (instance), memory, images, pipelines, render passes, textures, readback."""
