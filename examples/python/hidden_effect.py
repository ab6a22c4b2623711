"""A leg with a hidden effect, found from Python: simulate, diagnose, add the effect, see the
held-out error fall, and watch the online estimator learn a link's mass sample by sample.

    PYTHONPATH=build/python /usr/bin/python3 examples/python/hidden_effect.py [OUT_DIR]

writes OUT_DIR/residual.png (held-out residual of the knee before and after adding the effect) and
OUT_DIR/online_mass.png (a link's mass as the online estimator learns it, with one standard
deviation), and prints what it found. OUT_DIR defaults to the current directory.
"""
import os
import sys

import matplotlib

matplotlib.use("Agg")  # files only, no display
import matplotlib.pyplot as plt
import numpy as np

import inertial

here = os.path.dirname(os.path.abspath(__file__))
urdf = os.path.join(here, "..", "leg3.urdf")
out = sys.argv[1] if len(sys.argv) > 1 else "."

# 1. The true leg: the URDF's links 10 % off (a seeded draw of log-Cholesky theta) and Coulomb
#    friction of 0.8 N m on every joint, which the URDF does not know.
truth = inertial.Robot.from_urdf(urdf, effects="coulomb")
x_true = truth.prior_parameters()
rng = np.random.default_rng(1)
bodies = 10 * len(truth.body_names)
x_true[:bodies] = rng.uniform(-0.1, 0.1, bodies)
for k, name in enumerate(truth.parameter_names):
    if name.startswith("coulomb@"):
        x_true[k] = np.log(0.8)
train = truth.simulate(x=x_true, duration=20, rate=200, seed=3, noise_tau=0.05)
test = truth.simulate(x=x_true, duration=10, rate=200, seed=4, noise_tau=0.05)

# 2. The URDF alone, diagnosed: what is missing?
leg = inertial.Robot.from_urdf(urdf)
d = inertial.diagnose(leg, train, validate=test)
best = d["candidates"][0]
print(f"diagnose says: {best['explanation']} (explains {100 * best['explained']:.0f} % of the held-out error)")

# 3. Fit without and with the effect; the held-out residual before and after.
before = inertial.identify(leg, train, validate=test)
with_friction = inertial.Robot.from_urdf(urdf, effects="coulomb")
after = inertial.identify(with_friction, train, validate=test)
print(f"held-out RMS: {before['rms_validation']['total']:.3f} N m without the effect, "
      f"{after['rms_validation']['total']:.3f} N m with it (noise 0.05 N m)")
knee = leg.joint_names.index("knee")
r_before = leg.inverse_dynamics(test["q"], test["qd"], test["qdd"], x=before["x"])[:, knee] - test["tau"][:, knee]
r_after = with_friction.inverse_dynamics(test["q"], test["qd"], test["qdd"], x=after["x"])[:, knee] - test["tau"][:, knee]
fig, ax = plt.subplots(figsize=(8, 3.5))
ax.plot(test["t"], r_before, lw=0.7, label="links only")
ax.plot(test["t"], r_after, lw=0.7, label="links + Coulomb friction")
ax.set_xlabel("t [s]")
ax.set_ylabel("knee residual [N m]")
ax.set_title("Held-out torque residual")
ax.legend()
fig.tight_layout()
fig.savefig(os.path.join(out, "residual.png"), dpi=120)

# 4. The online estimator, sample by sample: a link's mass and its standard deviation. A serial
#    leg's joint torques see each link's mass only in part (the batch fit lists it under
#    "held_by_prior"), so the band stays wide; take the link the data pin best.
est = inertial.OnlineEstimator(with_friction)
shank = min(range(len(after["bodies"])),
            key=lambda k: after["bodies"][k]["uncertainty"]["mass_std"] / after["bodies"][k]["mass"])
link = with_friction.body_names[shank]
times, masses, stds = [], [], []
for i in range(len(train["t"])):
    est.update(train["t"][i], train["q"][i], train["qd"][i], train["qdd"][i], train["tau"][i])
    if i % 100 == 99:
        b = est.estimate()["bodies"][shank]
        times.append(train["t"][i])
        masses.append(b["mass"])
        stds.append(b.get("uncertainty", {}).get("mass_std", np.nan))
est.finish()
final = est.estimate()["bodies"][shank]
true_mass = inertial.mass_com_inertia(truth.coefficients(x_true)[10 * shank:10 * shank + 10])[0]
print(f"{link} mass: online {final['mass']:.4f} +- {final['uncertainty']['mass_std']:.4f} kg, batch {after['bodies'][shank]['mass']:.4f} kg, true {true_mass:.4f} kg")
masses, stds = np.array(masses), np.array(stds)
fig, ax = plt.subplots(figsize=(8, 3.5))
ax.fill_between(times, masses - stds, masses + stds, alpha=0.3, label="one standard deviation")
ax.plot(times, masses, label="online estimate")
ax.axhline(true_mass, color="k", ls="--", lw=0.8, label="true")
ax.set_xlabel("t [s]")
ax.set_ylabel(f"{link} mass [kg]")
ax.legend()
fig.tight_layout()
fig.savefig(os.path.join(out, "online_mass.png"), dpi=120)
print("wrote", os.path.join(out, "residual.png"), "and", os.path.join(out, "online_mass.png"))
