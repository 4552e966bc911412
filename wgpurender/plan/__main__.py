"""``python -m wgpurender.plan SCENE.toml``: print the scene's plan."""

import sys

from .build import main

sys.exit(main())
