#!/usr/bin/env python3
"""Numerical checks of the `smlt_phong` Mitsuba plugin (mitsuba_phong.py) against float64
references computed here, for exponents 10, 1e3 and 1e5 and view directions from normal to
grazing (and one from the back side):

(a) the pdf integrates to the lobe's fraction above the surface. The integral is taken in the
    lobe's own coordinates (u = 1 - cos^(n+1) alpha, phi about the mirror direction, where the
    lobe's density is uniform), so that a lobe of 1e5 needs no Monte Carlo; the expected
    fraction is a 1D integral over u of the share of each cone of the lobe that lies above the
    surface (in closed form per cone). The plugin's own samples must also succeed with that
    probability, and their mean weight f cos / pdf must equal the albedo, likewise a 1D
    integral of a closed form per cone.
(b) sample() returns pdf() of its direction as the density, and eval()/pdf() as the weight;
    failed samples (pdf 0) weigh 0.
(c) f is symmetric in its two directions, the same on both sides of the surface, and 0 for
    directions on opposite sides.
(d) f at the sampled directions agrees with f in float64 (the cancellation-free evaluation;
    the naive float32 cos(alpha)^n is printed beside it for comparison).

Prints one line per exponent and view and exits non-zero when a check fails.

    python3 check_phong.py        (DRJIT_LIBLLVM_PATH must point at a libLLVM for llvm_ad_rgb)
"""

import argparse
import math
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

EXPONENTS = (10.0, 1e3, 1e5)
VIEW_Z = (1.0, 0.5, 0.1, 0.01, 0.002, -0.1)  # z of the view direction si.wi; < 0: the back side
AZIMUTH = 0.7  # of the view direction, radians
RHO = (0.95, 0.75, 0.35)

# Tolerances (float32 arithmetic in the plugin against float64 here).
TOL_INTEGRAL = 2e-3  # (a) grid integral against the 1D integral, absolute
TOL_SIGMAS = 5.0  # (a) Monte Carlo estimates, in standard errors
TOL_RATIO = 1e-5  # (b) relative
TOL_SYMMETRY = 2e-3  # (c) relative, where the lobe is above 1e-6 of its peak
TOL_F64 = 2e-3  # (d) relative, likewise


def lobe_cos_sin(n, u):
    """cos(alpha), sin(alpha) (float64) of the lobe's coordinate u in [0, 1)."""
    x = np.log1p(-u) / (n + 1.0)
    cos_a = np.exp(x)
    return cos_a, np.sqrt(-np.expm1(x) * (1.0 + cos_a))


def basis(r):
    """Two unit vectors completing the unit vector r (float64) to an orthonormal basis."""
    helper = np.array([1.0, 0.0, 0.0]) if abs(r[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    s = np.cross(r, helper)
    s /= np.linalg.norm(s)
    return s, np.cross(r, s)


def expected(n, c, count=1 << 21):
    """The lobe's fraction above the surface and the albedo (per unit reflectance) for a mirror
    direction at cos(theta) = c > 0 above it, as midpoint sums over u of closed forms per cone:
    on the cone of half-angle alpha, z = a + b cos(phi) with a = c cos(alpha),
    b = sin(theta) sin(alpha); z > 0 for |phi| < phi0 = acos(-a/b), so the cone's share above
    is phi0/pi and its mean of max(z, 0) is (a phi0 + b sin(phi0))/pi."""
    u = (np.arange(count) + 0.5) / count
    cos_a, sin_a = lobe_cos_sin(n, u)
    a = c * cos_a
    b = math.sqrt(max(1.0 - c * c, 0.0)) * sin_a
    with np.errstate(divide="ignore", invalid="ignore"):
        phi0 = np.where(b > np.abs(a), np.arccos(np.clip(-a / b, -1.0, 1.0)), np.where(a > 0, math.pi, 0.0))
    fraction = float(np.mean(phi0 / math.pi))
    albedo = (n + 2.0) / (n + 1.0) * float(np.mean((a * phi0 + b * np.sin(phi0)) / math.pi))
    return fraction, albedo


def f64_lobe(n, wi, wo):
    """cos^n(alpha) in float64 for float64 copies of the plugin's float32 directions (rows)."""
    r = wi * np.array([-1.0, -1.0, 1.0])
    r = r / np.linalg.norm(r, axis=-1, keepdims=True)
    w = wo / np.linalg.norm(wo, axis=-1, keepdims=True)
    cos_alpha = np.sum(r * w, axis=-1)
    # 1 - cos(alpha) without cancellation, as |r - w|^2 / 2 (float64 is ample here).
    delta = 0.5 * np.sum((r - w) ** 2, axis=-1)
    return np.where(cos_alpha > 0, np.exp(n * np.log1p(-np.minimum(delta, 1.0))), 0.0)


def rel_error(a, b, floor):
    """max |a - b| / max(|b|, floor)."""
    if a.size == 0:
        return 0.0
    return float(np.max(np.abs(a - b) / np.maximum(np.abs(b), floor)))


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--variant", default="llvm_ad_rgb", help="a JIT variant")
    ap.add_argument("--grid", type=int, default=1024, help="(a): points per axis of the lobe's (u, phi) grid")
    ap.add_argument("--samples", type=int, default=1 << 20, help="samples per exponent and view")
    ap.add_argument("--seed", type=int, default=7)
    a = ap.parse_args()

    import mitsuba as mi

    mi.set_variant(a.variant)
    import mitsuba_phong

    mitsuba_phong.register()
    ctx = mi.BSDFContext()
    rng = np.random.default_rng(a.seed)
    failures = []

    def vec(rows):
        rows = np.asarray(rows, dtype=np.float32)
        return mi.Vector3f(mi.Float(rows[:, 0]), mi.Float(rows[:, 1]), mi.Float(rows[:, 2]))

    def interaction(wi_rows):
        si = mi.SurfaceInteraction3f()
        si.wi = vec(wi_rows)
        return si

    def check(ok, what):
        """Records a failed check; returns its label (the text up to the first space) if failed."""
        if not ok:
            failures.append(what)
        return [] if ok else [what.split()[0]]

    print(f"variant {a.variant}; grid {a.grid}^2; {a.samples} samples per exponent and view; reflectance {RHO}")
    print(f"{'n':>7} {'wi.z':>6} | {'fraction':>9} {'grid':>9} {'samples':>9} | {'albedo':>8} {'E[w]':>8} {'sig':>5}"
          f" | {'(b) pdf':>8} {'w/(f/p)':>8} | {'(c) sym':>8} {'2side':>7} | {'(d) f64':>8} {'naive':>8} | result")
    for n in EXPONENTS:
        bsdf = mi.load_dict({"type": mitsuba_phong.NAME, "reflectance": list(RHO), "exponent": n})
        for z in VIEW_Z:
            # The view direction in float32, and everything expected from that float32 vector.
            s = math.sqrt(1.0 - z * z)
            wi32 = np.array([[s * math.cos(AZIMUTH), s * math.sin(AZIMUTH), z]], dtype=np.float32)
            wi = wi32[0].astype(np.float64)
            wi /= np.linalg.norm(wi)
            side = 1.0 if wi[2] >= 0 else -1.0
            fraction, albedo = expected(n, abs(wi[2]))
            si = interaction(wi32)
            failed = []

            # (a) The pdf over the lobe's (u, phi) grid, divided by the lobe's own density there.
            g = (np.arange(a.grid) + 0.5) / a.grid
            cos_a, sin_a = lobe_cos_sin(n, g)
            phi = 2.0 * math.pi * g
            r = wi * np.array([-1.0, -1.0, 1.0])
            s_axis, t_axis = basis(r)
            dirs = (sin_a[:, None, None] * (np.cos(phi)[None, :, None] * s_axis + np.sin(phi)[None, :, None] * t_axis)
                    + cos_a[:, None, None] * r).reshape(-1, 3)
            density = (n + 1.0) / (2.0 * math.pi) * np.exp(n / (n + 1.0) * np.log1p(-g))
            pdf = np.array(bsdf.pdf(ctx, si, vec(dirs))).reshape(a.grid, a.grid)
            grid_integral = float(np.mean(pdf / density[:, None]))
            failed += check(abs(grid_integral - fraction) < TOL_INTEGRAL, f"(a) pdf integral n={n} z={z}")

            # The plugin's own samples: success rate and mean weight (sample1, the component
            # choice, is unused by a one-lobe BSDF).
            u = rng.random((a.samples, 3), dtype=np.float32)
            bs, weight = bsdf.sample(ctx, si, mi.Float(u[:, 2]), mi.Point2f(mi.Float(u[:, 0]), mi.Float(u[:, 1])))
            wo = np.array(bs.wo).T
            bs_pdf = np.array(bs.pdf)
            weight = np.array(weight).T
            ok = bs_pdf > 0
            m = a.samples
            rate = float(np.mean(ok))
            rate_se = math.sqrt(max(fraction * (1 - fraction), 1.0 / m) / m)
            w0 = weight[:, 0] / RHO[0]
            mean_w, mean_se = float(np.mean(w0)), max(float(np.std(w0)) / math.sqrt(m), 1e-9)
            sigmas = max(abs(rate - fraction) / rate_se, abs(mean_w - albedo) / mean_se)
            failed += check(sigmas < TOL_SIGMAS, f"(a) samples n={n} z={z}: {sigmas:.1f} sigma")

            # (b) The sample's density and weight against pdf() and eval()/pdf() there.
            f_cos, pdf_at = (np.array(x) for x in bsdf.eval_pdf(ctx, si, bs.wo))
            f_cos = f_cos.T
            pdf_only = np.array(bsdf.pdf(ctx, si, bs.wo))
            eval_only = np.array(bsdf.eval(ctx, si, bs.wo)).T
            err_pdf = max(rel_error(bs_pdf[ok], pdf_at[ok], 1e-30), rel_error(pdf_only, pdf_at, 1e-30),
                          rel_error(eval_only, f_cos, 1e-30))
            err_ratio = rel_error(weight[ok], f_cos[ok] / pdf_at[ok, None], 1e-30)
            failed_clean = bool(np.all(weight[~ok] == 0) and np.all(f_cos[~ok] == 0))
            failed += check(err_pdf < TOL_RATIO and err_ratio < TOL_RATIO and failed_clean,
                            f"(b) sample against eval/pdf n={n} z={z}")

            # (c) f(wi, wo) = f(wo, wi); the same with both directions mirrored through the
            # surface; 0 with one of them mirrored.
            cos_o = np.abs(wo[:, 2])
            f_fwd = f_cos[:, 0] / np.where(ok, cos_o, 1.0)
            back = np.array(bsdf.eval(ctx, interaction(wo), vec(np.repeat(wi32, m, axis=0)))).T[:, 0]
            f_bwd = back / abs(wi32[0, 2])
            peak = RHO[0] * (n + 2.0) / (2.0 * math.pi)
            keep = ok & (f_fwd > 1e-6 * peak)
            err_sym = rel_error(f_bwd[keep], f_fwd[keep], 1e-30)
            flip = np.array([1.0, 1.0, -1.0], dtype=np.float32)
            si_flip = interaction(wi32 * flip)
            mirrored = np.array(bsdf.eval(ctx, si_flip, vec(wo * flip))).T
            err_two = rel_error(mirrored[ok], f_cos[ok], 1e-30)
            opposite, opposite_pdf = (np.array(x) for x in bsdf.eval_pdf(ctx, si_flip, bs.wo))
            zero_across = bool(np.all(opposite.T[ok] == 0) and np.all(opposite_pdf[ok] == 0))
            failed += check(err_sym < TOL_SYMMETRY and err_two < TOL_RATIO and zero_across,
                            f"(c) symmetry n={n} z={z}")

            # (d) f against float64 (and the naive float32 cos(alpha)^n for comparison).
            f64 = peak * f64_lobe(n, wi[None, :], wo.astype(np.float64))
            keep64 = ok & (f64 > 1e-6 * peak)
            err_f64 = rel_error(f_fwd[keep64], f64[keep64], 1e-30)
            r32 = wi32[0] * np.array([-1.0, -1.0, 1.0], dtype=np.float32)
            naive = np.float32(peak) * np.maximum(wo @ r32, np.float32(0)) ** np.float32(n)
            err_naive = rel_error(naive[keep64], f64[keep64], 1e-30)
            failed += check(err_f64 < TOL_F64, f"(d) against float64 n={n} z={z}")

            result = "FAIL " + " ".join(sorted(set(failed))) if failed else "ok"
            print(f"{n:7.0e} {side * abs(wi[2]):6.3f} | {fraction:9.6f} {grid_integral:9.6f} {rate:9.6f} |"
                  f" {albedo:8.5f} {mean_w:8.5f} {sigmas:5.1f} | {err_pdf:8.1e} {err_ratio:8.1e} |"
                  f" {err_sym:8.1e} {err_two:7.1e} | {err_f64:8.1e} {err_naive:8.1e} | {result}", flush=True)

    print("columns: fraction = the lobe's share above the surface (1D integral), grid = the plugin's pdf integrated"
          " over the lobe's coordinates, samples = the plugin's sampling success rate; albedo (1D integral) against"
          " E[w], the mean sample weight over the reflectance (sig: the worse of the two Monte Carlo deviations in"
          " standard errors); (b) max relative difference of the sample's pdf from pdf() and of its weight from"
          " eval()/pdf(); (c) of f(wo, wi) from f(wi, wo) and of f with both directions mirrored through the"
          " surface; (d) of f from float64, and of a naive float32 cos(alpha)^n from float64 (not checked)")
    if failures:
        print(f"{len(failures)} checks failed:\n  " + "\n  ".join(failures))
        sys.exit(1)
    print("all checks passed")


if __name__ == "__main__":
    main()
