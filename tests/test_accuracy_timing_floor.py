"""``bench accuracy`` times at sizes where timings mean something, and says when one does not.

- The base size comes from the adapter type, in one place (core/plan/bench_size.py, through AdapterFacts): a
  software rasteriser keeps 160x120 for --quick, a hardware GPU gets a size whose 8x ground truth still fits
  WebGPU's default 8192 texture limit.
- The noise floor (bench/accuracy_floor.py): a time under twice an empty frame's reads "below timer
  resolution" in the tables.
"""

from __future__ import annotations

import pytest

from wgpurender.bench.accuracy_floor import BELOW, FLOOR_FACTOR, Floor
from wgpurender.bench.accuracy_knobs import GROUND_TRUTH_SS, SS_LEVELS
from wgpurender.core.plan import AdapterFacts
from wgpurender.core.plan.bench_size import accuracy_size


def test_software_adapter_keeps_small_sizes():
    assert AdapterFacts("CPU").accuracy_size("quick") == (160, 120)
    assert AdapterFacts("CPU").accuracy_size("full") == (400, 300)


@pytest.mark.parametrize("adapter_type", ["DiscreteGPU", "IntegratedGPU", "VirtualGPU"])
@pytest.mark.parametrize("preset", ["quick", "full"])
def test_a_gpu_times_at_least_36x_the_pixels_and_the_truth_fits_8192(adapter_type, preset):
    w, h = AdapterFacts(adapter_type).accuracy_size(preset)
    assert w * h >= 36 * 160 * 120  # 160x120 read 0.1 ms for every setting on an H100 (issue 33)
    assert max(w, h) * max(GROUND_TRUTH_SS, *SS_LEVELS) <= 8192  # WebGPU's default max-texture-dimension-2d
    assert w * 3 == h * 4  # the same 4:3 frame as lavapipe's sizes


def test_an_unknown_preset_is_refused():
    with pytest.raises(ValueError, match="choose one of"):
        accuracy_size("CPU", "medium")


def test_floor_labels_times_under_twice_the_empty_frame():
    f = Floor(gpu=0.05, wall=2.0)
    assert f.below(0.099, 50.0) and not f.below(0.1, 0.1)  # GPU time decides where it exists
    no_gpu = Floor(gpu=None, wall=2.0)
    assert no_gpu.below(None, 3.99) and not no_gpu.below(None, 4.0)
    assert no_gpu.below(1.0, 3.0)  # the floor has no GPU time: the wall time decides
    assert FLOOR_FACTOR == 2.0 and BELOW in f.describe() and "0.050 ms" in f.describe()


def test_report_prints_below_timer_resolution_instead_of_the_number():
    from wgpurender.bench.accuracy_report import _ms
    from wgpurender.wgpu_path.device.timing import Stats

    stats = Stats.of([0.1, 0.1, 0.1])
    assert _ms(stats, below=True) == BELOW
    assert _ms(stats) == "0.1 (0.1..0.1)"


def test_the_empty_frame_is_timed_on_the_gpu_and_the_wall():
    """lavapipe: the empty 8x8 frame's GPU time is a tenth of a ms or less, its wall time a few ms."""
    from wgpurender.bench.accuracy_run import noise_floor
    from wgpurender.wgpu_path.device.context import get_context

    floor = noise_floor(get_context(), 3)
    assert floor.wall > 0.0
    if floor.gpu is not None:
        assert 0.0 < floor.gpu < floor.wall
