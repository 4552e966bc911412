"""The API-free course core: the data every course step and the final scene share.

Plain numpy and dataclasses, no GPU API: geometry, cameras, lights, colours,
generated textures, sampler settings, shading constants, formats and sample
counts. Both rendering paths import it (``wgpurender/wgpu_path/stages/``,
``wgpurender/wgpu_path/scene/`` on wgpu; ``wgpurender/raw_path/`` on raw Vulkan)
and neither imports the other, so a "wgpu == raw Vulkan" comparison checks two
independent implementations of the same data. Tests take their expected values
from here (or from formulas), never from the module they check.

One module per course step or idea:

- :mod:`.formats`: output formats, MSAA sample counts, colour-space rules, scene-file detection;
- :mod:`.samplers`: the sampler description (filters, address modes, anisotropy);
- :mod:`.triangle`: the clear colour and the first triangle (steps 1-3);
- :mod:`.cubes`: the rotating cubes, their camera and light (step 4);
- :mod:`.textured`: the generated texture, the plane and its samplers (step 5);
- :mod:`.shading`: the final scene's shading constants and depth convention;
- :mod:`.effects`: the post effects as GPU-free specs (name, parameters with ranges, reach), the sRGB rule.

The layering rule this package anchors is written down in docs/architecture.md and
enforced by tests/test_layering.py.
"""
