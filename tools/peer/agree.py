"""Accuracy: does Mitsuba 3 render the converted bench scene as wedge does?

Two independent wedge references A, B (seeds 1, 2) and two Mitsuba images M1, M2 (seeds 1, 2),
all at the same spp. With one weight per pixel w = 1 / (r^2 + 0.01), r the mean of A and B (the
relMSE weight), D(X, Y) = mean w (X - Y)^2 has expectation
    D(M1, A) ~ var_M + var_A + bias^2,  D(M1, M2) ~ 2 var_M,  D(A, B) ~ 2 var_A,
so the ratio  D(M1, A) / ((D(M1, M2) + D(A, B)) / 2)  is 1 when the two renderers agree up to
noise and grows with any bias (a mirrored image, a wrong fov, a missing bounce). The mirrored
Mitsuba image's ratio is printed too, to show the check can fail.
"""
import os

import numpy as np

from . import runners


def weighted_d(x, y, w):
    return float(np.mean(w * (np.asarray(x, np.float64) - np.asarray(y, np.float64)) ** 2))


def agree(scene, wedge, res, spp, workdir, seed=1, log=print):
    a_path, b_path = (os.path.join(workdir, f"wedge-{k}.exr") for k in (1, 2))
    for s, p in ((seed, a_path), (seed + 1, b_path)):
        runners.wedge_render(wedge, scene, p, res, spp, s)
    A = runners.rgb_of(runners.read_exr(a_path))
    B = runners.rgb_of(runners.read_exr(b_path))
    ms = runners.MitsubaScene(scene, res, workdir=workdir)
    M1, _ = ms.render(spp, seed)
    M2, _ = ms.render(spp, seed + 1)
    for name, img in (("M1", M1), ("M2", M2)):
        bad = int(np.count_nonzero(~np.isfinite(img)))
        if bad:
            raise RuntimeError(f"Mitsuba image {name}: {bad} non-finite values")
    runners.write_exr(os.path.join(workdir, "mitsuba-1.exr"), M1)
    runners.write_exr(os.path.join(workdir, "mitsuba-2.exr"), M2)
    r = 0.5 * (A + B)
    w = 1.0 / (r * r + 0.01)
    d_ma, d_mm, d_ab = weighted_d(M1, A, w), weighted_d(M1, M2, w), weighted_d(A, B, w)
    floor = 0.5 * (d_mm + d_ab)
    ratio = d_ma / floor
    mirrored = weighted_d(M1[:, ::-1], A, w) / floor
    mean_ratio = float(np.mean(0.5 * (M1 + M2))) / float(np.mean(r))
    res_ = {"scene": os.path.basename(scene), "res": f"{res[0]}x{res[1]}", "spp": spp,
            "relmse_mitsuba_wedge": runners.relmse(M1, A), "relmse_wedge_wedge": runners.relmse(B, A),
            "var_ratio_mitsuba_over_wedge": d_mm / d_ab, "ratio": ratio, "mirrored_ratio": mirrored,
            "mean_ratio": mean_ratio}
    log(f"{res_['scene']:20s} {res_['res']} {spp} spp: relMSE(Mitsuba, wedge) {res_['relmse_mitsuba_wedge']:.3e}, "
        f"relMSE(wedge seed 2, wedge seed 1) {res_['relmse_wedge_wedge']:.3e}; "
        f"bias ratio {ratio:.3f} (1 = agreement at the noise floor; mirrored image: {mirrored:.1f}); "
        f"Mitsuba/wedge noise variance per sample {d_mm / d_ab:.2f}; mean brightness ratio {mean_ratio:.4f}")
    return res_


def noise(scene, wedges, res, spps, workdir, seed=101, log=print):
    """Per-sample efficiency without a reference: the relMSE-weighted variance of one image,
    D(X1, X2) / 2 for two renders of other seeds, per renderer and spp (weights from the
    mean of all images at the largest spp). wedges: {label: binary}."""
    ms = runners.MitsubaScene(scene, res, workdir=workdir)
    imgs = {}
    for spp in spps:
        for label, binary in wedges.items():
            pair = []
            for s in (seed, seed + 1):
                p = os.path.join(workdir, f"{label}-{spp}-{s}.exr")
                runners.wedge_render(binary, scene, p, res, spp, s)
                pair.append(runners.rgb_of(runners.read_exr(p)))
            imgs[(label, spp)] = pair
        imgs[("mitsuba", spp)] = [ms.render(spp, seed)[0], ms.render(spp, seed + 1)[0]]
    top = max(spps)
    r = np.mean([np.mean(v, axis=0) for (lab, spp), v in imgs.items() if spp == top], axis=0)
    w = 1.0 / (r * r + 0.01)
    rows = []
    labels = list(wedges) + ["mitsuba"]
    log("| spp | " + " | ".join(f"{lab} variance" for lab in labels) + " | " +
        " | ".join(f"{lab} / mitsuba" for lab in labels[:-1]) + " |")
    log("|---" * (1 + 2 * len(labels) - 1) + "|")
    for spp in spps:
        v = {lab: 0.5 * weighted_d(*imgs[(lab, spp)], w) for lab in labels}
        rows.append({"spp": spp, **v})
        log(f"| {spp} | " + " | ".join(f"{v[lab]:.3e}" for lab in labels) + " | " +
            " | ".join(f"{v[lab] / v['mitsuba']:.2f}" for lab in labels[:-1]) + " |")
    return rows
