"""Method.polish(): a few accelerated full_arap iterations from the current frame replace it as
the deformed vertices; the energy goes down to near the converged one, the handle and fixed
vertices stay exact, and the keywords have the house's errors."""

import numpy as np
import pytest

import msdeform
from test_method_class import bar, fixed_and_handle, LENGTH


def bend():
    """An eighth of a turn of the handle end about the z axis through the bar's end."""
    c, s = np.cos(np.pi / 4), np.sin(np.pi / 4)
    M = np.eye(4)
    M[:2, :2] = [[c, -s], [s, c]]
    M[:3, 3] = np.array([LENGTH, 0, 0]) - M[:3, :3] @ np.array([LENGTH, 0, 0])
    return M


def energy(V, F, V2):
    return msdeform.normalised_arap_energy(*msdeform.arap_energy_per_vertex(V, F, V2))


def test_polish_lowers_a_multiscale_bend_to_near_the_converged_energy():
    V, F = bar(subdivisions=4)
    status = fixed_and_handle(V)
    M = bend()
    reference = msdeform.Method(V, F, "full_arap")
    reference.set_handles(status)
    converged = energy(V, F, reference.drag_along(M, frames=3))

    e = msdeform.Method(V, F, "multiscale")
    e.set_handles(status)
    frame = e.drag_along(M, frames=3).copy()
    before = energy(V, F, frame)
    report = e.polish()
    assert set(report) == {"energy_before", "energy_start", "energy_after", "iterations",
                           "converged", "ms", "setup_ms"}
    assert report["energy_start"] >= report["energy_before"]  # the multi-scale handles are soft
    assert report["energy_before"] == pytest.approx(before, rel=1e-9)
    polished = e.deformed_vertices
    assert report["energy_after"] == pytest.approx(energy(V, F, polished), rel=1e-9)
    # (The frame's own energy may be below the converged one: its handle is soft.)
    assert converged * (1 - 1e-6) <= report["energy_after"] < 1.02 * converged
    assert report["energy_after"] < report["energy_start"]
    assert 0 < report["iterations"] <= 30 and report["setup_ms"] > 0
    # Exact constraints: the fixed end at rest, the handle at M applied to its rest positions.
    assert np.array_equal(polished[status == 0], V[status == 0])
    handle = V[status == 2] @ M[:3, :3].T + M[:3, 3]
    assert np.abs(polished[status == 2] - handle).max() < 1e-12
    # A second polish reuses the factorisation; with a zero budget it changes nothing.
    again = e.polish(max_iterations=0)
    assert again["iterations"] == 0 and again["setup_ms"] == 0
    assert again["energy_after"] == again["energy_before"] == report["energy_after"]
    # The next drag shows the method's own frame again (continued from its own state).
    dragged = e.drag(M)
    assert np.array_equal(e.deformed_vertices, dragged)
    assert not np.array_equal(dragged, polished)


def test_polish_keyword_errors():
    V, F = bar()
    e = msdeform.Method(V, F, "full_arap")
    with pytest.raises(RuntimeError, match="no handle layout"):
        e.polish()
    e.set_handles(fixed_and_handle(V))
    with pytest.raises(TypeError, match=r"unknown keyword 'max_iteration' \(did you mean "
                                        r"'max_iterations'\?\)"):
        e.polish(max_iteration=3)
    with pytest.raises(TypeError, match="max_iterations: expected an integer"):
        e.polish(max_iterations=2.5)
    with pytest.raises(ValueError, match="max_iterations: expected 0..1000000"):
        e.polish(max_iterations=-1)
    with pytest.raises(ValueError, match="time_budget_ms must be finite and >= 0"):
        e.polish(time_budget_ms=-1)
    with pytest.raises(ValueError, match=r"relative_tolerance must be in \[0, 1\]"):
        e.polish(relative_tolerance=2)
