"""Course step 3b: 4x MSAA into a multisampled image, resolved into a single-sample one.

The Vulkan version is a render pass with a 4-sample colour attachment and a
resolve attachment (pResolveAttachments). In wgpu the pass's colour attachment
is the multisampled view and ``resolve_target`` the single-sample output; the
resolve (average of the samples) happens at the end of the pass.
"""

from __future__ import annotations

from .triangle import Triangle


class Msaa(Triangle):
    name = "msaa"
    summary = "the triangle with 4x MSAA, resolved into a single-sample image"
    course_step = "3b: 4x MSAA with a resolve attachment"
    order = 3.1
    default_msaa = 4
