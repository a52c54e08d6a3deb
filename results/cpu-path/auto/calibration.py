"""Auto's predictions against what the renders reached. For each view of the auto bench and each
repeat, each candidate's predicted relMSE (auto.csv: for the render after the pilot) against its own
render's relMSE in the same repeat (results.csv, its last row, t ≈ 8 s), scaled by t / (t − pilot)
to the render's time after the pilot (relMSE falls as 1/time). Run in results/cpu-path/auto/:
    python3 calibration.py > calibration.txt"""
import csv
import math
import statistics

VIEWS = ["sibenik", "sponza", "banner2", "sunblind", "slit", "atrium1", "atrium2", "showcase/lamp", "showcase/sky"]


def geomean(values):
    return math.exp(statistics.mean(math.log(v) for v in values))


print("| view | pt: reached / predicted (runs 1, 2, 3) | naive: reached / predicted | pt's over naive's (geometric means) |")
print("|---|---|---|---|")
every = {"pt": [], "naive": []}
for view in VIEWS:
    choices = list(csv.DictReader(open(f"{view}/auto.csv")))
    rows = list(csv.DictReader(open(f"{view}/results.csv")))
    ratios = {}
    for method in ["pt", "naive"]:
        ratios[method] = []
        for c in (c for c in choices if c["method"] == method):
            last = max((r for r in rows if r["method"] == method and r["repeat"] == c["repeat"]),
                       key=lambda r: float(r["seconds"]))
            t = float(last["seconds"])
            reached = float(last["relmse"]) * t / (t - float(c["pilot_seconds"]))
            ratios[method].append(reached / float(c["predicted_relmse"]))
        every[method] += ratios[method]
    runs = {m: " ".join(f"{r:.2f}" for r in ratios[m]) for m in ratios}
    print(f"| {view} | {runs['pt']} | {runs['naive']} | {geomean(ratios['pt']) / geomean(ratios['naive']):.2f} |")
print(f"\nAll views: reached / predicted, geometric mean: pt {geomean(every['pt']):.2f}, naive {geomean(every['naive']):.2f}; "
      f"range pt {min(every['pt']):.2f}–{max(every['pt']):.2f}, naive {min(every['naive']):.2f}–{max(every['naive']):.2f}")
