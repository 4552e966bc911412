"""Course step 3b: 4x MSAA: a 4-sample colour attachment resolved into the output (pResolveAttachments).

Same render pass as the triangle with samples > 1 (renderpass.single_pass): the
multisampled attachment is TRANSIENT (usage) and DONT_CARE on store; the resolve
(average of the 4 samples) is written at the end of the subpass.
"""

from __future__ import annotations

from .triangle import Triangle


class Msaa(Triangle):
    name = "msaa"
    summary = "the triangle with 4x MSAA, resolved into a single-sample image"
    order = 3.1
    default_msaa = 4
