"""The combination experiment (README.md): pt's and naive's 4 s images combined per block of
pixels with inverse-variance weights, against each method's 8 s image, on the bench's relMSE.
Weights three ways: an oracle's (every seed's error against the reference), leave-one-out (the
other two seeds' errors against the reference) and a pilot's (two 0.25 s halves per method, the
median of the four as the denominators' reference, as `auto::assess` does). Run in the folder of
render.sh's images: python combine.py VIEWS_FOLDER"""
import sys
import numpy as np
import OpenEXR, Imath


def load(path):
    f = OpenEXR.InputFile(path)
    dw = f.header()["dataWindow"]
    w, h = dw.max.x - dw.min.x + 1, dw.max.y - dw.min.y + 1
    pt = Imath.PixelType(Imath.PixelType.FLOAT)
    return np.stack([np.frombuffer(f.channel(c, pt), np.float32).reshape(h, w) for c in "RGB"], -1).astype(np.float64)


def relmse(x, r):
    return ((x - r) ** 2 / (r * r + 0.01)).mean()


views = sys.argv[1]
print("| view | block | smoothing | pt 8 s | naive 8 s | oracle 4+4 | leave-one-out 4+4 | pilot 4+4 | pilot / best single | pilot's predicted gain |")
print("|---|---|---|---|---|---|---|---|---|---|")
for v in ["sunblind", "slit", "banner2"]:
    r = load(f"{views}/ref_{v}.exr")
    h, w, _ = r.shape
    I = {(m, s, t): load(f"{v}_{m}_{s}_{t}.exr") for m in ["pt", "naive"] for s in [1, 2, 3] for t in [4, 8]}
    P = {(m, s): load(f"p_{v}_{m}_{s}.exr") for m in ["pt", "naive"] for s in range(11, 17)}
    single = {m: np.mean([relmse(I[(m, s, 8)], r) for s in [1, 2, 3]]) for m in ["pt", "naive"]}
    for B in [4, 8]:
        for smooth in [0, 1]:
            def blocksum(t):
                hb, wb = (h + B - 1) // B, (w + B - 1) // B
                p = np.zeros((hb * B, wb * B, 3))
                p[:h, :w] = t
                s = p.reshape(hb, B, wb, B, 3).sum((1, 3))
                for _ in range(smooth):  # a 3×3 box over the blocks
                    q = np.pad(s, ((1, 1), (1, 1), (0, 0)), mode="edge")
                    s = sum(q[i:i + hb, j:j + wb] for i in range(3) for j in range(3)) / 9
                return s

            def expand(t):
                return np.repeat(np.repeat(t, B, 0), B, 1)[:h, :w]

            def err(m, s):
                return blocksum((I[(m, s, 4)] - r) ** 2 / (r * r + 0.01))

            def combined(s, ea, eb):
                wa = expand(eb / (ea + eb + 1e-30))
                return relmse(wa * I[("pt", s, 4)] + (1 - wa) * I[("naive", s, 4)], r)

            oracle, loo, pilot, gain = [], [], [], []
            for k, s in enumerate([1, 2, 3]):
                others = [q for q in [1, 2, 3] if q != s]
                oracle.append(combined(s, np.mean([err("pt", q) for q in [1, 2, 3]], 0),
                                       np.mean([err("naive", q) for q in [1, 2, 3]], 0)))
                loo.append(combined(s, np.mean([err("pt", q) for q in others], 0),
                                    np.mean([err("naive", q) for q in others], 0)))
                a, b = 11 + 2 * k, 12 + 2 * k
                ref = np.median(np.stack([P[(m, q)] for m in ["pt", "naive"] for q in (a, b)]), 0)
                var = {m: blocksum((P[(m, a)] - P[(m, b)]) ** 2 / 4 / (ref * ref + 0.01)) + 1e-30 for m in ["pt", "naive"]}
                pilot.append(combined(s, var["pt"], var["naive"]))
                # What the pilot predicts: the half-and-half combination against the better method alone.
                both = (1 / (0.5 / var["pt"] + 0.5 / var["naive"])).sum()
                gain.append(min(var["pt"].sum(), var["naive"].sum()) / both)
            best = min(single.values())
            print(f"| {v} | {B} | {smooth} | {single['pt']:.3g} | {single['naive']:.3g} | {np.mean(oracle):.3g} | "
                  f"{np.mean(loo):.3g} | {np.mean(pilot):.3g} | {best / np.mean(pilot):.2f} | {np.mean(gain):.2f} |")
