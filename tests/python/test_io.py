"""Mesh, .sel and .def files through the module: round trips and the files' own contents."""

import numpy as np
import pytest

import msdeform
from conftest import read_off_exact


def test_read_mesh_gives_the_files_vertices_and_faces(meshes):
    V, F = msdeform.read_mesh(meshes / "cactus.off")
    # The OFF text parsed independently: the same doubles, the same faces.
    V_text, F_text = read_off_exact(meshes / "cactus.off")
    assert V.dtype == np.float64 and V.shape == (620, 3)
    assert F.dtype == np.int32 and F.shape == (1236, 3)
    assert np.array_equal(V, V_text)
    assert np.array_equal(F, F_text)


@pytest.mark.parametrize("extension", ["off", "obj", "ply"])
def test_mesh_round_trip_is_exact_for_float_coordinates(meshes, tmp_path, extension):
    V, F = msdeform.read_mesh(meshes / "cactus.off")
    path = tmp_path / f"copy.{extension}"
    msdeform.write_mesh(path, V, F)
    V2, F2 = msdeform.read_mesh(path)
    assert np.array_equal(V2, V)
    assert np.array_equal(F2, F)


def test_written_file_holds_the_doubles_and_reading_gives_them_back(tmp_path):
    rng = np.random.default_rng(3)
    V = rng.normal(size=(30, 3))
    F = np.array([[0, 1, 2], [2, 3, 4], [5, 6, 7]], dtype=np.int64)  # any integer dtype
    path = tmp_path / "random.off"
    msdeform.write_mesh(str(path), V, F)
    V_text, F_text = read_off_exact(path)
    assert np.array_equal(V_text, V)
    assert np.array_equal(F_text, F)
    V_read, _ = msdeform.read_mesh(path)
    assert np.array_equal(V_read, V)


# Values a detour through float, or a parser that is not correctly rounded, would change:
# decimals without a finite binary form, subnormals, the ends of the double range, values
# beyond the float range, a negative zero.
AWKWARD = [0.1, 1 / 3, -2 / 3, 1e-300, -1.2345678901234567e-300, 5e-324, 2.2250738585072014e-308,
           -2.2250738585072009e-308, 1e300, -1.7976931348623157e308, 3.4028235677973366e38, 1e39,
           -0.0, 0.0, 123456789.12345679, 1.0000000000000002, np.pi, -9007199254740992.0,
           1.401298464324817e-45, 0.30000000000000004, 6.02214076e23, 22.0, 23.0, 24.0, 25.0, 26.0,
           27.0]


@pytest.mark.parametrize("extension", ["off", "obj", "ply"])
def test_write_then_read_is_the_identity_bit_for_bit(tmp_path, extension):
    V = np.array(AWKWARD, dtype=np.float64).reshape(9, 3)
    F = np.array([[0, k, k + 1] for k in range(1, 8)], dtype=np.int32)
    path = tmp_path / f"awkward.{extension}"
    msdeform.write_mesh(path, V, F)
    V2, F2 = msdeform.read_mesh(path)
    assert V2.view(np.uint64).tolist() == V.view(np.uint64).tolist()  # -0.0 is not 0.0 here
    assert np.array_equal(F2, F)


def test_read_mesh_reports_dropped_faces(tmp_path):
    path = tmp_path / "drops.off"
    path.write_text("OFF\n4 3 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 1 2\n3 0 0 3\n3 1 2 0\n")
    V, F, report = msdeform.read_mesh(path, with_report=True)
    assert F.tolist() == [[0, 1, 2]]
    assert report["dropped_degenerate_faces"] == 1
    assert report["dropped_duplicate_faces"] == 1
    assert report["notice"].startswith(str(path) + ": dropped")


def _sel_status_by_hand(path, num_vertices):
    """The .sel format read without msdeform: '#' comments, a count line, then one status per line."""
    lines = [line.split("#")[0].strip() for line in open(path)]
    values = [line for line in lines if line]
    statuses = [int(value) for value in values if value.lstrip("-").isdigit()]
    return np.array(statuses[-num_vertices:], dtype=np.int32)


def test_read_sel_is_the_per_vertex_status(meshes):
    status = msdeform.read_sel(meshes / "cactus.sel", 620)
    assert status.dtype == np.int32 and status.shape == (620,)
    assert np.array_equal(status, _sel_status_by_hand(meshes / "cactus.sel", 620))
    assert np.bincount(status).tolist() == [68, 465, 87]


def test_read_sel_without_a_count_takes_the_files(meshes, tmp_path):
    # The file has one status a vertex: no count needed; a count still checks the mesh's.
    status = msdeform.read_sel(meshes / "cactus.sel")
    assert np.array_equal(status, msdeform.read_sel(meshes / "cactus.sel", 620))
    assert np.array_equal(status, msdeform.read_sel(meshes / "cactus.sel", np.int64(620)))
    with pytest.raises(OSError, match=r"has 620 statuses but the mesh has 621 vertices"):
        msdeform.read_sel(meshes / "cactus.sel", 621)
    with pytest.raises(TypeError, match=r"^num_vertices: expected an integer \(the mesh's "
                                        r"vertex count\) or None, got '620'$"):
        msdeform.read_sel(meshes / "cactus.sel", "620")
    (tmp_path / "none.sel").write_text("0\n1\n")
    with pytest.raises(OSError, match=r"no handle vertex"):
        msdeform.read_sel(tmp_path / "none.sel")


def test_sel_round_trip(meshes, tmp_path):
    status = msdeform.read_sel(meshes / "cactus.sel", 620)
    msdeform.write_sel(tmp_path / "copy.sel", status)
    assert np.array_equal(msdeform.read_sel(tmp_path / "copy.sel", 620), status)


def test_read_def_is_the_files_matrix_and_round_trips_exactly(meshes, tmp_path):
    M = msdeform.read_def(meshes / "cactus.def")
    numbers = [float(x) for line in open(meshes / "cactus.def") for x in line.split("#")[0].split()]
    assert M.shape == (4, 4)
    assert np.array_equal(M.ravel(), np.array(numbers[-16:]))
    rotation = np.array([[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]])
    M2 = np.eye(4)
    M2[:3, :3] = rotation
    M2[:3, 3] = [0.1, 1e-17, np.pi]
    msdeform.write_def(tmp_path / "turn.def", M2)
    assert np.array_equal(msdeform.read_def(tmp_path / "turn.def"), M2)
    # 3x4 is accepted and means the same.
    msdeform.write_def(tmp_path / "turn34.def", M2[:3])
    assert np.array_equal(msdeform.read_def(tmp_path / "turn34.def"), M2)


def test_drag_path_ends_at_the_target_and_starts_one_step_from_identity():
    M = np.eye(4)
    M[:3, 3] = [3.0, 0.0, 0.0]
    path = msdeform.drag_path(M, [0.0, 0.0, 0.0], 3)
    assert path.shape == (3, 4, 4)
    assert np.allclose(path[0][:3, 3], [1.0, 0.0, 0.0], atol=1e-15)
    assert np.allclose(path[1][:3, 3], [2.0, 0.0, 0.0], atol=1e-15)
    assert np.array_equal(path[-1], M)


def test_drag_path_of_a_six_digit_rotation_is_rigid_at_every_frame():
    # data/meshes/cactus.def's matrix: a rotation printed with six digits.
    M = np.array([[0.999641, 0.021031, 0.016579, -0.019322],
                  [-0.022776, 0.342021, 0.939416, -0.134331],
                  [0.014087, -0.939457, 0.342378, 0.821073],
                  [0.0, 0.0, 0.0, 1.0]])
    path = msdeform.drag_path(M, [0.1, 0.2, 0.3], 30)
    for frame in path:
        A = frame[:3, :3]
        assert np.abs(A.T @ A - np.eye(3)).max() < 1e-5
        assert abs(np.linalg.det(A) - 1.0) < 1e-5
    assert np.array_equal(path[-1], M)


def test_bounding_box_diagonal():
    assert msdeform.bounding_box_diagonal([[0, 0, 0], [3, 4, 12]]) == 13.0
