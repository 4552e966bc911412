"""The API-free core: course data, scene model, plan, uniform layouts, image I/O, compare, tolerances.

No module here imports wgpu or vulkan (tests/test_layering.py checks it): both paths build on it.
"""
