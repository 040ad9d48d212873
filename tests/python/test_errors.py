"""Bad input raises a Python exception carrying the C++ message; nothing crashes.

The files are the command line's bad-input corpus (tests/data/bad/MANIFEST.tsv): each entry
that names a mesh, .sel, .def or scenario file and an error must raise that same error here.
"""

import os
import pathlib

import numpy as np
import pytest

import msdeform

BAD = pathlib.Path(os.environ.get("MSDEFORM_SOURCE_DIR", ".")) / "tests" / "data" / "bad"


def corpus():
    """(name, expected substring, kind) of every failing corpus entry of one file."""
    entries = []
    for line in open(BAD / "MANIFEST.tsv"):
        if line.startswith("#") or not line.strip():
            continue
        name, _, expected, arguments = line.rstrip("\n").split("\t")
        if expected == "-":
            continue
        for kind in ("mesh", "sel", "def", "scenario"):
            if f"--{kind}=@BAD@/{name}" in arguments.split():
                entries.append(pytest.param(name, expected, kind, id=name))
    return entries


@pytest.fixture(scope="module")
def bar():
    V, F = msdeform.read_mesh(BAD / "bar.off")
    return V, F


def test_the_corpus_is_there():
    assert len(corpus()) > 50


@pytest.mark.parametrize("name,expected,kind", corpus())
def test_corpus_entry_raises_the_command_lines_message(name, expected, kind, bar):
    path = BAD / name
    if kind == "mesh":
        with pytest.raises(OSError, match=None) as raised:
            msdeform.read_mesh(path)
    elif kind == "sel":
        with pytest.raises(OSError) as raised:
            msdeform.read_sel(path, len(bar[0]))
    elif kind == "def":
        if "the solve failed" in expected:  # a valid file whose drag cannot be solved
            d = msdeform.Method(*bar)
            d.set_handles(BAD / "bar.sel")
            with pytest.raises(RuntimeError) as raised:
                d.drag(msdeform.read_def(path))
            expected = "the solve failed"
        else:
            with pytest.raises(OSError) as raised:
                msdeform.read_def(path)
    else:
        with pytest.raises(OSError) as raised:
            msdeform.load_scenario(path)
    assert expected in str(raised.value)


def test_arrays_of_the_wrong_shape_or_type(bar):
    V, F = bar
    with pytest.raises(ValueError, match=r"F: expected an array of shape \(m, 3\), got shape \(144, 2\)"):
        msdeform.Method(V, F[:, :2])
    with pytest.raises(TypeError, match="V: expected an array of real numbers, got dtype"):
        msdeform.Method(V.astype(str), F)
    with pytest.raises(TypeError, match="F: expected an array of integers"):
        msdeform.Method(V, F.astype(np.float64))
    out_of_range = F.copy()
    out_of_range[3, 1] = len(V)
    with pytest.raises(ValueError, match="face 3"):
        msdeform.Method(V, out_of_range)
    with pytest.raises(ValueError, match="vertex 0 has a non-finite coordinate"):
        msdeform.write_mesh("never_written.off", np.full_like(V, np.nan), F)
    assert not os.path.exists("never_written.off")


def test_bad_options():
    V, F = msdeform.read_mesh(BAD / "bar.off")
    with pytest.raises(TypeError, match="w_cn"):
        msdeform.Method(V, F, w_cn=3.0)
    with pytest.raises(ValueError, match=r"^w_con=-1: expected a finite weight > 0 \(at 0 the handle would not follow"):
        msdeform.Method(V, F, w_con=-1.0)
    with pytest.raises(ValueError, match="method"):
        msdeform.Method(V, F, method="multi")
    with pytest.raises(ValueError, match=r"unknown flag --w_cn \(did you mean --w_con\?\)"):
        msdeform.options_from_flags({"w_cn": 1})
    # At w_con = 0 the handle stayed where it was and the drag reported success.
    with pytest.raises(ValueError, match=r"^w_con=0: expected a finite weight > 0 \(at 0 the handle would not follow"):
        msdeform.Method(V, F, w_con=0.0)


def test_limits_that_crashed():
    """Each of these crashed the process (libgomp, the thread pool, the harmonic factorisation)
    or ran out of memory; now each raises ValueError naming the limit."""
    V, F = msdeform.read_mesh(BAD / "bar.off")
    with pytest.raises(ValueError, match=r"^graph\.num_threads=100000: expected an integer in "
                                         r"0\.\.1024 \(0: OpenMP default\)$"):
        msdeform.Method(V, F, graph={"num_threads": 100000})
    # The keyword sets graph.num_threads too, which is checked first.
    with pytest.raises(ValueError, match=r"^graph\.num_threads=100000: expected an integer in 0\.\.1024"):
        msdeform.Method(V, F, num_threads=100000)
    with pytest.raises(ValueError, match=r"^rigidity\.region_half_width=2147483647: expected an integer in 1\.\.8"):
        msdeform.Method(V, F, rigidity={"region_half_width": 2147483647})
    # bar.off is 4 x 1 x 1: 500 cells per diagonal is about 6.5M particles.
    with pytest.raises(ValueError, match=r"the lattice has \d+ particles, more than 500000; use a "
                                         r"larger cell width"):
        msdeform.Method(V, F, lattice={"cells_per_diagonal": 500})
    scenario = BAD / "slab_x.json"
    for frames in (-1, msdeform.MAX_SCENARIO_FRAMES + 1, 2**31 - 1):
        with pytest.raises(ValueError, match=r"frames: expected 0\.\.100000 \(0: the scenario's\)"):
            msdeform.load_scenario(scenario, frames=frames)
    assert len(msdeform.load_scenario(scenario, frames=3).path) == 3


def test_bad_handles_and_drags(bar):
    V, F = bar
    d = msdeform.Method(V, F)
    with pytest.raises(RuntimeError, match="set_handles"):
        d.drag(np.eye(4))
    with pytest.raises(ValueError, match="status"):
        d.set_handles(np.ones(len(V) - 1, dtype=np.int32))
    with pytest.raises(ValueError, match="no vertex|no handle"):
        d.set_handles(np.ones(len(V), dtype=np.int32))
    with pytest.raises(OSError, match="cannot open"):
        d.set_handles(BAD / "no_such.sel")
    d.set_handles(BAD / "bar.sel")
    not_affine = np.eye(4)
    not_affine[3, 0] = 1.0
    with pytest.raises(ValueError, match="M"):
        d.drag(not_affine)
    with pytest.raises(ValueError, match="M"):
        d.drag(np.eye(3))
    # The Method still works after every failure above.
    assert np.array_equal(d.drag(np.eye(4)).shape, V.shape)


def test_files_that_cannot_be_written(tmp_path, bar):
    V, F = bar
    with pytest.raises(OSError, match="cannot write format"):
        msdeform.write_mesh(tmp_path / "out.stl", V, F)
    with pytest.raises(OSError, match=str(tmp_path / "no" / "folder")):
        msdeform.write_mesh(tmp_path / "no" / "folder" / "out.off", V, F)
    with pytest.raises(TypeError, match="path"):
        msdeform.read_mesh(42)
    assert list(tmp_path.iterdir()) == []
