"""Subcommands of the CLI, one module each, found by wgpurender.cli."""
