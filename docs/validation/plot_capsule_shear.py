#!/usr/bin/python3
"""Capsule in simple shear: D(t) of each run against Ramanujan & Pozrikidis 1998, and steady D
against Ca. Reads docs/validation/capsule_shear_ca<Ca>.csv (written by dld-capsule-shear --csv)
and tests/data/capsule_shear/neo_hookean_pozrikidis1998_ca_<Ca>.csv.
Run from the repository root: /usr/bin/python3 docs/validation/plot_capsule_shear.py"""
import numpy as np
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt

CAS = ["0.025", "0.05", "0.1", "0.2"]
SETTLED = 0.7  # steady D: mean over the last 30 % of the strain (as dld-capsule-shear)


def load(path):
    d = np.loadtxt(path, delimiter=",", comments="#", ndmin=2)
    return d[np.argsort(d[:, 0])]


fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(11, 4.2))
ca_sim, d_sim, ca_ref, d_ref = [], [], [], []
for i, ca in enumerate(CAS):
    color = f"C{i}"
    ref = load(f"tests/data/capsule_shear/neo_hookean_pozrikidis1998_ca_{ca}.csv")
    ax1.plot(ref[:, 0], ref[:, 1], "--", color=color, lw=1)
    ca_ref.append(float(ca))
    d_ref.append(ref[-1, 1])
    try:
        sim = load(f"docs/validation/capsule_shear_ca{ca}.csv")
    except OSError:
        continue
    ax1.plot(sim[:, 0], sim[:, 1], "-", color=color, label=f"Ca = {ca}")
    t_end = sim[-1, 0]
    ca_sim.append(float(ca))
    d_sim.append(sim[sim[:, 0] >= SETTLED * t_end, 1].mean())
ax1.set_xlabel(r"$\dot\gamma t$")
ax1.set_ylabel("Taylor deformation D")
ax1.set_title("D(t): this code (solid), Ramanujan & Pozrikidis 1998 (dashed)", fontsize=9)
ax1.legend(fontsize=8)
ax1.set_xlim(0, 8)
ax1.set_ylim(0, 0.6)

ca_line = np.linspace(0, 0.06, 20)
ax2.plot(ca_line, 25 / 4 * ca_line, ":", color="gray", label="small deformation, D = 25 Ca / 4")
ax2.plot(ca_ref, d_ref, "ks--", mfc="none", label="Ramanujan & Pozrikidis 1998")
ax2.errorbar(ca_ref, d_ref, yerr=0.05 * np.array(d_ref), fmt="none", ecolor="k", capsize=3, lw=0.8)
ax2.plot(ca_sim, d_sim, "o-", color="C3", label="this code (a = 6, steady mean)")
# Resolution check: a = 8 (box 64 x 64 x 80, 5120 faces), shorter runs, mean over the last 30 %.
ca8, d8s = [], []
for ca in CAS:
    try:
        a8 = load(f"docs/validation/capsule_shear_ca{ca}_a8.csv")
    except OSError:
        continue
    ca8.append(float(ca))
    d8s.append(a8[a8[:, 0] >= SETTLED * a8[-1, 0], 1].mean())
    r = d_ref[CAS.index(ca)]
    print(f"Ca {ca}, a = 8 (to gammadot t = {a8[-1, 0]:.1f}): D {d8s[-1]:.4f} error "
          f"{100 * (d8s[-1] / r - 1):+.2f} %")
if ca8:
    ax2.plot(ca8, d8s, "^", color="C2", label="a = 8 (shorter runs, last 30 %)")
ax2.set_xlabel(r"Ca = $\mu\dot\gamma a / E_s$, $E_s = 3 G_s$")
ax2.set_ylabel("steady D")
ax2.set_title("steady D against Ca (error bars: 5 %)", fontsize=9)
ax2.legend(fontsize=8)
fig.tight_layout()
fig.savefig("docs/validation/capsule_shear.png", dpi=110)
for c, d in zip(ca_sim, d_sim):
    r = d_ref[ca_ref.index(c)]
    print(f"Ca {c}: D {d:.4f} reference {r:.4f} error {100 * (d / r - 1):+.2f} %")
