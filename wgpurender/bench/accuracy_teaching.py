"""What each accuracy measurement teaches, in words: the one home of the explanations that the report page
(wgpurender/report/teaching.py) and docs/accuracy.md both print (tests/test_accuracy_doc_figures.py checks the
doc carries them word for word).
"""

from __future__ import annotations

STILL_FRAME = (
    "Why the final-scene sweep shows MSAA 1 about equal to MSAA 4, and nearest sampling beating trilinear: a still "
    "frame against a supersampled truth scores how close one image is, nothing more. The final scene has few "
    "geometric edges (a few silhouettes over large textured, lit surfaces), and MSAA adds samples only where an "
    "edge crosses a pixel, so it changes few pixels and its error barely moves; on the notebook's triangle "
    "(examples/course_tour.ipynb, section 4), which is nearly all edge, MSAA 4x clearly lowers the error. The "
    "final scene's bricks are only mildly minified: nearest sampling keeps their contrast and errs in scattered "
    "single pixels, while trilinear filtering blurs a little everywhere, which one frame charges more. What mip-maps "
    "and MSAA are for is temporal: under slow motion point samples jump from texel to texel (shimmer) and stair-"
    "stepped edges crawl. The shimmer measure shows it: on a plane minified to the horizon trilinear's "
    "frame-to-frame error is a fraction of nearest's and bilinear's, and MSAA 4x crawls less than no anti-aliasing."
)

SHIMMER = (
    "Shimmer: the camera moves by a fraction of a pixel per frame; shimmer is the mean difference between the "
    "renderer's frame-to-frame change and the exact truth's own change (linear light). A still frame cannot see it."
)

HDR = (
    "HDR target: a plane lit by a bright light (radiance up to about 3) is tone-mapped with Reinhard's curve "
    "c / (1 + c). An 8-bit scene image clips at 1 before the curve, so the whole hot spot comes out flat at 0.5; "
    "a float scene image (rgba16float or rgba32float) keeps the gradient. On a dim scene (shading precision) the "
    "formats are within a step of each other."
)

TEXTS = {"still frame": STILL_FRAME, "shimmer": SHIMMER, "HDR target": HDR}
