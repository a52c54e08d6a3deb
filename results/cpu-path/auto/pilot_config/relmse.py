# relMSE (against REF, denominators r² + 0.01, as the bench's) of each image CFG_SEED.exr, and
# the estimate of one image's from pairs of seeds ((A − B)²/2, as auto's halves):
#   python3 relmse.py REF CFG…
import sys, glob, numpy as np, OpenEXR, Imath
def read(p):
    f = OpenEXR.InputFile(p); dw = f.header()["dataWindow"]
    w, h = dw.max.x - dw.min.x + 1, dw.max.y - dw.min.y + 1
    return np.stack([np.frombuffer(f.channel(c, Imath.PixelType(Imath.PixelType.FLOAT)), np.float32).reshape(h, w) for c in "RGB"], -1).astype(np.float64)
ref = read(sys.argv[1])
den = ref ** 2 + 0.01
for cfg in sys.argv[2:]:
    files = sorted(glob.glob(f"{cfg}_*.exr"))
    imgs = [read(f) for f in files]
    true = [((i - ref) ** 2 / den).mean() for i in imgs]
    # halves' estimate of one image's relMSE from pairs (1,2), (3,4): (A-B)^2/2 per value
    halves = [(((imgs[k] - imgs[k + 1]) ** 2 / 2) / den).mean() for k in range(0, len(imgs) - 1, 2)]
    print(cfg, "true relMSE per image", " ".join(f"{t:.3e}" for t in true), "| mean", f"{np.mean(true):.3e}",
          "| pairs' estimate", " ".join(f"{h:.3e}" for h in halves))
