from wgpurender.cli import main

raise SystemExit(main())
