"""The learner's side of the course (docs/exercises.md): a step to write yourself, checked against the raw-Vulkan
reference with a diagnosis of the classic mistakes.

- catalogue.py: per step and path, the parts the learner writes and the mistakes, as snippets of the solution;
- source.py: the solution's source (the project's own stage or shader), the starter and the mistakes cut from it;
- starter.py: ``wgpurender exercise``'s folder (the starter, its test, a README, the goal image);
- render.py: a stage file (or step 6's shader) rendered the way its step is checked;
- sandbox.py: the learner's file rendered in a process of its own, with a time limit and their own traceback;
- check.py: ``wgpurender check``'s verdict, metrics, heatmaps and diagnosis;
- pytest_plugin.py: the ``pytest11`` plugin that grades a class of submissions.

A tool (outside the core and the paths): it imports both paths' registries and renderers.
"""
