"""msdeform.Method, the one class for every name in msdeform.METHODS: known answers on a
procedural bar, drag_along over a path, the statistics, the graph members, and the keyword
errors with the command line's "did you mean"."""

import re
import subprocess

import numpy as np
import pytest

import msdeform

LENGTH = 8


def bar(length=LENGTH, subdivisions=2):
    """A closed box [0, length] x [0, 1] x [0, 1] of `subdivisions` squares a unit, two
    outward triangles a square (the C++ tests' MakeBar in NumPy)."""
    n = np.array([length, 1, 1]) * subdivisions
    quads = []
    for axis in range(3):
        u, v = [a for a in range(3) if a != axis]
        for side in (0.0, 1.0):
            i, j = np.meshgrid(np.arange(n[u] + 1), np.arange(n[v] + 1), indexing="ij")
            grid = np.zeros(i.shape + (3,))
            grid[..., axis] = side * n[axis]
            grid[..., u], grid[..., v] = i, j
            corners = [grid[:-1, :-1], grid[1:, :-1], grid[1:, 1:], grid[:-1, 1:]]
            quads.append(np.stack(corners, axis=2).reshape(-1, 4, 3))
    quads = np.concatenate(quads)
    V, inverse = np.unique(quads.reshape(-1, 3), axis=0, return_inverse=True)
    quads = inverse.reshape(-1, 4)
    F = np.concatenate([quads[:, [0, 1, 2]], quads[:, [0, 2, 3]]])
    # Outward: the box is convex, so a face's normal points away from its centre.
    normal = np.cross(V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]])
    inward = (normal * (V[F].mean(axis=1) - n / 2)).sum(axis=1) < 0
    F[inward] = F[inward][:, ::-1]
    return V / subdivisions, F.astype(np.int32)


def both_ends_handle(V):
    """Both ends of the bar (x <= 1 and x >= LENGTH - 1) one moveable handle, the middle free."""
    status = np.ones(len(V), dtype=np.int32)
    status[(V[:, 0] <= 1.0) | (V[:, 0] >= LENGTH - 1.0)] = 2
    return status


def fixed_and_handle(V):
    """x <= 1 fixed, x >= LENGTH - 1 the moveable handle, the middle free."""
    status = both_ends_handle(V)
    status[V[:, 0] <= 1.0] = 0
    return status


def translation(t):
    M = np.eye(4)
    M[:3, 3] = t
    return M


T = translation([0.3, -1.2, 2.0])

# Every method holds the handle vertices exactly: CGAL's ARAP and SR-ARAP, FastLSM, rigid cells
# and the converged ARAP drive them; the graph methods hold them by position terms (w_con),
# which a translation of every handle meets with zero energy, so their solve lands on it to
# round-off. Measured on this bar: the graph methods, rigid cells and full ARAP 1e-14 or
# less, CGAL's two 5e-10 and 3e-10 (their iterations stop at a tolerance).
EXACT = 1e-9
# Shape matching with a few steps a frame: the free vertices follow the handle over frames
# (this bar: 1.7 after one frame, 8e-4 after 20, 4e-5 after 100).
LAGGING = {"fastlsm"}


def test_the_bar_is_a_closed_box():
    V, F = bar()
    assert len(V) == 17 * 3 * 3 - 15 * 1 * 1  # a 17 x 3 x 3 grid of points, hollow
    assert V.min(axis=0).tolist() == [0, 0, 0] and V.max(axis=0).tolist() == [LENGTH, 1, 1]
    # Closed and consistently oriented: every directed edge once, its reverse once.
    edges = np.concatenate([F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]])
    assert len(np.unique(edges, axis=0)) == len(edges)
    assert set(map(tuple, edges)) == set(map(tuple, edges[:, ::-1]))
    # Outward: the divergence theorem gives the box's volume.
    volume = np.einsum("ij,ij->i", V[F[:, 0]], np.cross(V[F[:, 1]], V[F[:, 2]])).sum() / 6
    assert volume == pytest.approx(LENGTH)


@pytest.mark.parametrize("method", msdeform.METHODS)
def test_every_method_translates_the_bar_with_its_handles(method):
    """Translating every handle moves the whole bar by the translation: at once when the whole
    mesh is the handle; with both ends the handle and the middle free, the handle at once and
    the middle at once too (or over frames for a method in LAGGING)."""
    V, F = bar()
    e = msdeform.Method(V, F, method)
    assert e.name == method and e.graph == (method in msdeform.GRAPH_METHODS)
    e.set_handles(np.full(len(V), 2))
    assert np.abs(e.drag(T) - (V + T[:3, 3])).max() < EXACT
    status = both_ends_handle(V)
    e.set_handles(status)
    V2 = e.drag(T)
    handle = status == 2
    assert np.abs(V2[handle] - (V[handle] + T[:3, 3])).max() < EXACT
    if method not in LAGGING:
        assert np.abs(V2 - (V + T[:3, 3])).max() < EXACT
        return
    errors = [np.abs(V2 - (V + T[:3, 3])).max()]
    for _ in range(19):
        errors.append(np.abs(e.drag(T) - (V + T[:3, 3])).max())
    assert all(later < earlier for earlier, later in zip(errors, errors[1:])), errors
    assert errors[-1] < 1e-3 * np.linalg.norm(T[:3, 3])


@pytest.mark.parametrize("method", msdeform.METHODS)
def test_drag_along_reaches_the_path_s_end(method):
    """drag_along(M, frames=3) drags through M's thirds and ends on M; the fixed end stays at
    rest and the handle on its target."""
    V, F = bar()
    e = msdeform.Method(V, F, method)
    status = fixed_and_handle(V)
    e.set_handles(status)
    path = e.drag_path(T, frames=3)
    expected = np.stack([translation(T[:3, 3] * k / 3) for k in (1, 2, 3)])
    assert np.abs(path - expected).max() < 1e-15
    V2 = e.drag_along(T, frames=3)
    assert len(e.frame_stats) == 3 and e.failed_frames == []
    fixed, handle = status == 0, status == 2
    held = 0.1 * np.linalg.norm(T[:3, 3])  # the static baselines hold ends by w_con
    exact = not e.graph or e.fixed_region_exact
    assert np.abs(V2[fixed] - V[fixed]).max() <= (0.0 if exact else held), method
    assert np.abs(V2[handle] - (V[handle] + T[:3, 3])).max() < (EXACT if not e.graph else held)
    # The middle moved, less than the handle.
    middle = np.abs(V[:, 0] - LENGTH / 2) < 0.01
    rise = (V2[middle] - V[middle]) @ T[:3, 3] / (T[:3, 3] @ T[:3, 3])
    assert (rise > 0).all() and (rise < 1).all(), method
    # The same path given as an array: the same vertices.
    again = msdeform.Method(V, F, method)
    again.set_handles(status)
    assert np.array_equal(again.drag_along(path), V2)


@pytest.mark.parametrize("method", msdeform.METHODS)
def test_statistics_are_per_frame_since_set_handles(method):
    V, F = bar()
    e = msdeform.Method(V, F, method)
    assert e.last_stats is None and e.frame_stats == [] and e.failed_frames == []
    e.set_handles(both_ends_handle(V))
    e.drag(T)
    e.drag_along(np.stack([T, T]))
    stats = e.frame_stats
    assert len(stats) == 3
    assert set(stats[0]) == {"frame_ms", "solve_ms", "skin_ms", "iterations", "factorizations",
                             "initial_cost", "final_cost", "converged", "trace"}
    assert e.last_stats["frame_ms"] == stats[-1]["frame_ms"]
    for frame in stats:
        assert frame["frame_ms"] >= frame["solve_ms"] >= 0
        assert frame["trace"].ndim == 2 and frame["trace"].shape[1] == 2
        assert isinstance(frame["converged"], bool)
    assert e.precompute_ms >= 0 and e.setup_ms >= 0 and e.rigidity_ms >= 0
    assert e.num_variables >= 0 and e.nodes_optimized >= 0
    e.set_handles(both_ends_handle(V))
    assert e.last_stats is None and e.frame_stats == []


@pytest.mark.parametrize("method", msdeform.METHODS)
def test_every_method_has_the_mesh_members(method):
    V, F = bar()
    e = msdeform.Method(V, F, method)
    assert np.array_equal(e.V, V) and np.array_equal(e.F, F)
    assert e.diagonal == pytest.approx(msdeform.bounding_box_diagonal(V), rel=1e-15)
    assert isinstance(e.options, msdeform.DeformerOptions)
    status = fixed_and_handle(V)
    e.set_handles(status)
    assert np.array_equal(e.status, status)
    assert np.allclose(e.handle_centroid, V[status == 2].mean(axis=0), rtol=0, atol=1e-15)
    rest_normals = e.deformed_normals.copy()
    assert np.allclose(np.linalg.norm(rest_normals, axis=1), 1.0, rtol=0, atol=1e-12)
    # The whole mesh translated: the normals do not change.
    e.set_handles(np.full(len(V), 2))
    e.drag(T)
    assert np.abs(e.deformed_normals - rest_normals).max() < 1e-9, method


GRAPH_MEMBERS = ["num_scales", "num_graphs", "relative_extent", "extent", "handle_extent",
                 "node_extent", "selection", "fixed_region_exact", "selected_scale",
                 "node_positions", "node_classes", "node_rotations", "node_translations",
                 "num_coherence_terms", "num_position_terms", "num_skinned_vertices"]


@pytest.mark.parametrize("method", msdeform.METHODS)
def test_graph_members_work_for_graph_methods_and_name_the_method_otherwise(method):
    V, F = bar()
    e = msdeform.Method(V, F, method)
    e.set_handles(fixed_and_handle(V))
    e.drag(T)
    graphs = ", ".join(msdeform.GRAPH_METHODS)
    for member in GRAPH_MEMBERS:
        if e.graph:
            getattr(e, member)
        else:
            message = f"{member}: {method} is not a deformation-graph method (those are {graphs})"
            with pytest.raises(AttributeError, match="^" + re.escape(message) + "$"):
                getattr(e, member)
            assert not hasattr(e, member)
    if e.graph:
        assert np.array_equal(e.graph_node_positions(e.selected_scale), e.node_positions)
    else:
        with pytest.raises(AttributeError, match=f"^graph_node_positions: {method} is not"):
            e.graph_node_positions(1)


def test_lattice_members_name_a_method_without_one():
    V, F = bar()
    for method in msdeform.METHODS:
        e = msdeform.Method(V, F, method)
        try:
            lattice = e.cell_width, e.num_surface_particles, e.particle_positions
        except AttributeError as error:
            assert str(error) == f"cell_width: {method} has no lattice"
            continue
        assert lattice[0] > 0 and len(lattice[2]) >= lattice[1] > 0
    with pytest.raises(AttributeError, match=r"^particle_positions: cgal_arap has no lattice$"):
        msdeform.Method(V, F, "cgal_arap").particle_positions


def test_the_name_defaults_to_the_options_method():
    V, F = bar()
    assert msdeform.Method(V, F).name == "multiscale"
    assert msdeform.Method(V, F, options={"method": "static"}).name == "static"
    assert msdeform.Method(V, F, options=msdeform.DeformerOptions(method="static_dense")).name \
        == "static_dense"
    # A name given wins; a graph method's options then carry it.
    e = msdeform.Method(V, F, "static", options={"method": "multiscale"})
    assert e.name == "static" and e.options.method == "static"
    with pytest.raises(TypeError, match=r"^method: expected a name in msdeform.METHODS \(a str\) "
                                        r"or None, got 3$"):
        msdeform.Method(V, F, 3)


def test_deformer_is_gone_with_a_pointer():
    with pytest.raises(AttributeError, match=r"^msdeform.Deformer is msdeform.Method now"):
        msdeform.Deformer
    with pytest.raises(AttributeError, match=r"^module 'msdeform' has no attribute 'Deformr'$"):
        msdeform.Deformr


@pytest.mark.parametrize("method", ["multiscale", "fastlsm"])
def test_deform_is_the_one_off_form(method):
    V, F = bar()
    status = fixed_and_handle(V)
    own = {"fastlsm_steps": 3} if method == "fastlsm" else {}
    e = msdeform.Method(V, F, method, **own)
    e.set_handles(status)
    expected = e.drag_along(T, frames=2)
    V2 = msdeform.deform(V, F, status, T, frames=2, method=method, **own)
    assert np.array_equal(V2, expected) and V2.flags.writeable


UNKNOWN_TAIL = ("; the options are the fields of msdeform.DeformerOptions and the methods' own "
                "keywords (help(msdeform.Method) lists them)")


@pytest.mark.parametrize("typo,nearest", [("w_cn", "w_con"), ("fastlsm_stepz", "fastlsm_steps"),
                                          ("cgal_iteration", "cgal_iterations"),
                                          ("max_iteration", "max_iterations")])
def test_an_unknown_keyword_names_the_nearest_as_the_command_line_does(cli, typo, nearest):
    V, F = bar()
    message = f"unknown option '{typo}' (did you mean '{nearest}'?)" + UNKNOWN_TAIL
    for method in ("multiscale", "fastlsm"):
        with pytest.raises(TypeError, match="^" + re.escape(message) + "$"):
            msdeform.Method(V, F, method, **{typo: 1})
    scenario = msdeform.Scenario(V, F, fixed_and_handle(V), T)
    with pytest.raises(TypeError, match="^" + re.escape(message) + "$"):
        msdeform.run_method(scenario, "fastlsm", **{typo: 1})
    # The command line offers the same flag for the same typo.
    result = subprocess.run([str(cli), f"--{typo}=1"], capture_output=True, text=True)
    assert result.returncode != 0
    assert f"unknown flag --{typo} (did you mean --{nearest}?)" in result.stderr


def test_a_keyword_far_from_every_option_offers_none():
    V, F = bar()
    with pytest.raises(TypeError, match="^" + re.escape("unknown option 'zzzzzzzz'" + UNKNOWN_TAIL)
                       + "$"):
        msdeform.Method(V, F, zzzzzzzz=1)


def test_a_nested_options_keyword_names_the_nearest_field():
    V, F = bar()
    with pytest.raises(TypeError, match=r"unknown option 'max_iteration' \(did you mean "
                                        r"'max_iterations'\?\)"):
        msdeform.Method(V, F, stopping={"max_iteration": 5})
    with pytest.raises(TypeError, match=r"^DeformerOptions: unknown option 'w_cn' \(did you mean "
                                        r"'w_con'\?\)"):
        msdeform.Method(V, F, options={"w_cn": 1.0})


@pytest.mark.parametrize("method,keyword,value,flag,readers", [
    ("cgal_arap", "w_con", 5, "--w_con=5", "multiscale, static, static_dense"),
    ("cgal_arap", "backend", "ceres", "--backend=ceres", "multiscale, static, static_dense"),
    ("cgal_arap", "solver", "ceres", "--solver=ceres", "multiscale, static, static_dense"),
    ("cgal_arap", "fastlsm_steps", 4, "--fastlsm_steps=4", "fastlsm"),
    ("multiscale", "cgal_iterations", 5, "--cgal_iterations=5", "cgal_arap, cgal_sr_arap"),
    ("fastlsm", "num_threads", 2, "--num_threads=2",
     "multiscale, static, static_dense, rigid_cells, full_arap"),
])
def test_an_option_the_method_does_not_read_is_refused_as_on_the_command_line(
        cli, tmp_path, method, keyword, value, flag, readers):
    V, F = bar()
    name = flag[2:].split("=")[0]
    message = f"{keyword}: not an option of the {method} method (an option of {readers})"
    with pytest.raises(TypeError, match="^" + re.escape(message) + "$"):
        msdeform.Method(V, F, method, **{keyword: value})
    if keyword in msdeform.DeformerOptions.fields or keyword in msdeform.DeformerOptions.aliases:
        # A dict `options` holds DeformerOptions fields (the methods' own are keywords).
        with pytest.raises(TypeError, match="^" + re.escape(message) + "$"):
            msdeform.Method(V, F, method, options={keyword: value})
    # The command line: the same words, the flag as typed, no output.
    result = subprocess.run([str(cli), f"--method={method}", flag, "--quiet"],
                            capture_output=True, text=True, cwd=tmp_path)
    assert result.returncode == 1
    assert result.stderr == (f"msdeform: {flag}: not an option of the {method} method "
                             f"(an option of {readers})\n"), name
    assert not (tmp_path / "msdeform_out").exists()


def test_options_the_method_reads_are_taken():
    V, F = bar()
    msdeform.Method(V, F, "cgal_arap", cgal_iterations=5)
    msdeform.Method(V, F, "fastlsm", cell_width=0.5, fastlsm_steps=3)
    msdeform.Method(V, F, "full_arap", num_threads=2)
    msdeform.Method(V, F, "rigid_cells", cell_width=0.5)
    msdeform.Method(V, F, "multiscale", w_con=5, solver="ceres")
    # A DeformerOptions object sets every field, none by name: not refused.
    msdeform.Method(V, F, "cgal_arap", options=msdeform.DeformerOptions(w_con=5))
    # The constructor's help lists what each method reads, from the registry.
    doc = msdeform.Method.__init__.__doc__
    assert "cgal_arap: none;" in doc and "fastlsm: lattice;" in doc
    assert "full_arap: num_threads;" in doc
