"""The default study from Python: CLICdet, ttbar at 3 TeV with 30 BX of
gamma gamma -> hadrons; efficiency versus pT (as `conftrack run`).

    PYTHONPATH=build/python python3 python/examples/default_study.py [events]
"""
import sys

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt
import conftrack

n = int(sys.argv[1]) if len(sys.argv) > 1 else 10
events = conftrack.simulate("ttbar3tev", detector="clicdet", events=n, seed=1,
                            overlay_bx=30)
results = conftrack.reconstruct_many([e.hits for e in events], threads=0)
summary = conftrack.evaluate(events, results)
print(f"{n} events: efficiency {summary['efficiency']['all']:.3f} "
      f"(pT > 1 GeV {summary['efficiency']['pt_above_1GeV']:.3f}), "
      f"fake rate {summary['fake_rate']:.4f}")

h = summary["histograms"]["efficiency_vs_pt"]
centres = (h["edges"][1:] * h["edges"][:-1]) ** 0.5
plt.errorbar(centres, h["value"], yerr=h["uncertainty"], fmt="o")
plt.xscale("log")
plt.xlabel("pT [GeV]")
plt.ylabel("efficiency")
plt.title("CLICdet, ttbar 3 TeV + 30 BX")
plt.savefig("efficiency_vs_pt.png", dpi=120)
print("wrote efficiency_vs_pt.png")
