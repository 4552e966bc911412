"""Write the scene file that frames one sample as run.py frames every held-out sample (square, msaa 4, its lights).

    PYTHONPATH=. python docs/runs/2026-11-27-heldout-khronos/specgloss-after/frame.py MODEL.gltf OUT.toml
"""

import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))
import run  # noqa: E402  (the run's own framing and lights)
from gltf_view import frame, mesh_boxes  # noqa: E402

model = Path(sys.argv[1])
Path(sys.argv[2]).write_text(run.scene_toml(str(model), frame(mesh_boxes(model), (0, 0, 1), zoom=1.0)))
