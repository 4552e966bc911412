"""``python -m wgpurender.core.plan SCENE.toml``: print the scene's plan."""

import sys

from wgpurender.core.plan.resolve import main

sys.exit(main())
