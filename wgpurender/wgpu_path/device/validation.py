"""The wgpu path's validation messages, kept: one logging handler for the tests and for ``demo --validation``.

With $WGPURENDER_VALIDATION set, the Vulkan validation layer's messages (and wgpu's own validation
errors) arrive as records on the ``wgpu`` logger. :func:`collect_validation_messages` attaches a
handler that keeps them (they are still printed); the test fixture fails a test that triggered one,
and the demo reports how many it saw. The raw path has its own debug messenger (raw_path/device/validation.py).
"""

from __future__ import annotations

import logging

import wgpu  # noqa: F401  (imported first: wgpu installs its own logger class for the "wgpu" logger)


class ValidationMessages(logging.Handler):
    """Keeps the text of every validation record at WARNING or above."""

    def __init__(self) -> None:
        super().__init__(level=logging.WARNING)
        self.messages: list[str] = []

    def emit(self, record: logging.LogRecord) -> None:
        text = record.getMessage()
        if "VALIDATION" in text or "Validation Error" in text:
            self.messages.append(text)


def collect_validation_messages() -> ValidationMessages:
    """A :class:`ValidationMessages` handler attached to the ``wgpu`` logger."""
    handler = ValidationMessages()
    logging.getLogger("wgpu").addHandler(handler)
    return handler
