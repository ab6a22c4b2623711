"""OnlineEstimator sample by sample: after a log it equals `inertial replay --json` of the same log
(the same pipeline, fed the same samples), and the batch fit to within the online fit's rounding;
a glitched sample is refused and counted, wrong shapes raise; 10^5 updates leak nothing."""
import gc
import tracemalloc

import numpy as np
import pytest

import inertial
from conftest import cli, cli_json, source


@pytest.fixture(scope="module")
def log(tmp_path_factory):
    path = tmp_path_factory.mktemp("online") / "log.csv"
    cli("simulate", "--model", source("examples", "leg3.urdf"), "--out", str(path), "--duration", "10", "--rate", "200",
        "--perturb", "0.1", "--noise-tau", "0.02", "--seed", "5")
    data = np.genfromtxt(path, delimiter=",", names=True)
    return path, data


def columns(data, key, names):
    return np.column_stack([data[key + "_" + j] for j in names])


def feed(est, data, names):
    q, qd, qdd, tau = (columns(data, k, names) for k in ("q", "qd", "qdd", "tau"))
    return [est.update(data["t"][i], q[i], qd[i], qdd[i], tau[i]) for i in range(len(data))]


def test_after_a_log_it_is_replay(log):
    path, data = log
    robot = inertial.Robot.from_urdf(source("examples", "leg3.urdf"))
    est = inertial.OnlineEstimator(robot)
    statuses = feed(est, data, robot.joint_names)
    assert statuses.count("accepted") > 0.9 * len(data)
    est.finish()
    mine = est.estimate()
    reference = cli_json("replay", "--model", source("examples", "leg3.urdf"), "--log", str(path))["estimate"]
    for key in ("bodies", "effects", "noise"):
        assert mine[key] == reference[key], key
    batch = cli_json("identify", "--model", source("examples", "leg3.urdf"), "--data", str(path), "--no-outlier-rejection")
    # The batch fit of the same samples: the same objective, minimized from statistics summed in
    # another order, whose rounding moves the minimum along directions only the prior holds
    # (docs/online.md: the masses agree to about 1e-4).
    for b_online, b_batch in zip(mine["bodies"], batch["bodies"]):
        assert b_online["mass"] == pytest.approx(b_batch["mass"], rel=1e-3)
    predicted = est.predict(columns(data, "q", robot.joint_names), columns(data, "qd", robot.joint_names),
                            columns(data, "qdd", robot.joint_names))
    residual = predicted - columns(data, "tau", robot.joint_names)
    assert np.sqrt(np.mean(residual ** 2)) == pytest.approx(0.02, rel=0.2)  # at the noise


def test_glitches_and_bad_shapes(log):
    _, data = log
    robot = inertial.Robot.from_urdf(source("examples", "leg3.urdf"))
    est = inertial.OnlineEstimator(robot)
    z = np.zeros(3)
    est.update(0.0, z, z, z, z)  # the first sample primes the pipeline, whatever it says
    refused = est.update(0.01, np.array([np.nan, 0, 0]), z, z, z)
    assert refused not in ("accepted", "held"), refused
    assert est.update(0.005, z, z, z, z) not in ("accepted", "held")  # out of order
    assert est.counters()["received"] == 3
    with pytest.raises(ValueError, match=r"tau: expected 3 numbers, got an array of shape \(2,\)"):
        est.update(0.02, z, z, z, np.zeros(2))
    with pytest.raises(ValueError, match="estimator: "):
        inertial.OnlineEstimator(robot, estimator="kalman_magic")
    with pytest.raises(ValueError, match="t: not finite"):
        est.update(np.nan, z, z, z, z)
    assert est.update(0.03, z, z, z, z) not in ("out_of_order",)  # a refused time stamp changed nothing
    assert est.predict(z, z, z).shape == (3,)
    assert np.isfinite(est.estimate()["x"]).all()


def test_no_reference_leaks_over_many_updates(log):
    _, data = log
    robot = inertial.Robot.from_urdf(source("examples", "leg3.urdf"))
    est = inertial.OnlineEstimator(robot)  # gauss_newton: its solves run in update() when due
    q, qd, qdd, tau = (columns(data, k, robot.joint_names) for k in ("q", "qd", "qdd", "tau"))
    n, period = 100_000, len(data)
    dt = data["t"][1] - data["t"][0]
    for i in range(1000):  # warm up: first-sample allocations
        est.update(i * dt, q[i % period], qd[i % period], qdd[i % period], tau[i % period])
    gc.collect()
    tracemalloc.start()
    before = tracemalloc.take_snapshot()
    for i in range(1000, n):
        k = i % period
        est.update(i * dt, q[k], qd[k], qdd[k], tau[k])
    gc.collect()
    after = tracemalloc.take_snapshot()
    tracemalloc.stop()
    grown = sum(s.size_diff for s in after.compare_to(before, "filename"))
    assert grown < 10_000, grown  # bytes: nothing kept per call


def test_save_restore_replay_and_the_model_file(log, tmp_path):
    path, data = log
    urdf = source("examples", "leg3.urdf")
    robot = inertial.Robot.from_urdf(urdf)
    half = len(data) // 2
    whole = inertial.OnlineEstimator(robot)
    feed(whole, data, robot.joint_names)
    first = inertial.OnlineEstimator(robot)
    feed(first, data[:half], robot.joint_names)
    checkpoint = tmp_path / "state.json"
    first.save(str(checkpoint))
    second = inertial.OnlineEstimator(robot)
    second.restore(str(checkpoint))
    feed(second, data[half:], robot.joint_names)
    for est in (whole, second):
        est.finish()
    np.testing.assert_allclose(second.estimate()["x"], whole.estimate()["x"], rtol=1e-9, atol=1e-12)
    with pytest.raises(ValueError, match="another model or estimator"):
        inertial.OnlineEstimator(robot, estimator="ekf").restore(str(checkpoint))
    # replay() of the file is the estimator fed by hand.
    replayed = inertial.replay(robot, str(path))
    assert replayed["estimate"]["bodies"] == whole.estimate()["bodies"]
    assert replayed["accepted"] == whole.counters()["accepted"]
    # The estimate as a model file, judged by the CLI on the log: at the noise.
    model = tmp_path / "online.urdf"
    whole.write_urdf(model)  # a pathlib.Path
    judged = cli_json("validate", "--model", str(model), "--data", str(path))
    assert judged["rms"]["total"] == pytest.approx(0.02, rel=0.2)
    with pytest.raises(ValueError, match="own URDF"):
        whole.write_urdf(urdf)
    with pytest.raises(ValueError, match="own URDF"):
        whole.save(urdf)
    with pytest.raises(ValueError, match="restore into a new OnlineEstimator"):
        whole.restore(str(checkpoint))
