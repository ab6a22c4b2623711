"""inertial.identify equals `inertial identify --json` on the same log, number for number (the same
library, read the same way), from a file and from the same samples as arrays; bad input raises with
the CLI's message."""
import numpy as np
import pytest

import inertial
from conftest import cli, cli_json, source


@pytest.fixture(scope="module")
def logs(tmp_path_factory):
    d = tmp_path_factory.mktemp("logs")
    train, test = d / "train.csv", d / "test.csv"
    for path, seed in ((train, "3"), (test, "4")):
        cli("simulate", "--model", source("examples", "leg3.urdf"), "--out", str(path), "--duration", "6", "--rate",
            "200", "--perturb", "0.1", "--effects", "viscous", "--noise-tau", "0.02", "--seed", seed)
    return train, test


def without_timing(result):
    return {k: v for k, v in result.items() if k not in ("fit_seconds", "x")}


def test_identify_equals_the_cli(logs):
    train, test = logs
    r = inertial.Robot.from_urdf(source("examples", "leg3.urdf"), effects="viscous")
    result = inertial.identify(r, str(train), validate=str(test))
    reference = cli_json("identify", "--model", source("examples", "leg3.urdf"), "--effects", "viscous", "--data",
                         str(train), "--validate", str(test))
    assert without_timing(result) == without_timing(reference)
    assert result["x"].shape == (r.num_parameters,)
    assert all(b["physically_consistent"] for b in result["bodies"])


def test_identify_on_arrays_is_identify_on_the_file(logs):
    train, _ = logs
    r = inertial.Robot.from_urdf(source("examples", "leg3.urdf"), effects="viscous")
    data = np.genfromtxt(train, delimiter=",", names=True)
    # The CSV's numbers are the arrays' own (the file holds round-trip digits).
    arrays = {"t": data["t"]}
    for key in ("q", "qd", "qdd", "tau"):
        arrays[key] = np.column_stack([data[key + "_" + j] for j in r.joint_names])
    from_arrays = inertial.identify(r, arrays)
    from_file = inertial.identify(r, str(train))
    assert without_timing(from_arrays) == without_timing(from_file)


def test_bad_logs_raise_with_the_clis_message(tmp_path, logs):
    r = inertial.Robot.from_urdf(source("examples", "leg3.urdf"))
    missing = str(tmp_path / "missing.csv")
    with pytest.raises(ValueError) as raised:
        inertial.identify(r, missing)
    _, _, err = cli("identify", "--model", source("examples", "leg3.urdf"), "--data", missing, check=False)
    assert str(raised.value) in err
    with pytest.raises(ValueError, match=r"data\['tau'\]: expected an array of shape \(3, 3\), got \(3, 2\)"):
        inertial.identify(r, {"t": np.arange(3.0), "q": np.zeros((3, 3)), "qd": np.zeros((3, 3)),
                              "qdd": np.zeros((3, 3)), "tau": np.zeros((3, 2))})
    with pytest.raises(ValueError, match=r"data\['t'\]: not an array of numbers"):
        inertial.identify(r, {"t": ["a", "b", "c"], "q": np.zeros((3, 3)), "qd": np.zeros((3, 3)),
                              "qdd": np.zeros((3, 3)), "tau": np.zeros((3, 3))})
    with pytest.raises(ValueError, match=r"data\['t'\]: time must increase strictly"):
        inertial.identify(r, {"t": np.array([0.0, 1.0, 1.0]), "q": np.zeros((3, 3)), "qd": np.zeros((3, 3)),
                              "qdd": np.zeros((3, 3)), "tau": np.zeros((3, 3))})


def test_validate_and_diagnose_equal_the_cli(logs):
    train, test = logs
    urdf = source("examples", "leg3.urdf")
    leg = inertial.Robot.from_urdf(urdf)
    assert inertial.validate(leg, str(test)) == cli_json("validate", "--model", urdf, "--data", str(test))
    mine = inertial.diagnose(leg, str(train), validate=str(test))
    reference = cli_json("diagnose", "--model", urdf, "--data", str(train), "--validate", str(test))
    shared = set(mine) & set(reference)
    assert len(shared) >= 0.8 * len(reference), sorted(set(reference) - set(mine))
    for key in shared - {"fit_seconds", "seconds", "validation_source"}:
        assert mine[key] == reference[key], key
    # The hidden viscous friction of the simulated leg is what it names first.
    with_effect = inertial.Robot.from_urdf(urdf, effects="viscous")
    assert inertial.identify(with_effect, str(train), validate=str(test))["rms_validation"]["total"] < \
        inertial.identify(leg, str(train), validate=str(test))["rms_validation"]["total"]


def test_simulate_equals_the_cli(tmp_path):
    urdf = source("examples", "leg3.urdf")
    path = tmp_path / "sim.csv"
    cli("simulate", "--model", urdf, "--out", str(path), "--duration", "2", "--rate", "100", "--seed", "9")
    data = np.genfromtxt(path, delimiter=",", names=True)
    leg = inertial.Robot.from_urdf(urdf)
    mine = leg.simulate(duration=2, rate=100, seed=9)
    np.testing.assert_array_equal(mine["t"], data["t"])
    for key in ("q", "qd", "qdd", "tau"):
        np.testing.assert_array_equal(mine[key], np.column_stack([data[key + "_" + j] for j in leg.joint_names]), key)


def test_the_identified_model_file_predicts_what_the_fit_predicts(logs, tmp_path):
    train, test = logs
    r = inertial.Robot.from_urdf(source("examples", "leg3.urdf"), effects="viscous")
    result = inertial.identify(r, str(train), validate=str(test))
    model = tmp_path / "fit.urdf"
    r.write_urdf(result["x"], str(model))
    judged = cli_json("validate", "--model", str(model), "--data", str(test))
    assert judged["rms"]["total"] == pytest.approx(result["rms_validation"]["total"], rel=1e-9)
    again = inertial.validate(inertial.Robot.from_urdf(str(model)), str(test))
    assert again["rms"] == judged["rms"]
