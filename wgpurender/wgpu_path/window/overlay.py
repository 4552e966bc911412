"""The demo window's settings overlay: the plan's knobs, turned live, beside what they cost.

Dear ImGui (imgui-bundle) drawn by wgpu-py's own backend (``wgpu.utils.imgui.ImguiWgpuBackend``), as
SaschaWillems' Vulkan samples draw their settings panel: a well-kept immediate-mode UI with a wgpu renderer
that wgpu-py ships and tests, so the overlay is one small module. It shows frame time, GPU time per pass
(timestamp queries) and the plan's texture memory, and one widget per knob of core/plan/live.py; a change is
handed to the window, which re-resolves the plan and rebuilds only when the plan changed.

The overlay is drawn after the frame was read back, in its own render pass that loads the frame: screenshots,
``--record`` and the tests' shots are the scene without the panel. Input: the window routes mouse events here
first; while the pointer is over the panel (``wants_mouse``) the orbit camera does not see them. ``rects``
keeps each widget's centre, so a test can click a knob where a user would (``--test-input`` ``click NAME``).
"""

from __future__ import annotations

from collections.abc import Callable

import wgpu

from wgpurender.core.plan.live import CHOICES, LiveKnobs

PANEL_POS = (8.0, 8.0)


def available() -> str:
    """"" when imgui-bundle imports, else the one line that says how to get it."""
    try:
        import imgui_bundle  # noqa: F401
    except ImportError:
        return "no settings overlay: imgui-bundle is not installed (pip install 'wgpurender[overlay]'; --no-overlay)"
    return ""


def _label(value) -> str:
    if value is None:
        return "scene's"
    if isinstance(value, bool):
        return "on" if value else "off"
    return str(value)


class Overlay:
    """One ImGui context and its wgpu renderer for one window; ``on_change(name, value)`` gets every knob turn."""

    def __init__(self, device: wgpu.GPUDevice, fmt: str, knobs: LiveKnobs, effect_names: list[str],
                 on_change: Callable[[str, object], None], scene: bool = True) -> None:
        """``scene``: the drawable is a scene (every knob); a stage has MSAA only."""
        from imgui_bundle import imgui
        from wgpu.utils.imgui import ImguiWgpuBackend

        self.imgui = imgui
        self.context = imgui.create_context()
        imgui.set_current_context(self.context)
        self.backend = ImguiWgpuBackend(device, fmt)
        self.device, self.knobs, self.effect_names, self.on_change = device, knobs, effect_names, on_change
        self.scene = scene
        self.stats: dict = {"frame_ms": 0.0, "gpu_ms": {}, "memory": "", "plan": ""}
        self.rects: dict[str, tuple[float, float]] = {}
        self.panel = (0.0, 0.0, 0.0, 0.0)  # x0, y0, x1, y1 of the panel as last drawn
        self.pointer = (-1.0, -1.0)
        self.held = False  # a button went down on the panel and is still down (a slider being dragged)

    # -- input ------------------------------------------------------------------------
    def mouse_pos(self, x: float, y: float) -> None:
        self.imgui.set_current_context(self.context)
        self.pointer = (float(x), float(y))
        self.backend.io.add_mouse_pos_event(float(x), float(y))

    def mouse_button(self, button: int, down: bool) -> None:
        self.imgui.set_current_context(self.context)
        self.held = down and self._over_panel()
        self.backend.io.add_mouse_button_event(button, down)

    def _over_panel(self) -> bool:
        x, y = self.pointer
        x0, y0, x1, y1 = self.panel
        return x0 <= x < x1 and y0 <= y < y1

    @property
    def wants_mouse(self) -> bool:
        """The pointer is over the panel (as last drawn), or a press that began on it is still held. Decided from
        the events themselves, not from ImGui's want_capture_mouse: that is updated only when the panel is drawn,
        so at a low frame rate a click on the panel, its release and a press on the scene can all arrive before
        the next frame, and the stale flag swallowed the press that starts the drag."""
        return self._over_panel() or self.held

    # -- drawing ----------------------------------------------------------------------
    def record(self, encoder: wgpu.GPUCommandEncoder, texture: wgpu.GPUTexture) -> None:
        imgui = self.imgui
        imgui.set_current_context(self.context)
        self.backend.io.display_size = (float(texture.size[0]), float(texture.size[1]))
        self.backend.io.display_framebuffer_scale = (1.0, 1.0)
        imgui.new_frame()
        try:
            self._panel()
        finally:
            imgui.render()
        render_pass = encoder.begin_render_pass(label="overlay", color_attachments=[
            {"view": texture.create_view(), "load_op": "load", "store_op": "store"}])
        self.backend.render(imgui.get_draw_data(), render_pass)
        render_pass.end()

    def _keep_rect(self, name: str) -> None:
        lo, hi = self.imgui.get_item_rect_min(), self.imgui.get_item_rect_max()
        self.rects[name] = ((lo.x + hi.x) / 2, (lo.y + hi.y) / 2)

    def _panel(self) -> None:
        imgui = self.imgui
        imgui.set_next_window_pos(imgui.ImVec2(*PANEL_POS), imgui.Cond_.always)
        imgui.set_next_window_bg_alpha(0.8)
        imgui.begin("settings", None, imgui.WindowFlags_.always_auto_resize | imgui.WindowFlags_.no_move)
        s = self.stats
        imgui.text(f"frame {s['frame_ms']:.2f} ms ({1e3 / max(s['frame_ms'], 1e-6):.0f} FPS)")
        for label, ms in s["gpu_ms"].items():
            imgui.text(f"  GPU {label}: {ms:.3f} ms")
        if s["memory"]:
            imgui.text(f"plan memory: {s['memory']}")
        imgui.separator()
        self._combo("msaa", "MSAA")
        if self.scene:
            self._combo("anisotropy", "anisotropy")
            for k, name in enumerate(self.effect_names):
                changed, on = imgui.checkbox(f"{name}##effect{k}", self.knobs.effects[k])
                self._keep_rect(f"effect:{k}")
                if changed:
                    self.on_change(f"effect:{k}", on)
            self._combo("post_fuse", "post fusion")
            self._combo("post_path", "post path")
            self._combo("depth_format", "depth")
            changed, on = imgui.checkbox("reverse-Z", self.knobs.reverse_z)
            self._keep_rect("reverse_z")
            if changed:
                self.on_change("reverse_z", on)
        if s["plan"]:
            imgui.text(s["plan"])
        pos, size = imgui.get_window_pos(), imgui.get_window_size()
        self.panel = (pos.x, pos.y, pos.x + size.x, pos.y + size.y)
        imgui.end()

    def _combo(self, name: str, label: str) -> None:
        """One radio button per choice (clickable in one go, unlike a combo box's popup)."""
        imgui = self.imgui
        imgui.text(label)
        current = getattr(self.knobs, name)
        for value in CHOICES[name]:
            imgui.same_line()
            if imgui.radio_button(f"{_label(value)}##{name}", current == value):
                if current != value:
                    self.on_change(name, value)
            self._keep_rect(f"{name}={_label(value)}")
