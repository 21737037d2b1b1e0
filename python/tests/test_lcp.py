"""hopsim.lcp: the Siconos sample problems with their known solutions, an LCP without a
solution, and bad input (clear errors, never a crash)."""

import numpy as np
import pytest

from hopsim import _hopsim, lcp

#: Known solutions of tests/data/lcp (its README).
KNOWN = {
    "lcp_trivial.dat": 1.0 / np.arange(1, 10),
    "lcp_deudeu.dat": np.array([4.0 / 3.0, 7.0 / 3.0]),
    "lcp_exp_murty.dat": np.array([1.0, 0, 0, 0, 0, 0]),
}


def assert_complementary(m, q, z, w, tol=1e-9):
    """The LCP's three conditions, checked here independently of the solver."""
    scale = max(1.0, np.abs(q).max())
    np.testing.assert_allclose(w, m @ z + q, atol=tol * scale)
    assert z.min() >= -tol * scale and w.min() >= -tol * scale
    assert abs(z @ w) <= tol * scale


@pytest.mark.parametrize("name", sorted(KNOWN))
def test_sample_problems_are_solved(name, lcp_data):
    m, q = lcp.read_dat(lcp_data / name)
    solution = lcp.solve(m, q)
    assert solution.status == "solved" and solution.solved
    assert solution.certificate["holds"]
    np.testing.assert_allclose(solution.z, KNOWN[name], rtol=1e-12, atol=1e-12)
    assert_complementary(m, q, solution.z, solution.w)


def test_every_repository_dat_file_is_solved_or_refused_clearly(lcp_data):
    files = sorted(lcp_data.glob("*.dat"))
    assert len(files) >= 3
    for path in files:
        m, q = lcp.read_dat(path)
        s = lcp.solve(m, q)
        assert s.status in ("solved", "ray_termination", "pivot_limit", "numerical_breakdown")
        if s.solved:
            assert_complementary(m, q, s.z, s.w)


def test_lists_and_integers_are_accepted():
    s = lcp.solve([[2, 1], [1, 2]], [-5, -6])
    np.testing.assert_allclose(s.z, [4 / 3, 7 / 3], rtol=1e-14)
    assert s.method == "lemke" and s.pivots >= 1


def test_nonnegative_q_is_trivial():
    s = lcp.solve(np.eye(3), np.ones(3))
    assert (s.status, s.method, s.pivots) == ("solved", "trivial", 0)
    np.testing.assert_array_equal(s.z, 0.0)
    np.testing.assert_array_equal(s.w, 1.0)


def test_lcp_without_solution_is_not_called_solved():
    # w = -z - 1 ≥ 0 needs z ≤ -1 < 0: no solution.
    s = lcp.solve([[-1.0]], [-1.0])
    assert s.status == "ray_termination" and not s.solved
    assert not s.certificate["holds"]


def test_fortran_ordered_matrix_gives_the_same_answer():
    m = np.array([[4.0, 1.0, 0.0], [1.0, 3.0, 1.0], [0.0, 1.0, 2.0]])
    q = np.array([-1.0, -2.0, -1.0])
    a, b = lcp.solve(m, q), lcp.solve(np.asfortranarray(m), q)
    np.testing.assert_array_equal(a.z, b.z)


@pytest.mark.parametrize(
    "m, q, error",
    [
        (np.eye(2), np.ones(3), ValueError),  # q of another length
        (np.ones((2, 3)), np.ones(2), ValueError),  # not square
        (np.ones((2, 2, 2)), np.ones(2), ValueError),  # not a matrix
        (np.ones(4), np.ones(2), ValueError),
        (np.eye(2), np.ones((2, 1)), ValueError),
        (np.eye(2, dtype=complex), np.ones(2), TypeError),
        (np.eye(2, dtype=bool), np.ones(2), TypeError),
        (np.array([["a", "b"], ["c", "d"]]), np.ones(2), TypeError),
        (np.array([[1.0, np.nan], [0.0, 1.0]]), np.ones(2), ValueError),
        (np.eye(2), np.array([1.0, np.inf]), ValueError),
        ([[1.0, 2.0], [3.0]], [1.0, 1.0], ValueError),  # ragged
        (None, np.ones(2), TypeError),
    ],
)
def test_bad_input_is_a_clear_error(m, q, error):
    with pytest.raises(error) as info:
        lcp.solve(m, q)
    assert str(info.value)


def test_extension_refuses_wrong_dtypes_without_crashing():
    with pytest.raises(TypeError):
        _hopsim.lcp_solve(np.eye(2, dtype=np.int64), np.ones(2))
    with pytest.raises(TypeError):
        _hopsim.lcp_solve(np.eye(2), np.ones(2, dtype=np.float32))
    with pytest.raises(ValueError):
        _hopsim.lcp_solve(np.ones((2, 3)), np.ones(2))


def test_unreadable_dat_file_is_a_value_error(tmp_path):
    bad = tmp_path / "bad.dat"
    bad.write_text("2\n0\n2\n2\n2 2\n1 0\n")
    with pytest.raises(ValueError):
        lcp.read_dat(bad)
    with pytest.raises(ValueError):
        lcp.read_dat(tmp_path / "missing.dat")
