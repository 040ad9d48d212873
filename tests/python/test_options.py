"""The options table from Python (scales/deformer_options.h): one vocabulary with the command
line, the table's rows, and the keyword classes derived from it."""

import pytest

import msdeform
from msdeform import _msdeform


def test_solver_and_backend_are_one_keyword(meshes):
    assert msdeform.DeformerOptions(solver="ceres").backend == "ceres"
    assert msdeform.DeformerOptions(backend="ceres") == msdeform.DeformerOptions(solver="ceres")
    V, F = msdeform.read_mesh(meshes / "cactus.off")
    assert msdeform.Method(V, F, solver="ceres").options.backend == "ceres"
    assert msdeform.options_from_flags({"backend": "ceres"}).backend == "ceres"
    assert msdeform.options_from_flags({"solver": "ceres"}).backend == "ceres"


def test_command_line_spellings_and_dotted_names_are_keywords():
    options = msdeform.DeformerOptions(cell_width=0.5, half_free="none", threads=3,
                                       **{"selection.member_extent": "mean",
                                          "rigidity.model": "paper"})
    assert options.lattice.cell_width == 0.5
    assert options.selection.half_free == "none"
    assert options.rigidity.model == "paper"
    # --rigidity is rigidity.model on the command line; in Python `rigidity` is the nested
    # options, which keeps the keyword.
    assert "rigidity" not in msdeform.DeformerOptions.aliases
    assert options.num_threads == 3
    assert options.selection.member_extent == "mean"
    described = dict(msdeform.describe_options({"threads": 3}))
    assert described["graph.num_threads"] == "3"
    flags = msdeform.options_from_flags({"selection.member_extent": "mean", "w_con": 1000})
    assert flags.selection.member_extent == "mean" and flags.w_con == 1000


def test_rows_are_the_description():
    # The Deformer's rows, then the methods' own (test_methods.py).
    rows = [row for row in _msdeform.option_rows() if not row["keywords"]]
    assert [(row["name"], row["default"]) for row in rows] == msdeform.describe_options()
    backend = next(row for row in rows if row["name"] == "backend")
    assert backend["aliases"] == ["solver"] and backend["choices"] == ["gauss_newton", "ceres"]
    assert backend["flag_topic"] == "solver"
    # Every top-level row is a keyword of the class, with the row's help as its doc.
    for row in rows:
        head = row["name"].split(".")[0]
        assert head in msdeform.DeformerOptions.fields
        if "." not in row["name"]:
            assert getattr(msdeform.DeformerOptions, head).__doc__.startswith(row["help"])


def test_bad_values_name_the_option():
    with pytest.raises(ValueError, match=r"^--solver=newton: expected gauss_newton or ceres$"):
        msdeform.options_from_flags({"solver": "newton"})
    with pytest.raises(ValueError, match=r"DeformerOptions.backend: unknown value 'newton'; "
                                         r"expected one of gauss_newton, ceres"):
        msdeform.DeformerOptions(solver="newton")
    with pytest.raises(ValueError, match=r"^rigidity.damping=1: expected a number in \[0, 1\)$"):
        msdeform.options_from_flags({"rigidity.damping": 1.0})
    with pytest.raises(TypeError, match="unknown option 'solvr'"):
        msdeform.DeformerOptions(solvr="ceres")


def test_two_spellings_of_one_option_with_different_values_are_refused():
    # As the command line refuses --threads=3 --num_threads=4.
    with pytest.raises(TypeError, match=r"one option \(num_threads\), given twice"):
        msdeform.DeformerOptions(threads=3, num_threads=4)
    with pytest.raises(TypeError, match=r"one option \(backend\), given twice"):
        msdeform.DeformerOptions(solver="ceres", backend="gauss_newton")
    # The same value under both spellings is one option given once.
    options = msdeform.DeformerOptions(solver="ceres", backend="ceres")
    assert options.backend == "ceres"
