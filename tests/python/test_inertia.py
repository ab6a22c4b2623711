"""The parameterizations on arrays: against the C++ program `inertial convert` on the same numbers
(bit for bit), the Jacobian against central finite differences, round trips, and bad input raising
with the message the CLI gives."""
import numpy as np
import pytest

import inertial
from conftest import cli_json

RNG = np.random.default_rng(20261206)
BOX = inertial.pi_from_mass_com_inertia(2.0, [0.02, -0.01, 0.05], np.diag([0.01, 0.02, 0.025]))


def test_log_cholesky_equals_the_cli_bit_for_bit():
    for _ in range(5):
        theta = RNG.uniform(-0.5, 0.5, 10)
        pi = inertial.log_cholesky(theta)
        ref = cli_json("convert", "--from", "theta", "--to", "pi", "--", *[repr(v) for v in theta])
        assert list(pi) == ref["pi"]
        relative = inertial.log_cholesky(theta, reference=BOX)
        ref = cli_json("convert", "--from", "theta", "--to", "pi", "--reference", ",".join(repr(v) for v in BOX), "--",
                       *[repr(v) for v in theta])
        assert list(relative) == ref["pi"]


def test_jacobian_against_central_differences():
    for reference in (None, BOX):
        theta = RNG.uniform(-0.4, 0.4, 10)
        J = inertial.log_cholesky_jacobian(theta, reference=reference)
        h = 1e-6
        numeric = np.column_stack([
            (inertial.log_cholesky(theta + h * e, reference=reference) -
             inertial.log_cholesky(theta - h * e, reference=reference)) / (2 * h) for e in np.eye(10)])
        assert J.shape == (10, 10)
        np.testing.assert_allclose(J, numeric, rtol=1e-6, atol=1e-8)


def test_round_trips():
    theta = RNG.uniform(-0.5, 0.5, 10)
    np.testing.assert_allclose(inertial.log_cholesky_inverse(inertial.log_cholesky(theta)), theta, atol=1e-12)
    np.testing.assert_allclose(inertial.log_cholesky_inverse(BOX, reference=BOX), np.zeros(10), atol=1e-12)
    m, c, I = inertial.mass_com_inertia(BOX)
    assert m == 2.0
    np.testing.assert_allclose(c, [0.02, -0.01, 0.05], atol=1e-15)
    np.testing.assert_allclose(I, np.diag([0.01, 0.02, 0.025]), atol=1e-15)
    J = inertial.pseudo_inertia(BOX)
    assert J.shape == (4, 4) and J[3, 3] == 2.0
    np.testing.assert_allclose(inertial.pi_from_pseudo_inertia(J), BOX, atol=1e-15)


def test_consistency_and_its_margins():
    report = inertial.check_consistency(BOX)
    assert report["fully_consistent"]
    # Principal moments 0.01, 0.02, 0.025 about the COM: the tightest triangle margin is
    # 0.01 + 0.02 - 0.025 = 0.005.
    assert report["min_triangle_margin"] == pytest.approx(0.005, abs=1e-15)
    rod = inertial.pi_from_mass_com_inertia(1.0, [0, 0, 0], np.diag([0.01, 0.01, 0.03]))  # 0.01 + 0.01 < 0.03
    bad = inertial.check_consistency(rod)
    assert not bad["fully_consistent"] and not bad["triangle_inequalities"]
    assert bad["min_triangle_margin"] == pytest.approx(-0.01, abs=1e-15)
    assert not inertial.check_consistency([np.nan] * 10)["finite"]


def test_bad_input_raises_naming_it():
    with pytest.raises(ValueError, match=r"theta: expected 10 numbers, got an array of shape \(3,\)"):
        inertial.log_cholesky([1.0, 2.0, 3.0])
    with pytest.raises(ValueError, match="theta: not every number is finite"):
        inertial.log_cholesky([np.nan] + [0.0] * 9)
    huge = [400.0] + [0.0] * 9
    with pytest.raises(ValueError) as raised:
        inertial.log_cholesky(huge)
    _, _, err = __import__("conftest").cli("convert", "--from", "theta", "--to", "pi", "--", *map(repr, huge),
                                           check=False)
    assert str(raised.value) in err, (str(raised.value), err)
    with pytest.raises(ValueError, match="inertia: not symmetric"):
        inertial.pi_from_mass_com_inertia(1.0, [0, 0, 0], np.arange(9.0).reshape(3, 3))
    rod = inertial.pi_from_mass_com_inertia(1.0, [0, 0, 0], np.diag([0.01, 0.01, 0.03]))
    with pytest.raises(ValueError) as raised:
        inertial.log_cholesky_inverse(rod)
    code, _, err = __import__("conftest").cli("convert", "--from", "pi", "--to", "theta", "--",
                                              *[repr(v) for v in rod], check=False)
    assert code != 0
    # The CLI's reason, word for word.
    reason = str(raised.value).split("physically consistent: ", 1)[1]
    assert reason in err, (reason, err)
