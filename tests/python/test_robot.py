"""Robot on arrays: the regressor times the coefficients against recursive Newton-Euler (two
algorithms), against the CLI's identify predictions, shapes, and bad input with the CLI's
messages."""
import numpy as np
import pytest

import inertial
from conftest import cli, source

RNG = np.random.default_rng(7)


def robot(effects=""):
    return inertial.Robot.from_urdf(source("examples", "leg3.urdf"), effects=effects)


def states(n, N=None):
    shape = (n,) if N is None else (N, n)
    return RNG.uniform(-1, 1, shape), RNG.uniform(-2, 2, shape), RNG.uniform(-5, 5, shape)


def test_regressor_times_coefficients_is_newton_euler():
    r = robot("viscous,coulomb,armature@hip")
    assert r.joint_names == ["abad", "hip", "knee"]
    x = RNG.uniform(-0.3, 0.3, r.num_parameters)
    w = r.coefficients(x)
    q, qd, qdd = states(3, 20)
    A = r.regressor(q, qd, qdd)
    assert A.shape == (20, 3, r.num_features)
    tau = r.inverse_dynamics(q, qd, qdd, x=x)
    assert tau.shape == (20, 3)
    np.testing.assert_allclose(A @ w, tau, rtol=1e-10, atol=1e-10)
    one = r.inverse_dynamics(q[0], qd[0], qdd[0], x=x)
    assert one.shape == (3,)
    np.testing.assert_array_equal(one, tau[0])
    np.testing.assert_array_equal(r.regressor(q[0], qd[0], qdd[0]), A[0])


def test_the_urdf_as_it_is_predicts_what_validate_predicts(tmp_path):
    log = tmp_path / "log.csv"
    cli("simulate", "--model", source("examples", "leg3.urdf"), "--out", str(log), "--duration", "1", "--rate", "100")
    data = np.genfromtxt(log, delimiter=",", names=True)
    r = robot()
    q = np.column_stack([data["q_" + j] for j in r.joint_names])
    qd = np.column_stack([data["qd_" + j] for j in r.joint_names])
    qdd = np.column_stack([data["qdd_" + j] for j in r.joint_names])
    tau = np.column_stack([data["tau_" + j] for j in r.joint_names])
    # The simulator's torques are the URDF's own inverse dynamics at the logged state (no noise);
    # the CSV holds them to its printed digits.
    np.testing.assert_allclose(r.inverse_dynamics(q, qd, qdd), tau, rtol=1e-9, atol=1e-9)


def test_bad_input_raises_with_the_clis_message():
    r = robot()
    with pytest.raises(ValueError, match=r"q: expected 3 numbers, got an array of shape \(2,\)"):
        r.inverse_dynamics([0.0, 0.0], [0.0] * 3, [0.0] * 3)
    with pytest.raises(ValueError, match=r"qd: expected an array of shape \(4, 3\), got \(5, 3\)"):
        r.regressor(np.zeros((4, 3)), np.zeros((5, 3)), np.zeros((4, 3)))
    with pytest.raises(ValueError, match="qdd: not every number is finite"):
        r.inverse_dynamics([0.0] * 3, [0.0] * 3, [0.0, np.nan, 0.0])
    with pytest.raises(ValueError) as raised:
        robot("viscous@nowhere")
    _, _, err = cli("identify", "--model", source("examples", "leg3.urdf"), "--data", "x.csv", "--effects",
                    "viscous@nowhere", check=False)
    assert str(raised.value).split("effects: ", 1)[1] in err
    with pytest.raises(ValueError, match="x: gives coefficients beyond the range of double precision"):
        r.coefficients(np.full(r.num_parameters, 1e3))
    missing = source("examples", "no_such_robot.urdf")
    with pytest.raises(ValueError) as raised:
        inertial.Robot.from_urdf(missing)
    _, _, err = cli("identify", "--model", missing, "--data", "x.csv", check=False)
    assert str(raised.value) in err


def test_a_robot_without_moving_joints_is_refused(tmp_path):
    urdf = tmp_path / "fixed.urdf"
    urdf.write_text('<robot name="r"><link name="base"/><link name="tool"><inertial><mass value="1"/>'
                    '<inertia ixx="1" iyy="1" izz="1" ixy="0" ixz="0" iyz="0"/></inertial></link>'
                    '<joint name="j" type="fixed"><parent link="base"/><child link="tool"/></joint></robot>')
    with pytest.raises(ValueError, match="has no moving joint"):
        inertial.Robot.from_urdf(urdf)
